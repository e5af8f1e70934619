//! The calls of one FMI version as the shared interpreter makes them: `St`, a status of either
//! version; `Handle`; `StepOut`, what fmi3DoStep writes besides its status; and the `Api` trait
//! that `fmi2.rs` and `fmi3.rs` implement. Uses only the FMU crate's status types (and names
//! `Program` for the two hooks a version adds to the interpreter).

use super::program::Program;
use connector_fmu::fmi2::types::fmi2Status;
use connector_fmu::fmi3::types::fmi3Status;
use connector_fmu::variables::Variant;
use std::ffi::{c_char, c_void};

/// A status of either version (same numbering; Pending is FMI 2.0 only).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum St {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
    Pending = 5,
}

impl From<fmi2Status> for St {
    fn from(s: fmi2Status) -> St {
        match s {
            fmi2Status::OK => St::Ok,
            fmi2Status::Warning => St::Warning,
            fmi2Status::Discard => St::Discard,
            fmi2Status::Error => St::Error,
            fmi2Status::Fatal => St::Fatal,
            fmi2Status::Pending => St::Pending,
        }
    }
}

impl From<fmi3Status> for St {
    fn from(s: fmi3Status) -> St {
        match s {
            fmi3Status::OK => St::Ok,
            fmi3Status::Warning => St::Warning,
            fmi3Status::Discard => St::Discard,
            fmi3Status::Error => St::Error,
            fmi3Status::Fatal => St::Fatal,
        }
    }
}

pub(super) const OK: St = St::Ok;

/// An instance or FMU state handle of either version.
pub(super) type Handle = *mut c_void;

/// What fmi3DoStep writes besides its status (FMI 2.0: nothing).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepOut {
    pub(super) event_handling_needed: u8,
    pub(super) terminate: u8,
    pub(super) early_return: u8,
    /// lastSuccessfulTime, as bits (compared bit for bit)
    pub(super) last: u64,
}

/// The calls of one FMI version that the shared interpreter makes, each with the name of the
/// exported function (which the FMU's message must contain). Pointer arguments mirror the C
/// signatures, so that NULLs and wrong counts can be passed.
pub trait Api: Sized {
    /// Number of operation codes (the FMI 2.0 program format has 32).
    const N_OPS: u8;
    const SET_REAL: &'static str;
    const GET_REAL: &'static str;
    const SET_INT: &'static str;
    const GET_INT: &'static str;
    const SET_BOOL: &'static str;
    const GET_BOOL: &'static str;
    const GET_STATE: &'static str;
    const SET_STATE: &'static str;
    const FREE_STATE: &'static str;
    const STATE_SIZE: &'static str;
    const SERIALIZE: &'static str;
    const DESERIALIZE: &'static str;
    const SETUP: &'static str;
    const ENTER_INIT: &'static str;
    const EXIT_INIT: &'static str;
    const DO_STEP: &'static str;
    const RESET: &'static str;
    const TERMINATE: &'static str;
    const DIR_DER: &'static str;
    const DEBUG_LOGGING: &'static str;
    const TIME: &'static str;
    /// The third call of the NULL-array operation.
    const NULL_THIRD: &'static str;

    fn set_real(c: Handle, vr: *const u32, n: usize, x: *const f64) -> St;
    fn get_real(c: Handle, vr: *const u32, n: usize, x: *mut f64) -> St;
    fn set_int(c: Handle, vr: *const u32, n: usize, x: *const i32) -> St;
    fn get_int(c: Handle, vr: *const u32, n: usize, x: *mut i32) -> St;
    /// One Boolean, given as the C int of FMI 2.0 (FMI 3.0: its low byte).
    fn set_bool(c: Handle, vr: u32, x: i32) -> St;
    fn get_bools(c: Handle, vrs: &[u32]) -> St;
    fn get_state(c: Handle, s: *mut Handle) -> St;
    fn set_state(c: Handle, s: Handle) -> St;
    fn free_state(c: Handle, s: *mut Handle) -> St;
    fn state_size(c: Handle, s: Handle, n: *mut usize) -> St;
    fn serialize(c: Handle, s: Handle, p: *mut u8, n: usize) -> St;
    fn deserialize(c: Handle, p: *const u8, n: usize, s: *mut Handle) -> St;
    /// fmi2SetupExperiment; FMI 3.0: fmi3EnterInitializationMode with these times.
    fn setup(c: Handle, start: f64, stop_defined: bool, stop: f64) -> St;
    fn enter_init(c: Handle) -> St;
    fn exit_init(c: Handle) -> St;
    fn do_step(c: Handle, t: f64, h: f64) -> (St, Option<StepOut>);
    fn reset(c: Handle) -> St;
    fn terminate(c: Handle) -> St;
    fn dir_der(c: Handle, unknowns: &[u32], knowns: &[u32], seed: &[f64], out: &mut [f64]) -> St;
    fn debug_logging(c: Handle, on: bool, n: usize, categories: *const *const c_char) -> St;
    /// The FMU's current time.
    fn time(c: Handle, t: &mut f64) -> St;
    /// NULL arrays with count n.
    fn null_third(c: Handle, n: usize) -> St;
    fn free_instance(c: Handle);
    /// A valid instance of `v` logging under `env` (for the final clean-up).
    fn instantiate_valid(env: usize, v: Variant) -> Handle;

    /// The program's instantiation of instance slot `i` from the bytes.
    fn instantiate(p: &mut Program<'_, Self>, i: usize);
    /// The operations of this version only (codes the shared interpreter hands over).
    fn special(p: &mut Program<'_, Self>, i: usize, v: Variant, op: u8);
}
