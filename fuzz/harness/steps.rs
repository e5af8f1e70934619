//! DoStep as the program makes it, from the FMU's time (sometimes from an arbitrary one), and
//! the checks after an OK step (invariant 8: earlyReturn, lastSuccessfulTime, the FMU's time,
//! `event.time` and `event.count`). Uses `api` and `program`.

use super::api::{Api, St, StepOut, OK};
use super::program::{output_vr, Program, MAX_STEPS};

/// The FMU's time tolerance at `t` (the FMU accepts a currentCommunicationPoint this close).
fn time_tol(t: f64) -> f64 {
    1e-9 * t.abs().max(1.0)
}

impl<A: Api> Program<'_, A> {
    /// The FMU's current time when it can tell.
    fn fmu_time_opt(&mut self, i: usize) -> Option<f64> {
        let mut t = 0.0;
        let s = self.call(i, A::TIME, |c| A::time(c, &mut t));
        (s == OK).then_some(t)
    }

    /// The FMU's current time when it can tell, else 0.
    pub(super) fn fmu_time(&mut self, i: usize) -> f64 {
        self.fmu_time_opt(i).unwrap_or(0.0)
    }

    /// One DoStep from the FMU's time (sometimes from an arbitrary time) with invariant 8.
    pub(super) fn do_step(&mut self, i: usize) -> Option<St> {
        if self.steps >= MAX_STEPS {
            return None;
        }
        self.steps += 1;
        let h = self.b.step();
        let t = if self.b.u8().is_multiple_of(8) {
            self.b.real()
        } else {
            self.fmu_time(i)
        };
        self.trace.push(format!("doStep[{i}] t={t:e} h={h:e}"));
        let (s, out) = self.step_checked(i, t, h);
        self.trace.push(format!("  -> {s:?} {out:?}"));
        Some(s)
    }

    /// DoStep(t, h) with the checks of invariant 8 after OK.
    pub(super) fn step_checked(&mut self, i: usize, t: f64, h: f64) -> (St, Option<StepOut>) {
        let mut out = None;
        let s = self.call(i, A::DO_STEP, |c| {
            let (s, o) = A::do_step(c, t, h);
            out = o;
            s
        });
        if s == OK {
            self.after_step(i, t, h, out);
        }
        (s, out)
    }

    /// Invariant 8 after an OK DoStep(t, h).
    fn after_step(&mut self, i: usize, t: f64, h: f64, out: Option<StepOut>) {
        let Some(inst) = self.inst[i].as_ref() else {
            return;
        };
        let (v, early_allowed) = (inst.variant, inst.early_allowed);
        let tol = time_tol(t);
        let now = self.fmu_time_opt(i);
        let (early, last) = match out {
            Some(o) => {
                if o.event_handling_needed != 0 || o.terminate != 0 || o.early_return > 1 {
                    self.fail(format!("{} OK with {o:?}", A::DO_STEP));
                }
                let last = f64::from_bits(o.last);
                (o.early_return == 1, last)
            }
            // FMI 2.0: the FMU's time is fmi2LastSuccessfulTime
            None => (false, now.unwrap_or(f64::NAN)),
        };
        if early {
            self.early_returns += 1;
            if !early_allowed {
                self.fail(format!(
                    "{} returned early without earlyReturnAllowed",
                    A::DO_STEP
                ));
            }
            if !(last > t && last < t + h) {
                self.fail(format!(
                    "{} returned early at lastSuccessfulTime {last:e} outside ({t:e}, {:e})",
                    A::DO_STEP,
                    t + h
                ));
            }
        } else if (last - (t + h)).abs() > tol || last.is_nan() {
            self.fail(format!(
                "{} OK without early return but lastSuccessfulTime {last:e} != t + h = {:e}",
                A::DO_STEP,
                t + h
            ));
        }
        if now.map(f64::to_bits) != Some(last.to_bits()) {
            self.fail(format!(
                "after {} the FMU's time {now:?} is not lastSuccessfulTime {last:e}",
                A::DO_STEP
            ));
        }
        if let Some(vr) = output_vr(v, "event.time") {
            let mut et = f64::NAN;
            let s = self.call(i, A::GET_REAL, |c| A::get_real(c, &vr, 1, &mut et));
            if s != OK {
                self.fail(format!("event.time not readable after an OK step: {s:?}"));
            }
            let inside = (et > t || et == t + h) && et <= t + h + tol;
            if !inside || (early && et != last) {
                self.fail(format!(
                    "event.time {et:e} after a step ({t:e}, {h:e}) (early return {early}, lastSuccessfulTime {last:e})"
                ));
            }
        }
        if let Some(vr) = output_vr(v, "event.count") {
            let mut n = i32::MIN;
            let s = self.call(i, A::GET_INT, |c| A::get_int(c, &vr, 1, &mut n));
            if s != OK || n < 0 || (early && n < 1) {
                self.fail(format!(
                    "event.count {n} ({s:?}) after a step (early return {early})"
                ));
            }
        }
    }
}
