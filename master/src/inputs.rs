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
    /// (variable index, continuous, values).
    columns: Vec<(usize, bool, Vec<f64>)>,
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
            columns.push((vi, continuous, Vec::new()));
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
                col.2.push(num(j + 1)?);
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

    fn value_at(&self, values: &[f64], continuous: bool, t: f64) -> f64 {
        let n = self.times.len();
        // the last row at or before t
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
        for (vi, continuous, values) in &self.columns {
            let var = &md.variables[*vi];
            let x = self.value_at(values, *continuous, t);
            let v = match var.ty.family() {
                Family::Real => Value::Real(x),
                Family::Boolean => Value::Boolean(x != 0.0),
                _ => Value::Integer(x as i64),
            };
            slave
                .set_value(var, &v, t)
                .map_err(|e| e.element(&self.file))?;
        }
        Ok(())
    }
}
