//! An input file for a lone FMU, as fmusim reads it: a CSV whose first column is time and whose
//! header names the FMU's inputs. At each communication point t the inputs are set to the
//! file's value at t: continuous Reals interpolated linearly between rows (at a repeated time,
//! the later row), every other input held from the last row at or before t; before the first
//! row the first, after the last the last. Uses slave.rs, model_description.rs and error.rs.

use crate::error::{Error, Result};
use crate::model_description::{Causality, Family, ModelDescription, Variability};
use crate::slave::{Slave, Value};

/// The input file, by column.
#[derive(Debug, Clone)]
pub struct InputTable {
    file: String,
    times: Vec<f64>,
    columns: Vec<Column>,
}

/// One input's values, as numbers (Reals) or exact integers (every integer type and Boolean,
/// UInt64 as its bits in an i64).
#[derive(Debug, Clone)]
struct Column {
    var: usize,
    continuous: bool,
    reals: Vec<f64>,
    ints: Vec<i64>,
}

impl InputTable {
    /// Reads the CSV `text` (named `file` in messages) against the FMU's inputs.
    pub fn parse(text: &str, file: &str, md: &ModelDescription) -> Result<InputTable> {
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let header = lines
            .next()
            .ok_or_else(|| Error::new("the input file is empty").element(file))?;
        let names: Vec<String> = header
            .split(',')
            .map(|s| s.trim().trim_matches('"').to_string())
            .collect();
        let mut columns = Vec::new();
        for name in names.iter().skip(1) {
            let (vi, var) = md.variable(name).ok_or_else(|| {
                Error::new("the input file names a variable the FMU does not have")
                    .element(file)
                    .variable(name)
            })?;
            if var.causality != Causality::Input {
                return Err(Error::new(format!(
                    "the input file sets it, but it is a {} variable, not an input",
                    var.causality.name()
                ))
                .element(file)
                .variable(name));
            }
            if !matches!(
                var.ty.family(),
                Family::Real | Family::Integer | Family::Boolean
            ) {
                return Err(
                    Error::new(format!("{:?} inputs cannot be read from a file", var.ty))
                        .element(file)
                        .variable(name),
                );
            }
            let continuous =
                var.ty.family() == Family::Real && var.variability == Variability::Continuous;
            columns.push(Column {
                var: vi,
                continuous,
                reals: Vec::new(),
                ints: Vec::new(),
            });
        }
        let mut times = Vec::new();
        for (n, line) in lines.enumerate() {
            let cells: Vec<&str> = line.split(',').collect();
            if cells.len() != names.len() {
                return Err(Error::new(format!(
                    "row {} has {} cells, the header {}",
                    n + 2,
                    cells.len(),
                    names.len()
                ))
                .element(file));
            }
            let num = |i: usize| -> Result<f64> {
                let c = cells[i].trim();
                match c {
                    "true" => Ok(1.0),
                    "false" => Ok(0.0),
                    _ => c.parse::<f64>().map_err(|_| {
                        Error::new(format!("row {}: '{c}' is not a number", n + 2))
                            .element(file)
                            .variable(&names[i])
                    }),
                }
            };
            let t = num(0)?;
            if times.last().is_some_and(|&last| t < last) {
                return Err(Error::new(format!("row {}: time {t} goes back", n + 2)).element(file));
            }
            times.push(t);
            for (j, col) in columns.iter_mut().enumerate() {
                let var = &md.variables[col.var];
                if var.ty.family() == Family::Real {
                    col.reals.push(num(j + 1)?);
                } else {
                    let c = cells[j + 1].trim();
                    let n: i128 = match c {
                        "true" => 1,
                        "false" => 0,
                        _ => c
                            .parse::<i128>()
                            .or_else(|_| num(j + 1).map(|x| x as i128))?,
                    };
                    let bits = if var.ty == crate::model_description::VarType::UInt64 {
                        u64::try_from(n).map(|u| u as i64).ok()
                    } else {
                        i64::try_from(n).ok()
                    };
                    col.ints.push(bits.ok_or_else(|| {
                        Error::new(format!(
                            "row {}: {n} is out of the range of {:?}",
                            n + 2,
                            var.ty
                        ))
                        .element(file)
                        .variable(&names[j + 1])
                    })?);
                }
            }
        }
        if times.is_empty() {
            return Err(Error::new("the input file has no rows").element(file));
        }
        Ok(InputTable {
            file: file.to_string(),
            times,
            columns,
        })
    }

    /// The index of the last row at or before t (0 before the first).
    fn row(&self, t: f64) -> usize {
        self.times.partition_point(|&x| x <= t).max(1) - 1
    }

    fn value_at(&self, values: &[f64], continuous: bool, t: f64) -> f64 {
        let n = self.times.len();
        let i = self.times.partition_point(|&x| x <= t);
        if i == 0 {
            return values[0];
        }
        if i == n || !continuous {
            return values[i - 1];
        }
        let (t0, t1) = (self.times[i - 1], self.times[i]);
        let (y0, y1) = (values[i - 1], values[i]);
        if t1 == t0 {
            y1
        } else {
            y0 + (y1 - y0) * (t - t0) / (t1 - t0)
        }
    }

    /// Sets the slave's inputs to their values at t.
    pub fn apply(&self, slave: &mut Slave, t: f64) -> Result<()> {
        let md = std::sync::Arc::clone(&slave.md);
        for col in &self.columns {
            let var = &md.variables[col.var];
            let v = match var.ty.family() {
                Family::Real => Value::Real(self.value_at(&col.reals, col.continuous, t)),
                Family::Boolean => Value::Boolean(col.ints[self.row(t)] != 0),
                _ => Value::Integer(col.ints[self.row(t)]),
            };
            slave
                .set_value(var, &v, t)
                .map_err(|e| e.element(&self.file))?;
        }
        Ok(())
    }
}
