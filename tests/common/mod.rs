//! The one test support module for everything that calls the exported FMI functions directly,
//! as an importer would through the shared library: the integration tests (`mod common;`), the
//! fuzz harness (`fuzz/harness/`, also replayed by `tests/fuzz_smoke.rs`) and the native
//! benchmark (`benches/native/`), the latter two through `#[path = ".../tests/common/mod.rs"]`.
//!
//! - the logger and the callback struct: messages recorded per componentEnvironment key
//!   (`new_env`, `callbacks`, `log_of`, `log_len`, `log_since`, `forget_log`);
//! - value references by name from the variable table (`vr`, `Fmu::vr`);
//! - `instantiate_raw` and `Fmu`, an instance freed on drop, with checked calls;
//! - `fnv1a`, the checksum of serialized FMU states;
//! - `fmi3`: the same for the FMI 3.0 exports (its logger, `Fmu3`, `expect_error!`) and the
//!   FMI 2.0 twin of an FMI 3.0 instance, for the `abi_fmi3_*` tests.
#![allow(dead_code)]

pub mod fmi3;

use connector_fmu::fmi2::exports::*;
use connector_fmu::fmi2::types::*;
use connector_fmu::variables::{table, Causality, Start, Variant};
use std::collections::BTreeMap;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard};

/// fmi2CoSimulation as the C int an importer passes.
pub const CO_SIMULATION: c_int = 1;

/// One message the FMU sent to the importer's logger.
#[derive(Clone, Debug)]
pub struct LogLine {
    /// Instance name as given by the FMU.
    pub instance: String,
    /// fmi2Status as int.
    pub status: c_int,
    /// Category name.
    pub category: String,
    /// Message exactly as received (with `%` doubled by the FMU).
    pub message: String,
}

/// Every message, keyed by the componentEnvironment its instance was given, so that tests
/// running in parallel do not see each other's messages.
static LOG: Mutex<BTreeMap<usize, Vec<LogLine>>> = Mutex::new(BTreeMap::new());
/// Source of unique componentEnvironment keys (never dereferenced, never reused).
static NEXT_ENV: AtomicUsize = AtomicUsize::new(1);

fn text(p: *const c_char) -> String {
    if p.is_null() {
        return "<NULL>".into();
    }
    // SAFETY: the FMU passes NUL-terminated strings that live for the duration of the call.
    unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
}

/// The test logger: a plain five-argument function (stable Rust cannot define a C-variadic one).
extern "C" fn test_logger(
    env: *mut c_void,
    instance: *const c_char,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
) {
    let line = LogLine {
        instance: text(instance),
        status,
        category: text(category),
        message: text(message),
    };
    log().entry(env as usize).or_default().push(line);
}

fn log() -> MutexGuard<'static, BTreeMap<usize, Vec<LogLine>>> {
    LOG.lock().unwrap_or_else(|e| e.into_inner())
}

/// A fresh componentEnvironment key.
pub fn new_env() -> usize {
    NEXT_ENV.fetch_add(1, Ordering::Relaxed)
}

/// The messages logged for `env` so far.
pub fn log_of(env: usize) -> Vec<LogLine> {
    log_since(env, 0)
}

/// The number of messages logged for `env` so far.
pub fn log_len(env: usize) -> usize {
    log().get(&env).map_or(0, Vec::len)
}

/// The messages logged for `env` after the first `n`.
pub fn log_since(env: usize, n: usize) -> Vec<LogLine> {
    log()
        .get(&env)
        .map_or_else(Vec::new, |l| l.get(n..).unwrap_or_default().to_vec())
}

/// Drops the messages of `env` (a long-running caller, the fuzz harness, keeps memory flat).
pub fn forget_log(env: usize) {
    log().remove(&env);
}

/// Callback struct whose logger records into `LOG` under `env`.
pub fn callbacks(env: usize) -> fmi2CallbackFunctions {
    let plain: extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char) =
        test_logger;
    // SAFETY: both are C-ABI function pointers; the FMU calls the logger with exactly the five
    // fixed arguments (its contract, B4), whose types have the same ABI here (fmi2Status is a
    // #[repr(C)] enum passed as int). Calling a non-variadic function through a variadic
    // pointer with only the fixed arguments is what fmpy's ctypes callback does too.
    let logger = unsafe {
        std::mem::transmute::<
            extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char),
            fmi2CallbackLogger,
        >(plain)
    };
    fmi2CallbackFunctions {
        logger: Some(logger),
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: env as *mut c_void,
    }
}

/// The GUID of a variant.
pub fn guid(v: Variant) -> String {
    table(v).guid.clone()
}

/// Value reference of a variable of `v` (panics when the variant has none of that name).
pub fn vr(v: Variant, name: &str) -> u32 {
    table(v)
        .vars
        .iter()
        .find(|x| x.name == name)
        .unwrap_or_else(|| panic!("{v:?} has no variable {name}"))
        .vr
}

/// Calls fmi2Instantiate with optional (NULL) strings; returns the component.
pub fn instantiate_raw(
    name: Option<&str>,
    fmu_type: c_int,
    guid: Option<&str>,
    functions: Option<&fmi2CallbackFunctions>,
    logging_on: bool,
) -> fmi2Component {
    let name = name.map(|s| CString::new(s).unwrap());
    let guid = guid.map(|s| CString::new(s).unwrap());
    let ptr = |s: &Option<CString>| s.as_ref().map_or(std::ptr::null(), |s| s.as_ptr());
    let f = functions.map_or(std::ptr::null(), |f| f as *const _);
    fmi2Instantiate(
        ptr(&name),
        fmu_type,
        ptr(&guid),
        std::ptr::null(),
        f,
        fmi2False,
        fmi2Boolean::from(logging_on),
    )
}

/// One instance, freed on drop.
pub struct Fmu {
    pub c: fmi2Component,
    pub env: usize,
    pub variant: Variant,
}

impl Drop for Fmu {
    fn drop(&mut self) {
        fmi2FreeInstance(self.c);
        forget_log(self.env);
    }
}

impl Fmu {
    /// A new instance of `v` (panics when fmi2Instantiate refuses).
    pub fn new(v: Variant) -> Fmu {
        Fmu::with_logging(v, false)
    }

    /// A new instance with loggingOn as given.
    pub fn with_logging(v: Variant, logging_on: bool) -> Fmu {
        let env = new_env();
        let cb = callbacks(env);
        let c = instantiate_raw(
            Some("test instance"),
            CO_SIMULATION,
            Some(&guid(v)),
            Some(&cb),
            logging_on,
        );
        assert!(
            !c.is_null(),
            "fmi2Instantiate refused {v:?}: {:?}",
            log_of(env)
        );
        Fmu { c, env, variant: v }
    }

    /// Messages logged by this instance so far.
    pub fn log(&self) -> Vec<LogLine> {
        log_of(self.env)
    }

    /// Number of messages logged so far.
    pub fn log_len(&self) -> usize {
        log_len(self.env)
    }

    /// Whether the variant has a variable of this name.
    pub fn has(&self, name: &str) -> bool {
        table(self.variant).vars.iter().any(|v| v.name == name)
    }

    /// Value reference of a variable (panics when the variant has none of that name).
    pub fn vr(&self, name: &str) -> u32 {
        vr(self.variant, name)
    }

    /// Value references of the Real (resp. Integer) outputs.
    pub fn outputs(&self, integer: bool) -> Vec<u32> {
        table(self.variant)
            .vars
            .iter()
            .filter(|v| v.causality == Causality::Output)
            .filter(|v| matches!(v.start, Start::Integer(_)) == integer)
            .map(|v| v.vr)
            .collect()
    }

    /// fmi2SetReal of one variable.
    pub fn set_real(&self, name: &str, x: f64) -> fmi2Status {
        fmi2SetReal(self.c, &self.vr(name), 1, &x)
    }

    /// fmi2SetReal of one variable when the variant has it.
    pub fn set_real_if(&self, name: &str, x: f64) {
        if self.has(name) {
            assert_eq!(
                self.set_real(name, x),
                fmi2Status::OK,
                "{name}: {:?}",
                self.log()
            );
        }
    }

    /// fmi2GetReal of one variable, asserting OK.
    pub fn get_real(&self, name: &str) -> f64 {
        let mut x = f64::NAN;
        let s = fmi2GetReal(self.c, &self.vr(name), 1, &mut x);
        assert_eq!(s, fmi2Status::OK, "{name}: {:?}", self.log());
        x
    }

    /// fmi2GetReal of several VRs, asserting OK.
    pub fn get_reals(&self, vrs: &[u32]) -> Vec<f64> {
        let mut out = vec![f64::NAN; vrs.len()];
        let s = fmi2GetReal(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr());
        assert_eq!(s, fmi2Status::OK, "{:?}", self.log());
        out
    }

    /// fmi2GetInteger of several VRs, asserting OK.
    pub fn get_integers(&self, vrs: &[u32]) -> Vec<i32> {
        let mut out = vec![i32::MIN; vrs.len()];
        let s = fmi2GetInteger(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr());
        assert_eq!(s, fmi2Status::OK, "{:?}", self.log());
        out
    }

    /// fmi2SetupExperiment(start 0, no tolerance, no stop time).
    pub fn setup(&self) -> fmi2Status {
        fmi2SetupExperiment(self.c, fmi2False, 0.0, 0.0, fmi2False, 0.0)
    }

    /// Setup and enter initialization mode, asserting OK.
    pub fn enter_init(&self) {
        assert_eq!(self.setup(), fmi2Status::OK, "{:?}", self.log());
        assert_eq!(
            fmi2EnterInitializationMode(self.c),
            fmi2Status::OK,
            "{:?}",
            self.log()
        );
    }

    /// Exit initialization mode, asserting OK.
    pub fn exit_init(&self) {
        assert_eq!(
            fmi2ExitInitializationMode(self.c),
            fmi2Status::OK,
            "{:?}",
            self.log()
        );
    }

    /// Setup, enter and exit initialization mode, asserting OK.
    pub fn init(&self) {
        self.enter_init();
        self.exit_init();
    }

    /// fmi2DoStep.
    pub fn step(&self, t: f64, h: f64) -> fmi2Status {
        fmi2DoStep(self.c, t, h, fmi2False)
    }

    /// The current FMU state through its bytes: fmi2GetFMUstate, fmi2SerializeFMUstate and
    /// fmi2DeSerializeFMUstate, each asserted OK; the returned state is the caller's to free.
    pub fn round_trip_state(&self) -> fmi2FMUstate {
        let mut s: fmi2FMUstate = std::ptr::null_mut();
        assert_eq!(fmi2GetFMUstate(self.c, &mut s), fmi2Status::OK);
        let mut n = 0usize;
        assert_eq!(
            fmi2SerializedFMUstateSize(self.c, s, &mut n),
            fmi2Status::OK
        );
        let mut bytes = vec![0u8; n];
        assert_eq!(
            fmi2SerializeFMUstate(self.c, s, bytes.as_mut_ptr().cast(), n),
            fmi2Status::OK
        );
        assert_eq!(fmi2FreeFMUstate(self.c, &mut s), fmi2Status::OK);
        let mut back: fmi2FMUstate = std::ptr::null_mut();
        let status = fmi2DeSerializeFMUstate(self.c, bytes.as_ptr().cast(), n, &mut back);
        assert_eq!(status, fmi2Status::OK, "{:?}", self.log());
        back
    }
}

/// FNV-1a 64 of `bytes`, the checksum the serialized FMU state ends with: lets a test or the fuzz
/// harness patch serialized bytes and still pass the checksum, to reach the validation behind it.
pub fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Asserts that `status` is fmi2Error and that exactly one new message, an fmi2Error naming
/// `fname`, was logged since `before` messages.
#[track_caller]
pub fn assert_error_logged(f: &Fmu, before: usize, status: fmi2Status, fname: &str) {
    let log = f.log();
    assert_eq!(status, fmi2Status::Error, "{fname}: {:?}", &log[before..]);
    assert_eq!(
        log.len(),
        before + 1,
        "{fname} must log exactly one message: {:?}",
        &log[before..]
    );
    let line = &log[before];
    assert_eq!(line.status, fmi2Status::Error as c_int, "{line:?}");
    assert_eq!(line.category, "logStatusError", "{line:?}");
    assert!(
        line.message.contains(fname),
        "message does not name {fname}: {line:?}"
    );
}
