//! FMI 3.0 support of the `abi_fmi3_*` tests (declared from `tests/common/mod.rs`, so every
//! program that includes the support module compiles it; its `#![allow(dead_code)]` covers this
//! module too):
//!
//! - the FMI 3.0 logger: messages recorded as (env key, status, category, message), read back
//!   per componentEnvironment key with `log_of` (keys from the support module's `new_env`);
//! - `instantiate`, `instantiate_with`: fmi3InstantiateCoSimulation with a token and flags;
//! - `Fmu3`, an instance freed on drop, with checked calls;
//! - `assert_error_logged` and `expect_error!`: a refused call is fmi3Error with one message that
//!   names the function;
//! - `outputs`: the value references of a variant's Real (resp. Int32) outputs;
//! - the FMI 2.0 twin: `drive` sets up a variant through the fmi2* exports (`Fmu2`, the
//!   support module's `Fmu`) and through the fmi3* exports alike.

use super::{new_env, text, Fmu};
use connector_fmu::fmi2::exports as f2;
use connector_fmu::fmi2::types::fmi2Status;
use connector_fmu::fmi3::exports::*;
use connector_fmu::fmi3::types::*;
use connector_fmu::variables::{table, Causality, Start, Variant};
use std::ffi::{c_char, c_void, CString};
use std::ptr::null;
use std::sync::Mutex;

pub const OK: fmi3Status = fmi3Status::OK;
pub const ERR: fmi3Status = fmi3Status::Error;
/// The communication step most tests take.
pub const H: f64 = 1e-3;

/// (env key, status, category, message) of every message any test received.
static LOG: Mutex<Vec<(usize, fmi3Status, String, String)>> = Mutex::new(Vec::new());

/// The test logger of FMI 3.0 instances (logMessage).
pub extern "C" fn logger(
    env: *mut c_void,
    status: fmi3Status,
    category: *const c_char,
    message: *const c_char,
) {
    LOG.lock().unwrap_or_else(|e| e.into_inner()).push((
        env as usize,
        status,
        text(category),
        text(message),
    ));
}

/// (status, category, message) of the messages logged for `env` so far.
pub fn log_of(env: usize) -> Vec<(fmi3Status, String, String)> {
    let log = LOG.lock().unwrap_or_else(|e| e.into_inner());
    log.iter()
        .filter(|l| l.0 == env)
        .map(|l| (l.1, l.2.clone(), l.3.clone()))
        .collect()
}

/// fmi3InstantiateCoSimulation with the given token and eventModeUsed (earlyReturnAllowed
/// false), logging under `env`.
pub fn instantiate(token: &str, event_mode_used: bool, env: usize) -> fmi3Instance {
    instantiate_with(token, event_mode_used, false, env)
}

/// fmi3InstantiateCoSimulation with the given token, eventModeUsed and earlyReturnAllowed.
pub fn instantiate_with(
    token: &str,
    event_mode_used: bool,
    early: bool,
    env: usize,
) -> fmi3Instance {
    let name = CString::new("fmi3 test").unwrap();
    let token = CString::new(token).unwrap();
    fmi3InstantiateCoSimulation(
        name.as_ptr(),
        token.as_ptr(),
        null(),
        fmi3False,
        fmi3False,
        u8::from(event_mode_used),
        u8::from(early),
        null(),
        0,
        env as *mut c_void,
        Some(logger),
        None,
    )
}

/// One FMI 3.0 instance, freed on drop.
pub struct Fmu3 {
    pub c: fmi3Instance,
    pub env: usize,
    pub variant: Variant,
}

impl Drop for Fmu3 {
    fn drop(&mut self) {
        fmi3FreeInstance(self.c);
    }
}

impl Fmu3 {
    pub fn new(v: Variant) -> Fmu3 {
        Fmu3::with_early_return(v, false)
    }

    /// An instance with earlyReturnAllowed = `early`.
    pub fn with_early_return(v: Variant, early: bool) -> Fmu3 {
        let env = new_env();
        let c = instantiate_with(&table(v).guid, false, early, env);
        assert!(!c.is_null(), "{v:?}: {:?}", log_of(env));
        Fmu3 { c, env, variant: v }
    }

    pub fn log(&self) -> Vec<(fmi3Status, String, String)> {
        log_of(self.env)
    }

    pub fn has(&self, name: &str) -> bool {
        table(self.variant).vars.iter().any(|v| v.name == name)
    }

    pub fn vr(&self, name: &str) -> u32 {
        table(self.variant)
            .vars
            .iter()
            .find(|v| v.name == name)
            .unwrap_or_else(|| panic!("{:?} has no {name}", self.variant))
            .vr
    }

    pub fn set_real_if(&self, name: &str, x: f64) {
        if self.has(name) {
            let s = fmi3SetFloat64(self.c, &self.vr(name), 1, &x, 1);
            assert_eq!(s, OK, "{name}: {:?}", self.log());
        }
    }

    pub fn get_reals(&self, vrs: &[u32]) -> Vec<f64> {
        let mut out = vec![f64::NAN; vrs.len()];
        let s = fmi3GetFloat64(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), out.len());
        assert_eq!(s, OK, "{:?}", self.log());
        out
    }

    pub fn get_ints(&self, vrs: &[u32]) -> Vec<i32> {
        let mut out = vec![i32::MIN; vrs.len()];
        let s = fmi3GetInt32(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), out.len());
        assert_eq!(s, OK, "{:?}", self.log());
        out
    }

    pub fn enter_init(&self) {
        let s = fmi3EnterInitializationMode(self.c, fmi3False, 0.0, 0.0, fmi3False, 0.0);
        assert_eq!(s, OK, "{:?}", self.log());
    }

    pub fn exit_init(&self) {
        assert_eq!(fmi3ExitInitializationMode(self.c), OK, "{:?}", self.log());
    }

    pub fn init(&self) {
        self.enter_init();
        self.exit_init();
    }

    /// fmi3DoStep; returns the status and the four outputs.
    pub fn step(&self, t: f64, h: f64) -> (fmi3Status, [u8; 3], f64) {
        let (mut e, mut term, mut early, mut last) = (9u8, 9u8, 9u8, f64::NAN);
        let s = fmi3DoStep(
            self.c, t, h, fmi3False, &mut e, &mut term, &mut early, &mut last,
        );
        (s, [e, term, early], last)
    }
}

/// Asserts fmi3Error with exactly one new message, an error naming `fname`.
#[track_caller]
pub fn assert_error_logged(f: &Fmu3, before: usize, status: fmi3Status, fname: &str) {
    let log = f.log();
    assert_eq!(status, ERR, "{fname}: {:?}", &log[before..]);
    assert_eq!(
        log.len(),
        before + 1,
        "{fname} must log exactly one message: {:?}",
        &log[before..]
    );
    let (s, cat, msg) = &log[before];
    assert_eq!(*s, ERR, "{msg}");
    assert_eq!(cat, "logStatusError", "{msg}");
    assert!(msg.starts_with(&format!("{fname}: ")), "{msg}");
}

/// `expect_error!(f, "fmi3Name", call)`: `call` answers fmi3Error and logs exactly one message,
/// an error naming `fmi3Name` (`assert_error_logged` must be in scope). Like `dead_code` for the
/// functions, the two lints are off for the programs that include this module and do not use it.
#[allow(unused_macros)]
macro_rules! expect_error {
    ($f:expr, $name:expr, $call:expr) => {{
        let n = $f.log().len();
        let s = $call;
        assert_error_logged(&$f, n, s, $name);
    }};
}
#[allow(unused_imports)]
pub(crate) use expect_error;

/// Value references of the Real (resp. Int32) outputs.
pub fn outputs(v: Variant, integer: bool) -> Vec<u32> {
    table(v)
        .vars
        .iter()
        .filter(|x| x.causality == Causality::Output)
        .filter(|x| matches!(x.start, Start::Integer(_)) == integer)
        .map(|x| x.vr)
        .collect()
}

// ------------------------------------------------------------------ the FMI 2.0 twin

/// Sets a named parameter or input on both twins.
pub type SetBoth<'a> = &'a dyn Fn(&str, f64);
/// The set-up of a twin run: the parameters and initial inputs, through a `SetBoth`.
pub type Setup<'a> = &'a dyn Fn(SetBoth);

/// An FMI 2.0 instance of the same variant (through the fmi2* exports).
pub struct Fmu2(pub Fmu);

/// The two twins of variant `v`, both through initialization with the same `setup`.
pub fn drive(v: Variant, setup: Setup) -> (Fmu2, Fmu3) {
    let f2i = Fmu2(Fmu::new(v));
    let f3i = Fmu3::new(v);
    assert_eq!(f2i.0.setup(), fmi2Status::OK);
    assert_eq!(f2::fmi2EnterInitializationMode(f2i.0.c), fmi2Status::OK);
    f3i.enter_init();
    setup(&|name, x| {
        f2i.0.set_real_if(name, x);
        f3i.set_real_if(name, x);
    });
    f2i.0.exit_init();
    f3i.exit_init();
    (f2i, f3i)
}
