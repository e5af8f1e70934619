//! Hand-written C types of FMI 2.0 (`fmi2TypesPlatform.h`, `fmi2FunctionTypes.h`), once for
//! both FMUs.
//!
//! Enums that C *sends* (`fmi2Type`, `fmi2StatusKind`, `fmi2Boolean`) arrive as `c_int` and are
//! converted with `TryFrom` / `!= 0` or compared with the `FMI2_*` constants: a value outside
//! the Rust enum is an error, never UB. `fmi2Status` is only ever *returned* to C (or passed to
//! its callbacks), so it is a `#[repr(C)]` enum; each FMU maps its own status levels onto it.
//! Uses only std; the `fmi2` boundaries of connector_fmu (src/fmi2) and body_fmu
//! (bodies/src/fmi2) use it through their `types` modules, and both FMI 3.0 loggers reuse the
//! FMI 2.0 environment pointer type.
#![allow(non_camel_case_types, non_snake_case, non_upper_case_globals)]

use std::ffi::{c_char, c_double, c_int, c_uint, c_void};

/// Opaque instance handle (the FMU's instance behind the pointer).
pub type fmi2Component = *mut c_void;
/// The importer's opaque pointer, handed back to its callbacks unchanged.
pub type fmi2ComponentEnvironment = *mut c_void;
/// Opaque FMU state (a `Box<Snapshot>` behind the pointer).
pub type fmi2FMUstate = *mut c_void;
/// Value reference.
pub type fmi2ValueReference = c_uint;
/// Real.
pub type fmi2Real = c_double;
/// Integer.
pub type fmi2Integer = c_int;
/// Boolean (`fmi2True` = 1, `fmi2False` = 0; any non-zero value reads as true).
pub type fmi2Boolean = c_int;
/// Character.
pub type fmi2Char = c_char;
/// NUL-terminated C string.
pub type fmi2String = *const fmi2Char;
/// Byte of a serialized FMU state.
pub type fmi2Byte = c_char;

/// fmi2True.
pub const fmi2True: fmi2Boolean = 1;
/// fmi2False.
pub const fmi2False: fmi2Boolean = 0;

/// `fmi2CoSimulation` of `fmi2Type`, as the `c_int` C passes (fmi2ModelExchange = 0).
pub const FMI2_CO_SIMULATION: c_int = 1;
/// `fmi2LastSuccessfulTime` of `fmi2StatusKind`, as the `c_int` C passes.
pub const FMI2_LAST_SUCCESSFUL_TIME: c_int = 2;
/// `fmi2Terminated` of `fmi2StatusKind`, as the `c_int` C passes.
pub const FMI2_TERMINATED: c_int = 3;

/// Status returned by every FMI function (`fmi2OK` … `fmi2Pending`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum fmi2Status {
    /// fmi2OK
    OK = 0,
    /// fmi2Warning
    Warning = 1,
    /// fmi2Discard
    Discard = 2,
    /// fmi2Error
    Error = 3,
    /// fmi2Fatal
    Fatal = 4,
    /// fmi2Pending (never returned: steps are synchronous)
    Pending = 5,
}

/// `fmi2Type`, converted from the `c_int` that C passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum fmi2Type {
    /// fmi2ModelExchange = 0
    ModelExchange,
    /// fmi2CoSimulation = 1
    CoSimulation,
}

impl TryFrom<c_int> for fmi2Type {
    type Error = c_int;
    fn try_from(v: c_int) -> Result<Self, c_int> {
        match v {
            0 => Ok(fmi2Type::ModelExchange),
            1 => Ok(fmi2Type::CoSimulation),
            other => Err(other),
        }
    }
}

/// `fmi2StatusKind`, converted from the `c_int` that C passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum fmi2StatusKind {
    /// fmi2DoStepStatus = 0
    DoStepStatus,
    /// fmi2PendingStatus = 1
    PendingStatus,
    /// fmi2LastSuccessfulTime = 2
    LastSuccessfulTime,
    /// fmi2Terminated = 3
    Terminated,
}

impl TryFrom<c_int> for fmi2StatusKind {
    type Error = c_int;
    fn try_from(v: c_int) -> Result<Self, c_int> {
        match v {
            0 => Ok(fmi2StatusKind::DoStepStatus),
            1 => Ok(fmi2StatusKind::PendingStatus),
            2 => Ok(fmi2StatusKind::LastSuccessfulTime),
            3 => Ok(fmi2StatusKind::Terminated),
            other => Err(other),
        }
    }
}

impl fmi2StatusKind {
    /// The C spelling, for log messages.
    pub fn name(self) -> &'static str {
        match self {
            fmi2StatusKind::DoStepStatus => "fmi2DoStepStatus",
            fmi2StatusKind::PendingStatus => "fmi2PendingStatus",
            fmi2StatusKind::LastSuccessfulTime => "fmi2LastSuccessfulTime",
            fmi2StatusKind::Terminated => "fmi2Terminated",
        }
    }
}

/// `fmi2CallbackLogger`: C-variadic; the FMU calls it with the five fixed arguments only and a
/// message in which every `%` is doubled (importers use it as a printf format).
pub type fmi2CallbackLogger = unsafe extern "C" fn(
    componentEnvironment: fmi2ComponentEnvironment,
    instanceName: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    message: fmi2String,
    ...
);
/// `fmi2CallbackAllocateMemory` (not used: canNotUseMemoryManagementFunctions).
pub type fmi2CallbackAllocateMemory = unsafe extern "C" fn(nobj: usize, size: usize) -> *mut c_void;
/// `fmi2CallbackFreeMemory` (not used).
pub type fmi2CallbackFreeMemory = unsafe extern "C" fn(obj: *mut c_void);
/// `fmi2StepFinished` (not used: steps are synchronous).
pub type fmi2StepFinished =
    unsafe extern "C" fn(componentEnvironment: fmi2ComponentEnvironment, status: fmi2Status);

/// `fmi2CallbackFunctions`; every callback may be NULL (`None`) in C, so each is an `Option`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct fmi2CallbackFunctions {
    /// Logger (required by this FMU).
    pub logger: Option<fmi2CallbackLogger>,
    /// Memory allocation (ignored).
    pub allocateMemory: Option<fmi2CallbackAllocateMemory>,
    /// Memory release (ignored).
    pub freeMemory: Option<fmi2CallbackFreeMemory>,
    /// Asynchronous step completion (ignored).
    pub stepFinished: Option<fmi2StepFinished>,
    /// The importer's pointer, passed back to the logger.
    pub componentEnvironment: fmi2ComponentEnvironment,
}
