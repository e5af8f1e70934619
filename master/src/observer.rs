//! What is recorded, kept apart from what is computed: an observer receives the columns once
//! and then the output slots at each sampled time. `CsvFile` writes `time` and the columns,
//! row by row (flushed when the run ends, whether it ends well or not, so the rows before a
//! failure are kept); `Memory` keeps them for the Python bindings. Uses exchange.rs and error.rs.

use crate::error::{Error, Result};
use crate::exchange::{Exchange, Slot};
use std::io::Write;

/// Receives the samples of a run.
pub trait Observer {
    /// The column names (without `time`), once before the first sample.
    fn start(&mut self, columns: &[String]) -> Result<()>;
    /// One sample at time t.
    fn sample(&mut self, t: f64, x: &Exchange) -> Result<()>;
    /// The run has ended (well or not).
    fn finish(&mut self) -> Result<()>;
}

/// Writes a CSV file.
pub struct CsvFile {
    path: String,
    out: std::io::BufWriter<std::fs::File>,
    line: String,
    /// Rows written.
    pub rows: u64,
}

impl CsvFile {
    /// Creates (truncates) the file.
    pub fn create(path: &str) -> Result<CsvFile> {
        let f = std::fs::File::create(path)
            .map_err(|e| Error::new(format!("cannot write the output file: {e}")).element(path))?;
        Ok(CsvFile {
            path: path.to_string(),
            out: std::io::BufWriter::new(f),
            line: String::new(),
            rows: 0,
        })
    }
    fn io(&self, e: std::io::Error) -> Error {
        Error::new(format!("cannot write the output file: {e}")).element(&self.path)
    }
}

fn quote(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

impl Observer for CsvFile {
    fn start(&mut self, columns: &[String]) -> Result<()> {
        let mut h = String::from("time");
        for c in columns {
            h.push(',');
            h.push_str(&quote(c));
        }
        writeln!(self.out, "{h}").map_err(|e| self.io(e))
    }
    fn sample(&mut self, t: f64, x: &Exchange) -> Result<()> {
        use std::fmt::Write as _;
        self.line.clear();
        // `{:?}` writes the shortest decimal that reads back to the same f64
        let _ = write!(self.line, "{t:?}");
        for (_, slot) in &x.columns {
            self.line.push(',');
            let _ = match *slot {
                Slot::Real(i) => write!(self.line, "{:?}", x.reals[i]),
                Slot::Int(i) | Slot::Bool(i) => write!(self.line, "{}", x.ints[i]),
                Slot::UInt(i) => write!(self.line, "{}", x.ints[i] as u64),
                Slot::Str(i) => write!(self.line, "{}", quote(&x.strings[i])),
            };
        }
        self.line.push('\n');
        self.rows += 1;
        let r = self.out.write_all(self.line.as_bytes());
        r.map_err(|e| self.io(e))
    }
    fn finish(&mut self) -> Result<()> {
        let r = self.out.flush();
        r.map_err(|e| self.io(e))
    }
}

/// Keeps the samples in memory: `time` and one f64 per numeric column per row (Booleans 0/1),
/// strings apart.
#[derive(Debug, Default, Clone)]
pub struct Memory {
    /// Column names (without `time`).
    pub columns: Vec<String>,
    /// Sample times.
    pub time: Vec<f64>,
    /// Row-major values, `columns.len()` per row (NaN for a String column).
    pub values: Vec<f64>,
    /// String columns' values, row-major, one per String column per row.
    pub strings: Vec<String>,
}

impl Observer for Memory {
    fn start(&mut self, columns: &[String]) -> Result<()> {
        self.columns = columns.to_vec();
        Ok(())
    }
    fn sample(&mut self, t: f64, x: &Exchange) -> Result<()> {
        self.time.push(t);
        for (_, slot) in &x.columns {
            self.values.push(match *slot {
                Slot::Real(i) => x.reals[i],
                Slot::Int(i) | Slot::Bool(i) => x.ints[i] as f64,
                Slot::UInt(i) => x.ints[i] as u64 as f64,
                Slot::Str(i) => {
                    self.strings.push(x.strings[i].clone());
                    f64::NAN
                }
            });
        }
        Ok(())
    }
    fn finish(&mut self) -> Result<()> {
        Ok(())
    }
}
