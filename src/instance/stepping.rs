//! fmi2DoStep: advance from t to t + h along the input extrapolation; the step's status.
//!
//! Uses the instance (mod.rs), the model's access rules, snapshot and table, and the physics' step
//! and events; nothing below the instance uses it.

use super::ModelInstance;
use super::{singular_text, Call, FmiVersion};
use crate::error::{Category, FmuError, FmuResult, Level};
use crate::model::access::{nodes_into, non_finite_cause, write_node};
use crate::model::snapshot::{EventRecord, LastEvent, Mode};
use crate::model::variables::POSE_TWIST;
use crate::physics::connector::{Extrapolation, State};
use crate::physics::events::{self, Values, EVENT_TOL};
use crate::physics::kinematics::Node;
use crate::physics::math::Real;
use crate::physics::step::{advance_into, Ends, Met, Rates, StepError, Tracking};

impl ModelInstance {
    /// Extrapolation rates of node n for a step from t (hold; linear from the input
    /// derivatives where set and the node's own velocities elsewhere; second order, with the
    /// accelerations from the velocity inputs of the previous communication point where no
    /// input derivative gives them; or second order along the acceleration inputs).
    #[inline]
    fn rates(&self, n: usize, node: &Node, t: Real) -> Rates {
        if self.s.params.extrapolation == Extrapolation::Linear
            && self.s.input_der_set[n] == [false; POSE_TWIST]
        {
            // the usual case, inline: along the node's own velocities
            return Rates::from_velocities(node);
        }
        self.rates_general(n, node, t)
    }

    /// `rates` in general (input derivatives, second order, accelerations), out of line.
    #[inline(never)]
    fn rates_general(&self, n: usize, node: &Node, t: Real) -> Rates {
        let (q, der, set) = (
            &self.s.inputs[n][3..7],
            &self.s.input_der[n],
            &self.s.input_der_set[n],
        );
        match self.s.params.extrapolation {
            Extrapolation::Hold => Rates::HOLD,
            Extrapolation::Linear => Rates::linear(node, q, der, set),
            Extrapolation::Quadratic => {
                let prev = self
                    .s
                    .history
                    .as_ref()
                    .filter(|(t0, _)| t > *t0)
                    .map(|(t0, vel)| (t - t0, &vel[n]));
                Rates::quadratic(node, q, der, set, prev)
            }
            Extrapolation::Accelerations => {
                let acc = std::array::from_fn(|i| self.s.inputs[n][POSE_TWIST + i]);
                Rates::along(node, q, der, set, &acc)
            }
        }
    }

    /// fmi2DoStep / fmi3DoStep: advance from t to t + h along the input extrapolation,
    /// locating the events on the way; with early return (FMI 3.0's earlyReturnAllowed) the
    /// step ends at the first one. Returns whether it did (the FMU's time is then the event's).
    pub fn do_step(&mut self, t: Real, h: Real) -> FmuResult<bool> {
        self.allowed(Call::DoStep)?;
        if !h.is_finite() || h <= 0.0 {
            return Err(FmuError::error(format!(
                "communicationStepSize {h:?} must be finite and > 0"
            )));
        }
        let tol = 1e-9 * t.abs().max(1.0);
        if !t.is_finite() || (t - self.s.time).abs() > tol {
            return Err(FmuError::error(format!(
                "currentCommunicationPoint {t:?} does not match the FMU time {:?}",
                self.s.time
            )));
        }
        if !(t + h).is_finite() {
            return Err(FmuError::error(format!(
                "the step's end currentCommunicationPoint + communicationStepSize = {t:?} + {h:?} is not finite"
            )));
        }
        let mut nodes = [Node::default(); 2];
        nodes_into(&self.s.inputs, &mut nodes)?;
        let [a, b] = &nodes;
        let (ra, rb) = (self.rates(0, a, t), self.rates(1, b, t));
        let before = self.wants(Category::Events).then_some(self.s.state);
        // the event functions at the step's start: from the outputs at its inputs where the
        // last step's are at hand (state) or the values are needed; the sides at the last
        // step's end where every function was far from its event there (`events::far`),
        // whether or not a read left its outputs in the cache (a memo: the step must not
        // depend on it); where the outputs cannot be evaluated the step below reports why
        let exact: Values;
        let start: Option<(&Values, bool)> = if !events::tracked(self.ct, &self.s.params) {
            None
        } else {
            match (&self.s.events, self.s.outputs.stepped()) {
                (Some(r), None) if r.far => Some((&r.end, false)),
                _ => match self.outputs_keeping(false) {
                    Ok(_) => match self.s.outputs.get() {
                        Some(o) => {
                            exact = events::values(self.ct, &self.s.params, &self.s.state, o);
                            Some((&exact, true))
                        }
                        None => None,
                    },
                    Err(_) => None,
                },
            }
        };
        let track = start.map(|(start, exact)| Tracking {
            start,
            exact,
            stop_at_first: self.early_return,
            // an event within the location tolerance of the start is met there, not stopped
            // at; and the time must move on
            min_tau: (2.0 * Real::EPSILON * t.abs()).max(EVENT_TOL * h),
            t0: t,
        });
        // the outputs at t + h are evaluated into the cache's spare buffer: it becomes the
        // cache when the step is accepted, and a refused step leaves the cache as it was
        let mut next = State::default();
        let mut ends = [Node::default(); 2];
        match advance_into(
            self.ct,
            &self.s.params,
            &self.s.state,
            (a, &ra),
            (b, &rb),
            h,
            track,
            Ends {
                outputs: self.s.outputs.spare(),
                state: &mut next,
                nodes: &mut ends,
                events: &mut self.event_end,
            },
        ) {
            Ok(met) => {
                let end = &self.event_end;
                let far = start.map(|(start, _)| events::far_on(&end.v, end.on, start));
                if self.s.params.extrapolation == Extrapolation::Quadratic {
                    // the accelerations of the next step come from this step's start, also
                    // across an event (a body's acceleration is continuous where a friction
                    // effect or a stop elsewhere changes; where the event changes it, an FMI 2.0
                    // importer can give it as input derivatives)
                    let vel = |n: usize| {
                        let x = &self.s.inputs[n];
                        [x[7], x[8], x[9], x[10], x[11], x[12]]
                    };
                    self.s.history = Some((t, [vel(0), vel(1)]));
                }
                self.s.state = next;
                self.s.time = if met.stopped { t + met.tau } else { t + h };
                self.s.event = LastEvent {
                    time: t + met.tau,
                    count: met.count as i32,
                };
                let o = self.s.outputs.spare();
                (o.event_time, o.event_count) = (self.s.event.time, self.s.event.count);
                // the event functions at this step's end, and whether each is far from its
                // event, judged by its change since the start (exact, or the last step's end)
                match (far, &mut self.s.events) {
                    // in place: the record is as large as the functions' values
                    (Some(far), Some(r)) => (r.end, r.far) = (self.event_end.v, far),
                    (far, events) => {
                        *events = far.map(|far| EventRecord {
                            end: self.event_end.v,
                            far,
                        })
                    }
                }
                write_node(&mut self.s.inputs[0], &ends[0]);
                write_node(&mut self.s.inputs[1], &ends[1]);
                self.s.input_der_set = [[false; POSE_TWIST]; 2];
                // the outputs of the last substep, on the nodes as they are written back and
                // the state it commits, are the cache: part of the FMU state (`model::cache`),
                // so a restored state reports what was read at saving, bit for bit
                self.s.outputs.commit_step();
                if let Some(before) = before {
                    self.log_transitions(&before, &self.s.state);
                    if met.count > 0 {
                        self.log_events(&met);
                    }
                }
                Ok(met.stopped)
            }
            Err(e) => {
                self.s.mode = Mode::Error;
                // the state is kept whole, its cached outputs too (`model::cache`): what is
                // read after a refused step is what was read before it, and what a restore of
                // the state reads
                let cause = match e {
                    StepError::NotFinite(_) => {
                        non_finite_cause(self.table, self.s.outputs.spare(), &self.s.inputs)
                    }
                    _ => String::new(),
                };
                let recover = match self.fmi {
                    FmiVersion::V2 => "fmi2Reset or fmi2SetFMUstate recovers",
                    FmiVersion::V3 => "fmi3Reset or fmi3SetFMUState recovers",
                };
                Err(step_error(t, h, e, &cause, recover))
            }
        }
    }

    /// Logs stop and stick/slip transitions under logEvents (kept out of fmi2DoStep's code).
    #[cold]
    #[inline(never)]
    fn log_transitions(&self, before: &State, after: &State) {
        for k in 0..6 {
            let (s0, s1) = (before.stop_status[k], after.stop_status[k]);
            if s0 != s1 {
                let what = |s: i8| match s {
                    -1 => "at the lower stop",
                    1 => "at the upper stop",
                    _ => "free",
                };
                self.log(
                    Level::Ok,
                    Category::Events,
                    &format!(
                        "t = {}: component {} {} (was {})",
                        self.s.time,
                        k + 1,
                        what(s1),
                        what(s0)
                    ),
                );
            }
        }
        let pairs = [
            ("sliding", before.friction.status, after.friction.status),
            ("spin", before.friction.status_r1, after.friction.status_r1),
        ];
        for (what, s0, s1) in pairs {
            if s0 != s1 {
                self.log(
                    Level::Ok,
                    Category::Events,
                    &format!(
                        "t = {}: {what} friction {:?} (was {:?})",
                        self.s.time, s1, s0
                    ),
                );
            }
        }
    }

    /// Logs the events located in the step under logEvents.
    #[cold]
    #[inline(never)]
    fn log_events(&self, met: &Met) {
        let how = if met.stopped {
            "the step ends there (early return)"
        } else {
            "stepped through"
        };
        self.log(
            Level::Ok,
            Category::Events,
            &format!(
                "{} event(s) in the step, the first at t = {}; {how}",
                met.count, self.s.event.time
            ),
        );
    }

    /// fmi2GetRealStatus (fmi2LastSuccessfulTime).
    pub fn last_successful_time(&self) -> FmuResult<Real> {
        self.allowed(Call::Status)?;
        Ok(self.s.time)
    }

    /// fmi2GetBooleanStatus (fmi2Terminated): the slave never asks to terminate.
    pub fn terminated_status(&self) -> FmuResult<bool> {
        self.allowed(Call::Status)?;
        Ok(false)
    }
}

/// The message of a refused fmi2DoStep(t, h) (off the hot path).
#[cold]
#[inline(never)]
fn step_error(t: Real, h: Real, e: StepError, not_finite: &str, recover: &str) -> FmuError {
    FmuError::error(match e {
        StepError::Singular(s, tau) => format!(
            "at t = {:?}: {}; the state at t = {t:?} is kept ({recover})",
            t + tau,
            singular_text(s)
        ),
        StepError::NotFinite(tau) => format!(
            "at t = {:?}: {not_finite}; the state at t = {t:?} is kept",
            t + tau
        ),
        StepError::TooManySubsteps(n) => format!(
            "the step h = {h:?} would need {n:e} internal substeps (more than {}); use a smaller step or a larger cosim.maxSubstep",
            crate::physics::step::MAX_SUBSTEPS
        ),
    })
}
