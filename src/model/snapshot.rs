//! The instance's data: everything that influences the future (`fmi2GetFMUstate` copies it).
//! Plain data over the variable table's types (`variables`); how a snapshot starts from the
//! table's start values is an access rule (`access::initial_snapshot`).
//!
//! Uses the table's types (`variables`), the output cache (`cache`) and the physics' state;
//! `access`, `state_bytes` and the instance use it.

use super::cache::OutputCache;
use super::variables::{NodeInputs, PoseTwist, Variant, POSE_TWIST};
use crate::physics::connector::{Params, State};
use crate::physics::events::Values;
use crate::physics::math::Real;

/// Where the instance is in the FMI 2.0 Co-Simulation state machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// After fmi2Instantiate / fmi2Reset.
    Instantiated = 1,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    InitializationMode = 2,
    /// Ready for fmi2DoStep.
    StepComplete = 4,
    /// A step returned fmi2Discard.
    StepFailed = 8,
    /// A step was cancelled (never: steps are synchronous).
    StepCanceled = 16,
    /// After fmi2Terminate.
    Terminated = 32,
    /// After an fmi2Error from fmi2DoStep or fmi2ExitInitializationMode.
    Error = 64,
    /// After a caught panic: only fmi2FreeInstance is left.
    Fatal = 128,
}

/// Everything that influences the future; `fmi2GetFMUstate` copies it.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot {
    /// The variant the state belongs to.
    pub variant: Variant,
    /// State-machine mode.
    pub mode: Mode,
    /// Current time (s).
    pub time: Real,
    /// Start time from fmi2SetupExperiment.
    pub start_time: Real,
    /// Parameters.
    pub params: Params,
    /// Node inputs a, b.
    pub inputs: [NodeInputs; 2],
    /// First-order input derivatives of the pose and twist (valid for the next step).
    pub input_der: [PoseTwist; 2],
    /// Which input derivatives are set.
    pub input_der_set: [[bool; POSE_TWIST]; 2],
    /// Committed connector state.
    pub state: State,
    /// The events the last step met.
    pub event: LastEvent,
    /// The last communication point a step started from: its time and the velocity inputs
    /// (v, ω) of nodes a and b there (second-order extrapolation takes accelerations from it).
    pub history: Option<(Real, [[Real; 6]; 2])>,
    /// The event functions at the end of the last step, and whether each was far from its
    /// event then (`events::far`): whether the next step needs their exact values at its start.
    /// None whenever the state, the parameters or the mode change, so that the step after
    /// evaluates them.
    pub events: Option<EventRecord>,
    /// The outputs at the current inputs and committed state where they are known: those the
    /// last step ended with (state: a restored state reads what was read when it was saved), or
    /// a read's (a memo, not state; `cache`).
    pub outputs: OutputCache,
}

/// The event functions at the end of the last step (NaN: not taking part).
#[derive(Clone, Copy, Debug)]
pub struct EventRecord {
    /// Their values there.
    pub end: Values,
    /// Whether every one was far from its event, judged by its change over that step.
    pub far: bool,
}

impl PartialEq for EventRecord {
    /// Bit for bit (NaN marks a function not taking part, and equals itself here).
    fn eq(&self, other: &Self) -> bool {
        let bits = |v: &Values| v.map(Real::to_bits);
        bits(&self.end) == bits(&other.end) && self.far == other.far
    }
}

/// The events the last step met (the outputs event.time and event.count).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LastEvent {
    /// Time of the first event in the last step; its end when none (the current time before
    /// the first step).
    pub time: Real,
    /// Number of events in the last step.
    pub count: i32,
}
