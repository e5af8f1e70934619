//! The time loop: instantiate every component, set its parameters and start values,
//! initialise the system (connections carried in Initialization Mode until they settle),
//! then step on the integer grid of time.rs with the chosen method, telling the observer at
//! each sampled point. A failure after the first sample ends the run with the error in the
//! outcome and the observer's rows kept; a component asking to terminate ends it normally.
//! Uses structure.rs, slave.rs, exchange.rs, algorithm/, order.rs, time.rs, inputs.rs,
//! observer.rs and error.rs.

use crate::algorithm::{gauss_seidel, jacobi, Method};
use crate::error::{Error, Result};
use crate::exchange::Exchange;
use crate::inputs::InputTable;
use crate::observer::Observer;
use crate::order;
use crate::slave::Slave;
use crate::structure::System;
use crate::time::{Grid, GridKind};
use std::time::{Duration, Instant};

/// How to run.
#[derive(Debug, Clone)]
pub struct Settings {
    /// The coupling method.
    pub method: Method,
    /// The communication step H (default: the archive's base step or the FMU's stepSize).
    pub step: Option<f64>,
    /// The stop time (default: the DefaultExperiment's).
    pub stop: Option<f64>,
    /// The sampling interval (default: every communication point).
    pub interval: Option<f64>,
    /// The time grid.
    pub grid: GridKind,
    /// Time the FMI calls (the master's own time against the FMUs').
    pub profile: bool,
    /// Echo what the FMUs log.
    pub log: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            method: Method::Jacobi,
            step: None,
            stop: None,
            interval: None,
            grid: GridKind::Exact,
            profile: false,
            log: false,
        }
    }
}

/// How a run went.
#[derive(Debug, Clone, Default)]
pub struct Outcome {
    /// Steps completed.
    pub steps: u64,
    /// The communication step.
    pub step: f64,
    /// FMI calls made, all components.
    pub calls: u64,
    /// CPU seconds of the stepping loop (process CPU, every thread).
    pub cpu: f64,
    /// Wall seconds of the stepping loop.
    pub wall: f64,
    /// Wall seconds inside the FMUs' functions during the loop (when profiling).
    pub fmu_time: f64,
    /// The start time.
    pub start: f64,
    /// The time reached.
    pub end: f64,
    /// Samples written.
    pub rows: u64,
    /// The component that asked to terminate, and when.
    pub terminated: Option<(String, f64)>,
    /// The failure that ended the run, if any.
    pub error: Option<Error>,
}

impl Outcome {
    /// CPU seconds per simulated second.
    pub fn cpu_per_second(&self) -> f64 {
        let span = self.end - self.start;
        if span > 0.0 {
            self.cpu / span
        } else {
            0.0
        }
    }
}

fn settle(slaves: &mut [Slave], x: &mut Exchange, t: f64) -> Result<()> {
    let n = slaves.len();
    let mut prev: Option<Vec<u64>> = None;
    for _ in 0..=n {
        for c in 0..n {
            x.read(slaves, c, t)?;
        }
        let now = x.inputs_snapshot();
        if prev.as_ref() == Some(&now) {
            break;
        }
        for c in 0..n {
            x.write(slaves, c, t)?;
        }
        prev = Some(now);
    }
    Ok(())
}

/// Instantiates and initialises the system; the slaves, exchange and grid, ready to step.
fn initialise(
    sys: &System,
    s: &Settings,
    inputs: Option<&InputTable>,
) -> Result<(Vec<Slave>, Exchange, Grid, f64)> {
    let start = sys.start.unwrap_or(0.0);
    let stop = s.stop.or(sys.stop).ok_or_else(|| {
        Error::new(
            "no stop time: the archive or FMU has no DefaultExperiment stopTime; give --stop",
        )
    })?;
    let step = s
        .step
        .or(sys.step)
        .ok_or_else(|| Error::new("no step: the archive or FMU names none; give --step"))?;
    let grid = Grid::new(s.grid, start, stop, step)?;
    let mut x = Exchange::new(sys)?;
    let mut slaves = Vec::with_capacity(sys.components.len());
    for comp in &sys.components {
        let fmu = &sys.fmus[comp.fmu];
        let mut slave = Slave::new(fmu, &comp.name, s.log)
            .map_err(|e| e.component(&comp.name).element(&fmu.source).at(start))?;
        slave.profile = s.profile;
        slave.setup(start, Some(stop))?;
        for sv in &comp.starts {
            let var = &fmu.md.variables[sv.var];
            slave
                .set_value(var, &sv.value, start)
                .map_err(|e| e.element(&sv.origin))?;
        }
        slaves.push(slave);
    }
    if let (Some(table), Some(slave)) = (inputs, slaves.first_mut()) {
        table.apply(slave, start)?;
    }
    for slave in &mut slaves {
        slave.enter_initialization()?;
    }
    settle(&mut slaves, &mut x, start)?;
    for slave in &mut slaves {
        slave.exit_initialization()?;
    }
    for c in 0..slaves.len() {
        x.read(&mut slaves, c, start)?;
    }
    Ok((slaves, x, grid, start))
}

/// Runs the system; `Err` only for what fails before the first sample (settings,
/// instantiation, initialization), everything later is `Outcome::error`.
pub fn run(
    sys: &System,
    s: &Settings,
    inputs: Option<&InputTable>,
    observer: &mut dyn Observer,
) -> Result<Outcome> {
    let order = match s.method {
        Method::GaussSeidel => order::gauss_seidel(sys)?,
        Method::Jacobi => (0..sys.components.len()).collect(),
    };
    let (mut slaves, mut x, mut grid, start) = initialise(sys, s, inputs)?;
    let every = match s.interval {
        Some(dt) => grid.steps_per_sample(dt)?,
        None => 1,
    };
    let names: Vec<String> = x.columns.iter().map(|(n, _)| n.clone()).collect();
    observer.start(&names)?;
    observer.sample(start, &x)?;
    let mut out = Outcome {
        step: grid.step(),
        start,
        end: start,
        rows: 1,
        ..Default::default()
    };
    for slave in &mut slaves {
        slave.fmu_time = Duration::ZERO;
    }
    let cpu = cpu_time::ProcessTime::now();
    let wall = Instant::now();
    let n = grid.steps();
    for k in 0..n {
        let (t, h) = grid.advance(k);
        let r = (|| -> Result<Option<usize>> {
            if let (Some(table), Some(slave)) = (inputs, slaves.first_mut()) {
                table.apply(slave, t)?;
            }
            match s.method {
                Method::Jacobi => jacobi::step(&mut slaves, &mut x, t, h),
                Method::GaussSeidel => gauss_seidel::step(&mut slaves, &mut x, &order, t, h),
            }
        })();
        match r {
            Err(e) => {
                out.error = Some(e.at(t));
                break;
            }
            Ok(ends) => {
                out.steps = k + 1;
                out.end = grid.time(k + 1);
                if ends.is_some() || (k + 1) % every == 0 {
                    if let Err(e) = observer.sample(out.end, &x) {
                        out.error = Some(e);
                        break;
                    }
                    out.rows += 1;
                }
                if let Some(c) = ends {
                    out.terminated = Some((sys.components[c].name.clone(), out.end));
                    break;
                }
            }
        }
    }
    out.cpu = cpu.elapsed().as_secs_f64();
    out.wall = wall.elapsed().as_secs_f64();
    out.fmu_time = slaves.iter().map(|s| s.fmu_time.as_secs_f64()).sum();
    if out.error.is_none() {
        for slave in &mut slaves {
            if let Err(e) = slave.terminate() {
                out.error = Some(e.at(out.end));
                break;
            }
        }
    }
    out.calls = slaves.iter().map(|s| s.calls).sum();
    if let Err(e) = observer.finish() {
        out.error.get_or_insert(e);
    }
    Ok(out)
}
