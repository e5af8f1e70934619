//! Test support for everything that calls the Body FMU's exported functions as an importer
//! would: the loggers of both FMI versions (messages recorded per environment key, so tests
//! running in parallel do not see each other's), value references by name from the variable
//! table, and `Fmu2` / `Fmu3`, instances freed on drop with checked calls by variable name.
//! Uses the crate's exports, types and variable table only.
#![allow(dead_code)]

use body_fmu::fmi2::exports::*;
use body_fmu::fmi2::types::*;
use body_fmu::fmi3::exports::*;
use body_fmu::fmi3::types::*;
use body_fmu::variables::{by_name, guid};
use std::collections::BTreeMap;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard};

/// One message the FMU sent to the importer's logger.
#[derive(Clone, Debug)]
pub struct LogLine {
    /// status as int
    pub status: c_int,
    /// category name
    pub category: String,
    /// message as received (FMI 2.0: `%` doubled)
    pub message: String,
}

static LOG: Mutex<BTreeMap<usize, Vec<LogLine>>> = Mutex::new(BTreeMap::new());
static NEXT_ENV: AtomicUsize = AtomicUsize::new(1);

fn text(p: *const c_char) -> String {
    if p.is_null() {
        return "<NULL>".into();
    }
    // SAFETY: the FMU passes NUL-terminated strings that live for the duration of the call.
    unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
}

fn log() -> MutexGuard<'static, BTreeMap<usize, Vec<LogLine>>> {
    LOG.lock().unwrap_or_else(|e| e.into_inner())
}

fn record(env: *mut c_void, status: c_int, category: *const c_char, message: *const c_char) {
    let line = LogLine {
        status,
        category: text(category),
        message: text(message),
    };
    log().entry(env as usize).or_default().push(line);
}

/// The FMI 2.0 test logger: a plain five-argument function (stable Rust cannot define a
/// C-variadic one).
extern "C" fn logger2(
    env: *mut c_void,
    _instance: *const c_char,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
) {
    record(env, status, category, message);
}

/// The FMI 3.0 test logger.
extern "C" fn logger3(
    env: *mut c_void,
    status: fmi3Status,
    category: *const c_char,
    message: *const c_char,
) {
    record(env, status as c_int, category, message);
}

/// A fresh environment key.
pub fn new_env() -> usize {
    NEXT_ENV.fetch_add(1, Ordering::Relaxed)
}

/// The messages logged for `env` so far.
pub fn log_of(env: usize) -> Vec<LogLine> {
    log().get(&env).cloned().unwrap_or_default()
}

/// FMI 2.0 callbacks whose logger records under `env`.
pub fn callbacks(env: usize) -> fmi2CallbackFunctions {
    type Plain = extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);
    // SAFETY: both are C-ABI function pointers; the FMU calls the logger with exactly the five
    // fixed arguments, whose types have the same ABI (fmi2Status is a #[repr(C)] enum passed
    // as int), as fmpy's ctypes callback receives them.
    let logger = unsafe { std::mem::transmute::<Plain, fmi2CallbackLogger>(logger2 as Plain) };
    fmi2CallbackFunctions {
        logger: Some(logger),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: env as *mut c_void,
    }
}

/// The FMI 3.0 log callback.
pub fn logger3_fn() -> Option<fmi3LogMessageCallback> {
    Some(logger3)
}

/// Value reference of a variable by name (panics for an unknown name).
pub fn vr(name: &str) -> u32 {
    by_name(name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .vr
}

/// A C string.
pub fn cs(s: &str) -> CString {
    CString::new(s).unwrap()
}

/// The outputs in table order: r, q, v, w, energies.
pub const OUTPUTS: [&str; 15] = [
    "r[1]",
    "r[2]",
    "r[3]",
    "q.w",
    "q.x",
    "q.y",
    "q.z",
    "v[1]",
    "v[2]",
    "v[3]",
    "w[1]",
    "w[2]",
    "w[3]",
    "energy.kinetic",
    "energy.potential",
];

/// An FMI 2.0 instance, freed on drop.
pub struct Fmu2 {
    /// the component
    pub c: fmi2Component,
    /// its environment key (for `log_of`)
    pub env: usize,
    /// the time of the next step
    pub t: f64,
}

impl Fmu2 {
    /// Instantiates with this model's GUID (logging off).
    pub fn new() -> Self {
        let env = new_env();
        let cb = callbacks(env);
        let (name, g) = (cs("body"), cs(guid()));
        let c = fmi2Instantiate(name.as_ptr(), 1, g.as_ptr(), std::ptr::null(), &cb, 0, 0);
        assert!(!c.is_null(), "{:?}", log_of(env));
        Fmu2 { c, env, t: 0.0 }
    }

    /// Sets a Real by name.
    pub fn set(&self, name: &str, x: f64) -> fmi2Status {
        fmi2SetReal(self.c, &vr(name), 1, &x)
    }

    /// Sets an Integer by name.
    pub fn set_int(&self, name: &str, x: i32) -> fmi2Status {
        fmi2SetInteger(self.c, &vr(name), 1, &x)
    }

    /// A Real by name (panics on a refusal).
    pub fn get(&self, name: &str) -> f64 {
        let mut x = f64::NAN;
        assert_eq!(
            fmi2GetReal(self.c, &vr(name), 1, &mut x),
            fmi2Status::OK,
            "{name}"
        );
        x
    }

    /// The outputs in `OUTPUTS` order.
    pub fn outputs(&self) -> [f64; 15] {
        let vrs = OUTPUTS.map(vr);
        let mut x = [f64::NAN; 15];
        assert_eq!(
            fmi2GetReal(self.c, vrs.as_ptr(), 15, x.as_mut_ptr()),
            fmi2Status::OK
        );
        x
    }

    /// SetupExperiment(0) and EnterInitializationMode.
    pub fn enter(&self) {
        assert_eq!(
            fmi2SetupExperiment(self.c, 0, 0.0, 0.0, 0, 0.0),
            fmi2Status::OK
        );
        assert_eq!(fmi2EnterInitializationMode(self.c), fmi2Status::OK);
    }

    /// EnterInitializationMode after SetupExperiment and ExitInitializationMode.
    pub fn init(&self) {
        self.enter();
        assert_eq!(
            fmi2ExitInitializationMode(self.c),
            fmi2Status::OK,
            "{:?}",
            log_of(self.env)
        );
    }

    /// A step of h from the FMU's time (panics on a refusal).
    pub fn step(&mut self, h: f64) {
        assert_eq!(
            fmi2DoStep(self.c, self.t, h, 1),
            fmi2Status::OK,
            "{:?}",
            log_of(self.env)
        );
        self.t += h;
    }

    /// The number of messages so far.
    pub fn log_len(&self) -> usize {
        log_of(self.env).len()
    }
}

impl Drop for Fmu2 {
    fn drop(&mut self) {
        fmi2FreeInstance(self.c);
    }
}

/// An FMI 3.0 instance, freed on drop.
pub struct Fmu3 {
    /// the instance
    pub c: fmi3Instance,
    /// its environment key (for `log_of`)
    pub env: usize,
    /// the time of the next step
    pub t: f64,
}

impl Fmu3 {
    /// Instantiates with this model's instantiationToken.
    pub fn new() -> Self {
        let env = new_env();
        let (name, g) = (cs("body3"), cs(guid()));
        let c = fmi3InstantiateCoSimulation(
            name.as_ptr(),
            g.as_ptr(),
            std::ptr::null(),
            0,
            0,
            0,
            0,
            std::ptr::null(),
            0,
            env as *mut c_void,
            logger3_fn(),
            None,
        );
        assert!(!c.is_null(), "{:?}", log_of(env));
        Fmu3 { c, env, t: 0.0 }
    }

    /// Sets a Float64 by name.
    pub fn set(&self, name: &str, x: f64) -> fmi3Status {
        fmi3SetFloat64(self.c, &vr(name), 1, &x, 1)
    }

    /// Sets an Int32 by name.
    pub fn set_int(&self, name: &str, x: i32) -> fmi3Status {
        fmi3SetInt32(self.c, &vr(name), 1, &x, 1)
    }

    /// A Float64 by name (panics on a refusal).
    pub fn get(&self, name: &str) -> f64 {
        let mut x = f64::NAN;
        assert_eq!(
            fmi3GetFloat64(self.c, &vr(name), 1, &mut x, 1),
            fmi3Status::OK,
            "{name}"
        );
        x
    }

    /// The outputs in `OUTPUTS` order.
    pub fn outputs(&self) -> [f64; 15] {
        let vrs = OUTPUTS.map(vr);
        let mut x = [f64::NAN; 15];
        let st = fmi3GetFloat64(self.c, vrs.as_ptr(), 15, x.as_mut_ptr(), 15);
        assert_eq!(st, fmi3Status::OK);
        x
    }

    /// EnterInitializationMode (start time 0).
    pub fn enter(&self) {
        assert_eq!(
            fmi3EnterInitializationMode(self.c, 0, 0.0, 0.0, 0, 0.0),
            fmi3Status::OK
        );
    }

    /// EnterInitializationMode and ExitInitializationMode.
    pub fn init(&self) {
        self.enter();
        assert_eq!(
            fmi3ExitInitializationMode(self.c),
            fmi3Status::OK,
            "{:?}",
            log_of(self.env)
        );
    }

    /// A step of h from the FMU's time (panics on a refusal); checks the step's outputs.
    pub fn step(&mut self, h: f64) {
        let (mut event, mut terminate, mut early, mut last) = (9, 9, 9, f64::NAN);
        let st = fmi3DoStep(
            self.c,
            self.t,
            h,
            1,
            &mut event,
            &mut terminate,
            &mut early,
            &mut last,
        );
        assert_eq!(st, fmi3Status::OK, "{:?}", log_of(self.env));
        assert_eq!((event, terminate, early), (0, 0, 0));
        self.t += h;
        assert_eq!(last, self.t);
    }

    /// The number of messages so far.
    pub fn log_len(&self) -> usize {
        log_of(self.env).len()
    }
}

impl Drop for Fmu3 {
    fn drop(&mut self) {
        fmi3FreeInstance(self.c);
    }
}

/// A small deterministic generator (64-bit LCG), uniform in [0, 1).
pub struct Lcg(pub u64);

impl Lcg {
    /// The next number in [0, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A number in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}
