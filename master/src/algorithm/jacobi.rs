//! Fixed-step Jacobi: every component steps from t to t + h on the inputs set at t, then every
//! output is read and every connection carries it to its input, ready for the next step (as
//! libcosim's fixed_step_algorithm and Ecos do). Uses slave.rs, exchange.rs and error.rs.

use crate::error::Result;
use crate::exchange::Exchange;
use crate::slave::{Slave, StepEnd};

/// One step; `Some(c)` when component c asked to end the simulation (every component still
/// completes the step).
pub fn step(slaves: &mut [Slave], x: &mut Exchange, t: f64, h: f64) -> Result<Option<usize>> {
    let mut ends = None;
    for (c, s) in slaves.iter_mut().enumerate() {
        if s.do_step(t, h)? == StepEnd::Terminate && ends.is_none() {
            ends = Some(c);
        }
    }
    let next = t + h;
    for c in 0..slaves.len() {
        x.read(slaves, c, next)?;
    }
    for c in 0..slaves.len() {
        x.write(slaves, c, next)?;
    }
    Ok(ends)
}
