//! One FMU instance: the FMI 2.0 Co-Simulation state machine and lifecycle over the model's
//! data. Safe Rust, no FMI C types: the boundary in `fmi2` converts pointers and statuses,
//! names the FMI function in messages, and logs what this layer returns.
//!
//! - this file: the state machine, lifecycle, outputs at the current inputs, FMU state;
//! - `values`: get and set through the variable table (all or nothing);
//! - `stepping`: fmi2DoStep and its status;
//! - `derivatives`: input derivatives and directional derivatives.

mod derivatives;
mod memo;
mod stepping;
mod values;

use crate::error::{Category, FmuError, FmuResult, Level};
use crate::model::access::{initial_snapshot, nodes_of, non_finite_cause, Ty};
use crate::model::slots::{real_tables, RealTables};
use crate::model::snapshot::Snapshot;
use crate::model::variables::{table, NodeInputs, PoseTwist, Table, Variant, POSE_TWIST};
use crate::physics::connector::{evaluate_pose, Outputs, State};
use crate::physics::events::Taking;
use crate::physics::friction::Eval;
use crate::physics::init::{initial_state, initial_state_at};
use crate::physics::kinematics::{
    Computed, ConnectionType, Node, NodeDual, Pose, Rotational, Singular, TriadSource,
};
use crate::physics::math::{Dual, Real};
use memo::{quat_bits, PointMemo, VrMemo};

#[cfg(test)]
mod tangent_tests;

pub use crate::model::snapshot::Mode;

/// The FMI version an instance answers for: it chooses the names in messages (states, types,
/// functions); the state machine and the model are the same.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmiVersion {
    /// FMI 2.0 Co-Simulation (fmi2Instantiate).
    V2,
    /// FMI 3.0 Co-Simulation (fmi3InstantiateCoSimulation): Step Mode is `Mode::StepComplete`.
    V3,
}

impl FmiVersion {
    /// The prefix of the version's function names (`fmi2`, `fmi3`).
    pub fn prefix(self) -> &'static str {
        match self {
            FmiVersion::V2 => "fmi2",
            FmiVersion::V3 => "fmi3",
        }
    }

    /// A variable type as this version spells it.
    pub fn type_name(self, ty: Ty) -> &'static str {
        match (ty, self) {
            (Ty::Real, FmiVersion::V2) => "Real",
            (Ty::Integer, FmiVersion::V2) => "Integer",
            (Ty::Real, FmiVersion::V3) => "Float64",
            (Ty::Integer, FmiVersion::V3) => "Int32",
            (Ty::Boolean, _) => "Boolean",
        }
    }

    /// A mode as this version's state machine names it.
    pub fn mode_name(self, m: Mode) -> String {
        match (self, m) {
            (FmiVersion::V3, Mode::StepComplete) => "StepMode".to_string(),
            _ => format!("{m:?}"),
        }
    }
}

/// The FMI calls whose allowed states differ (Reference-FMUs masks, CS columns).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    /// fmi2FreeInstance, fmi2Reset, FMU state functions
    Lifecycle,
    /// fmi2SetupExperiment, fmi2EnterInitializationMode
    Setup,
    /// fmi2ExitInitializationMode
    ExitInit,
    /// fmi2Terminate
    Terminate,
    /// fmi2Get{Real,Integer,Boolean,String}, fmi2GetDirectionalDerivative
    Get,
    /// fmi2Set{Real,Integer,Boolean,String}, fmi2SetRealInputDerivatives
    Set,
    /// fmi2GetRealOutputDerivatives
    OutputDerivatives,
    /// fmi2DoStep
    DoStep,
    /// fmi2Get*Status
    Status,
}

impl Call {
    fn mask(self) -> u32 {
        use Mode::*;
        let m = |ms: &[Mode]| ms.iter().fold(0u32, |acc, &x| acc | x as u32);
        match self {
            Call::Lifecycle => m(&[
                Instantiated,
                InitializationMode,
                StepComplete,
                StepFailed,
                StepCanceled,
                Terminated,
                Error,
            ]),
            Call::Setup => m(&[Instantiated]),
            Call::ExitInit => m(&[InitializationMode]),
            Call::Terminate => m(&[StepComplete, StepFailed]),
            Call::Get => m(&[
                InitializationMode,
                StepComplete,
                StepFailed,
                StepCanceled,
                Terminated,
                Error,
            ]),
            Call::Set => m(&[Instantiated, InitializationMode, StepComplete]),
            Call::OutputDerivatives => {
                m(&[StepComplete, StepFailed, StepCanceled, Terminated, Error])
            }
            Call::DoStep => m(&[StepComplete]),
            Call::Status => m(&[StepComplete, StepFailed, StepCanceled, Terminated]),
        }
    }
}

/// Where log messages go: the boundary implements it with the importer's callback.
pub trait LogSink: Send {
    /// Writes one message.
    fn log(&self, level: Level, category: Category, message: &str);
}

/// One FMU instance.
pub struct ModelInstance {
    /// The variant's variable table.
    pub table: &'static Table,
    /// The same table as what fmi2SetReal / fmi2GetReal do with each VR.
    real: &'static RealTables,
    ct: ConnectionType,
    name: String,
    logger: Box<dyn LogSink>,
    logging_on: bool,
    categories: [bool; 4],
    fmi: FmiVersion,
    s: Snapshot,
    /// Whether fmi3DoStep stops at the first event (earlyReturnAllowed).
    early_return: bool,
    /// The last VR list of fmi2SetReal's per-step path, resolved to input slots.
    set_memo: VrMemo,
    /// The last VR list of fmi2GetReal's per-step path, resolved to node-load slots.
    get_memo: VrMemo,
    /// The unknowns of the last directional derivative, with their rows in
    /// `access::continuous_row`.
    unknown_memo: VrMemo,
    /// The frames and centred triad of the last point read (at new inputs) or differentiated
    /// at.
    point_memo: PointMemo,
    /// Where a directional derivative evaluates the kernel in `Dual`.
    tangent: Box<TangentBuffers>,
    /// Where a step writes the event functions at its end (its record, `Snapshot::events`,
    /// takes them from here when the step is accepted).
    event_end: Taking,
}

/// The outputs and next state of a directional derivative's evaluation in `Dual`, kept with
/// the instance: the evaluation overwrites every field of both, so they need no clearing
/// between calls (fresh ones cost a memset of each, over two kilobytes per call, and an
/// `Outputs<Dual>` returned by value was copied three times).
#[derive(Default)]
struct TangentBuffers {
    o: Outputs<Dual>,
    next: State<Dual>,
}

impl ModelInstance {
    /// A new instance of `variant` in Mode::Instantiated, with start values.
    pub fn new(variant: Variant, name: &str, logger: Box<dyn LogSink>, logging_on: bool) -> Self {
        let table = table(variant);
        ModelInstance {
            table,
            real: real_tables(table),
            ct: table.spec.connection,
            name: name.to_string(),
            logger,
            logging_on,
            categories: [true; 4],
            fmi: FmiVersion::V2,
            s: initial_snapshot(table),
            early_return: false,
            set_memo: VrMemo::default(),
            get_memo: VrMemo::default(),
            unknown_memo: VrMemo::default(),
            point_memo: PointMemo::default(),
            tangent: Box::default(),
            event_end: Taking::NONE,
        }
    }

    /// The same instance stopping its steps at the first event when `allowed` (FMI 3.0's
    /// earlyReturnAllowed).
    pub fn with_early_return(mut self, allowed: bool) -> Self {
        self.early_return = allowed;
        self
    }

    /// The same instance answering for another FMI version (names in its messages).
    pub fn with_version(mut self, fmi: FmiVersion) -> Self {
        self.fmi = fmi;
        self
    }

    /// The FMI version the instance answers for.
    pub fn version(&self) -> FmiVersion {
        self.fmi
    }

    /// The instance name given to fmi2Instantiate.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Current mode.
    pub fn mode(&self) -> Mode {
        self.s.mode
    }

    /// Current time (s).
    pub fn time(&self) -> Real {
        self.s.time
    }

    /// Logs one message: errors and warnings always (every non-OK status is explained),
    /// events and call traces only when logging is on for their category.
    pub fn log(&self, level: Level, category: Category, message: &str) {
        let always = matches!(category, Category::Error | Category::Warning);
        if always || (self.logging_on && self.categories[category as usize]) {
            self.logger.log(level, category, message);
        }
    }

    /// Whether a category is being logged (to skip formatting otherwise).
    pub fn wants(&self, category: Category) -> bool {
        self.logging_on && self.categories[category as usize]
    }

    /// Marks the instance fatal after a caught panic.
    pub fn set_fatal(&mut self) {
        self.s.mode = Mode::Fatal;
    }

    /// Checks that `call` is allowed in the current mode (the boundary names the function).
    pub fn allowed(&self, call: Call) -> FmuResult<()> {
        if call.mask() & self.s.mode as u32 != 0 {
            Ok(())
        } else {
            Err(FmuError::error(format!(
                "the call is not allowed in state {}",
                self.fmi.mode_name(self.s.mode)
            )))
        }
    }

    /// fmi2SetDebugLogging.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> FmuResult<()> {
        let mut set = [categories.is_empty(); 4];
        for name in categories {
            match Category::from_name(name) {
                Some(c) => set[c as usize] = true,
                None => return Err(FmuError::error(format!("unknown log category \"{name}\""))),
            }
        }
        self.logging_on = on;
        self.categories = set;
        Ok(())
    }

    /// fmi2SetupExperiment (tolerance is not used: the kernel has no error-controlled solver).
    pub fn setup_experiment(&mut self, start: Real, _stop: Option<Real>) -> FmuResult<()> {
        self.allowed(Call::Setup)?;
        if !start.is_finite() {
            return Err(FmuError::error("startTime is not finite"));
        }
        self.s.start_time = start;
        self.s.time = start;
        self.s.event.time = start;
        Ok(())
    }

    /// fmi2EnterInitializationMode.
    pub fn enter_initialization_mode(&mut self) -> FmuResult<()> {
        self.allowed(Call::Setup)?;
        self.s.mode = Mode::InitializationMode;
        self.s.outputs.clear();
        Ok(())
    }

    /// fmi2ExitInitializationMode: checks the parameters, fixes the initial geometry.
    pub fn exit_initialization_mode(&mut self) -> FmuResult<()> {
        self.allowed(Call::ExitInit)?;
        self.s
            .params
            .check(&self.ct.roles())
            .map_err(|name| FmuError::error(format!("invalid parameter {name}")))?;
        let (a, b) = self.nodes()?;
        let st = initial_state(self.ct, &self.s.params, &a, &b).map_err(singular_error)?;
        // A start whose outputs or dissipation power are not finite (velocity inputs so large
        // that c·v² overflows) is refused: no step could succeed from it, and its state would
        // not de-serialize (regression 005). The instance stays in Initialization Mode.
        self.evaluate_at(&self.s.inputs, Eval::Read)?;
        if !st.power.iter().all(|x| x.is_finite()) {
            return Err(FmuError::error(
                "the dissipation power at the initial inputs is not finite (velocity inputs too large)",
            ));
        }
        self.s.state = st;
        self.s.mode = Mode::StepComplete;
        self.s.events = None;
        self.s.outputs.clear();
        Ok(())
    }

    /// fmi2Terminate.
    pub fn terminate(&mut self) -> FmuResult<()> {
        self.allowed(Call::Terminate)?;
        self.s.mode = Mode::Terminated;
        Ok(())
    }

    /// fmi2Reset: back to start values in Mode::Instantiated.
    pub fn reset(&mut self) -> FmuResult<()> {
        self.allowed(Call::Lifecycle)?;
        self.s = initial_snapshot(self.table);
        Ok(())
    }

    /// The nodes from the current inputs (quaternions normalised; a bad one is refused).
    fn nodes(&self) -> FmuResult<(Node, Node)> {
        nodes_of(&self.s.inputs)
    }

    /// Outputs at the given inputs with the committed state (in initialization: with the
    /// state the instance would start from at those inputs).
    fn evaluate_at(&self, inputs: &[NodeInputs; 2], mode: Eval) -> FmuResult<Outputs> {
        let mut o = Outputs::default();
        let s = &self.s;
        let at = At::of(s, inputs);
        evaluate_at_into(self.table, self.ct, &at, mode, &mut o, None)?;
        Ok(o)
    }

    /// The outputs with their exact derivatives along the direction `seed` of the inputs
    /// (forward-mode, `math::Dual`), at the current inputs and committed state (in
    /// initialization: with the state the instance would start from, which moves with the
    /// inputs), written into `self.tangent.o`. `mode` is `Eval::Tangent`: friction on the
    /// branch of its status here. Written in place, like the step's outputs (see
    /// `TangentBuffers`).
    fn tangent_into(&mut self, seed: &[PoseTwist; 2], mode: Eval) -> FmuResult<()> {
        let u = &self.s.inputs;
        let mut dual: [NodeDual; 2] = [[Dual::default(); POSE_TWIST]; 2];
        for ((d, u), s) in dual.iter_mut().zip(u).zip(seed) {
            for ((d, &u), &s) in d.iter_mut().zip(u).zip(s) {
                *d = Dual::new(u, s);
            }
        }
        let quat = |n: usize| [u[n][3], u[n][4], u[n][5], u[n][6]];
        let frames = self.point_memo.frames([quat(0), quat(1)]);
        let pose = Pose::of_inputs(&dual[0], &dual[1], frames);
        let p = &self.s.params;
        let st = if self.s.mode == Mode::InitializationMode {
            initial_state_at(self.ct, p, &pose).map_err(singular_error)?
        } else {
            self.s.state.lift()
        };
        // the centred triad at this point, the same for every direction (`PointMemo`): the
        // triad itself where the direction leaves both orientations alone (no seed on them;
        // `geometry_into` reads it only where the frames are constants), else the values of
        // its libm calls, recorded where the memo does not hold them yet; REVOLUTE's rotations
        // likewise where the direction leaves both orientations alone
        let beta = st.branches.beta;
        let mut recorded = None;
        let frames_fixed = seed.iter().all(|s| s[3..7] == [0.0; 4]);
        let triad = if self.ct.rot == Rotational::Revolute && frames_fixed {
            let alpha = st.branches.alpha;
            TriadSource::Revolute(self.point_memo.revolute(alpha).map_err(singular_error)?)
        } else if !self.ct.centred() {
            TriadSource::Compute
        } else if frames_fixed {
            self.point_memo.triad(beta).map_err(singular_error)?
        } else {
            self.point_memo.trig(beta, &mut recorded)
        };
        let TangentBuffers { o, next } = &mut *self.tangent;
        evaluate_pose(self.ct, p, &st, &pose, triad, mode, (o, next)).map_err(singular_error)?;
        self.point_memo.remember(beta, recorded);
        Ok(())
    }

    /// Outputs at the current inputs and committed state, cached until something changes. A
    /// centred triad computed on the way is kept for the directional derivatives at the same
    /// point (`PointMemo::read`): a linear-implicit master reads the loads there first.
    #[inline]
    fn outputs(&mut self) -> FmuResult<&Outputs> {
        self.outputs_keeping(true)
    }

    /// `outputs`, the triad kept only with `keep` (a step's own read at its start is not
    /// followed by derivatives at that point: the step moves on).
    #[inline]
    fn outputs_keeping(&mut self, keep: bool) -> FmuResult<&Outputs> {
        if self.s.outputs.get().is_none() {
            self.read_outputs(keep)?;
        }
        // just filled when it was empty
        self.s
            .outputs
            .get()
            .ok_or_else(|| FmuError::error("no outputs"))
    }

    /// `outputs` where the cache is empty: the evaluation, out of line (a read after a step,
    /// the usual one, finds the step's outputs cached).
    #[inline(never)]
    fn read_outputs(&mut self, keep: bool) -> FmuResult<()> {
        let s = &mut self.s;
        let at = At {
            mode: s.mode,
            params: &s.params,
            state: &s.state,
            event: s.event,
            inputs: &s.inputs,
        };
        evaluate_at_into(
            self.table,
            self.ct,
            &at,
            Eval::Read,
            s.outputs.spare(),
            (keep && self.ct.centred()).then_some(&mut self.point_memo),
        )?;
        s.outputs.commit_read();
        Ok(())
    }

    /// fmi2GetFMUstate.
    pub fn get_state(&self) -> FmuResult<Snapshot> {
        self.allowed(Call::Lifecycle)?;
        Ok(self.s.clone())
    }

    /// Refuses an FMU state made by an instance of another variant:
    /// its parameters and inputs follow another variable table.
    pub fn own_state(&self, s: &Snapshot) -> FmuResult<()> {
        if s.variant == self.s.variant {
            return Ok(());
        }
        Err(FmuError::error(format!(
            "the state belongs to {}, not {}; refused",
            s.variant.spec().model_identifier,
            self.table.spec.model_identifier
        )))
    }

    /// fmi2SetFMUstate.
    pub fn set_state(&mut self, s: &Snapshot) -> FmuResult<()> {
        self.allowed(Call::Lifecycle)?;
        self.own_state(s)?;
        // with its cached outputs (`model::cache`)
        self.s = s.clone();
        Ok(())
    }

    /// fmi2DeSerializeFMUstate: validates bytes and returns the snapshot they hold.
    pub fn deserialize(&self, bytes: &[u8]) -> FmuResult<Snapshot> {
        self.allowed(Call::Lifecycle)?;
        crate::model::state_bytes::decode(self.table, bytes)
            .map_err(|why| FmuError::error(format!("{why}; state not restored")))
    }

    /// fmi2SerializeFMUstate: the snapshot as versioned bytes.
    pub fn serialize(&self, s: &Snapshot) -> Vec<u8> {
        crate::model::state_bytes::encode(self.table, s)
    }
}

/// What an evaluation of the outputs reads of a snapshot: its mode, parameters, committed state
/// and last events, at the given inputs (its own, or others). Borrowed field by field, so that
/// the outputs can be evaluated into the snapshot's own cache (`Snapshot::outputs`).
struct At<'s> {
    mode: Mode,
    params: &'s crate::physics::connector::Params,
    state: &'s State,
    event: crate::model::snapshot::LastEvent,
    inputs: &'s [NodeInputs; 2],
}

impl<'s> At<'s> {
    /// The snapshot `s` at `inputs`.
    fn of(s: &'s Snapshot, inputs: &'s [NodeInputs; 2]) -> At<'s> {
        At {
            mode: s.mode,
            params: &s.params,
            state: &s.state,
            event: s.event,
            inputs,
        }
    }
}

/// Outputs at `s.inputs` with the committed state of `s` (in initialization: with the state
/// the instance would start from at those inputs), written into `o`; with `memo`, the centred
/// triad is the one it holds for these inputs, else computed there (`PointMemo::read`).
fn evaluate_at_into(
    t: &Table,
    ct: ConnectionType,
    s: &At,
    mode: Eval,
    o: &mut Outputs,
    memo: Option<&mut PointMemo>,
) -> FmuResult<()> {
    let inputs = s.inputs;
    let (a, b) = nodes_of(inputs)?;
    let init;
    let st = if s.mode == Mode::InitializationMode {
        init = initial_state(ct, s.params, &a, &b).map_err(singular_error)?;
        &init
    } else {
        s.state
    };
    let mut next = State::default();
    let pose = Pose::of(&a, &b);
    let known = match memo {
        Some(memo) => {
            let quat = |n: usize| [inputs[n][3], inputs[n][4], inputs[n][5], inputs[n][6]];
            let quats = quat_bits([quat(0), quat(1)]);
            let frames = [pose.ra, pose.rb];
            memo.read(quats, &frames, st.branches.beta)
                .map_err(singular_error)?
        }
        None => None,
    };
    let out = (&mut *o, &mut next);
    match known {
        Some(triad) => evaluate_pose(
            ct,
            s.params,
            st,
            &pose,
            TriadSource::Given(triad),
            mode,
            out,
        ),
        None => evaluate_pose(ct, s.params, st, &pose, Computed, mode, out),
    }
    .map_err(singular_error)?;
    (o.event_time, o.event_count) = (s.event.time, s.event.count);
    if !crate::physics::step::outputs_finite(o) {
        return Err(FmuError::error(format!(
            "at these inputs {}",
            non_finite_cause(t, o, inputs)
        )));
    }
    Ok(())
}

fn singular_text(s: Singular) -> String {
    match s {
        Singular::FlexionNearPi(a) => format!(
            "flexion angle α = {a:?} rad is at the singular configuration α → π (shafts folded back)"
        ),
        Singular::RevoluteUndefined => {
            "PLANAR rotation α is undefined: e3b is perpendicular to the 2-3 plane of node a"
                .to_string()
        }
        Singular::NotFinite => "a connector position is not finite".to_string(),
    }
}

fn singular_error(s: Singular) -> FmuError {
    FmuError::error(singular_text(s))
}
