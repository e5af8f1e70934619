//! The command line: `master run ARCHIVE.ssp|MODEL.fmu --method jacobi|gauss_seidel --step H
//! [--stop T] [--start COMPONENT.VARIABLE=VALUE ...] [--interval DT] [--input FILE.csv]
//! [--grid exact|diff|ns|sum] [--profile] [--log] --out FILE.csv`. Parses the arguments, runs, writes
//! the CSV and prints one summary line; returns the exit status. Uses the crate's public API.

use crate::algorithm::Method;
use crate::error::{Error, Result};
use crate::execution::{self, Outcome, Settings};
use crate::inputs::InputTable;
use crate::observer::CsvFile;
use crate::structure::System;
use crate::time::GridKind;
use std::path::PathBuf;

/// The usage text.
pub const USAGE: &str =
    "usage: master run ARCHIVE.ssp|MODEL.fmu [--method jacobi|gauss_seidel] [--step H] [--stop T]
                  [--start COMPONENT.VARIABLE=VALUE ...] [--interval DT] [--input FILE.csv]
                  [--grid exact|diff|ns|sum] [--profile] [--log] --out FILE.csv";

/// Parsed arguments of `run`.
#[derive(Debug, Clone)]
pub struct Args {
    /// The archive or FMU.
    pub path: PathBuf,
    /// Settings.
    pub settings: Settings,
    /// `--start` assignments.
    pub starts: Vec<(String, String)>,
    /// `--input`.
    pub input: Option<String>,
    /// `--out`.
    pub out: String,
}

fn number(flag: &str, v: &str) -> Result<f64> {
    v.parse::<f64>()
        .map_err(|_| Error::new(format!("{flag} wants a number, not '{v}'")))
}

/// Parses the arguments after the program name.
pub fn parse(args: &[String]) -> Result<Args> {
    let mut it = args.iter();
    match it.next().map(String::as_str) {
        Some("run") => {}
        Some(other) => return Err(Error::new(format!("unknown command '{other}'\n{USAGE}"))),
        None => return Err(Error::new(USAGE)),
    }
    let mut path = None;
    let mut settings = Settings::default();
    let (mut starts, mut input, mut out) = (Vec::new(), None, None);
    while let Some(a) = it.next() {
        let mut value = |flag: &str| {
            it.next()
                .cloned()
                .ok_or_else(|| Error::new(format!("{flag} needs a value\n{USAGE}")))
        };
        match a.as_str() {
            "--method" => settings.method = Method::parse(&value(a)?)?,
            "--step" => settings.step = Some(number(a, &value(a)?)?),
            "--stop" => settings.stop = Some(number(a, &value(a)?)?),
            "--interval" => settings.interval = Some(number(a, &value(a)?)?),
            "--grid" => settings.grid = GridKind::parse(&value(a)?)?,
            "--input" => input = Some(value(a)?),
            "--out" => out = Some(value(a)?),
            "--profile" => settings.profile = true,
            "--log" => settings.log = true,
            "--start" => {
                let v = value(a)?;
                let (name, val) = v.split_once('=').ok_or_else(|| {
                    Error::new(format!("--start wants COMPONENT.VARIABLE=VALUE, not '{v}'"))
                })?;
                starts.push((name.to_string(), val.to_string()));
            }
            flag if flag.starts_with("--") => {
                return Err(Error::new(format!("unknown option {flag}\n{USAGE}")))
            }
            p if path.is_none() => path = Some(PathBuf::from(p)),
            extra => {
                return Err(Error::new(format!(
                    "unexpected argument '{extra}'\n{USAGE}"
                )))
            }
        }
    }
    let path = path.ok_or_else(|| Error::new(format!("no archive or FMU given\n{USAGE}")))?;
    let out = out.ok_or_else(|| Error::new(format!("--out FILE.csv is required\n{USAGE}")))?;
    Ok(Args {
        path,
        settings,
        starts,
        input,
        out,
    })
}

/// Opens the system, applies the start values and reads the input file.
pub fn prepare(
    path: &std::path::Path,
    starts: &[(String, String)],
    input: Option<&str>,
) -> Result<(System, Option<InputTable>)> {
    let mut sys = System::open(path)?;
    for (name, value) in starts {
        sys.add_start(name, value, "--start")?;
    }
    let table = match input {
        None => None,
        Some(file) => {
            if !sys.lone {
                return Err(Error::new("an input file drives a lone FMU; an archive's inputs come from its connections").element(file));
            }
            let text = std::fs::read_to_string(file)
                .map_err(|e| Error::new(format!("cannot read it: {e}")).element(file))?;
            Some(InputTable::parse(&text, file, sys.md(0))?)
        }
    };
    Ok((sys, table))
}

/// The summary line of a run.
pub fn summary(sys: &System, s: &Settings, o: &Outcome, out: &str) -> String {
    let mut line = format!(
        "{}: {} steps of {} s to t = {}, {}: {} FMI calls, CPU {:.3e} s per simulated second; {} rows in {out}",
        sys.name,
        o.steps,
        o.step,
        o.end,
        s.method.name(),
        o.calls,
        o.cpu_per_second(),
        o.rows
    );
    if s.profile {
        line.push_str(&format!(
            "; wall {:.3e} s, in the FMUs {:.3e} s, the master's own {:.3e} s",
            o.wall,
            o.fmu_time,
            o.wall - o.fmu_time
        ));
    }
    if let Some((c, t)) = &o.terminated {
        line.push_str(&format!(
            "; component '{c}' asked to terminate at t = {t}: a normal end"
        ));
    }
    line
}

/// Runs the command line; the exit status.
pub fn main(args: &[String]) -> i32 {
    let a = match parse(args) {
        Ok(a) => a,
        Err(e) => {
            eprintln!("master: {e}");
            return 2;
        }
    };
    let (sys, table) = match prepare(&a.path, &a.starts, a.input.as_deref()) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("master: {e}");
            return 1;
        }
    };
    let mut csv = match CsvFile::create(&a.out) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("master: {e}");
            return 1;
        }
    };
    match execution::run(&sys, &a.settings, table.as_ref(), &mut csv) {
        Err(e) => {
            let _ = std::fs::remove_file(&a.out);
            eprintln!("master: {e}");
            1
        }
        Ok(o) => {
            println!("{}", summary(&sys, &a.settings, &o, &a.out));
            match &o.error {
                Some(e) => {
                    eprintln!("master: {e} (the {} rows before are in {})", o.rows, a.out);
                    1
                }
                None => 0,
            }
        }
    }
}
