//! One FMU instance: the FMI 2.0 Co-Simulation state machine, get/set through the variable
//! table, initialization, stepping, FMU state. Safe Rust, no FMI C types: the boundary in
//! `fmi2` converts pointers and statuses and logs what this layer returns.

use crate::error::{Category, FmuError, FmuResult, Level};
use crate::physics::connector::{evaluate_into, Extrapolation, Outputs, Params, State};
use crate::physics::friction::{Eval, Status};
use crate::physics::init::initial_state;
use crate::physics::kinematics::{ConnectionType, Node, Singular};
use crate::physics::math::{quat_from_wxyz, Real, Vec3};
use crate::physics::step::{advance_into, Rates, StepError};
use crate::variables::{
    table, Causality, CompOut, CompPar, Field, FrictionField, ScalarPar, Start, Table, VarSpec,
    Variability, Variant,
};
use std::sync::OnceLock;

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

/// Node inputs as set (raw, before normalisation): r(3), q(4: w x y z), v(3), ω(3).
pub type NodeInputs = [Real; 13];

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
    /// First-order input derivatives (valid for the next step) and which are set.
    pub input_der: [NodeInputs; 2],
    /// Which input derivatives are set.
    pub input_der_set: [[bool; 13]; 2],
    /// Committed connector state.
    pub state: State,
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
    s: Snapshot,
    /// Outputs at the current inputs and committed state.
    cache: OutputCache,
}

fn start_snapshot(t: &Table) -> Snapshot {
    let mut params = Params::default();
    let mut inputs = [[0.0; 13]; 2];
    for v in &t.vars {
        if let Start::Real(Some(x)) = v.start {
            let _ = write_real(&mut params, &mut inputs, v.field, x);
        }
        if let Start::Integer(Some(x)) = v.start {
            let _ = write_int(&mut params, v.field, x);
        }
    }
    // nodes rest at the origin with identity orientation until inputs say otherwise
    inputs[0][3] = 1.0;
    inputs[1][3] = 1.0;
    Snapshot {
        variant: t.spec.variant,
        mode: Mode::Instantiated,
        time: 0.0,
        start_time: 0.0,
        params,
        inputs,
        input_der: [[0.0; 13]; 2],
        input_der_set: [[false; 13]; 2],
        state: State::default(),
    }
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
            s: start_snapshot(table),
            cache: OutputCache::new(),
        }
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

    /// Logs an error result once and passes it on.
    pub fn report<T>(&mut self, r: FmuResult<T>) -> FmuResult<T> {
        if let Err(e) = &r {
            self.log(e.level, e.category(), &e.message);
        }
        r
    }

    /// Marks the instance fatal after a caught panic.
    pub fn set_fatal(&mut self) {
        self.s.mode = Mode::Fatal;
    }

    /// Checks that `call` (named `fname` in messages) is allowed in the current mode.
    pub fn allowed(&self, call: Call, fname: &str) -> FmuResult<()> {
        if call.mask() & self.s.mode as u32 != 0 {
            Ok(())
        } else {
            Err(FmuError::error(format!(
                "{fname} is not allowed in state {:?}",
                self.s.mode
            )))
        }
    }

    /// fmi2SetDebugLogging.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> FmuResult<()> {
        let mut set = [categories.is_empty(); 4];
        for name in categories {
            match Category::from_name(name) {
                Some(c) => set[c as usize] = true,
                None => {
                    return Err(FmuError::error(format!(
                        "fmi2SetDebugLogging: unknown log category \"{name}\""
                    )))
                }
            }
        }
        self.logging_on = on;
        self.categories = set;
        Ok(())
    }

    /// fmi2SetupExperiment (tolerance is not used: the kernel has no error-controlled solver).
    pub fn setup_experiment(&mut self, start: Real, _stop: Option<Real>) -> FmuResult<()> {
        self.allowed(Call::Setup, "fmi2SetupExperiment")?;
        if !start.is_finite() {
            return Err(FmuError::error(
                "fmi2SetupExperiment: startTime is not finite",
            ));
        }
        self.s.start_time = start;
        self.s.time = start;
        Ok(())
    }

    /// fmi2EnterInitializationMode.
    pub fn enter_initialization_mode(&mut self) -> FmuResult<()> {
        self.allowed(Call::Setup, "fmi2EnterInitializationMode")?;
        self.s.mode = Mode::InitializationMode;
        self.cache.clear();
        Ok(())
    }

    /// fmi2ExitInitializationMode: checks the parameters, fixes the initial geometry.
    pub fn exit_initialization_mode(&mut self) -> FmuResult<()> {
        self.allowed(Call::ExitInit, "fmi2ExitInitializationMode")?;
        self.s.params.check(&self.ct.roles()).map_err(|name| {
            FmuError::error(format!(
                "fmi2ExitInitializationMode: invalid parameter {name}"
            ))
        })?;
        let (a, b) = self
            .nodes()
            .map_err(|e| FmuError::error(format!("fmi2ExitInitializationMode: {}", e.message)))?;
        let st = initial_state(self.ct, &self.s.params, &a, &b)
            .map_err(|e| singular_error("fmi2ExitInitializationMode", e))?;
        // A start whose outputs or dissipation power are not finite (velocity inputs so large
        // that c·v² overflows) is refused: no step could succeed from it, and its state would
        // not de-serialize (regression 005). The instance stays in Initialization Mode.
        self.evaluate_at(&self.s.inputs, Eval::Read, "fmi2ExitInitializationMode")?;
        if !st.power.iter().all(|x| x.is_finite()) {
            return Err(FmuError::error(
                "fmi2ExitInitializationMode: the dissipation power at the initial inputs is not finite (velocity inputs too large)",
            ));
        }
        self.s.state = st;
        self.s.mode = Mode::StepComplete;
        self.cache.clear();
        Ok(())
    }

    /// fmi2Terminate.
    pub fn terminate(&mut self) -> FmuResult<()> {
        self.allowed(Call::Terminate, "fmi2Terminate")?;
        self.s.mode = Mode::Terminated;
        Ok(())
    }

    /// fmi2Reset: back to start values in Mode::Instantiated.
    pub fn reset(&mut self) -> FmuResult<()> {
        self.allowed(Call::Lifecycle, "fmi2Reset")?;
        self.s = start_snapshot(self.table);
        self.cache.clear();
        Ok(())
    }

    /// Looks a VR up and checks its type, naming the function in errors.
    #[inline]
    fn var(&self, vr: u32, want: Ty, fname: &str) -> FmuResult<&'static VarSpec> {
        match self.table.get(vr) {
            Some(v) if Ty::of(&v.start) == want => Ok(v),
            found => Err(var_error(vr, found, want, fname)),
        }
    }

    /// The (node, index) of a Real node input `vr` given a finite `what` value `x`, or the
    /// error that names the variable (input derivatives, directional-derivative seeds).
    fn finite_input(&self, vr: u32, x: Real, what: &str, fname: &str) -> FmuResult<(usize, usize)> {
        let v = self.var(vr, Ty::Real, fname)?;
        let Field::Input { node, idx } = v.field else {
            return Err(FmuError::error(format!(
                "{fname}: {} is not an input",
                v.name
            )));
        };
        if !x.is_finite() {
            return Err(FmuError::error(format!(
                "{fname}: the {what} for {} is not finite",
                v.name
            )));
        }
        Ok((node as usize, idx as usize))
    }

    /// Checks that `v` may be set in the current mode.
    fn settable(&self, v: &VarSpec, fname: &str) -> FmuResult<()> {
        let ok = match (v.causality, v.variability) {
            (Causality::Output, _) => false,
            (Causality::Parameter, Variability::Fixed) => {
                matches!(self.s.mode, Mode::Instantiated | Mode::InitializationMode)
            }
            _ => true,
        };
        if ok {
            Ok(())
        } else if v.causality == Causality::Output {
            Err(FmuError::error(format!(
                "{fname}: {} is an output and cannot be set",
                v.name
            )))
        } else {
            Err(FmuError::error(format!(
                "{fname}: fixed parameter {} cannot be set in state {:?}",
                v.name, self.s.mode
            )))
        }
    }

    /// Applies a batch of sets to a copy and commits only when every value is accepted.
    #[inline(never)]
    fn set_batch<T: Copy>(
        &mut self,
        vrs: &[u32],
        values: &[T],
        ty: Ty,
        fname: &str,
        write: impl Fn(&mut Params, &mut [NodeInputs; 2], Field, T) -> Result<(), &'static str>,
    ) -> FmuResult<()> {
        self.allowed(Call::Set, fname)?;
        let mut touches_params = false;
        for &vr in vrs {
            let v = self.var(vr, ty, fname)?;
            self.settable(v, fname)?;
            touches_params |= v.causality == Causality::Parameter;
        }
        if !touches_params {
            // the per-step path: node inputs only, no parameter copy or check
            let mut inputs = self.s.inputs;
            for (&vr, &x) in vrs.iter().zip(values) {
                let v = self.var(vr, ty, fname)?;
                write(&mut self.s.params, &mut inputs, v.field, x).map_err(|why| {
                    FmuError::error(format!("{fname}: {} {why}; value not set", v.name))
                })?;
            }
            if inputs != self.s.inputs {
                self.s.inputs = inputs;
                self.cache.clear();
            }
            return Ok(());
        }
        let mut params = self.s.params;
        let mut inputs = self.s.inputs;
        for (&vr, &x) in vrs.iter().zip(values) {
            let v = self.var(vr, ty, fname)?;
            write(&mut params, &mut inputs, v.field, x).map_err(|why| {
                FmuError::error(format!("{fname}: {} {why}; value not set", v.name))
            })?;
        }
        if self.s.mode == Mode::StepComplete && params != self.s.params {
            params.check(&self.ct.roles()).map_err(|name| {
                FmuError::error(format!("{fname}: invalid parameter {name}; values not set"))
            })?;
        }
        if params != self.s.params || inputs != self.s.inputs {
            self.s.params = params;
            self.s.inputs = inputs;
            self.cache.clear();
        }
        Ok(())
    }

    /// fmi2SetReal.
    pub fn set_real(&mut self, vrs: &[u32], values: &[Real]) -> FmuResult<()> {
        const F: &str = "fmi2SetReal";
        // The per-step path: finite values of node inputs only, written in place in one pass;
        // the first value that is not for this path puts the inputs back as they were and
        // hands the whole call to the general batch, which names the culprit (all or nothing).
        self.allowed(Call::Set, F)?;
        let index = &*self.real.input_index;
        let before = self.s.inputs;
        let flat = self.s.inputs.as_flattened_mut();
        for (&vr, &x) in vrs.iter().zip(values) {
            let j = index.get(vr as usize).copied().unwrap_or(NO_INDEX);
            match flat.get_mut(j as usize) {
                Some(u) if x.is_finite() => *u = x,
                _ => {
                    self.s.inputs = before;
                    return self.set_batch(vrs, values, Ty::Real, F, write_real);
                }
            }
        }
        // Outputs are evaluated again when read: a function of the inputs and the committed
        // state, so an unchanged value reads back the same bits.
        self.cache.clear();
        Ok(())
    }

    /// fmi2SetInteger.
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> FmuResult<()> {
        self.set_batch(vrs, values, Ty::Integer, "fmi2SetInteger", |p, _, f, x| {
            write_int(p, f, x)
        })
    }

    /// fmi2SetBoolean.
    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> FmuResult<()> {
        self.set_batch(
            vrs,
            values,
            Ty::Boolean,
            "fmi2SetBoolean",
            |p, _, f, x| match f {
                Field::CompParam {
                    par: CompPar::RefGiven,
                    k,
                } => {
                    p.ref_given[k as usize] = x;
                    Ok(())
                }
                _ => Err("is not a Boolean"),
            },
        )
    }

    /// fmi2SetString: there are no String variables.
    pub fn set_string(&mut self, vrs: &[u32]) -> FmuResult<()> {
        self.allowed(Call::Set, "fmi2SetString")?;
        match vrs.first() {
            None => Ok(()),
            Some(vr) => Err(FmuError::error(format!(
                "fmi2SetString: unknown value reference {vr} (this FMU has no String variables)"
            ))),
        }
    }

    /// fmi2GetString: there are no String variables.
    pub fn get_string(&mut self, vrs: &[u32]) -> FmuResult<()> {
        self.allowed(Call::Get, "fmi2GetString")?;
        match vrs.first() {
            None => Ok(()),
            Some(vr) => Err(FmuError::error(format!(
                "fmi2GetString: unknown value reference {vr} (this FMU has no String variables)"
            ))),
        }
    }

    /// The nodes from the current inputs (quaternions normalised; a bad one is refused).
    fn nodes(&self) -> FmuResult<(Node, Node)> {
        nodes_of(&self.s.inputs)
    }

    /// Outputs at the given inputs with the committed state (in initialization: with the
    /// state the instance would start from at those inputs).
    fn evaluate_at(&self, inputs: &[NodeInputs; 2], mode: Eval, fname: &str) -> FmuResult<Outputs> {
        let mut o = Outputs::default();
        evaluate_at_into(self.ct, &self.s, inputs, mode, fname, &mut o)?;
        Ok(o)
    }

    /// Outputs at the current inputs and committed state, cached until something changes.
    fn outputs(&mut self, fname: &str) -> FmuResult<&Outputs> {
        if self.cache.get().is_none() {
            let s = &self.s;
            evaluate_at_into(self.ct, s, &s.inputs, Eval::Read, fname, self.cache.spare())?;
            self.cache.commit_spare();
        }
        // just filled when it was empty
        self.cache
            .get()
            .ok_or_else(|| FmuError::error(format!("{fname}: no outputs")))
    }

    /// A get call: every VR is checked (type and existence) before anything is written, the
    /// outputs are evaluated once when one is asked for, then `read` fills each slot.
    fn get_values<T>(
        &mut self,
        vrs: &[u32],
        out: &mut [T],
        ty: Ty,
        fname: &str,
        read: impl Fn(&Snapshot, &VarSpec, Option<&Outputs>) -> T,
    ) -> FmuResult<()> {
        self.allowed(Call::Get, fname)?;
        let mut any_output = false;
        for &vr in vrs {
            any_output |= self.var(vr, ty, fname)?.causality == Causality::Output;
        }
        if any_output {
            self.outputs(fname)?;
        }
        let o = self.cache.get();
        for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
            *slot = read(&self.s, self.var(vr, ty, fname)?, o);
        }
        Ok(())
    }

    /// fmi2GetReal.
    pub fn get_real(&mut self, vrs: &[u32], out: &mut [Real]) -> FmuResult<()> {
        const F: &str = "fmi2GetReal";
        // The per-step path: node loads only (the usual read after a step), then every VR a
        // Real variable (else the general get names the culprit); all are checked before
        // anything is written, then read through the slot tables.
        self.allowed(Call::Get, F)?;
        let index = &*self.real.load_index;
        let load = |vr: u32| index.get(vr as usize).copied().unwrap_or(NO_INDEX);
        if vrs.iter().all(|&vr| load(vr) != NO_INDEX) {
            let o = self.outputs(F)?;
            let loads = node_loads(o);
            for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
                if let Some(&l) = loads.get(load(vr) as usize) {
                    *slot = l;
                }
            }
            return Ok(());
        }
        let mut any_output = false;
        for &vr in vrs {
            match self.real.slots.get(vr as usize) {
                Some(RealSlot::Load(_) | RealSlot::Output(_)) => any_output = true,
                Some(RealSlot::Input(_) | RealSlot::Param(_)) => {}
                _ => return self.get_real_general(vrs, out),
            }
        }
        if any_output {
            self.outputs(F)?;
        }
        let (o, loads) = match self.cache.get() {
            Some(o) => (Some(o), node_loads(o)),
            None => (None, [0.0; 12]),
        };
        let (slots, s) = (&self.real.slots, &self.s);
        for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
            *slot = match (slots[vr as usize], o) {
                (RealSlot::Input(j), _) => s.inputs.as_flattened()[j as usize],
                (RealSlot::Load(j), _) => loads[j as usize],
                (RealSlot::Output(f), Some(o)) => read_output(o, f),
                (RealSlot::Output(f) | RealSlot::Param(f), _) => read_real_param(&s.params, f),
                (RealSlot::None, _) => 0.0,
            };
        }
        Ok(())
    }

    /// fmi2GetReal through the variable table (reports unknown VRs and VRs of other types).
    #[cold]
    fn get_real_general(&mut self, vrs: &[u32], out: &mut [Real]) -> FmuResult<()> {
        self.get_values(vrs, out, Ty::Real, "fmi2GetReal", |s, v, o| {
            match (v.field, o) {
                (Field::Input { node, idx }, _) => s.inputs[node as usize][idx as usize],
                (f, Some(o)) if v.causality == Causality::Output => read_output(o, f),
                (f, _) => read_real_param(&s.params, f),
            }
        })
    }

    /// fmi2GetInteger.
    pub fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> FmuResult<()> {
        self.get_values(vrs, out, Ty::Integer, "fmi2GetInteger", |s, v, o| {
            match (v.field, o) {
                (Field::StopStatus(k), Some(o)) => o.cslst[k as usize],
                (Field::Friction(FrictionField::Status), Some(o)) => o.friction.status as i32,
                (Field::Friction(FrictionField::StatusR1), Some(o)) => o.friction.status_r1 as i32,
                (f, _) => read_int_param(&s.params, f),
            }
        })
    }

    /// fmi2GetBoolean.
    pub fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> FmuResult<()> {
        self.get_values(vrs, out, Ty::Boolean, "fmi2GetBoolean", |s, v, _| {
            match v.field {
                Field::CompParam { k, .. } => s.params.ref_given[k as usize],
                _ => false,
            }
        })
    }

    /// fmi2SetRealInputDerivatives (first order only; valid for the next fmi2DoStep).
    pub fn set_real_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[Real],
    ) -> FmuResult<()> {
        const F: &str = "fmi2SetRealInputDerivatives";
        self.allowed(Call::Set, F)?;
        let mut der = self.s.input_der;
        let mut set = self.s.input_der_set;
        for ((&vr, &order), &x) in vrs.iter().zip(orders).zip(values) {
            let (node, idx) = self.finite_input(vr, x, "derivative", F)?;
            if order != 1 {
                return Err(FmuError::error(format!(
                    "{F}: derivative order {order} of {} is not supported (only 1); not set",
                    self.table.get(vr).map_or("?", |v| v.name.as_str())
                )));
            }
            der[node][idx] = x;
            set[node][idx] = true;
        }
        self.s.input_der = der;
        self.s.input_der_set = set;
        Ok(())
    }

    /// Extrapolation rates of node n for the coming step: the input derivatives where set,
    /// else the node's own velocity and angular velocity.
    fn rates(&self, n: usize, node: &Node) -> Rates {
        if self.s.params.extrapolation == Extrapolation::Hold {
            return Rates::HOLD;
        }
        let der = &self.s.input_der[n];
        let set = &self.s.input_der_set[n];
        if *set == [false; 13] {
            // what the general case below gives without derivatives
            return Rates::from_velocities(node);
        }
        let v3 = |i: usize, fb: Vec3| {
            let pick = |j: usize, f: Real| if set[j] { der[j] } else { f };
            Vec3::new(pick(i, fb.x), pick(i + 1, fb.y), pick(i + 2, fb.z))
        };
        let dth = if set[3..7].iter().any(|&s| s) {
            // q̇ = ½ ω ⊗ q (ω in W)  ⇒  ω = 2 (q̇ ⊗ q*), q̇ scaled like the normalised q
            let u = &self.s.inputs[n];
            let norm = (u[3] * u[3] + u[4] * u[4] + u[5] * u[5] + u[6] * u[6]).sqrt();
            let qd = nalgebra::Quaternion::new(der[3], der[4], der[5], der[6]) / norm;
            (qd * node.q.quaternion().conjugate() * 2.0).imag()
        } else {
            node.w
        };
        Rates {
            dr: v3(0, node.v),
            dth,
            dv: v3(7, Vec3::zeros()),
            dw: v3(10, Vec3::zeros()),
        }
    }

    /// fmi2DoStep: advance from t to t + h along the input extrapolation.
    pub fn do_step(&mut self, t: Real, h: Real) -> FmuResult<()> {
        const F: &str = "fmi2DoStep";
        self.allowed(Call::DoStep, F)?;
        if !h.is_finite() || h <= 0.0 {
            return Err(FmuError::error(format!(
                "{F}: communicationStepSize {h:?} must be finite and > 0"
            )));
        }
        let tol = 1e-9 * t.abs().max(1.0);
        if !t.is_finite() || (t - self.s.time).abs() > tol {
            return Err(FmuError::error(format!(
                "{F}: currentCommunicationPoint {t:?} does not match the FMU time {:?}",
                self.s.time
            )));
        }
        let (a, b) = self
            .nodes()
            .map_err(|e| FmuError::error(format!("{F}: {}", e.message)))?;
        let (ra, rb) = (self.rates(0, &a), self.rates(1, &b));
        let before = self.wants(Category::Events).then_some(self.s.state);
        // the outputs at t + h are evaluated into the cache's spare buffer: it becomes the
        // cache when the step is accepted, and a failed step leaves the cache as it was
        let mut next = State::default();
        match advance_into(
            self.ct,
            &self.s.params,
            &self.s.state,
            (&a, &ra),
            (&b, &rb),
            h,
            (self.cache.spare(), &mut next),
        ) {
            Ok((a1, b1)) => {
                self.s.state = next;
                self.s.time = t + h;
                write_node(&mut self.s.inputs[0], &a1);
                write_node(&mut self.s.inputs[1], &b1);
                self.s.input_der_set = [[false; 13]; 2];
                // Outputs are a function of (inputs, committed state) alone: the last substep
                // was evaluated on the nodes exactly as they are written back, from the angle
                // branches and friction state it commits, so its outputs are that function's
                // value (bit for bit: a restored FMU state reports what was read at saving).
                self.cache.commit_spare();
                if let Some(before) = before {
                    self.log_transitions(&before, &self.s.state);
                }
                Ok(())
            }
            Err(e) => {
                self.s.mode = Mode::Error;
                Err(step_error(t, h, e))
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

    /// fmi2GetRealStatus (fmi2LastSuccessfulTime).
    pub fn last_successful_time(&self) -> FmuResult<Real> {
        self.allowed(Call::Status, "fmi2GetRealStatus")?;
        Ok(self.s.time)
    }

    /// fmi2GetBooleanStatus (fmi2Terminated): the slave never asks to terminate.
    pub fn terminated_status(&self) -> FmuResult<bool> {
        self.allowed(Call::Status, "fmi2GetBooleanStatus")?;
        Ok(false)
    }

    /// fmi2GetFMUstate.
    pub fn get_state(&self) -> FmuResult<Snapshot> {
        self.allowed(Call::Lifecycle, "fmi2GetFMUstate")?;
        Ok(self.s.clone())
    }

    /// Refuses an FMU state made by an instance of another variant (`fname` names the caller):
    /// its parameters and inputs follow another variable table.
    pub fn own_state(&self, s: &Snapshot, fname: &str) -> FmuResult<()> {
        if s.variant == self.s.variant {
            return Ok(());
        }
        Err(FmuError::error(format!(
            "{fname}: the state belongs to {}, not {}; refused",
            s.variant.spec().model_identifier,
            self.table.spec.model_identifier
        )))
    }

    /// fmi2SetFMUstate.
    pub fn set_state(&mut self, s: &Snapshot) -> FmuResult<()> {
        self.allowed(Call::Lifecycle, "fmi2SetFMUstate")?;
        self.own_state(s, "fmi2SetFMUstate")?;
        self.s = s.clone();
        self.cache.clear();
        Ok(())
    }
}

/// The outputs at the current inputs and committed state, in one of two buffers: a step (or
/// a read) evaluates into the spare one, which becomes the cache only when that succeeds. So
/// outputs are never copied, and a failed evaluation leaves the cache as it was.
struct OutputCache {
    buf: [Outputs; 2],
    /// The buffer holding the cache.
    cur: usize,
    /// Whether `buf[cur]` holds the outputs (else they are to be computed).
    valid: bool,
}

impl OutputCache {
    fn new() -> OutputCache {
        OutputCache {
            buf: [Outputs::default(); 2],
            cur: 0,
            valid: false,
        }
    }

    /// The cached outputs, None when they are to be computed.
    #[inline]
    fn get(&self) -> Option<&Outputs> {
        self.valid.then_some(&self.buf[self.cur])
    }

    /// Forgets the outputs (inputs, parameters or state changed).
    #[inline]
    fn clear(&mut self) {
        self.valid = false;
    }

    /// The buffer that is not the cache, to evaluate into.
    #[inline]
    fn spare(&mut self) -> &mut Outputs {
        &mut self.buf[1 - self.cur]
    }

    /// Makes the spare buffer, just filled, the cache.
    #[inline]
    fn commit_spare(&mut self) {
        self.cur = 1 - self.cur;
        self.valid = true;
    }
}

/// Outputs at `inputs` with the committed state of `s` (in initialization: with the state the
/// instance would start from at those inputs), written into `o`.
fn evaluate_at_into(
    ct: ConnectionType,
    s: &Snapshot,
    inputs: &[NodeInputs; 2],
    mode: Eval,
    fname: &str,
    o: &mut Outputs,
) -> FmuResult<()> {
    let (a, b) =
        nodes_of(inputs).map_err(|e| FmuError::error(format!("{fname}: {}", e.message)))?;
    let init;
    let st = if s.mode == Mode::InitializationMode {
        init = initial_state(ct, &s.params, &a, &b).map_err(|e| singular_error(fname, e))?;
        &init
    } else {
        &s.state
    };
    let mut next = State::default();
    evaluate_into(ct, &s.params, st, &a, &b, mode, (o, &mut next))
        .map_err(|e| singular_error(fname, e))?;
    if !crate::physics::step::outputs_finite(o) {
        return Err(FmuError::error(format!(
            "{fname}: the outputs at these inputs are not finite"
        )));
    }
    Ok(())
}

/// The message of a refused fmi2DoStep(t, h) (off the hot path).
#[cold]
#[inline(never)]
fn step_error(t: Real, h: Real, e: StepError) -> FmuError {
    const F: &str = "fmi2DoStep";
    FmuError::error(match e {
        StepError::Singular(s, tau) => format!(
            "{F}: at t = {:?}: {}; the state at t = {t:?} is kept (fmi2Reset or fmi2SetFMUstate recovers)",
            t + tau,
            singular_text(s)
        ),
        StepError::NotFinite(tau) => format!(
            "{F}: at t = {:?}: an output would not be finite; the state at t = {t:?} is kept",
            t + tau
        ),
        StepError::TooManySubsteps(n) => format!(
            "{F}: the step h = {h:?} would need {n:e} internal substeps (more than {}); use a smaller step or a larger cosim.maxSubstep",
            crate::physics::step::MAX_SUBSTEPS
        ),
    })
}

/// The nodes from raw inputs (quaternions normalised; a bad one is refused).
fn nodes_of(inputs: &[NodeInputs; 2]) -> FmuResult<(Node, Node)> {
    let mut out = [Node::default(); 2];
    for (n, node) in out.iter_mut().enumerate() {
        let u = &inputs[n];
        let q = quat_from_wxyz(u[3], u[4], u[5], u[6]).ok_or_else(|| {
                let nm = ["a", "b"][n];
                FmuError::error(format!(
                    "orientation {nm}.q = ({:?}, {:?}, {:?}, {:?}) is not a rotation: its norm is below 1e-6 or not finite",
                    u[3], u[4], u[5], u[6]
                ))
            })?;
        *node = Node {
            r: Vec3::new(u[0], u[1], u[2]),
            q,
            v: Vec3::new(u[7], u[8], u[9]),
            w: Vec3::new(u[10], u[11], u[12]),
        };
    }
    Ok((out[0], out[1]))
}

/// FMI base types, for the type check of get/set calls.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Ty {
    Real,
    Integer,
    Boolean,
}

impl Ty {
    fn of(s: &Start) -> Ty {
        match s {
            Start::Real(_) => Ty::Real,
            Start::Integer(_) => Ty::Integer,
            Start::Boolean(_) => Ty::Boolean,
        }
    }
}

/// What fmi2SetReal / fmi2GetReal do with one value reference: the variable table reduced to
/// what the per-step calls need, indexed by VR (built once per variant).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RealSlot {
    /// No Real variable has this VR: the general path reports it.
    None,
    /// A node input (`Field::Input`), by its index 13·node + idx in the flattened inputs.
    Input(u8),
    /// A node load (`Field::Load`), by its index 3·which + i: fa, ma, fb, mb.
    Load(u8),
    /// Any other Real output: read from the outputs at the current inputs.
    Output(Field),
    /// A Real parameter: read from the parameters (set through the checked batch).
    Param(Field),
}

/// No fast index for this VR (see `RealTables`).
const NO_INDEX: u8 = u8::MAX;

/// The Real slots of a variant's table by VR, and two compact views of them for the per-step
/// calls: VR → the flat index of a node input (fmi2SetReal) and VR → the index of a node load
/// (fmi2GetReal), `NO_INDEX` for every other VR.
struct RealTables {
    slots: Box<[RealSlot]>,
    input_index: Box<[u8]>,
    load_index: Box<[u8]>,
}

/// The Real tables of a variant (built once per variant).
fn real_tables(t: &'static Table) -> &'static RealTables {
    static TABLES: [OnceLock<RealTables>; 5] = [
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
    ];
    TABLES[t.spec.variant as usize].get_or_init(|| {
        let n = t.vars.iter().map(|v| v.vr as usize + 1).max().unwrap_or(0);
        let mut slots = vec![RealSlot::None; n];
        for v in &t.vars {
            if Ty::of(&v.start) != Ty::Real || !t.get(v.vr).is_some_and(|x| std::ptr::eq(x, v)) {
                continue;
            }
            slots[v.vr as usize] = match (v.field, v.causality) {
                (Field::Input { node, idx }, _) => RealSlot::Input(13 * node + idx),
                (Field::Load { which, i }, Causality::Output) => RealSlot::Load(3 * which + i),
                (f, Causality::Output) => RealSlot::Output(f),
                (f, _) => RealSlot::Param(f),
            };
        }
        let index = |pick: fn(RealSlot) -> Option<u8>| -> Box<[u8]> {
            slots.iter().map(|&s| pick(s).unwrap_or(NO_INDEX)).collect()
        };
        RealTables {
            input_index: index(|s| match s {
                RealSlot::Input(j) => Some(j),
                _ => None,
            }),
            load_index: index(|s| match s {
                RealSlot::Load(j) => Some(j),
                _ => None,
            }),
            slots: slots.into_boxed_slice(),
        }
    })
}

/// The message for an unknown VR or a VR of another type (off the hot path).
#[cold]
fn var_error(vr: u32, found: Option<&VarSpec>, want: Ty, fname: &str) -> FmuError {
    match found {
        None => FmuError::error(format!("{fname}: unknown value reference {vr}")),
        Some(v) => FmuError::error(format!(
            "{fname}: variable {} (vr {vr}) is of type {:?}, not {want:?}",
            v.name,
            Ty::of(&v.start)
        )),
    }
}

/// The node loads side by side, indexed by `RealSlot::Load`: fa, ma, fb, mb.
#[inline]
fn node_loads(o: &Outputs) -> [Real; 12] {
    let (fa, ma, fb, mb) = (o.fa, o.ma, o.fb, o.mb);
    [
        fa.x, fa.y, fa.z, ma.x, ma.y, ma.z, fb.x, fb.y, fb.z, mb.x, mb.y, mb.z,
    ]
}

/// Writes an extrapolated node back into the inputs.
fn write_node(u: &mut NodeInputs, n: &Node) {
    let q = n.q.quaternion();
    *u = [
        n.r.x, n.r.y, n.r.z, q.w, q.i, q.j, q.k, n.v.x, n.v.y, n.v.z, n.w.x, n.w.y, n.w.z,
    ];
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

fn singular_error(fname: &str, s: Singular) -> FmuError {
    FmuError::error(format!("{fname}: {}", singular_text(s)))
}

/// Writes a Real value into parameters or inputs after checking it.
pub(crate) fn write_real(
    p: &mut Params,
    u: &mut [NodeInputs; 2],
    f: Field,
    x: Real,
) -> Result<(), &'static str> {
    let finite = |x: Real| {
        if x.is_finite() {
            Ok(x)
        } else {
            Err("is not finite")
        }
    };
    let nonneg = |x: Real| {
        if !x.is_finite() {
            Err("is not finite")
        } else if x < 0.0 {
            Err("must not be negative")
        } else {
            Ok(x)
        }
    };
    match f {
        Field::Input { node, idx } => u[node as usize][idx as usize] = finite(x)?,
        Field::CompParam { par, k } => {
            let k = k as usize;
            match par {
                CompPar::Stiffness => p.k[k] = nonneg(x)?,
                CompPar::Damping => p.c[k] = nonneg(x)?,
                CompPar::RefValue => p.ref_value[k] = finite(x)?,
                CompPar::StopLower | CompPar::StopUpper => {
                    if x.is_nan() {
                        return Err("is NaN");
                    }
                    if par == CompPar::StopLower {
                        p.stop_lower[k] = x
                    } else {
                        p.stop_upper[k] = x
                    }
                }
                CompPar::RefGiven => return Err("is not a Real"),
            }
        }
        Field::Param(s) => {
            use ScalarPar::*;
            let fr = &mut p.friction;
            match s {
                StopK => p.stop.k = nonneg(x)?,
                StopC => p.stop.c = nonneg(x)?,
                StopKr => p.stop.k_rot = nonneg(x)?,
                StopCr => p.stop.c_rot = nonneg(x)?,
                ConK => p.constraint.k = nonneg(x)?,
                ConC => p.constraint.c = nonneg(x)?,
                ConKr => p.constraint.k_rot = nonneg(x)?,
                ConCr => p.constraint.c_rot = nonneg(x)?,
                MuS => fr.mu_static = nonneg(x)?,
                MuK => fr.mu_kinetic = nonneg(x)?,
                Decay => fr.decay = nonneg(x)?,
                Radius => fr.radius = nonneg(x)?,
                Fint => fr.f_int = finite(x)?,
                Mint => fr.m_int = finite(x)?,
                StickK | StickKr => {
                    let v = nonneg(x)?;
                    if v == 0.0 {
                        return Err("must be > 0");
                    }
                    if s == StickK {
                        fr.k_stick = v
                    } else {
                        fr.k_stick_r1 = v
                    }
                }
                StickC => fr.c_stick = nonneg(x)?,
                StickCr => fr.c_stick_r1 = nonneg(x)?,
                MaxForce => {
                    if x.is_nan() || x < 0.0 {
                        return Err("must be >= 0 (+INF: no cap)");
                    }
                    fr.max_force = x
                }
                MaxSubstep => p.max_substep = nonneg(x)?,
                Coupling | Extrapolation => return Err("is not a Real"),
            }
        }
        _ => return Err("cannot be set"),
    }
    Ok(())
}

/// Writes an Integer parameter after checking it.
pub(crate) fn write_int(p: &mut Params, f: Field, x: i32) -> Result<(), &'static str> {
    match f {
        Field::Param(ScalarPar::Coupling) => match x {
            0 | 1 => p.friction.coupling = x,
            _ => return Err("must be 0 or 1"),
        },
        Field::Param(ScalarPar::Extrapolation) => {
            p.extrapolation = match x {
                0 => Extrapolation::Hold,
                1 => Extrapolation::Linear,
                _ => return Err("must be 0 (hold) or 1 (linear)"),
            }
        }
        _ => return Err("is not an Integer"),
    }
    Ok(())
}

pub(crate) fn read_real_param(p: &Params, f: Field) -> Real {
    use ScalarPar::*;
    let fr = &p.friction;
    match f {
        Field::CompParam { par, k } => {
            let k = k as usize;
            match par {
                CompPar::Stiffness => p.k[k],
                CompPar::Damping => p.c[k],
                CompPar::RefValue => p.ref_value[k],
                CompPar::StopLower => p.stop_lower[k],
                CompPar::StopUpper => p.stop_upper[k],
                CompPar::RefGiven => 0.0,
            }
        }
        Field::Param(s) => match s {
            StopK => p.stop.k,
            StopC => p.stop.c,
            StopKr => p.stop.k_rot,
            StopCr => p.stop.c_rot,
            ConK => p.constraint.k,
            ConC => p.constraint.c,
            ConKr => p.constraint.k_rot,
            ConCr => p.constraint.c_rot,
            MuS => fr.mu_static,
            MuK => fr.mu_kinetic,
            Decay => fr.decay,
            Radius => fr.radius,
            Fint => fr.f_int,
            Mint => fr.m_int,
            StickK => fr.k_stick,
            StickKr => fr.k_stick_r1,
            StickC => fr.c_stick,
            StickCr => fr.c_stick_r1,
            MaxForce => fr.max_force,
            MaxSubstep => p.max_substep,
            Coupling | Extrapolation => 0.0,
        },
        _ => 0.0,
    }
}

/// Node load 3·which + i: fa, ma, fb, mb.
#[inline]
fn load(o: &Outputs, j: u8) -> Real {
    let v = match j / 3 {
        0 => &o.fa,
        1 => &o.ma,
        2 => &o.fb,
        _ => &o.mb,
    };
    v[(j % 3) as usize]
}

fn read_output(o: &Outputs, f: Field) -> Real {
    match f {
        Field::Load { which, i } => load(o, 3 * which + i),
        Field::Comp { out, k } => {
            let k = k as usize;
            match out {
                CompOut::Position => o.cp[k],
                CompOut::Motion => o.cu[k],
                CompOut::Velocity => o.cv[k],
                CompOut::Total => o.ctf[k],
                CompOut::Elastic => o.cef[k],
                CompOut::Viscous => o.cvf[k],
                CompOut::Friction => o.csf[k],
                CompOut::Reaction => o.crf[k],
            }
        }
        Field::Friction(ff) => {
            let fr = &o.friction;
            match ff {
                FrictionField::Cnf => fr.cnf,
                FrictionField::Cnm1 => fr.cnm1,
                FrictionField::Csfc => fr.csfc,
                FrictionField::Csmc1 => fr.csmc1,
                FrictionField::Slip => fr.slip,
                FrictionField::SlipR1 => fr.slip_r1,
                FrictionField::Status => fr.status as i32 as Real,
                FrictionField::StatusR1 => fr.status_r1 as i32 as Real,
            }
        }
        Field::Energy(i) => {
            let e = &o.energy;
            [e.stored, e.damping, e.friction, e.stops][i as usize]
        }
        _ => 0.0,
    }
}

impl ModelInstance {
    /// fmi2GetDirectionalDerivative: J·dknown, J = ∂(unknowns)/∂(knowns) at the current
    /// inputs and committed state: the connector's consistent tangent (stick: stick stiffness;
    /// slip: tangent of the return map; active stops and penalties included).
    ///
    /// A friction effect that slips at the current inputs (trial force on or beyond its limit)
    /// is differentiated on its slip branch (`Eval::Tangent`), so the derivative where a
    /// slipping step ended is the return map's slip tangent, not the average of the stick and
    /// slip sides of the kink.
    /// Computed as the central difference of the kernel's output function along dknown,
    /// (y(u + εδ) − y(u − εδ))/(2ε), ε = 1e-8·max(1, |u|)/|δ|: truncation O((ε/ℓ)²) with ℓ the
    /// smallest length over which the response bends (an elastic stick slip of µm still gives
    /// 1e-4 relative), round-off O(1e-16·|y|/ε), far below the stiffnesses involved;
    /// exact up to round-off for a linear connector. The committed state is not touched.
    pub fn directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        dknown: &[Real],
        out: &mut [Real],
    ) -> FmuResult<()> {
        const F: &str = "fmi2GetDirectionalDerivative";
        self.allowed(Call::Get, F)?;
        for &vr in unknowns {
            let v = self.var(vr, Ty::Real, F)?;
            if v.causality != Causality::Output || v.variability != Variability::Continuous {
                return Err(FmuError::error(format!(
                    "{F}: unknown {} is not a continuous Real output",
                    v.name
                )));
            }
        }
        let mut scale: Real = 1.0;
        let mut dmax: Real = 0.0;
        for (&vr, &d) in knowns.iter().zip(dknown) {
            let (node, idx) = self.finite_input(vr, d, "seed", F)?;
            scale = scale.max(self.s.inputs[node][idx].abs());
            dmax = dmax.max(d.abs());
        }
        if dmax == 0.0 {
            out.iter_mut().for_each(|x| *x = 0.0);
            return Ok(());
        }
        // J·δ is linear in δ: difference along δ/max|δ| and scale back by max|δ|, so that
        // neither huge nor denormal seeds make ε overflow or underflow (regression 003)
        let eps = 1e-8 * scale;
        // effects slipping at the current inputs are differentiated on their slip branch
        let here = self.outputs(F)?.friction;
        let mode = Eval::Tangent([here.status == Status::Slip, here.status_r1 == Status::Slip]);
        let shifted = |sign: Real| {
            let mut u = self.s.inputs;
            for (&vr, &d) in knowns.iter().zip(dknown) {
                if let Some(Field::Input { node, idx }) = self.table.get(vr).map(|v| v.field) {
                    u[node as usize][idx as usize] += sign * eps * (d / dmax);
                }
            }
            u
        };
        let plus = self.evaluate_at(&shifted(1.0), mode, F)?;
        let minus = self.evaluate_at(&shifted(-1.0), mode, F)?;
        for (&vr, slot) in unknowns.iter().zip(out.iter_mut()) {
            let v = self.var(vr, Ty::Real, F)?;
            let d =
                dmax * ((read_output(&plus, v.field) - read_output(&minus, v.field)) / (2.0 * eps));
            if !d.is_finite() {
                return Err(FmuError::error(format!(
                    "{F}: the derivative of {} along dvKnown is not finite (the seed's size {dmax:e} takes it beyond the range of a double)",
                    v.name
                )));
            }
            *slot = d;
        }
        Ok(())
    }

    /// fmi2DeSerializeFMUstate: validates bytes and returns the snapshot they hold.
    pub fn deserialize(&self, bytes: &[u8]) -> FmuResult<Snapshot> {
        self.allowed(Call::Lifecycle, "fmi2DeSerializeFMUstate")?;
        crate::state_bytes::decode(self.table, bytes).map_err(|why| {
            FmuError::error(format!(
                "fmi2DeSerializeFMUstate: {why}; state not restored"
            ))
        })
    }
}

/// fmi2SerializeFMUstate: the snapshot as versioned bytes.
pub fn serialize(table: &Table, s: &Snapshot) -> Vec<u8> {
    crate::state_bytes::encode(table, s)
}

/// An Integer parameter's value.
pub(crate) fn read_int_param(p: &Params, f: Field) -> i32 {
    match f {
        Field::Param(ScalarPar::Coupling) => p.friction.coupling,
        Field::Param(ScalarPar::Extrapolation) => match p.extrapolation {
            Extrapolation::Hold => 0,
            Extrapolation::Linear => 1,
        },
        _ => 0,
    }
}
