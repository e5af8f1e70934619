//! Hand-written C types of FMI 2.0 (`fmi2TypesPlatform.h`, `fmi2FunctionTypes.h`). Enums that
//! C sends (`fmi2Type`, `fmi2StatusKind`, `fmi2Boolean`) arrive as `c_int` and are compared,
//! never cast; `fmi2Status` is only returned, so it is a `#[repr(C)]` enum. Uses
//! `crate::error::Level`.
#![allow(non_camel_case_types, non_snake_case)]

use crate::error::Level;
use std::ffi::{c_char, c_double, c_int, c_uint, c_void};

/// Opaque instance handle (a `Box<Instance>` behind the pointer).
pub type fmi2Component = *mut c_void;
/// The importer's opaque pointer, handed back to its logger unchanged.
pub type fmi2ComponentEnvironment = *mut c_void;
/// Opaque FMU state (a `Box<Snapshot>` behind the pointer).
pub type fmi2FMUstate = *mut c_void;
/// Value reference.
pub type fmi2ValueReference = c_uint;
/// Real.
pub type fmi2Real = c_double;
/// Integer.
pub type fmi2Integer = c_int;
/// Boolean (any non-zero value reads as true).
pub type fmi2Boolean = c_int;
/// NUL-terminated C string.
pub type fmi2String = *const c_char;
/// Byte of a serialized FMU state.
pub type fmi2Byte = c_char;

/// `fmi2CoSimulation`, the only `fmi2Type` this FMU implements (fmi2ModelExchange = 0).
pub const FMI2_CO_SIMULATION: c_int = 1;
/// `fmi2LastSuccessfulTime` of `fmi2StatusKind`.
pub const FMI2_LAST_SUCCESSFUL_TIME: c_int = 2;
/// `fmi2Terminated` of `fmi2StatusKind`.
pub const FMI2_TERMINATED: c_int = 3;

/// Status returned by every FMI 2.0 function.
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

impl From<Level> for fmi2Status {
    fn from(l: Level) -> Self {
        match l {
            Level::Ok => fmi2Status::OK,
            Level::Error => fmi2Status::Error,
            Level::Fatal => fmi2Status::Fatal,
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

/// `fmi2CallbackFunctions`; every callback may be NULL in C, so each is an `Option`. Only the
/// logger is used (canNotUseMemoryManagementFunctions, synchronous steps).
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct fmi2CallbackFunctions {
    /// Logger (required).
    pub logger: Option<fmi2CallbackLogger>,
    /// Memory allocation (not used).
    pub allocateMemory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// Memory release (not used).
    pub freeMemory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// Asynchronous step completion (not used).
    pub stepFinished: Option<unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status)>,
    /// The importer's pointer, passed back to the logger.
    pub componentEnvironment: fmi2ComponentEnvironment,
}
