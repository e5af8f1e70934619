//! The FMI call-sequence fuzz harness, shared by the libFuzzer target
//! (`fuzz/fuzz_targets/fmi_calls.rs`) and its deterministic replay in `cargo test`
//! (`tests/fuzz_smoke.rs`, included there with `#[path]`). Logger, callbacks and the checksum
//! come from the tests' support module (`tests/common/mod.rs`, included here with `#[path]`).
//!
//! The input bytes are a program of FMI 2.0 calls or, when the first byte is 0xE0 or more, of
//! FMI 3.0 calls (that byte is the mode and is skipped; every committed FMI 2.0 seed starts
//! below it). One interpreter serves both versions: `Api` is the version's calls, `Program`
//! decodes and checks. A program is a header that instantiates one variant (or tries a bad
//! GUID/instantiationToken, type, name, eventModeUsed, callback), then a sequence of operations
//! on up to two instances, four FMU-state slots and two serialized-state buffers. Every exported
//! function is reachable, in FMI 3.0 also the ones this FMU refuses (Model Exchange, Scheduled
//! Execution, Event Mode, clocks, configuration, types it has no variables of); values come from
//! a pool of awkward floats (NaN, ±INF, ±1e308, 5e-324, −0.0, raw bits) and from plausible
//! physics (parameter sets, poses, velocities), so both the refusals and the kernel are exercised.
//!
//! Invariants checked after every call (a violation panics, which libFuzzer reports):
//! 1. no fmi2Fatal / fmi3Fatal (the boundary catches panics, but a caught panic is still a bug);
//! 2. a non-OK status is explained by exactly one non-OK log message of that status, whose text
//!    names the function; an OK status logs no non-OK message (FMI 3.0 instances made without a
//!    logger, which FMI 3.0 allows, are exempt);
//! 3. every Real/Float64 output (and directional or adjoint derivative) returned with OK is
//!    finite;
//! 4. a call that returns fmi2Error / fmi3Error leaves the instance's FMU state (parameters,
//!    inputs, input derivatives, time, connector state) byte-identical, apart from the mode;
//! 5. a state that Serialize wrote is accepted by DeSerialize and re-serializes to the same
//!    bytes; a state of another variant is refused by SetFMUstate and SerializeFMUstate alike;
//! 6. restoring an FMU state and repeating a step reproduces status and outputs (and in FMI 3.0
//!    earlyReturn and lastSuccessfulTime) bit for bit;
//! 7. instantiation with valid arguments succeeds, and a refusal is logged when a logger exists;
//! 8. after a DoStep(t, h) that returns OK: in FMI 3.0 eventHandlingNeeded and
//!    terminateSimulation are false; earlyReturn implies earlyReturnAllowed at instantiation and
//!    t < lastSuccessfulTime < t + h; without it lastSuccessfulTime = t + h (within the FMU's time
//!    tolerance 1e-9·max(|t|, 1)); the FMU's time (fmi3 `time`, fmi2LastSuccessfulTime) is then
//!    lastSuccessfulTime, and every step of a program starts at the FMU's time. Where the
//!    variant has the outputs `event.time` and `event.count` (looked up by name; checked only
//!    when present): t < event.time ≤ t + h (event.time = t + h when a denormal h does not
//!    move t), event.count ≥ 0, and after an early return event.time = lastSuccessfulTime and
//!    event.count ≥ 1;
//! 9. the FMI 3.0 functions of interfaces and features this FMU has not (Model Exchange,
//!    Scheduled Execution, Event Mode, clocks, configuration) answer fmi3Error (NULL for the
//!    instantiation functions).
#![allow(dead_code, clippy::too_many_lines)]

use connector_fmu::fmi2::exports::*;
use connector_fmu::fmi2::types::*;
use connector_fmu::fmi3::exports::*;
use connector_fmu::fmi3::types::*;
use connector_fmu::variables::{table, Causality, Start, Variability, Variant, VARIANTS};
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::marker::PhantomData;
use std::ptr::{null, null_mut};

// ------------------------------------------------------------------ logger

// The logger, callback struct and value lookups of the tests (one support module for the tests,
// this harness and the benchmark). Each program logs under a componentEnvironment key of its own.
#[path = "../tests/common/mod.rs"]
mod support;
use support::{LogLine, CO_SIMULATION};

/// The callback struct of program `env`, with or without a logger.
fn callbacks(env: usize, with_logger: bool) -> fmi2CallbackFunctions {
    let cb = support::callbacks(env);
    fmi2CallbackFunctions {
        logger: cb.logger.filter(|_| with_logger),
        ..cb
    }
}

/// The FMI 3.0 logger: hands each message to the support module's logger, so that messages of
/// both versions are recorded in one place under the program's key (instance name "fmi3").
extern "C" fn logger3(
    env: *mut c_void,
    status: fmi3Status,
    category: *const c_char,
    message: *const c_char,
) {
    let Some(log) = support::callbacks(env as usize).logger else {
        return;
    };
    let status = match status {
        fmi3Status::OK => fmi2Status::OK,
        fmi3Status::Warning => fmi2Status::Warning,
        fmi3Status::Discard => fmi2Status::Discard,
        fmi3Status::Error => fmi2Status::Error,
        fmi3Status::Fatal => fmi2Status::Fatal,
    };
    // SAFETY: the support logger reads exactly these five arguments (C strings that live for
    // the duration of the call, as the FMU passes them here).
    unsafe { log(env, c"fmi3".as_ptr(), status, category, message) };
}

// ------------------------------------------------------------------ status, version calls

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

const OK: St = St::Ok;

/// An instance or FMU state handle of either version.
type Handle = *mut c_void;

/// What fmi3DoStep writes besides its status (FMI 2.0: nothing).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StepOut {
    event_handling_needed: u8,
    terminate: u8,
    early_return: u8,
    /// lastSuccessfulTime, as bits (compared bit for bit)
    last: u64,
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

// ------------------------------------------------------------------ input decoding

/// The program bytes; reads past the end yield zeros.
pub struct Bytes<'a> {
    d: &'a [u8],
    i: usize,
}

impl<'a> Bytes<'a> {
    pub fn new(d: &'a [u8]) -> Self {
        Bytes { d, i: 0 }
    }
    fn done(&self) -> bool {
        self.i >= self.d.len()
    }
    fn u8(&mut self) -> u8 {
        let b = self.d.get(self.i).copied().unwrap_or(0);
        self.i += 1;
        b
    }
    fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    fn u64(&mut self) -> u64 {
        (self.u32() as u64) | ((self.u32() as u64) << 32)
    }
    /// A signed value in [−1, 1).
    fn unit(&mut self) -> f64 {
        (self.u16() as i16) as f64 / 32768.0
    }

    /// A float from the pool of awkward and ordinary values.
    fn real(&mut self) -> f64 {
        match self.u8() % 24 {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            3 => 1e308,
            4 => -1e308,
            5 => 5e-324,
            6 => -0.0,
            7 => 0.0,
            8 => 1.0,
            9 => -1.0,
            10 => f64::MAX,
            11 => f64::MIN_POSITIVE,
            12 => f64::from_bits(self.u64()),
            13 => std::f64::consts::PI * (self.u8() as i8) as f64 / 16.0,
            14 => 1e-12 * self.unit(),
            15 => 1e6 * self.unit(),
            16 => -5e-324,
            17 => 1e154 * self.unit(),
            _ => 10.0 * self.unit(),
        }
    }

    /// A step size: zero, negative, non-finite, huge, denormal, ordinary.
    fn step(&mut self) -> f64 {
        match self.u8() % 16 {
            0 => 0.0,
            1 => -1e-3,
            2 => f64::NAN,
            3 => f64::INFINITY,
            4 => 1e300,
            5 => 5e-324,
            6 => 1.0,
            7 => 1e-6,
            8 => 0.1 * (1.0 + self.unit()),
            9 => self.real(),
            _ => 1e-3 * (1.0 + 4.0 * (self.u8() as f64 / 255.0)),
        }
    }

    /// Four quaternion components (w, x, y, z).
    fn quat(&mut self) -> [f64; 4] {
        let axis_angle = |b: &mut Self, angle: f64| {
            let mut ax = [b.unit(), b.unit(), b.unit()];
            let n = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
            if n < 1e-3 {
                ax = [1.0, 0.0, 0.0];
            } else {
                ax.iter_mut().for_each(|x| *x /= n);
            }
            let (s, c) = (angle / 2.0).sin_cos();
            [c, s * ax[0], s * ax[1], s * ax[2]]
        };
        let about_x = |angle: f64| {
            let (s, c) = (angle / 2.0).sin_cos();
            [c, s, 0.0, 0.0]
        };
        let pi = std::f64::consts::PI;
        match self.u8() % 16 {
            0 => [0.0; 4],
            1 => [1e-7, 0.0, 0.0, 0.0],
            2 => [1e200, 0.0, 0.0, 1e200],
            3 => [f64::NAN, 0.0, 0.0, 1.0],
            4 => [1.0, f64::INFINITY, 0.0, 0.0],
            5 => [5e-324, 5e-324, 0.0, 0.0],
            6 => [self.real(), self.real(), self.real(), self.real()],
            7 => about_x(pi),
            8 => about_x(pi - 1e-3 * self.u8() as f64 / 128.0),
            9 => {
                let s = 1e-6 * (1.0 + self.unit());
                let q = about_x(self.unit() * pi);
                q.map(|x| x * s)
            }
            10 => {
                let s = 1e150;
                about_x(self.unit() * pi).map(|x| x * s)
            }
            _ => {
                let angle = pi * self.unit() * (1 + self.u8() % 2) as f64;
                axis_angle(self, angle)
            }
        }
    }

    /// A plausible parameter value for a parameter named `name`.
    fn param_value(&mut self, name: &str) -> f64 {
        if self.u8().is_multiple_of(8) {
            return self.real();
        }
        let u = self.unit();
        if name.starts_with("stop.lower") {
            -0.2 * u.abs()
        } else if name.starts_with("stop.upper") {
            0.2 * u.abs()
        } else if name.starts_with("reference.value") || name.ends_with("int") {
            u
        } else if name.contains("mu") {
            u.abs()
        } else if name.contains("R") && name.starts_with("friction.") && !name.contains("R1") {
            0.05 * u.abs()
        } else {
            10f64.powf(6.0 * u.abs()) - 1.0
        }
    }
}

// ------------------------------------------------------------------ the program state

/// Upper bound of DoStep calls per program (each can take up to MAX_SUBSTEPS substeps).
const MAX_STEPS: usize = 24;
/// Upper bound of operations per program.
const MAX_OPS: usize = 400;
/// First bytes from this value on select an FMI 3.0 program.
pub const FMI3_MODE: u8 = 0xE0;

pub struct Inst {
    c: Handle,
    variant: Variant,
    /// Whether the instance has a logger (FMI 3.0 allows none: invariant 2 is then skipped).
    logger: bool,
    /// earlyReturnAllowed at instantiation (FMI 3.0).
    early_allowed: bool,
}

/// A state slot and the variant of the instance that produced it.
#[derive(Clone, Copy)]
struct Slot {
    s: Handle,
    variant: Variant,
}

/// The componentEnvironment key a program's instances log under; its messages are dropped with it.
struct Env(usize);

impl Drop for Env {
    fn drop(&mut self) {
        support::forget_log(self.0);
    }
}

pub struct Program<'a, A: Api> {
    env: Env,
    b: Bytes<'a>,
    inst: [Option<Inst>; 2],
    slots: [Slot; 4],
    bufs: Vec<(Vec<u8>, Variant)>,
    steps: usize,
    trace: Vec<String>,
    /// FMI 3.0 DoSteps that returned early at an event (what `run` returns).
    early_returns: usize,
    api: PhantomData<A>,
}

fn variant_of(i: usize) -> Variant {
    VARIANTS[i % VARIANTS.len()].variant
}

/// Rewrites the checksum trailer of serialized state bytes (FNV-1a 64): lets mutated bytes
/// pass the checksum so that the field validation behind it is exercised.
fn fix_checksum(bytes: &mut [u8]) {
    if bytes.len() >= 8 {
        let n = bytes.len() - 8;
        let sum = support::fnv1a(&bytes[..n]);
        bytes[n..].copy_from_slice(&sum.to_le_bytes());
    }
}

/// Index of the mode byte in serialized bytes (after magic, version, id length and id).
fn mode_index(v: Variant) -> usize {
    4 + 2 + 1 + table(v).spec.model_identifier.len()
}

/// The instance's state as bytes with the mode byte and the checksum blanked (None when the
/// state cannot be taken, e.g. after a Fatal).
fn state_bytes<A: Api>(inst: &Inst) -> Option<Vec<u8>> {
    let mut s: Handle = null_mut();
    if A::get_state(inst.c, &mut s) != OK {
        return None;
    }
    let mut n: usize = 0;
    let mut out = None;
    if A::state_size(inst.c, s, &mut n) == OK {
        let mut buf = vec![0u8; n];
        if A::serialize(inst.c, s, buf.as_mut_ptr(), n) == OK {
            let m = mode_index(inst.variant);
            buf[m] = 0;
            let len = buf.len();
            buf[len - 8..].fill(0);
            out = Some(buf);
        }
    }
    A::free_state(inst.c, &mut s);
    out
}

fn reals_of(v: Variant, pred: impl Fn(&connector_fmu::variables::VarSpec) -> bool) -> Vec<u32> {
    table(v)
        .vars
        .iter()
        .filter(|x| matches!(x.start, Start::Real(_)) && pred(x))
        .map(|x| x.vr)
        .collect()
}

fn is_real_output(v: Variant, vr: u32) -> bool {
    table(v)
        .get(vr)
        .is_some_and(|x| x.causality == Causality::Output && matches!(x.start, Start::Real(_)))
}

/// Value reference of the variant's output `name` when it has one.
fn output_vr(v: Variant, name: &str) -> Option<u32> {
    table(v)
        .vars
        .iter()
        .find(|x| x.name == name && x.causality == Causality::Output)
        .map(|x| x.vr)
}

/// The FMU's time tolerance at `t` (the FMU accepts a currentCommunicationPoint this close).
fn time_tol(t: f64) -> f64 {
    1e-9 * t.abs().max(1.0)
}

/// The arguments of a directional (or adjoint) derivative call.
struct DerArgs {
    unknowns: Vec<u32>,
    knowns: Vec<u32>,
    seed: Vec<f64>,
}

impl<'a, A: Api> Program<'a, A> {
    fn new(data: &'a [u8]) -> Self {
        Program {
            env: Env(support::new_env()),
            b: Bytes::new(data),
            inst: [None, None],
            slots: [Slot {
                s: null_mut(),
                variant: Variant::Bushing,
            }; 4],
            bufs: Vec::new(),
            steps: 0,
            trace: Vec::new(),
            early_returns: 0,
            api: PhantomData,
        }
    }

    fn fail(&self, what: String) -> ! {
        if trace_wanted() {
            eprintln!("full program trace: {:#?}", self.trace);
        }
        panic!(
            "invariant violated: {what}\nprogram trace (last 40 ops): {:#?}",
            &self.trace[self.trace.len().saturating_sub(40)..]
        );
    }

    /// Checks invariants 1, 2 (and 4 through `before`) for one call on instance `i`.
    fn check(&mut self, i: usize, fname: &str, n0: usize, s: St, before: Option<Vec<u8>>) {
        let lines = support::log_since(self.env.0, n0);
        let bad: Vec<&LogLine> = lines.iter().filter(|l| l.status != 0).collect();
        if s == St::Fatal {
            self.fail(format!("{fname} returned Fatal: {lines:?}"));
        }
        let logger = self.inst[i].as_ref().is_some_and(|x| x.logger);
        if s == OK {
            if !bad.is_empty() {
                self.fail(format!("{fname} returned OK but logged {bad:?}"));
            }
        } else if logger {
            if bad.len() != 1 {
                self.fail(format!(
                    "{fname} returned {s:?} with {} non-OK messages (want exactly 1): {lines:?}",
                    bad.len()
                ));
            }
            let l = bad[0];
            if l.status != s as c_int {
                self.fail(format!(
                    "{fname} returned {s:?} but logged status {}: {l:?}",
                    l.status
                ));
            }
            let want_cat = if s == St::Warning {
                "logStatusWarning"
            } else {
                "logStatusError"
            };
            if l.category != want_cat || !l.message.contains(fname) {
                self.fail(format!(
                    "{fname}: message does not name the function or has the wrong category: {l:?}"
                ));
            }
        } else if !bad.is_empty() {
            self.fail(format!(
                "{fname}: an instance without logger logged {bad:?}"
            ));
        }
        if s == St::Error {
            if let (Some(b0), Some(inst)) = (before, self.inst[i].as_ref()) {
                if let Some(b1) = state_bytes::<A>(inst) {
                    if b0 != b1 {
                        let at = b0.iter().zip(&b1).position(|(x, y)| x != y);
                        self.fail(format!(
                            "{fname} returned Error but changed the FMU state (first differing byte {at:?}, lengths {} {})",
                            b0.len(),
                            b1.len()
                        ));
                    }
                }
            }
        }
    }

    /// Runs one call on instance i with invariant checks (state compared on Error).
    fn call(&mut self, i: usize, fname: &str, f: impl FnOnce(Handle) -> St) -> St {
        let Some(inst) = self.inst[i].as_ref() else {
            return St::Error;
        };
        let c = inst.c;
        let before = state_bytes::<A>(inst);
        let n0 = support::log_len(self.env.0);
        let s = f(c);
        self.check(i, fname, n0, s, before);
        s
    }

    fn variant(&self, i: usize) -> Option<Variant> {
        self.inst[i].as_ref().map(|x| x.variant)
    }

    /// A value reference: mostly one of the variant's variables of the wanted type, sometimes
    /// any variable of the variant, sometimes an arbitrary u32.
    fn vr(&mut self, v: Variant, ty: u8) -> u32 {
        let t = table(v);
        match self.b.u8() % 8 {
            0 => match self.b.u8() % 4 {
                0 => 0,
                1 => u32::MAX,
                2 => self.b.u16() as u32 % 512,
                _ => self.b.u32(),
            },
            1 => {
                let k = self.b.u8() as usize % t.vars.len();
                t.vars[k].vr
            }
            _ => {
                let want: Vec<u32> = t
                    .vars
                    .iter()
                    .filter(|x| match ty {
                        0 => matches!(x.start, Start::Real(_)),
                        1 => matches!(x.start, Start::Integer(_)),
                        _ => matches!(x.start, Start::Boolean(_)),
                    })
                    .map(|x| x.vr)
                    .collect();
                if want.is_empty() {
                    self.b.u32()
                } else {
                    want[self.b.u8() as usize % want.len()]
                }
            }
        }
    }

    /// Records an instantiation outcome (invariant 7): `c` NULL or not, `valid` arguments,
    /// log lines since `n0` when a logger was given.
    fn instantiated(
        &mut self,
        i: usize,
        fname: &str,
        c: Handle,
        valid: bool,
        n0: usize,
        inst: Inst,
    ) {
        if c.is_null() {
            let lines = support::log_since(self.env.0, n0);
            if valid {
                self.fail(format!("{fname} refused valid arguments: {lines:?}"));
            }
            if inst.logger
                && (lines.len() != 1
                    || lines[0].status != St::Error as c_int
                    || !lines[0].message.contains(fname))
            {
                self.fail(format!(
                    "{fname} refusal must log one error naming the function: {lines:?}"
                ));
            }
        } else {
            if !valid {
                self.fail(format!("{fname} accepted invalid arguments"));
            }
            self.inst[i] = Some(Inst { c, ..inst });
        }
    }

    fn free_instance(&mut self, i: usize) {
        if let Some(inst) = self.inst[i].take() {
            A::free_instance(inst.c);
        }
    }

    /// Reads every Real output (invariant 3) and Integer output; returns the Real bits and status.
    fn read_outputs(&mut self, i: usize) -> Option<(St, Vec<u64>, Vec<i32>)> {
        let v = self.variant(i)?;
        let vrs = reals_of(v, |x| x.causality == Causality::Output);
        let mut out = vec![f64::NAN; vrs.len()];
        let s = self.call(i, A::GET_REAL, |c| {
            A::get_real(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr())
        });
        if s == OK {
            if let Some(k) = out.iter().position(|x| !x.is_finite()) {
                let name = &table(v).get(vrs[k]).expect("known").name;
                self.fail(format!(
                    "{} returned OK with {name} = {}",
                    A::GET_REAL,
                    out[k]
                ));
            }
        }
        let ivrs: Vec<u32> = table(v)
            .vars
            .iter()
            .filter(|x| x.causality == Causality::Output && matches!(x.start, Start::Integer(_)))
            .map(|x| x.vr)
            .collect();
        let mut iout = vec![i32::MIN; ivrs.len()];
        let si = self.call(i, A::GET_INT, |c| {
            A::get_int(c, ivrs.as_ptr(), ivrs.len(), iout.as_mut_ptr())
        });
        if si != s {
            self.fail(format!(
                "{} {s:?} but {} {si:?} on outputs",
                A::GET_REAL,
                A::GET_INT
            ));
        }
        Some((s, out.iter().map(|x| x.to_bits()).collect(), iout))
    }

    /// The FMU's current time when it can tell.
    fn fmu_time_opt(&mut self, i: usize) -> Option<f64> {
        let mut t = 0.0;
        let s = self.call(i, A::TIME, |c| A::time(c, &mut t));
        (s == OK).then_some(t)
    }

    /// The FMU's current time when it can tell, else 0.
    fn fmu_time(&mut self, i: usize) -> f64 {
        self.fmu_time_opt(i).unwrap_or(0.0)
    }

    /// One DoStep from the FMU's time (sometimes from an arbitrary time) with invariant 8.
    fn do_step(&mut self, i: usize) -> Option<St> {
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
    fn step_checked(&mut self, i: usize, t: f64, h: f64) -> (St, Option<StepOut>) {
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

    /// Serializes a slot through instance i; on success checks invariant 5 and stores the bytes.
    fn serialize(&mut self, i: usize, k: usize) {
        let Some(v) = self.variant(i) else { return };
        let slot = self.slots[k];
        let mut n: usize = 0;
        let s = self.call(i, A::STATE_SIZE, |c| A::state_size(c, slot.s, &mut n));
        if s == OK && !slot.s.is_null() && slot.variant != v {
            self.fail(format!(
                "{} accepted a state of {:?} in a {v:?} instance",
                A::STATE_SIZE,
                slot.variant
            ));
        }
        if s != OK {
            n = 0;
        }
        // sometimes a buffer that is too small, or larger than needed
        let size = match self.b.u8() % 8 {
            0 => n.saturating_sub(1),
            1 => n + 16,
            2 => 0,
            _ => n,
        };
        let mut buf = vec![0u8; size.max(1)];
        let p = if size == 0 && self.b.u8().is_multiple_of(2) {
            null_mut()
        } else {
            buf.as_mut_ptr()
        };
        let s2 = self.call(i, A::SERIALIZE, |c| A::serialize(c, slot.s, p, size));
        if s2 == OK && !slot.s.is_null() && slot.variant != v {
            self.fail(format!(
                "{} accepted a state of {:?} in a {v:?} instance",
                A::SERIALIZE,
                slot.variant
            ));
        }
        if s2 == OK && s == OK && size >= n && n > 0 {
            buf.truncate(n);
            // invariant 5: the bytes are accepted and re-serialize identically
            let mut back: Handle = null_mut();
            let n_log = support::log_len(self.env.0);
            let s3 = self.call(i, A::DESERIALIZE, |c| {
                A::deserialize(c, buf.as_ptr(), n, &mut back)
            });
            if s3 != OK {
                let why: Vec<LogLine> = support::log_since(self.env.0, n_log)
                    .into_iter()
                    .filter(|l| l.status != 0)
                    .collect();
                self.fail(format!(
                    "{} refused bytes {} wrote: {s3:?} {why:?}",
                    A::DESERIALIZE,
                    A::SERIALIZE
                ));
            }
            let mut n2: usize = 0;
            let mut again = vec![0u8; n];
            let s4 = self.call(i, A::STATE_SIZE, |c| A::state_size(c, back, &mut n2));
            let s5 = self.call(i, A::SERIALIZE, |c| {
                A::serialize(c, back, again.as_mut_ptr(), n)
            });
            if s4 != OK || s5 != OK || n2 != n || again != buf {
                self.fail("serialize → deserialize → serialize is not the identity".into());
            }
            self.call(i, A::FREE_STATE, |c| A::free_state(c, &mut back));
            if self.bufs.len() >= 2 {
                self.bufs.remove(0);
            }
            self.bufs.push((buf, v));
        }
    }

    /// De-serializes (mutated) bytes into a slot.
    fn deserialize(&mut self, i: usize, k: usize) {
        let Some(v) = self.variant(i) else { return };
        let (mut bytes, from) = match (self.b.u8() % 4, self.bufs.is_empty()) {
            (0, _) | (_, true) => {
                let n = self.b.u8() as usize * 4;
                ((0..n).map(|_| self.b.u8()).collect::<Vec<u8>>(), None)
            }
            _ => {
                let j = self.b.u8() as usize % self.bufs.len();
                let (b, src) = self.bufs[j].clone();
                (b, Some(src))
            }
        };
        let mut mutated = false;
        let nmut = self.b.u8() % 4;
        for _ in 0..nmut {
            if bytes.is_empty() {
                break;
            }
            mutated = true;
            match self.b.u8() % 5 {
                0 => {
                    let at = self.b.u16() as usize % bytes.len();
                    bytes[at] ^= self.b.u8().max(1);
                }
                1 => {
                    let at = self.b.u16() as usize % bytes.len();
                    bytes.truncate(at);
                }
                2 => {
                    let n = self.b.u8() % 16;
                    for _ in 0..n {
                        bytes.push(self.b.u8());
                    }
                }
                _ => {
                    // an awkward f64 over 8 bytes at an arbitrary offset
                    let x = self.b.real().to_le_bytes();
                    let at = self.b.u16() as usize % bytes.len();
                    for (j, b) in x.iter().enumerate() {
                        if let Some(slot) = bytes.get_mut(at + j) {
                            *slot = *b;
                        }
                    }
                }
            }
        }
        if !self.b.u8().is_multiple_of(4) {
            fix_checksum(&mut bytes);
        }
        let size = if self.b.u8().is_multiple_of(16) {
            bytes.len() + 1 + self.b.u8() as usize // announced longer than given: only for NULL
        } else {
            bytes.len()
        };
        let p: *const u8 = if size != bytes.len() {
            null()
        } else {
            bytes.as_ptr()
        };
        self.trace.push(format!(
            "deserialize[{i}] -> slot {k} (len {size}, from {from:?}, mutated {mutated})"
        ));
        let mut slot = self.slots[k];
        let s = self.call(i, A::DESERIALIZE, |c| {
            A::deserialize(c, p, size, &mut slot.s)
        });
        if s == OK {
            slot.variant = v;
            if !mutated && from.is_some_and(|f| f != v) {
                self.fail(format!(
                    "{} accepted a {from:?} state in {v:?}",
                    A::DESERIALIZE
                ));
            }
        }
        self.slots[k] = slot;
    }

    /// Invariant 6: restore a state, repeat a step, compare.
    fn replay(&mut self, i: usize) {
        let Some(_) = self.variant(i) else { return };
        if self.steps + 2 > MAX_STEPS {
            return;
        }
        self.steps += 2;
        let mut s: Handle = null_mut();
        if self.call(i, A::GET_STATE, |c| A::get_state(c, &mut s)) != OK {
            return;
        }
        let h = self.b.step();
        let t = self.fmu_time(i);
        self.trace.push(format!("replay[{i}] t={t:e} h={h:e}"));
        let (s1, o1) = self.step_checked(i, t, h);
        let y1 = self.read_outputs(i);
        let r = self.call(i, A::SET_STATE, |c| A::set_state(c, s));
        if r != OK {
            self.fail(format!(
                "{} of its own fresh state failed: {r:?}",
                A::SET_STATE
            ));
        }
        let (s2, o2) = self.step_checked(i, t, h);
        let y2 = self.read_outputs(i);
        if s1 != s2 || y1 != y2 || o1 != o2 {
            // where the outputs differ: the read statuses, or the first differing value
            let diff = match (&y1, &y2) {
                (Some((r1, x1, n1)), Some((r2, x2, n2))) if r1 == r2 => {
                    let vrs = reals_of(self.variant(i).expect("live"), |x| {
                        x.causality == Causality::Output
                    });
                    match x1.iter().zip(x2).position(|(a, b)| a != b) {
                        Some(k) => format!(
                            "vr {}: {} vs {}",
                            vrs[k],
                            f64::from_bits(x1[k]),
                            f64::from_bits(x2[k])
                        ),
                        None => format!("integers {n1:?} vs {n2:?}"),
                    }
                }
                (a, b) => format!(
                    "reads {:?} vs {:?}",
                    a.as_ref().map(|x| x.0),
                    b.as_ref().map(|x| x.0)
                ),
            };
            self.fail(format!(
                "repeating a step after {} differs: {s1:?} vs {s2:?}, {o1:?} vs {o2:?}, outputs: {diff}",
                A::SET_STATE
            ));
        }
        self.call(i, A::FREE_STATE, |c| A::free_state(c, &mut s));
    }

    fn set_reals(&mut self, i: usize, v: Variant) {
        let n = 1 + self.b.u8() as usize % 4;
        let mut vrs = Vec::with_capacity(n);
        let mut xs = Vec::with_capacity(n);
        for _ in 0..n {
            vrs.push(self.vr(v, 0));
            xs.push(self.b.real());
        }
        self.trace.push(format!("setReal[{i}] {vrs:?} {xs:?}"));
        self.call(i, A::SET_REAL, |c| {
            A::set_real(c, vrs.as_ptr(), n, xs.as_ptr())
        });
    }

    /// A coherent parameter set: each parameter of the variant set (or not) to a plausible
    /// value, sometimes an awkward one; Integer parameters 0..3 (cosim.extrapolation's range;
    /// friction.coupling refuses 2 and 3).
    fn param_set(&mut self, i: usize, v: Variant) {
        let mut vrs = Vec::new();
        let mut xs = Vec::new();
        let mut ivrs = Vec::new();
        let mut ixs = Vec::new();
        for var in &table(v).vars {
            if var.causality != Causality::Parameter || self.b.u8() < 100 {
                continue;
            }
            match var.start {
                Start::Real(_) => {
                    vrs.push(var.vr);
                    xs.push(self.b.param_value(&var.name));
                }
                Start::Integer(_) => {
                    ivrs.push(var.vr);
                    ixs.push((self.b.u8() % 4) as i32);
                }
                Start::Boolean(_) => {}
            }
        }
        self.trace
            .push(format!("paramSet[{i}] {vrs:?} {xs:?} int {ivrs:?} {ixs:?}"));
        self.call(i, A::SET_REAL, |c| {
            A::set_real(c, vrs.as_ptr(), vrs.len(), xs.as_ptr())
        });
        self.call(i, A::SET_INT, |c| {
            A::set_int(c, ivrs.as_ptr(), ivrs.len(), ixs.as_ptr())
        });
    }

    /// A plausible motion: positions, orientations, velocities, angular velocities.
    fn motion(&mut self, i: usize, v: Variant) {
        let mut vrs = Vec::new();
        let mut xs = Vec::new();
        let scale = [0.01, 0.1, 1.0, 10.0][self.b.u8() as usize % 4];
        for node in ["a", "b"] {
            let q = self.b.quat();
            for var in &table(v).vars {
                if var.causality != Causality::Input || !var.name.starts_with(node) {
                    continue;
                }
                let x = match &var.name[2..] {
                    "q.w" => q[0],
                    "q.x" => q[1],
                    "q.y" => q[2],
                    "q.z" => q[3],
                    _ => scale * self.b.unit(),
                };
                vrs.push(var.vr);
                xs.push(x);
            }
        }
        self.trace.push(format!("motion[{i}] {xs:?}"));
        self.call(i, A::SET_REAL, |c| {
            A::set_real(c, vrs.as_ptr(), vrs.len(), xs.as_ptr())
        });
    }

    /// Unknowns (mostly continuous Real outputs), knowns (mostly inputs) and `n_seed` seeds
    /// (None: one per known) of a derivative call.
    fn der_args(&mut self, v: Variant, seeds_per_unknown: bool) -> DerArgs {
        let outs = reals_of(v, |x| {
            x.causality == Causality::Output && x.variability == Variability::Continuous
        });
        let ins = reals_of(v, |x| x.causality == Causality::Input);
        let nu = self.b.u8() as usize % 6;
        let nk = self.b.u8() as usize % 6;
        let unknowns: Vec<u32> = (0..nu)
            .map(|_| {
                if self.b.u8().is_multiple_of(8) {
                    self.vr(v, 0)
                } else {
                    outs[self.b.u8() as usize % outs.len()]
                }
            })
            .collect();
        let knowns: Vec<u32> = (0..nk)
            .map(|_| {
                if self.b.u8().is_multiple_of(8) {
                    self.vr(v, 0)
                } else {
                    ins[self.b.u8() as usize % ins.len()]
                }
            })
            .collect();
        let ns = if seeds_per_unknown { nu } else { nk };
        let seed: Vec<f64> = (0..ns)
            .map(|_| {
                if self.b.u8().is_multiple_of(2) {
                    self.b.real()
                } else {
                    self.b.unit()
                }
            })
            .collect();
        DerArgs {
            unknowns,
            knowns,
            seed,
        }
    }

    fn op(&mut self) {
        let i = (self.b.u8() & 1) as usize;
        if self.inst[i].is_none() {
            // an instance slot that is empty: make one (or stop trying when it is refused)
            A::instantiate(self, i);
            return;
        }
        let v = self.variant(i).expect("live");
        let op = self.b.u8() % A::N_OPS;
        match op {
            0..=2 => self.set_reals(i, v),
            3 => {
                let vr = self.vr(v, 1);
                let x = match self.b.u8() % 6 {
                    0 => i32::MIN,
                    1 => i32::MAX,
                    2 => -1,
                    _ => (self.b.u8() % 4) as i32,
                };
                self.trace.push(format!("setInteger[{i}] {vr} {x}"));
                self.call(i, A::SET_INT, |c| A::set_int(c, &vr, 1, &x));
            }
            4 => {
                let vr = self.vr(v, 2);
                let x = [0, 1, 2, -1][self.b.u8() as usize % 4];
                self.trace.push(format!("setBoolean[{i}] {vr} {x}"));
                self.call(i, A::SET_BOOL, |c| A::set_bool(c, vr, x));
            }
            5 => {
                let node = if self.b.u8().is_multiple_of(2) {
                    "a"
                } else {
                    "b"
                };
                let q = self.b.quat();
                let vrs: Vec<u32> = ["w", "x", "y", "z"]
                    .iter()
                    .filter_map(|c| {
                        let name = format!("{node}.q.{c}");
                        table(v).vars.iter().find(|x| x.name == name).map(|x| x.vr)
                    })
                    .collect();
                if vrs.len() == 4 {
                    self.trace.push(format!("setQuat[{i}] {node} {q:?}"));
                    self.call(i, A::SET_REAL, |c| {
                        A::set_real(c, vrs.as_ptr(), 4, q.as_ptr())
                    });
                }
            }
            6 => self.param_set(i, v),
            7 => self.motion(i, v),
            8 => {
                let start = if self.b.u8().is_multiple_of(4) {
                    self.b.real()
                } else {
                    0.0
                };
                let stop_def = self.b.u8() % 2;
                let stop = self.b.real();
                self.trace.push(format!("setup[{i}] {start:e}"));
                self.call(i, A::SETUP, |c| A::setup(c, start, stop_def == 1, stop));
            }
            9 => {
                self.trace.push(format!("enterInit[{i}]"));
                self.call(i, A::ENTER_INIT, |c| A::enter_init(c));
            }
            10 => {
                let s = self.call(i, A::EXIT_INIT, |c| A::exit_init(c));
                self.trace.push(format!("exitInit[{i}] -> {s:?}"));
            }
            11..=13 => {
                self.do_step(i);
            }
            14 => {
                self.trace.push(format!("readOutputs[{i}]"));
                self.read_outputs(i);
            }
            15 => {
                // random reads of any type
                let ty = self.b.u8() % 3;
                let n = self.b.u8() as usize % 5;
                let vrs: Vec<u32> = (0..n).map(|_| self.vr(v, ty)).collect();
                self.trace.push(format!("get[{i}] type {ty} {vrs:?}"));
                match ty {
                    0 => {
                        let mut out = vec![0.0; n];
                        let s = self.call(i, A::GET_REAL, |c| {
                            A::get_real(c, vrs.as_ptr(), n, out.as_mut_ptr())
                        });
                        if s == OK {
                            for (vr, x) in vrs.iter().zip(&out) {
                                if is_real_output(v, *vr) && !x.is_finite() {
                                    self.fail(format!(
                                        "{} OK with output vr {vr} = {x}",
                                        A::GET_REAL
                                    ));
                                }
                            }
                        }
                    }
                    1 => {
                        let mut out = vec![0; n];
                        self.call(i, A::GET_INT, |c| {
                            A::get_int(c, vrs.as_ptr(), n, out.as_mut_ptr())
                        });
                    }
                    _ => {
                        self.call(i, A::GET_BOOL, |c| A::get_bools(c, &vrs));
                    }
                }
            }
            16 => {
                let k = self.b.u8() as usize % 4;
                self.trace.push(format!("getState[{i}] -> slot {k}"));
                let mut slot = self.slots[k];
                if self.call(i, A::GET_STATE, |c| A::get_state(c, &mut slot.s)) == OK {
                    slot.variant = v;
                }
                self.slots[k] = slot;
            }
            17 => {
                let k = self.b.u8() as usize % 4;
                let slot = self.slots[k];
                self.trace
                    .push(format!("setState[{i}] <- slot {k} ({:?})", slot.variant));
                let s = self.call(i, A::SET_STATE, |c| A::set_state(c, slot.s));
                if s == OK && slot.variant != v {
                    self.fail(format!(
                        "{} accepted a {:?} state in {v:?}",
                        A::SET_STATE,
                        slot.variant
                    ));
                }
            }
            18 => {
                let k = self.b.u8() as usize % 4;
                self.trace.push(format!("freeState[{i}] slot {k}"));
                let mut slot = self.slots[k];
                self.call(i, A::FREE_STATE, |c| A::free_state(c, &mut slot.s));
                if !slot.s.is_null() {
                    self.fail(format!("{} did not set the handle to NULL", A::FREE_STATE));
                }
                self.slots[k] = slot;
            }
            19 => {
                let k = self.b.u8() as usize % 4;
                self.trace.push(format!("serialize[{i}] slot {k}"));
                self.serialize(i, k);
            }
            20 => {
                let k = self.b.u8() as usize % 4;
                self.deserialize(i, k);
            }
            21 => {
                self.trace.push(format!("reset[{i}]"));
                self.call(i, A::RESET, |c| A::reset(c));
            }
            22 => {
                self.trace.push(format!("terminate[{i}]"));
                self.call(i, A::TERMINATE, |c| A::terminate(c));
            }
            23 => {
                // directional derivative of outputs w.r.t. inputs (sometimes anything)
                let a = self.der_args(v, false);
                let mut out = vec![f64::NAN; a.unknowns.len()];
                self.trace.push(format!(
                    "dirDer[{i}] {:?} {:?} {:?}",
                    a.unknowns, a.knowns, a.seed
                ));
                let s = self.call(i, A::DIR_DER, |c| {
                    A::dir_der(c, &a.unknowns, &a.knowns, &a.seed, &mut out)
                });
                if s == OK {
                    if let Some(x) = out.iter().find(|x| !x.is_finite()) {
                        self.fail(format!("{} OK with a value {x}", A::DIR_DER));
                    }
                }
            }
            25 => {
                let on = self.b.u8() % 2;
                let n = self.b.u8() as usize % 4;
                let names: Vec<CString> = (0..n)
                    .map(|_| match self.b.u8() % 6 {
                        0 => c"logEvents".to_owned(),
                        1 => c"logAll".to_owned(),
                        2 => c"logStatusError".to_owned(),
                        3 => c"logStatusWarning".to_owned(),
                        _ => {
                            let k = self.b.u8() % 10;
                            let bytes: Vec<u8> = (0..k).map(|_| self.b.u8().max(1)).collect();
                            CString::new(bytes).expect("no NUL")
                        }
                    })
                    .collect();
                let ptrs: Vec<*const c_char> = names.iter().map(|s| s.as_ptr()).collect();
                let p = if n == 0 && self.b.u8().is_multiple_of(2) {
                    null()
                } else {
                    ptrs.as_ptr()
                };
                self.trace.push(format!("debugLogging[{i}] {on} {names:?}"));
                self.call(i, A::DEBUG_LOGGING, |c| A::debug_logging(c, on == 1, n, p));
            }
            28 => {
                // NULL arrays with a count (refused) and (NULL, 0) (legal)
                let n = self.b.u8() as usize % 3;
                self.trace.push(format!("nullArrays[{i}] n={n}"));
                self.call(i, A::SET_REAL, |c| A::set_real(c, null(), n, null()));
                self.call(i, A::GET_REAL, |c| A::get_real(c, null(), n, null_mut()));
                self.call(i, A::NULL_THIRD, |c| A::null_third(c, n));
                self.call(i, A::GET_STATE, |c| A::get_state(c, null_mut()));
            }
            29 => self.replay(i),
            30 => {
                self.trace.push(format!("free[{i}]"));
                self.free_instance(i);
            }
            31 => {
                // a short run of plain steps: drives the friction and stop state
                let n = 1 + self.b.u8() % 4;
                for _ in 0..n {
                    if self.do_step(i).is_none() {
                        break;
                    }
                }
                self.read_outputs(i);
            }
            _ => A::special(self, i, v, op),
        }
    }

    /// Runs the program to its end, then releases every state and instance.
    fn run(mut self) -> usize {
        A::instantiate(&mut self, 0);
        let mut ops = 0;
        while !self.b.done() && ops < MAX_OPS {
            self.op();
            ops += 1;
        }
        // release every state through a live instance (making one when none is left), then the
        // instances: nothing may leak (LeakSanitizer checks under cargo fuzz)
        if self.slots.iter().any(|s| !s.s.is_null()) && self.inst.iter().all(Option::is_none) {
            let c = A::instantiate_valid(self.env.0, Variant::Bushing);
            assert!(!c.is_null(), "cleanup instance");
            self.inst[0] = Some(Inst {
                c,
                variant: Variant::Bushing,
                logger: true,
                early_allowed: false,
            });
        }
        let c = self.inst.iter().flatten().next().map(|x| x.c);
        for k in 0..4 {
            if let Some(c) = c {
                let mut s = self.slots[k].s;
                assert_eq!(A::free_state(c, &mut s), OK, "free state {k}");
                self.slots[k].s = s;
            }
        }
        self.free_instance(0);
        self.free_instance(1);
        if trace_wanted() {
            eprintln!("program trace: {:#?}", self.trace);
        }
        self.early_returns
    }
}

/// Runs one program (FMI 3.0 when the first byte is FMI3_MODE or more); returns how many of
/// its steps returned early at an event. Panics when an invariant is violated.
pub fn run(data: &[u8]) -> usize {
    match data.first() {
        Some(&m) if m >= FMI3_MODE => Program::<Fmi3>::new(&data[1..]).run(),
        _ => Program::<Fmi2>::new(data).run(),
    }
}

/// `FMI_FUZZ_TRACE=1` prints each program's operations (to read what an input does).
fn trace_wanted() -> bool {
    static WANTED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *WANTED.get_or_init(|| std::env::var_os("FMI_FUZZ_TRACE").is_some())
}

// ------------------------------------------------------------------ FMI 2.0

/// The FMI 2.0 calls.
pub struct Fmi2;

impl Api for Fmi2 {
    const N_OPS: u8 = 32;
    const SET_REAL: &'static str = "fmi2SetReal";
    const GET_REAL: &'static str = "fmi2GetReal";
    const SET_INT: &'static str = "fmi2SetInteger";
    const GET_INT: &'static str = "fmi2GetInteger";
    const SET_BOOL: &'static str = "fmi2SetBoolean";
    const GET_BOOL: &'static str = "fmi2GetBoolean";
    const GET_STATE: &'static str = "fmi2GetFMUstate";
    const SET_STATE: &'static str = "fmi2SetFMUstate";
    const FREE_STATE: &'static str = "fmi2FreeFMUstate";
    const STATE_SIZE: &'static str = "fmi2SerializedFMUstateSize";
    const SERIALIZE: &'static str = "fmi2SerializeFMUstate";
    const DESERIALIZE: &'static str = "fmi2DeSerializeFMUstate";
    const SETUP: &'static str = "fmi2SetupExperiment";
    const ENTER_INIT: &'static str = "fmi2EnterInitializationMode";
    const EXIT_INIT: &'static str = "fmi2ExitInitializationMode";
    const DO_STEP: &'static str = "fmi2DoStep";
    const RESET: &'static str = "fmi2Reset";
    const TERMINATE: &'static str = "fmi2Terminate";
    const DIR_DER: &'static str = "fmi2GetDirectionalDerivative";
    const DEBUG_LOGGING: &'static str = "fmi2SetDebugLogging";
    const TIME: &'static str = "fmi2GetRealStatus";
    const NULL_THIRD: &'static str = "fmi2SetRealInputDerivatives";

    fn set_real(c: Handle, vr: *const u32, n: usize, x: *const f64) -> St {
        fmi2SetReal(c, vr, n, x).into()
    }
    fn get_real(c: Handle, vr: *const u32, n: usize, x: *mut f64) -> St {
        fmi2GetReal(c, vr, n, x).into()
    }
    fn set_int(c: Handle, vr: *const u32, n: usize, x: *const i32) -> St {
        fmi2SetInteger(c, vr, n, x).into()
    }
    fn get_int(c: Handle, vr: *const u32, n: usize, x: *mut i32) -> St {
        fmi2GetInteger(c, vr, n, x).into()
    }
    fn set_bool(c: Handle, vr: u32, x: i32) -> St {
        fmi2SetBoolean(c, &vr, 1, &x).into()
    }
    fn get_bools(c: Handle, vrs: &[u32]) -> St {
        let mut out = vec![0; vrs.len()];
        fmi2GetBoolean(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()).into()
    }
    fn get_state(c: Handle, s: *mut Handle) -> St {
        fmi2GetFMUstate(c, s).into()
    }
    fn set_state(c: Handle, s: Handle) -> St {
        fmi2SetFMUstate(c, s).into()
    }
    fn free_state(c: Handle, s: *mut Handle) -> St {
        fmi2FreeFMUstate(c, s).into()
    }
    fn state_size(c: Handle, s: Handle, n: *mut usize) -> St {
        fmi2SerializedFMUstateSize(c, s, n).into()
    }
    fn serialize(c: Handle, s: Handle, p: *mut u8, n: usize) -> St {
        fmi2SerializeFMUstate(c, s, p.cast(), n).into()
    }
    fn deserialize(c: Handle, p: *const u8, n: usize, s: *mut Handle) -> St {
        fmi2DeSerializeFMUstate(c, p.cast(), n, s).into()
    }
    fn setup(c: Handle, start: f64, stop_defined: bool, stop: f64) -> St {
        fmi2SetupExperiment(c, fmi2False, 0.0, start, stop_defined as fmi2Boolean, stop).into()
    }
    fn enter_init(c: Handle) -> St {
        fmi2EnterInitializationMode(c).into()
    }
    fn exit_init(c: Handle) -> St {
        fmi2ExitInitializationMode(c).into()
    }
    fn do_step(c: Handle, t: f64, h: f64) -> (St, Option<StepOut>) {
        (fmi2DoStep(c, t, h, fmi2False).into(), None)
    }
    fn reset(c: Handle) -> St {
        fmi2Reset(c).into()
    }
    fn terminate(c: Handle) -> St {
        fmi2Terminate(c).into()
    }
    fn dir_der(c: Handle, unknowns: &[u32], knowns: &[u32], seed: &[f64], out: &mut [f64]) -> St {
        fmi2GetDirectionalDerivative(
            c,
            unknowns.as_ptr(),
            unknowns.len(),
            knowns.as_ptr(),
            knowns.len(),
            seed.as_ptr(),
            out.as_mut_ptr(),
        )
        .into()
    }
    fn debug_logging(c: Handle, on: bool, n: usize, categories: *const *const c_char) -> St {
        fmi2SetDebugLogging(c, on as fmi2Boolean, n, categories).into()
    }
    fn time(c: Handle, t: &mut f64) -> St {
        // fmi2LastSuccessfulTime = 2
        fmi2GetRealStatus(c, 2, t).into()
    }
    fn null_third(c: Handle, n: usize) -> St {
        fmi2SetRealInputDerivatives(c, null(), n, null(), null()).into()
    }
    fn free_instance(c: Handle) {
        fmi2FreeInstance(c);
    }
    fn instantiate_valid(env: usize, v: Variant) -> Handle {
        let cb = callbacks(env, true);
        let guid = CString::new(table(v).guid.clone()).expect("no NUL");
        fmi2Instantiate(
            c"cleanup".as_ptr(),
            CO_SIMULATION,
            guid.as_ptr(),
            null(),
            &cb,
            fmi2False,
            fmi2False,
        )
    }

    fn instantiate(p: &mut Program<'_, Self>, i: usize) {
        let sel = p.b.u8();
        let flags = p.b.u8();
        let variant = variant_of(sel as usize);
        let mut valid = true;
        let guid = p.model_id(sel, variant, &mut valid);
        let name = p.instance_name(i, flags, &mut valid);
        let fmu_type = match (flags >> 4) % 8 {
            6 => {
                valid = false;
                0
            }
            7 => {
                let t = p.b.u32() as c_int;
                valid &= t == CO_SIMULATION;
                t
            }
            _ => CO_SIMULATION,
        };
        let logging_on = (flags >> 7) & 1;
        let cb_kind = p.b.u8() % 16;
        let cb = callbacks(p.env.0, cb_kind != 15);
        let cb_ptr: *const fmi2CallbackFunctions = if cb_kind == 14 { null() } else { &cb };
        let has_logger = cb_kind < 14;
        valid &= has_logger;
        let ptr = |s: &Option<CString>| s.as_ref().map_or(null(), |s| s.as_ptr());
        let n0 = support::log_len(p.env.0);
        let c = fmi2Instantiate(
            ptr(&name),
            fmu_type,
            ptr(&guid),
            null(),
            cb_ptr,
            fmi2False,
            logging_on as fmi2Boolean,
        );
        p.trace.push(format!(
            "instantiate[{i}] {variant:?} valid={valid} type={fmu_type} logging={logging_on} cb={cb_kind} -> {}",
            !c.is_null()
        ));
        let inst = Inst {
            c,
            variant,
            logger: has_logger,
            early_allowed: false,
        };
        p.instantiated(i, "fmi2Instantiate", c, valid, n0, inst);
    }

    fn special(p: &mut Program<'_, Self>, i: usize, v: Variant, op: u8) {
        match op {
            24 => {
                let n = 1 + p.b.u8() as usize % 4;
                let vrs: Vec<u32> = (0..n).map(|_| p.vr(v, 0)).collect();
                let orders: Vec<c_int> = (0..n)
                    .map(|_| [1, 1, 1, 0, 2, -1][p.b.u8() as usize % 6])
                    .collect();
                let xs: Vec<f64> = (0..n).map(|_| p.b.real()).collect();
                p.trace
                    .push(format!("inputDer[{i}] {vrs:?} {orders:?} {xs:?}"));
                p.call(i, "fmi2SetRealInputDerivatives", |c| {
                    fmi2SetRealInputDerivatives(c, vrs.as_ptr(), n, orders.as_ptr(), xs.as_ptr())
                        .into()
                });
            }
            26 => {
                let kind = [0, 1, 2, 3, -1, 99][p.b.u8() as usize % 6];
                let which = p.b.u8() % 5;
                p.trace.push(format!("status[{i}] fn {which} kind {kind}"));
                match which {
                    0 => {
                        let mut x = fmi2Status::OK;
                        p.call(i, "fmi2GetStatus", |c| {
                            fmi2GetStatus(c, kind, &mut x).into()
                        });
                    }
                    1 => {
                        let mut x = 0.0;
                        let s = p.call(i, "fmi2GetRealStatus", |c| {
                            fmi2GetRealStatus(c, kind, &mut x).into()
                        });
                        if s == OK && !x.is_finite() {
                            p.fail(format!("fmi2GetRealStatus OK with {x}"));
                        }
                    }
                    2 => {
                        let mut x = 0;
                        p.call(i, "fmi2GetIntegerStatus", |c| {
                            fmi2GetIntegerStatus(c, kind, &mut x).into()
                        });
                    }
                    3 => {
                        let mut x = 0;
                        p.call(i, "fmi2GetBooleanStatus", |c| {
                            fmi2GetBooleanStatus(c, kind, &mut x).into()
                        });
                    }
                    _ => {
                        let mut x: fmi2String = null();
                        p.call(i, "fmi2GetStringStatus", |c| {
                            fmi2GetStringStatus(c, kind, &mut x).into()
                        });
                    }
                }
            }
            27 => {
                p.trace.push(format!("cancel/outputDer/strings[{i}]"));
                p.call(i, "fmi2CancelStep", |c| fmi2CancelStep(c).into());
                let vr = p.vr(v, 0);
                let order = 1;
                let mut x = 0.0;
                let n = p.b.u8() as usize % 2;
                p.call(i, "fmi2GetRealOutputDerivatives", |c| {
                    fmi2GetRealOutputDerivatives(c, &vr, n, &order, &mut x).into()
                });
                let mut sx: fmi2String = null();
                p.call(i, "fmi2GetString", |c| {
                    fmi2GetString(c, &vr, n, &mut sx).into()
                });
                let val = c"x".as_ptr();
                p.call(i, "fmi2SetString", |c| {
                    fmi2SetString(c, &vr, n, &val).into()
                });
            }
            _ => unreachable!("FMI 2.0 has {} operation codes", Self::N_OPS),
        }
    }
}

impl<A: Api> Program<'_, A> {
    /// The GUID (FMI 2.0) or instantiationToken (FMI 3.0) of a header's selector `sel`: the
    /// variant's, random bytes or NULL (the last two make the arguments invalid).
    fn model_id(&mut self, sel: u8, variant: Variant, valid: &mut bool) -> Option<CString> {
        match sel % 16 {
            14 => {
                *valid = false;
                let n = self.b.u8() % 40;
                let bytes: Vec<u8> = (0..n).map(|_| self.b.u8().max(1)).collect();
                Some(CString::new(bytes).expect("no NUL"))
            }
            15 => {
                *valid = false;
                None
            }
            _ => Some(CString::new(table(variant).guid.clone()).expect("no NUL")),
        }
    }

    /// The instance name of a header's `flags`: empty, NULL or random bytes (perhaps not
    /// UTF-8) make the arguments invalid.
    fn instance_name(&mut self, i: usize, flags: u8, valid: &mut bool) -> Option<CString> {
        match flags % 16 {
            13 => {
                *valid = false;
                Some(CString::new("").expect("no NUL"))
            }
            14 => {
                *valid = false;
                None
            }
            15 => {
                let n = 1 + self.b.u8() % 12;
                let bytes: Vec<u8> = (0..n).map(|_| self.b.u8().max(1)).collect();
                *valid &= std::str::from_utf8(&bytes).is_ok();
                Some(CString::new(bytes).expect("no NUL"))
            }
            _ => Some(CString::new(format!("fuzz{i}")).expect("no NUL")),
        }
    }
}

// ------------------------------------------------------------------ FMI 3.0

/// The FMI 3.0 calls.
pub struct Fmi3;

use connector_fmu::model_description::fmi3::TIME_VR;

/// A C `bool` byte from the FMI 2.0-style int (any non-zero byte is true).
fn bool3(x: i32) -> fmi3Boolean {
    x as u8
}

impl Api for Fmi3 {
    const N_OPS: u8 = 40;
    const SET_REAL: &'static str = "fmi3SetFloat64";
    const GET_REAL: &'static str = "fmi3GetFloat64";
    const SET_INT: &'static str = "fmi3SetInt32";
    const GET_INT: &'static str = "fmi3GetInt32";
    const SET_BOOL: &'static str = "fmi3SetBoolean";
    const GET_BOOL: &'static str = "fmi3GetBoolean";
    const GET_STATE: &'static str = "fmi3GetFMUState";
    const SET_STATE: &'static str = "fmi3SetFMUState";
    const FREE_STATE: &'static str = "fmi3FreeFMUState";
    const STATE_SIZE: &'static str = "fmi3SerializedFMUStateSize";
    const SERIALIZE: &'static str = "fmi3SerializeFMUState";
    const DESERIALIZE: &'static str = "fmi3DeserializeFMUState";
    const SETUP: &'static str = "fmi3EnterInitializationMode";
    const ENTER_INIT: &'static str = "fmi3EnterInitializationMode";
    const EXIT_INIT: &'static str = "fmi3ExitInitializationMode";
    const DO_STEP: &'static str = "fmi3DoStep";
    const RESET: &'static str = "fmi3Reset";
    const TERMINATE: &'static str = "fmi3Terminate";
    const DIR_DER: &'static str = "fmi3GetDirectionalDerivative";
    const DEBUG_LOGGING: &'static str = "fmi3SetDebugLogging";
    const TIME: &'static str = "fmi3GetFloat64";
    const NULL_THIRD: &'static str = "fmi3GetOutputDerivatives";

    fn set_real(c: Handle, vr: *const u32, n: usize, x: *const f64) -> St {
        fmi3SetFloat64(c, vr, n, x, n).into()
    }
    fn get_real(c: Handle, vr: *const u32, n: usize, x: *mut f64) -> St {
        fmi3GetFloat64(c, vr, n, x, n).into()
    }
    fn set_int(c: Handle, vr: *const u32, n: usize, x: *const i32) -> St {
        fmi3SetInt32(c, vr, n, x, n).into()
    }
    fn get_int(c: Handle, vr: *const u32, n: usize, x: *mut i32) -> St {
        fmi3GetInt32(c, vr, n, x, n).into()
    }
    fn set_bool(c: Handle, vr: u32, x: i32) -> St {
        fmi3SetBoolean(c, &vr, 1, &bool3(x), 1).into()
    }
    fn get_bools(c: Handle, vrs: &[u32]) -> St {
        let mut out = vec![7u8; vrs.len()];
        let s: St = fmi3GetBoolean(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), vrs.len()).into();
        assert!(
            s != OK || out.iter().all(|&b| b <= 1),
            "fmi3GetBoolean OK wrote a byte other than 0 or 1: {out:?}"
        );
        s
    }
    fn get_state(c: Handle, s: *mut Handle) -> St {
        fmi3GetFMUState(c, s).into()
    }
    fn set_state(c: Handle, s: Handle) -> St {
        fmi3SetFMUState(c, s).into()
    }
    fn free_state(c: Handle, s: *mut Handle) -> St {
        fmi3FreeFMUState(c, s).into()
    }
    fn state_size(c: Handle, s: Handle, n: *mut usize) -> St {
        fmi3SerializedFMUStateSize(c, s, n).into()
    }
    fn serialize(c: Handle, s: Handle, p: *mut u8, n: usize) -> St {
        fmi3SerializeFMUState(c, s, p, n).into()
    }
    fn deserialize(c: Handle, p: *const u8, n: usize, s: *mut Handle) -> St {
        fmi3DeserializeFMUState(c, p, n, s).into()
    }
    fn setup(c: Handle, start: f64, stop_defined: bool, stop: f64) -> St {
        fmi3EnterInitializationMode(c, fmi3False, 0.0, start, u8::from(stop_defined), stop).into()
    }
    fn enter_init(c: Handle) -> St {
        fmi3EnterInitializationMode(c, fmi3False, 0.0, 0.0, fmi3False, 0.0).into()
    }
    fn exit_init(c: Handle) -> St {
        fmi3ExitInitializationMode(c).into()
    }
    fn do_step(c: Handle, t: f64, h: f64) -> (St, Option<StepOut>) {
        // sentinels: the FMU must write each output on OK
        let (mut e, mut term, mut early, mut last) = (7u8, 7u8, 7u8, f64::NAN);
        let s = fmi3DoStep(c, t, h, fmi3False, &mut e, &mut term, &mut early, &mut last);
        let out = StepOut {
            event_handling_needed: e,
            terminate: term,
            early_return: early,
            last: last.to_bits(),
        };
        (s.into(), Some(out))
    }
    fn reset(c: Handle) -> St {
        fmi3Reset(c).into()
    }
    fn terminate(c: Handle) -> St {
        fmi3Terminate(c).into()
    }
    fn dir_der(c: Handle, unknowns: &[u32], knowns: &[u32], seed: &[f64], out: &mut [f64]) -> St {
        fmi3GetDirectionalDerivative(
            c,
            unknowns.as_ptr(),
            unknowns.len(),
            knowns.as_ptr(),
            knowns.len(),
            seed.as_ptr(),
            seed.len(),
            out.as_mut_ptr(),
            out.len(),
        )
        .into()
    }
    fn debug_logging(c: Handle, on: bool, n: usize, categories: *const *const c_char) -> St {
        fmi3SetDebugLogging(c, u8::from(on), n, categories).into()
    }
    fn time(c: Handle, t: &mut f64) -> St {
        fmi3GetFloat64(c, &TIME_VR, 1, t, 1).into()
    }
    fn null_third(c: Handle, n: usize) -> St {
        fmi3GetOutputDerivatives(c, null(), n, null(), null_mut(), n).into()
    }
    fn free_instance(c: Handle) {
        fmi3FreeInstance(c);
    }
    fn instantiate_valid(env: usize, v: Variant) -> Handle {
        let token = CString::new(table(v).guid.clone()).expect("no NUL");
        fmi3InstantiateCoSimulation(
            c"cleanup".as_ptr(),
            token.as_ptr(),
            null(),
            fmi3False,
            fmi3False,
            fmi3False,
            fmi3False,
            null(),
            0,
            env as *mut c_void,
            Some(logger3),
            None,
        )
    }

    /// Header: variant/token byte, flags (name, eventModeUsed, loggingOn) as in FMI 2.0, then
    /// an options byte: earlyReturnAllowed (bits 0–1), requiredIntermediateVariables (bits
    /// 2–3), logger (bits 4–6: 7 = none, which FMI 3.0 allows), visible (bit 7).
    fn instantiate(p: &mut Program<'_, Self>, i: usize) {
        let sel = p.b.u8();
        let flags = p.b.u8();
        let opts = p.b.u8();
        let variant = variant_of(sel as usize);
        let mut valid = true;
        let token = p.model_id(sel, variant, &mut valid);
        let name = p.instance_name(i, flags, &mut valid);
        let event_mode_used = match (flags >> 4) % 8 {
            6 => 1,
            7 => p.b.u8(),
            _ => 0,
        };
        valid &= event_mode_used == 0;
        let logging_on = (flags >> 7) & 1;
        let early = [0u8, 1, 0, 0x80][(opts & 3) as usize];
        let required: Vec<u32> = match (opts >> 2) % 4 {
            1 => (0..1 + p.b.u8() % 3).map(|_| p.vr(variant, 0)).collect(),
            _ => Vec::new(),
        };
        let (req_ptr, n_req) = match (opts >> 2) % 4 {
            0 => (null(), 0),
            1 => (required.as_ptr(), required.len()),
            2 => {
                valid = false;
                (null(), 1 + p.b.u8() as usize % 3)
            }
            _ => (required.as_ptr(), 0), // a non-NULL array of 0 elements
        };
        let has_logger = (opts >> 4) % 8 != 7;
        let visible = opts >> 7;
        let ptr = |s: &Option<CString>| s.as_ref().map_or(null(), |s| s.as_ptr());
        let n0 = support::log_len(p.env.0);
        let c = fmi3InstantiateCoSimulation(
            ptr(&name),
            ptr(&token),
            null(),
            visible,
            logging_on,
            event_mode_used,
            early,
            req_ptr,
            n_req,
            p.env.0 as *mut c_void,
            if has_logger { Some(logger3) } else { None },
            None,
        );
        p.trace.push(format!(
            "fmi3 instantiate[{i}] {variant:?} valid={valid} eventModeUsed={event_mode_used} early={early} required={n_req} logger={has_logger} logging={logging_on} -> {}",
            !c.is_null()
        ));
        let inst = Inst {
            c,
            variant,
            logger: has_logger,
            early_allowed: early != 0,
        };
        p.instantiated(i, "fmi3InstantiateCoSimulation", c, valid, n0, inst);
    }

    fn special(p: &mut Program<'_, Self>, i: usize, v: Variant, op: u8) {
        match op {
            24 => adjoint(p, i, v),
            26 => other_types(p, i, v),
            27 => refused(p, i, v),
            32 => dependencies(p, i, v),
            33 => other_interfaces(p, i),
            34 => {
                // DoStep with a NULL output (refused) from the FMU's time
                let which = p.b.u8() % 4;
                let h = p.b.step();
                let t = p.fmu_time(i);
                p.trace.push(format!("doStepNull[{i}] output {which}"));
                let (mut b, mut last) = ([0u8; 3], 0.0);
                let [e, term, early] = &mut b;
                let ptrs: [*mut u8; 3] = [e, term, early];
                let s = p.call(i, "fmi3DoStep", |c| {
                    let n = |k: usize| {
                        if which as usize == k {
                            null_mut()
                        } else {
                            ptrs[k]
                        }
                    };
                    let l = if which == 3 { null_mut() } else { &mut last };
                    fmi3DoStep(c, t, h, fmi3False, n(0), n(1), n(2), l).into()
                });
                if s == OK {
                    p.fail("fmi3DoStep accepted a NULL output pointer".into());
                }
            }
            35 => {
                // the independent variable: readable with the others, never settable; and
                // nValues differing from nValueReferences
                let vr = p.vr(v, 0);
                let x = p.b.real();
                let vrs = [vr, TIME_VR];
                let mut out = [f64::NAN; 2];
                p.trace.push(format!("time/nValues[{i}] {vr} {x}"));
                let s = p.call(i, "fmi3GetFloat64", |c| {
                    fmi3GetFloat64(c, vrs.as_ptr(), 2, out.as_mut_ptr(), 2).into()
                });
                if s == OK
                    && (!out[1].is_finite() || (is_real_output(v, vr) && !out[0].is_finite()))
                {
                    p.fail(format!("fmi3GetFloat64 OK with {out:?}"));
                }
                let xs = [x, 0.0];
                let s = p.call(i, "fmi3SetFloat64", |c| {
                    fmi3SetFloat64(c, vrs.as_ptr(), 2, xs.as_ptr(), 2).into()
                });
                if s == OK {
                    p.fail("fmi3SetFloat64 set the independent variable time".into());
                }
                let nv = [0usize, 2, 3][p.b.u8() as usize % 3];
                let mut buf = [0.0; 3];
                p.call(i, "fmi3GetFloat64", |c| {
                    fmi3GetFloat64(c, &vr, 1, buf.as_mut_ptr(), nv).into()
                });
                p.call(i, "fmi3SetFloat64", |c| {
                    fmi3SetFloat64(c, &vr, 1, buf.as_ptr(), nv).into()
                });
                let iv = p.vr(v, 1);
                let mut ib = [0i32; 3];
                p.call(i, "fmi3GetInt32", |c| {
                    fmi3GetInt32(c, &iv, 1, ib.as_mut_ptr(), nv).into()
                });
            }
            36 | 37 => {
                p.do_step(i);
            }
            38 => p.replay(i),
            _ => {
                // GetOutputDerivatives: none provided (an empty request is OK)
                let n = p.b.u8() as usize % 3;
                let vrs: Vec<u32> = (0..n).map(|_| p.vr(v, 0)).collect();
                let orders = vec![1 + p.b.u8() as i32 % 2; n];
                let mut out = vec![0.0; n];
                p.trace.push(format!("outputDer[{i}] {vrs:?}"));
                let s = p.call(i, "fmi3GetOutputDerivatives", |c| {
                    fmi3GetOutputDerivatives(
                        c,
                        vrs.as_ptr(),
                        n,
                        orders.as_ptr(),
                        out.as_mut_ptr(),
                        n,
                    )
                    .into()
                });
                if s == OK && n > 0 {
                    p.fail(
                        "fmi3GetOutputDerivatives OK for a derivative it does not provide".into(),
                    );
                }
            }
        }
    }
}

/// fmi3GetAdjointDerivative (seed per unknown, sensitivity per known; sometimes a count off).
fn adjoint(p: &mut Program<'_, Fmi3>, i: usize, v: Variant) {
    let a = p.der_args(v, true);
    let off = p.b.u8() % 8;
    let n_seed = a.seed.len() + usize::from(off == 0);
    let n_sens = a.knowns.len() + usize::from(off == 1);
    let seed = [a.seed.clone(), vec![1.0]].concat();
    let mut out = vec![f64::NAN; a.knowns.len() + 1];
    p.trace.push(format!(
        "adjoint[{i}] {:?} {:?} {:?} off {off}",
        a.unknowns, a.knowns, a.seed
    ));
    let s = p.call(i, "fmi3GetAdjointDerivative", |c| {
        fmi3GetAdjointDerivative(
            c,
            a.unknowns.as_ptr(),
            a.unknowns.len(),
            a.knowns.as_ptr(),
            a.knowns.len(),
            seed.as_ptr(),
            n_seed,
            out.as_mut_ptr(),
            n_sens,
        )
        .into()
    });
    if s == OK {
        if off < 2 {
            p.fail("fmi3GetAdjointDerivative accepted a wrong nSeed or nSensitivity".into());
        }
        if let Some(x) = out[..n_sens].iter().find(|x| !x.is_finite()) {
            p.fail(format!("fmi3GetAdjointDerivative OK with a value {x}"));
        }
    }
}

/// Get/Set of the types this FMU has no variables of (an empty request is OK, any value
/// reference an error), with nValues sometimes differing from nValueReferences.
fn other_types(p: &mut Program<'_, Fmi3>, i: usize, v: Variant) {
    let which = p.b.u8() % 24;
    let n = p.b.u8() as usize % 3;
    let vrs: Vec<u32> = (0..n)
        .map(|_| {
            let ty = p.b.u8() % 3;
            p.vr(v, ty)
        })
        .collect();
    let nv = if p.b.u8().is_multiple_of(4) { n + 1 } else { n };
    p.trace
        .push(format!("otherType[{i}] {which} {vrs:?} nValues {nv}"));
    let vp = vrs.as_ptr();
    // room for nv values of any type (8 bytes each, aligned)
    let mut raw = [0u64; 4];
    let out = raw.as_mut_ptr();
    let mut sizes = [0usize; 4];
    let mut bins: [fmi3Binary; 4] = [null(); 4];
    let strs: [fmi3String; 4] = [c"x".as_ptr(); 4];
    macro_rules! pair {
        ($get:ident, $set:ident, $t:ty, $g:expr) => {{
            let s = if $g {
                p.call(i, stringify!($get), |c| {
                    $get(c, vp, n, out.cast::<$t>(), nv).into()
                })
            } else {
                p.call(i, stringify!($set), |c| {
                    $set(c, vp, n, out.cast::<$t>().cast_const(), nv).into()
                })
            };
            if s == OK && n > 0 {
                p.fail(format!(
                    "{} OK for a type this FMU has no variables of",
                    stringify!($get)
                ));
            }
        }};
    }
    let get = which.is_multiple_of(2);
    match which / 2 {
        0 => pair!(fmi3GetFloat32, fmi3SetFloat32, f32, get),
        1 => pair!(fmi3GetInt8, fmi3SetInt8, i8, get),
        2 => pair!(fmi3GetUInt8, fmi3SetUInt8, u8, get),
        3 => pair!(fmi3GetInt16, fmi3SetInt16, i16, get),
        4 => pair!(fmi3GetUInt16, fmi3SetUInt16, u16, get),
        5 => pair!(fmi3GetUInt32, fmi3SetUInt32, u32, get),
        6 => pair!(fmi3GetInt64, fmi3SetInt64, i64, get),
        7 => pair!(fmi3GetUInt64, fmi3SetUInt64, u64, get),
        8 => {
            if get {
                pair!(fmi3GetString, fmi3SetString, fmi3String, true);
            } else {
                let s = p.call(i, "fmi3SetString", |c| {
                    fmi3SetString(c, vp, n, strs.as_ptr(), nv).into()
                });
                if s == OK && n > 0 {
                    p.fail("fmi3SetString OK without String variables".into());
                }
            }
        }
        9 => {
            let s = if get {
                p.call(i, "fmi3GetBinary", |c| {
                    fmi3GetBinary(c, vp, n, sizes.as_mut_ptr(), bins.as_mut_ptr(), nv).into()
                })
            } else {
                p.call(i, "fmi3SetBinary", |c| {
                    fmi3SetBinary(c, vp, n, sizes.as_ptr(), bins.as_ptr(), nv).into()
                })
            };
            if s == OK && n > 0 {
                p.fail("fmi3Get/SetBinary OK without Binary variables".into());
            }
        }
        10 => {
            let s = if get {
                p.call(i, "fmi3GetClock", |c| {
                    fmi3GetClock(c, vp, n, out.cast()).into()
                })
            } else {
                p.call(i, "fmi3SetClock", |c| {
                    fmi3SetClock(c, vp, n, out.cast::<u8>().cast_const()).into()
                })
            };
            if s == OK && n > 0 {
                p.fail("fmi3Get/SetClock OK without clocks".into());
            }
        }
        _ => {
            // the supported types with a count off or Boolean bytes other than 0/1
            let mut b = [2u8, 255, 1, 0];
            let s = if get {
                p.call(i, "fmi3GetBoolean", |c| {
                    fmi3GetBoolean(c, vp, n, b.as_mut_ptr(), nv).into()
                })
            } else {
                p.call(i, "fmi3SetBoolean", |c| {
                    fmi3SetBoolean(c, vp, n, b.as_ptr(), nv).into()
                })
            };
            if s == OK && nv != n {
                p.fail("fmi3Get/SetBoolean OK with nValues != nValueReferences".into());
            }
        }
    }
}

/// The functions of Event Mode, clocks, configuration, Model Exchange and Scheduled Execution:
/// each answers fmi3Error (invariant 9), whatever the arguments.
fn refused(p: &mut Program<'_, Fmi3>, i: usize, v: Variant) {
    let which = p.b.u8() % 22;
    let vr = p.vr(v, 0);
    let x = p.b.real();
    let n = p.b.u8() as usize % 3;
    p.trace
        .push(format!("refused[{i}] {which} vr {vr} x {x} n {n}"));
    let mut f = [0.0f64; 4];
    let mut u = [0u64; 4];
    let mut u2 = [0u64; 4];
    let mut q = [0 as fmi3IntervalQualifier; 4];
    let mut b = [0u8; 6];
    let mut z = 0usize;
    let vrs = [vr; 4];
    let fp = f.as_mut_ptr();
    let name = |k: u8| -> &'static str {
        [
            "fmi3EnterEventMode",
            "fmi3UpdateDiscreteStates",
            "fmi3EvaluateDiscreteStates",
            "fmi3EnterStepMode",
            "fmi3EnterConfigurationMode",
            "fmi3ExitConfigurationMode",
            "fmi3GetIntervalDecimal",
            "fmi3GetIntervalFraction",
            "fmi3GetShiftDecimal",
            "fmi3GetShiftFraction",
            "fmi3SetIntervalDecimal",
            "fmi3SetIntervalFraction",
            "fmi3SetShiftDecimal",
            "fmi3SetShiftFraction",
            "fmi3EnterContinuousTimeMode",
            "fmi3CompletedIntegratorStep",
            "fmi3SetTime",
            "fmi3SetContinuousStates",
            "fmi3GetContinuousStateDerivatives",
            "fmi3GetEventIndicators",
            "fmi3GetContinuousStates",
            "fmi3GetNominalsOfContinuousStates",
        ][k as usize]
    };
    let s = p.call(i, name(which), |c| {
        let bp = b.as_mut_ptr();
        let s = match which {
            0 => fmi3EnterEventMode(c),
            1 => fmi3UpdateDiscreteStates(
                c,
                bp,
                bp.wrapping_add(1),
                bp.wrapping_add(2),
                bp.wrapping_add(3),
                bp.wrapping_add(4),
                fp,
            ),
            2 => fmi3EvaluateDiscreteStates(c),
            3 => fmi3EnterStepMode(c),
            4 => fmi3EnterConfigurationMode(c),
            5 => fmi3ExitConfigurationMode(c),
            6 => fmi3GetIntervalDecimal(c, vrs.as_ptr(), n, fp, q.as_mut_ptr()),
            7 => fmi3GetIntervalFraction(
                c,
                vrs.as_ptr(),
                n,
                u.as_mut_ptr(),
                u2.as_mut_ptr(),
                q.as_mut_ptr(),
            ),
            8 => fmi3GetShiftDecimal(c, vrs.as_ptr(), n, fp),
            9 => fmi3GetShiftFraction(c, vrs.as_ptr(), n, u.as_mut_ptr(), u2.as_mut_ptr()),
            10 => fmi3SetIntervalDecimal(c, vrs.as_ptr(), n, fp),
            11 => fmi3SetIntervalFraction(c, vrs.as_ptr(), n, u.as_ptr(), u2.as_ptr()),
            12 => fmi3SetShiftDecimal(c, vrs.as_ptr(), n, fp),
            13 => fmi3SetShiftFraction(c, vrs.as_ptr(), n, u.as_ptr(), u2.as_ptr()),
            14 => fmi3EnterContinuousTimeMode(c),
            15 => fmi3CompletedIntegratorStep(c, fmi3False, bp, bp.wrapping_add(1)),
            16 => fmi3SetTime(c, x),
            17 => fmi3SetContinuousStates(c, fp, n),
            18 => fmi3GetContinuousStateDerivatives(c, fp, n),
            19 => fmi3GetEventIndicators(c, fp, n),
            20 => fmi3GetContinuousStates(c, fp, n),
            _ => fmi3GetNominalsOfContinuousStates(c, fp, n),
        };
        s.into()
    });
    if s != St::Error {
        p.fail(format!("{} answered {s:?}, not fmi3Error", name(which)));
    }
    let which2 = p.b.u8() % 3;
    let name2 = [
        "fmi3GetNumberOfEventIndicators",
        "fmi3GetNumberOfContinuousStates",
        "fmi3ActivateModelPartition",
    ][which2 as usize];
    let s = p.call(i, name2, |c| {
        match which2 {
            0 => fmi3GetNumberOfEventIndicators(c, &mut z),
            1 => fmi3GetNumberOfContinuousStates(c, &mut z),
            _ => fmi3ActivateModelPartition(c, vr, x),
        }
        .into()
    });
    if s != St::Error {
        p.fail(format!("{name2} answered {s:?}, not fmi3Error"));
    }
}

/// fmi3GetNumberOfVariableDependencies then fmi3GetVariableDependencies (sometimes with a
/// wrong count); an OK answer lists value references of the variant.
fn dependencies(p: &mut Program<'_, Fmi3>, i: usize, v: Variant) {
    let ty = p.b.u8() % 3;
    let vr = p.vr(v, ty);
    let mut n = usize::MAX;
    p.trace.push(format!("dependencies[{i}] {vr}"));
    let s = p.call(i, "fmi3GetNumberOfVariableDependencies", |c| {
        fmi3GetNumberOfVariableDependencies(c, vr, &mut n).into()
    });
    let k = match (s, p.b.u8() % 4) {
        (OK, 0) => n + 1,
        (OK, _) => n,
        _ => p.b.u8() as usize % 3,
    };
    if k > table(v).vars.len() + 1 {
        p.fail(format!("fmi3GetNumberOfVariableDependencies OK with {n}"));
    }
    let mut e_dep = vec![usize::MAX; k];
    let mut indep = vec![u32::MAX; k];
    let mut e_indep = vec![usize::MAX; k];
    let mut kinds = vec![fmi3DependencyKind::Independent; k];
    let s2 = p.call(i, "fmi3GetVariableDependencies", |c| {
        fmi3GetVariableDependencies(
            c,
            vr,
            e_dep.as_mut_ptr(),
            indep.as_mut_ptr(),
            e_indep.as_mut_ptr(),
            kinds.as_mut_ptr(),
            k,
        )
        .into()
    });
    if s2 == OK {
        if s != OK || k != n {
            p.fail(format!(
                "fmi3GetVariableDependencies OK with nDependencies {k} (number: {s:?} {n})"
            ));
        }
        if indep.iter().any(|&x| table(v).get(x).is_none())
            || e_dep.iter().chain(&e_indep).any(|&e| e != 0)
        {
            p.fail(format!(
                "fmi3GetVariableDependencies OK with {indep:?} {e_dep:?} {e_indep:?}"
            ));
        }
    }
}

/// fmi3GetVersion, and the instantiation functions of the interfaces this FMU has not: NULL
/// and, with a logger, exactly one error naming the function.
fn other_interfaces(p: &mut Program<'_, Fmi3>, i: usize) {
    // SAFETY: fmi3GetVersion returns a static NUL-terminated string.
    let version = unsafe { CStr::from_ptr(fmi3GetVersion()) };
    if version.to_bytes() != b"3.0" {
        p.fail(format!("fmi3GetVersion {version:?}"));
    }
    let which = p.b.u8() % 4;
    let logger = which < 2;
    let log = if logger {
        Some(logger3 as fmi3LogMessageCallback)
    } else {
        None
    };
    let env = p.env.0 as *mut c_void;
    let token = CString::new(table(p.variant(i).expect("live")).guid.clone()).expect("no NUL");
    let n0 = support::log_len(p.env.0);
    p.trace.push(format!("otherInterface[{i}] {which}"));
    let (fname, c) = if which.is_multiple_of(2) {
        (
            "fmi3InstantiateModelExchange",
            fmi3InstantiateModelExchange(c"me".as_ptr(), token.as_ptr(), null(), 0, 0, env, log),
        )
    } else {
        (
            "fmi3InstantiateScheduledExecution",
            fmi3InstantiateScheduledExecution(
                c"se".as_ptr(),
                token.as_ptr(),
                null(),
                0,
                0,
                env,
                log,
                None,
                None,
                None,
            ),
        )
    };
    let lines = support::log_since(p.env.0, n0);
    if !c.is_null() {
        p.fail(format!("{fname} returned an instance"));
    }
    let want = usize::from(logger);
    if lines.len() != want
        || lines
            .iter()
            .any(|l| l.status != St::Error as c_int || !l.message.contains(fname))
    {
        p.fail(format!(
            "{fname} must log one error when it has a logger: {lines:?}"
        ));
    }
}
