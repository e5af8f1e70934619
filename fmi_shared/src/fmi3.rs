//! Hand-written C types of FMI 3.0 (`fmi3PlatformTypes.h`, `fmi3FunctionTypes.h`), once for
//! both FMUs.
//!
//! `fmi3Boolean` is C `bool`; it is taken as a byte (`u8`, same size and calling convention) so
//! that a value other than 0 or 1 from a careless importer reads as true instead of being an
//! invalid Rust `bool`; the FMUs only ever write 0 or 1. Enums that C sends
//! (`fmi3DependencyKind` is only written, `fmi3IntervalQualifier` only written) need no
//! conversion; `fmi3Status` is only returned, so it is a `#[repr(C)]` enum; each FMU maps its
//! own status levels onto it. Uses only std; the `fmi3` boundaries of connector_fmu (src/fmi3)
//! and body_fmu (bodies/src/fmi3) use it through their `types` modules.
#![allow(non_camel_case_types, non_snake_case, non_upper_case_globals)]

use std::ffi::{c_char, c_int, c_void};

/// Opaque instance handle (the FMU's instance behind the pointer).
pub type fmi3Instance = *mut c_void;
/// The importer's opaque pointer, handed back to its callbacks unchanged.
pub type fmi3InstanceEnvironment = *mut c_void;
/// Opaque FMU state (a `Box<Snapshot>` behind the pointer, as in FMI 2.0).
pub type fmi3FMUState = *mut c_void;
/// Value reference.
pub type fmi3ValueReference = u32;
/// Float64.
pub type fmi3Float64 = f64;
/// Float32.
pub type fmi3Float32 = f32;
/// Int32.
pub type fmi3Int32 = i32;
/// C `bool`, read as a byte (any non-zero value is true).
pub type fmi3Boolean = u8;
/// Character.
pub type fmi3Char = c_char;
/// NUL-terminated C string.
pub type fmi3String = *const fmi3Char;
/// Byte of a serialized FMU state or of a binary value.
pub type fmi3Byte = u8;
/// A binary value: pointer to its first byte.
pub type fmi3Binary = *const fmi3Byte;
/// Clock (C `bool`, read as a byte).
pub type fmi3Clock = u8;

/// fmi3True.
pub const fmi3True: fmi3Boolean = 1;
/// fmi3False.
pub const fmi3False: fmi3Boolean = 0;

/// Status returned by every FMI 3.0 function (`fmi3OK` … `fmi3Fatal`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum fmi3Status {
    /// fmi3OK
    OK = 0,
    /// fmi3Warning
    Warning = 1,
    /// fmi3Discard
    Discard = 2,
    /// fmi3Error
    Error = 3,
    /// fmi3Fatal
    Fatal = 4,
}

/// `fmi3DependencyKind` (only written by the FMU).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum fmi3DependencyKind {
    /// fmi3Independent
    Independent = 0,
    /// fmi3Constant
    Constant = 1,
    /// fmi3Fixed
    Fixed = 2,
    /// fmi3Tunable
    Tunable = 3,
    /// fmi3Discrete
    Discrete = 4,
    /// fmi3Dependent
    Dependent = 5,
}

/// `fmi3IntervalQualifier` (never written: this FMU has no clocks).
pub type fmi3IntervalQualifier = c_int;

/// `fmi3LogMessageCallback`: unlike FMI 2.0, not variadic and `message` is not a format.
pub type fmi3LogMessageCallback = unsafe extern "C" fn(
    instanceEnvironment: fmi3InstanceEnvironment,
    status: fmi3Status,
    category: fmi3String,
    message: fmi3String,
);

/// `fmi3IntermediateUpdateCallback` (never called: providesIntermediateUpdate = false).
pub type fmi3IntermediateUpdateCallback = unsafe extern "C" fn(
    instanceEnvironment: fmi3InstanceEnvironment,
    intermediateUpdateTime: fmi3Float64,
    intermediateVariableSetRequested: fmi3Boolean,
    intermediateVariableGetAllowed: fmi3Boolean,
    intermediateStepFinished: fmi3Boolean,
    canReturnEarly: fmi3Boolean,
    earlyReturnRequested: *mut fmi3Boolean,
    earlyReturnTime: *mut fmi3Float64,
);

/// `fmi3ClockUpdateCallback` (Scheduled Execution, refused).
pub type fmi3ClockUpdateCallback =
    unsafe extern "C" fn(instanceEnvironment: fmi3InstanceEnvironment);
/// `fmi3LockPreemptionCallback` (Scheduled Execution, refused).
pub type fmi3LockPreemptionCallback = unsafe extern "C" fn();
/// `fmi3UnlockPreemptionCallback` (Scheduled Execution, refused).
pub type fmi3UnlockPreemptionCallback = unsafe extern "C" fn();
