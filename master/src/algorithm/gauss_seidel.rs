//! Fixed-step Gauss-Seidel: the components step one after the other in the order of order.rs,
//! each from the newest outputs of the components before it (their values at t + h) and the
//! values at t of those after it. Uses slave.rs, exchange.rs and error.rs.

use crate::error::Result;
use crate::exchange::Exchange;
use crate::slave::{Slave, StepEnd};

/// One step in `order`; `Some(c)` when component c asked to end the simulation.
pub fn step(
    slaves: &mut [Slave],
    x: &mut Exchange,
    order: &[usize],
    t: f64,
    h: f64,
) -> Result<Option<usize>> {
    let mut ends = None;
    for &c in order {
        x.write(slaves, c, t)?;
        if slaves[c].do_step(t, h)? == StepEnd::Terminate && ends.is_none() {
            ends = Some(c);
        }
        x.read(slaves, c, t + h)?;
    }
    Ok(ends)
}
