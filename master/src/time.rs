//! Time on a grid of integer ticks: the communication point k is t_k = t_0 + k·H, computed
//! here and nowhere else, and the step from t_k is h_k = t_(k+1) − t_k. The default grid is
//! `Exact` (h_k = H exactly, t_k = t_0 + k·H as one product); the three others reproduce the
//! grids of fmusim (`Difference`: the same t_k, h_k = t_(k+1) − t_k), libcosim (integer
//! nanoseconds: t_k = t_0 + k·ns/1e9) and Ecos (the float sum t_(k+1) = t_k + H, steps of H),
//! so that runs can be compared on the same points.
//! Uses error.rs.

use crate::error::{Error, Result};

/// How the communication points are computed from the step count k.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GridKind {
    /// t_k = t_0 + k·H, h_k = H.
    Exact,
    /// fmusim: t_k = t_0 + k·H, h_k = t_(k+1) − t_k.
    Difference,
    /// libcosim: t_k = t_0 + (k·H_ns)/1e9 with H_ns = H in whole nanoseconds, h_k = t_(k+1) − t_k.
    Nanoseconds,
    /// Ecos: t_(k+1) = t_k + H, h_k = H.
    Sum,
}

impl GridKind {
    /// Parses `exact`, `diff`, `ns` or `sum`.
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "exact" => Ok(GridKind::Exact),
            "diff" => Ok(GridKind::Difference),
            "ns" => Ok(GridKind::Nanoseconds),
            "sum" => Ok(GridKind::Sum),
            other => Err(Error::new(format!(
                "unknown time grid '{other}'; there are: exact, diff, ns, sum"
            ))),
        }
    }
}

/// The time grid of one run: N steps of H from t_0.
#[derive(Debug, Clone)]
pub struct Grid {
    kind: GridKind,
    t0: f64,
    step: f64,
    steps: u64,
    ns: i64,
    sum: f64,
}

impl Grid {
    /// The grid from `start` to `stop` in steps of `step`; `step` must divide `stop − start`
    /// to 1e-9 relative (a run ends on its stop time, never a step short or long).
    pub fn new(kind: GridKind, start: f64, stop: f64, step: f64) -> Result<Self> {
        if !(step.is_finite() && step > 0.0) {
            return Err(Error::new(format!(
                "the step must be a positive number, not {step}"
            )));
        }
        if !(start.is_finite() && stop.is_finite() && stop > start) {
            return Err(Error::new(format!(
                "the stop time {stop} must be a number after the start time {start}"
            )));
        }
        let span = stop - start;
        let n = (span / step).round();
        if n < 1.0 || (n * step - span).abs() > 1e-9 * span {
            return Err(Error::new(format!(
                "the step {step} does not divide the time from {start} to {stop} into whole steps"
            )));
        }
        let ns = (step * 1e9).round();
        if kind == GridKind::Nanoseconds
            && (ns < 1.0 || (ns - step * 1e9).abs() > 1e-6 * step * 1e9)
        {
            return Err(Error::new(format!(
                "the ns grid needs a whole number of nanoseconds, not {step} s"
            )));
        }
        Ok(Grid {
            kind,
            t0: start,
            step,
            steps: n as u64,
            ns: ns as i64,
            sum: start,
        })
    }

    /// The number of steps N.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The nominal step H.
    pub fn step(&self) -> f64 {
        self.step
    }

    /// t_k. For the `Sum` grid, k must be the last point asked for or the next one (the sum is
    /// carried along); the execution asks in order.
    pub fn time(&mut self, k: u64) -> f64 {
        match self.kind {
            GridKind::Exact | GridKind::Difference => self.t0 + k as f64 * self.step,
            GridKind::Nanoseconds => self.t0 + ((k as i64 * self.ns) as f64) / 1e9,
            GridKind::Sum => self.sum,
        }
    }

    /// (t_k, h_k) of step k, and moves the `Sum` grid on to t_(k+1).
    pub fn advance(&mut self, k: u64) -> (f64, f64) {
        let t = self.time(k);
        match self.kind {
            GridKind::Exact => (t, self.step),
            GridKind::Difference => (t, self.t0 + (k + 1) as f64 * self.step - t),
            GridKind::Nanoseconds => {
                let next = self.t0 + (((k + 1) as i64 * self.ns) as f64) / 1e9;
                (t, next - t)
            }
            GridKind::Sum => {
                self.sum = t + self.step;
                (t, self.step)
            }
        }
    }

    /// How many steps make the sampling interval `dt` (it must be a whole number of steps).
    pub fn steps_per_sample(&self, dt: f64) -> Result<u64> {
        let m = (dt / self.step).round();
        if !(dt.is_finite() && m >= 1.0 && (m * self.step - dt).abs() <= 1e-9 * dt) {
            return Err(Error::new(format!(
                "the output interval {dt} is not a whole number of steps of {}",
                self.step
            )));
        }
        Ok(m as u64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_grid_is_k_times_h() {
        let mut g = Grid::new(GridKind::Exact, 0.0, 1.0, 0.1).unwrap();
        assert_eq!(g.steps(), 10);
        assert_eq!(g.advance(3), (3.0 * 0.1, 0.1));
    }

    #[test]
    fn sum_grid_adds_h() {
        let mut g = Grid::new(GridKind::Sum, 0.0, 1.0, 0.1).unwrap();
        let mut t = 0.0;
        for k in 0..10 {
            assert_eq!(g.advance(k).0, t);
            t += 0.1;
        }
    }

    #[test]
    fn ns_grid_is_libcosims() {
        let mut g = Grid::new(GridKind::Nanoseconds, 0.0, 1.0, 1e-3).unwrap();
        let (t, h) = g.advance(7);
        assert_eq!(t, (7 * 1_000_000) as f64 / 1e9);
        assert_eq!(h, (8 * 1_000_000) as f64 / 1e9 - t);
    }

    #[test]
    fn a_step_that_does_not_divide_is_refused() {
        assert!(Grid::new(GridKind::Exact, 0.0, 1.0, 0.3).is_err());
        let g = Grid::new(GridKind::Exact, 0.0, 1.0, 0.1).unwrap();
        assert_eq!(g.steps_per_sample(0.2).unwrap(), 2);
        assert!(g.steps_per_sample(0.15).is_err());
    }
}
