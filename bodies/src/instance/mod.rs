//! One Body instance without FMI types: the FMI state machine (which call is allowed when),
//! logging, and the lifecycle calls and the step. Its data (everything an FMU state holds) is
//! `data`, getting and setting values `values`, the FMU state and its bytes `snapshot`. Uses
//! those, `crate::physics` and `crate::error`.

mod data;
mod snapshot;
mod values;

pub use data::{Data, Mode};
pub use snapshot::Snapshot;

use crate::error::{Category, FmuError, FmuResult, Level};
use crate::physics;

/// Where log messages go (the importer's callback, behind the FMI boundary).
pub trait LogSink: Send {
    /// Writes one message.
    fn log(&self, level: Level, category: Category, message: &str);
}

/// The FMI version an instance was made through: it words messages and makes value reference
/// 0 the FMI 3.0 independent variable `time`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FmiVersion {
    /// FMI 2.0
    V2,
    /// FMI 3.0
    V3,
}

impl FmiVersion {
    /// "fmi2" or "fmi3", the prefix of the function names.
    pub fn prefix(self) -> &'static str {
        match self {
            FmiVersion::V2 => "fmi2",
            FmiVersion::V3 => "fmi3",
        }
    }
}

/// Calls whose permission depends on the state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    /// SetDebugLogging, status queries, (de)serialisation: any state
    Any,
    /// SetupExperiment, EnterInitializationMode
    Setup,
    /// ExitInitializationMode
    ExitInit,
    /// DoStep
    DoStep,
    /// Terminate
    Terminate,
    /// Get*
    Get,
    /// Set* (which variables, `values` decides)
    Set,
    /// GetFMUState, SetFMUState
    State,
}

/// One instance: its data, logger and logging switch.
pub struct Instance {
    data: Data,
    logger: Box<dyn LogSink>,
    log_all: bool,
    version: FmiVersion,
    fatal: bool,
}

impl Instance {
    /// A new instance in the Instantiated state; `logging_on` switches logAll on.
    pub fn new(logger: Box<dyn LogSink>, logging_on: bool, version: FmiVersion) -> Self {
        Instance {
            data: Data::new(),
            logger,
            log_all: logging_on,
            version,
            fatal: false,
        }
    }

    /// The FMI version this instance was made through.
    pub fn version(&self) -> FmiVersion {
        self.version
    }

    /// True from ExitInitializationMode on (Step Mode and after Terminate).
    pub fn initialized(&self) -> bool {
        matches!(self.data.mode, Mode::Step | Mode::Terminated)
    }

    /// The FMU's time.
    pub fn time(&self) -> f64 {
        self.data.time
    }

    /// Writes a message: errors always, logAll messages only when logging is on.
    pub fn log(&self, level: Level, category: Category, message: &str) {
        if category == Category::Error || self.log_all {
            self.logger.log(level, category, message);
        }
    }

    /// True when messages of `category` are written (to skip formatting them otherwise).
    pub fn wants(&self, category: Category) -> bool {
        category == Category::Error || self.log_all
    }

    /// Marks the instance unusable after a caught panic: only FreeInstance is left.
    pub fn set_fatal(&mut self) {
        self.fatal = true;
    }

    /// SetDebugLogging: `categories` empty switches every category; unknown names are refused
    /// (nothing changes then). logStatusError stays on whatever is asked.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> FmuResult<()> {
        self.allowed(Call::Any)?;
        let mut all = categories.is_empty();
        for name in categories {
            match Category::from_name(name) {
                Some(c) => all |= c == Category::All,
                None => {
                    return Err(FmuError::error(format!(
                        "unknown log category \"{name}\" (declared: logStatusError, logAll)"
                    )))
                }
            }
        }
        if all {
            self.log_all = on;
        }
        Ok(())
    }

    /// Ok when `call` is allowed now; otherwise the error naming the state.
    pub fn allowed(&self, call: Call) -> FmuResult<()> {
        let p = self.version.prefix();
        if self.fatal {
            return Err(FmuError::error(format!(
                "the instance had a fatal error; only {p}FreeInstance is allowed"
            )));
        }
        let mode = self.data.mode;
        let ok = match call {
            Call::Any | Call::State => true,
            Call::Setup => mode == Mode::Instantiated,
            Call::ExitInit => mode == Mode::Initialization,
            Call::DoStep | Call::Terminate => mode == Mode::Step,
            Call::Get => mode != Mode::Instantiated,
            Call::Set => mode != Mode::Terminated,
        };
        if ok {
            return Ok(());
        }
        let hint = match mode {
            Mode::Instantiated => format!(" (call {p}EnterInitializationMode first)"),
            Mode::Initialization if call == Call::DoStep => {
                format!(" (call {p}ExitInitializationMode first)")
            }
            Mode::Terminated => format!(" ({p}Reset starts again)"),
            _ => String::new(),
        };
        Err(FmuError::error(format!(
            "not allowed in {}{hint}",
            mode.text()
        )))
    }

    /// SetupExperiment (FMI 2.0; FMI 3.0 passes the start time to EnterInitializationMode).
    pub fn setup_experiment(&mut self, start_time: f64) -> FmuResult<()> {
        self.allowed(Call::Setup)?;
        if !start_time.is_finite() {
            return Err(FmuError::error(format!(
                "startTime {start_time:?} is not finite"
            )));
        }
        self.data.start_time = start_time;
        self.data.time = start_time;
        Ok(())
    }

    /// EnterInitializationMode: outputs now follow the start parameters.
    pub fn enter_initialization_mode(&mut self) -> FmuResult<()> {
        self.allowed(Call::Setup)?;
        self.data.mode = Mode::Initialization;
        Ok(())
    }

    /// ExitInitializationMode: the parameters are checked together and the body starts from
    /// them; refused (staying in Initialization Mode) with a message naming them.
    pub fn exit_initialization_mode(&mut self) -> FmuResult<()> {
        self.allowed(Call::ExitInit)?;
        self.data.body = physics::initial(&self.data.params()).map_err(FmuError::error)?;
        self.data.mode = Mode::Step;
        Ok(())
    }

    /// DoStep: the body moves from the FMU time t over h under the inputs held; time = t + h.
    /// A refused step changes nothing.
    pub fn do_step(&mut self, t: f64, h: f64) -> FmuResult<()> {
        self.allowed(Call::DoStep)?;
        if !h.is_finite() || h <= 0.0 {
            return Err(FmuError::error(format!(
                "communicationStepSize {h:?} must be finite and > 0"
            )));
        }
        if !t.is_finite() || (t - self.data.time).abs() > 1e-9 * t.abs().max(1.0) {
            return Err(FmuError::error(format!(
                "currentCommunicationPoint {t:?} does not match the FMU time {:?}",
                self.data.time
            )));
        }
        let end = t + h;
        if !end.is_finite() {
            return Err(FmuError::error(format!(
                "the step's end currentCommunicationPoint + communicationStepSize = {t:?} + {h:?} is not finite"
            )));
        }
        let d = &self.data;
        let params = d.params();
        let body = physics::step(&params, &d.body, &d.load(&params), end - d.start_time, h)
            .map_err(FmuError::error)?;
        self.data.body = body;
        self.data.time = end;
        Ok(())
    }

    /// Terminate.
    pub fn terminate(&mut self) -> FmuResult<()> {
        self.allowed(Call::Terminate)?;
        self.data.mode = Mode::Terminated;
        Ok(())
    }

    /// Reset: start values, time 0, the Instantiated state (from any state but after a fatal
    /// error).
    pub fn reset(&mut self) -> FmuResult<()> {
        self.allowed(Call::Any)?;
        self.data = Data::new();
        Ok(())
    }

    /// The FMU state now.
    pub fn get_state(&self) -> FmuResult<Snapshot> {
        self.allowed(Call::State)?;
        Ok(Snapshot::of(&self.data))
    }

    /// Restores an FMU state (validated when it was made).
    pub fn set_state(&mut self, s: &Snapshot) -> FmuResult<()> {
        self.allowed(Call::State)?;
        self.data = *s.data();
        Ok(())
    }

    /// The serialized bytes of an FMU state.
    pub fn serialize(&self, s: &Snapshot) -> FmuResult<Vec<u8>> {
        self.allowed(Call::Any)?;
        Ok(s.to_bytes())
    }

    /// An FMU state from serialized bytes, refused (naming why) unless they are a valid state
    /// of this FMU.
    pub fn deserialize(&self, bytes: &[u8]) -> FmuResult<Snapshot> {
        self.allowed(Call::Any)?;
        Snapshot::from_bytes(bytes).map_err(FmuError::error)
    }

    /// Ok when a status query may be answered now (any state but after a fatal error).
    pub fn status_allowed(&self) -> FmuResult<()> {
        self.allowed(Call::Any)
    }
}
