//! The exported FMI 3.0 Co-Simulation functions, called as an importer calls them: lifecycle,
//! the state machine (illegal calls per state), NULL arguments, bad values, instantiation
//! refusals, the functions this FMU does not support, variable dependencies against the FMI 2.0
//! model structure, FMU state round trips, and the FMI 2.0 twin: the same variant driven
//! through fmi2* and fmi3* gives the same outputs and directional derivatives bit for bit.

mod common;

use connector_fmu::fmi2::exports as f2;
use connector_fmu::fmi2::types::fmi2Status;
use connector_fmu::fmi3::exports::*;
use connector_fmu::fmi3::types::*;
use connector_fmu::variables::{table, Causality, Start, Variability, Variant, VARIANTS};
use quick_xml::events::Event;
use quick_xml::reader::Reader;
use std::ffi::{c_char, c_void, CStr, CString};
use std::ptr::{null, null_mut};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

const OK: fmi3Status = fmi3Status::OK;
const ERR: fmi3Status = fmi3Status::Error;
const H: f64 = 1e-3;

// ------------------------------------------------------------------ helpers

/// (env key, status, category, message) of every message any test received.
static LOG: Mutex<Vec<(usize, fmi3Status, String, String)>> = Mutex::new(Vec::new());
static NEXT_ENV: AtomicUsize = AtomicUsize::new(1_000_000);

fn text(p: *const c_char) -> String {
    if p.is_null() {
        return "<NULL>".into();
    }
    // SAFETY: the FMU passes NUL-terminated strings that live for the duration of the call.
    unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
}

extern "C" fn logger(
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

fn log_of(env: usize) -> Vec<(fmi3Status, String, String)> {
    let log = LOG.lock().unwrap_or_else(|e| e.into_inner());
    log.iter()
        .filter(|l| l.0 == env)
        .map(|l| (l.1, l.2.clone(), l.3.clone()))
        .collect()
}

fn new_env() -> usize {
    NEXT_ENV.fetch_add(1, Ordering::Relaxed)
}

/// fmi3InstantiateCoSimulation with the given token and eventModeUsed (earlyReturnAllowed
/// false), logging under `env`.
fn instantiate(token: &str, event_mode_used: bool, env: usize) -> fmi3Instance {
    instantiate_with(token, event_mode_used, false, env)
}

/// fmi3InstantiateCoSimulation with the given token, eventModeUsed and earlyReturnAllowed.
fn instantiate_with(token: &str, event_mode_used: bool, early: bool, env: usize) -> fmi3Instance {
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
struct Fmu3 {
    c: fmi3Instance,
    env: usize,
    variant: Variant,
}

impl Drop for Fmu3 {
    fn drop(&mut self) {
        fmi3FreeInstance(self.c);
    }
}

impl Fmu3 {
    fn new(v: Variant) -> Fmu3 {
        Fmu3::with_early_return(v, false)
    }

    /// An instance with earlyReturnAllowed = `early`.
    fn with_early_return(v: Variant, early: bool) -> Fmu3 {
        let env = new_env();
        let c = instantiate_with(&table(v).guid, false, early, env);
        assert!(!c.is_null(), "{v:?}: {:?}", log_of(env));
        Fmu3 { c, env, variant: v }
    }

    fn log(&self) -> Vec<(fmi3Status, String, String)> {
        log_of(self.env)
    }

    fn has(&self, name: &str) -> bool {
        table(self.variant).vars.iter().any(|v| v.name == name)
    }

    fn vr(&self, name: &str) -> u32 {
        table(self.variant)
            .vars
            .iter()
            .find(|v| v.name == name)
            .unwrap_or_else(|| panic!("{:?} has no {name}", self.variant))
            .vr
    }

    fn set_real_if(&self, name: &str, x: f64) {
        if self.has(name) {
            let s = fmi3SetFloat64(self.c, &self.vr(name), 1, &x, 1);
            assert_eq!(s, OK, "{name}: {:?}", self.log());
        }
    }

    fn get_reals(&self, vrs: &[u32]) -> Vec<f64> {
        let mut out = vec![f64::NAN; vrs.len()];
        let s = fmi3GetFloat64(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), out.len());
        assert_eq!(s, OK, "{:?}", self.log());
        out
    }

    fn get_ints(&self, vrs: &[u32]) -> Vec<i32> {
        let mut out = vec![i32::MIN; vrs.len()];
        let s = fmi3GetInt32(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), out.len());
        assert_eq!(s, OK, "{:?}", self.log());
        out
    }

    fn enter_init(&self) {
        let s = fmi3EnterInitializationMode(self.c, fmi3False, 0.0, 0.0, fmi3False, 0.0);
        assert_eq!(s, OK, "{:?}", self.log());
    }

    fn exit_init(&self) {
        assert_eq!(fmi3ExitInitializationMode(self.c), OK, "{:?}", self.log());
    }

    fn init(&self) {
        self.enter_init();
        self.exit_init();
    }

    /// fmi3DoStep; returns the status and the four outputs.
    fn step(&self, t: f64, h: f64) -> (fmi3Status, [u8; 3], f64) {
        let (mut e, mut term, mut early, mut last) = (9u8, 9u8, 9u8, f64::NAN);
        let s = fmi3DoStep(
            self.c, t, h, fmi3False, &mut e, &mut term, &mut early, &mut last,
        );
        (s, [e, term, early], last)
    }
}

/// Asserts fmi3Error with exactly one new message, an error naming `fname`.
#[track_caller]
fn assert_error_logged(f: &Fmu3, before: usize, status: fmi3Status, fname: &str) {
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

macro_rules! expect_error {
    ($f:expr, $name:expr, $call:expr) => {{
        let n = $f.log().len();
        let s = $call;
        assert_error_logged(&$f, n, s, $name);
    }};
}

/// Value references of the Real (resp. Int32) outputs.
fn outputs(v: Variant, integer: bool) -> Vec<u32> {
    table(v)
        .vars
        .iter()
        .filter(|x| x.causality == Causality::Output)
        .filter(|x| matches!(x.start, Start::Integer(_)) == integer)
        .map(|x| x.vr)
        .collect()
}

// ------------------------------------------------------------------ lifecycle

#[test]
fn version_is_3_0() {
    // SAFETY: a static NUL-terminated string.
    let v = unsafe { CStr::from_ptr(fmi3GetVersion()) };
    assert_eq!(v.to_str().unwrap(), "3.0");
}

#[test]
fn full_lifecycle_every_variant_steps_to_the_end_of_each_step() {
    for spec in VARIANTS {
        let f = Fmu3::new(spec.variant);
        f.enter_init();
        for k in 1..=6 {
            f.set_real_if(&format!("elasticity.k{k}"), 100.0);
            f.set_real_if(&format!("damping.c{k}"), 1.0);
        }
        f.set_real_if("b.r[1]", 0.02);
        f.exit_init();
        f.set_real_if("b.v[1]", 0.1);
        let ys = outputs(spec.variant, false);
        let mut t = 0.0;
        for _ in 0..10 {
            let (s, flags, last) = f.step(t, H);
            assert_eq!(s, OK, "{:?}: {:?}", spec.variant, f.log());
            assert_eq!(
                flags,
                [0, 0, 0],
                "no event, no termination, no early return"
            );
            assert_eq!(last, t + H, "lastSuccessfulTime is t + h");
            t += H;
            assert!(f.get_reals(&ys).iter().all(|y| y.is_finite()));
            // time (vr 0) reads the FMU's time
            assert_eq!(f.get_reals(&[0]), vec![t]);
        }
        assert_eq!(fmi3Terminate(f.c), OK);
        assert!(f.get_reals(&ys).iter().all(|y| y.is_finite()));
        assert_eq!(fmi3Reset(f.c), OK);
        f.init();
        assert_eq!(
            f.step(0.0, H).0,
            OK,
            "after reset the time starts again at 0"
        );
        assert!(f.log().is_empty(), "{:?}", f.log());
    }
}

#[test]
fn start_time_is_taken_from_enter_initialization_mode() {
    let f = Fmu3::new(Variant::Bushing);
    assert_eq!(
        fmi3EnterInitializationMode(f.c, fmi3True, 1e-6, 2.5, fmi3True, 3.0),
        OK
    );
    f.exit_init();
    assert_eq!(f.get_reals(&[0]), vec![2.5]);
    assert_eq!(f.step(2.5, H).2, 2.5 + H);
    expect_error!(f, "fmi3DoStep", f.step(0.0, H).0);

    let g = Fmu3::new(Variant::Bushing);
    expect_error!(
        g,
        "fmi3EnterInitializationMode",
        fmi3EnterInitializationMode(g.c, fmi3False, 0.0, f64::NAN, fmi3False, 0.0)
    );
}

// ------------------------------------------------------------------ state machine

#[test]
fn illegal_calls_per_state_are_errors_with_one_message() {
    let f = Fmu3::new(Variant::Bushing);
    let vr = f.vr("b.r[1]");
    let out = f.vr("a.f[1]");
    let (mut x, mut s) = (0.0, null_mut::<c_void>());
    // Instantiated
    expect_error!(
        f,
        "fmi3ExitInitializationMode",
        fmi3ExitInitializationMode(f.c)
    );
    expect_error!(f, "fmi3DoStep", f.step(0.0, H).0);
    expect_error!(f, "fmi3Terminate", fmi3Terminate(f.c));
    expect_error!(f, "fmi3GetFloat64", fmi3GetFloat64(f.c, &out, 1, &mut x, 1));
    expect_error!(f, "fmi3EnterStepMode", fmi3EnterStepMode(f.c));
    // Initialization Mode
    f.enter_init();
    expect_error!(
        f,
        "fmi3EnterInitializationMode",
        fmi3EnterInitializationMode(f.c, fmi3False, 0.0, 0.0, fmi3False, 0.0)
    );
    expect_error!(f, "fmi3DoStep", f.step(0.0, H).0);
    expect_error!(f, "fmi3Terminate", fmi3Terminate(f.c));
    expect_error!(f, "fmi3EnterStepMode", fmi3EnterStepMode(f.c));
    // Step Mode
    f.exit_init();
    expect_error!(
        f,
        "fmi3EnterInitializationMode",
        fmi3EnterInitializationMode(f.c, fmi3False, 0.0, 0.0, fmi3False, 0.0)
    );
    expect_error!(
        f,
        "fmi3ExitInitializationMode",
        fmi3ExitInitializationMode(f.c)
    );
    expect_error!(f, "fmi3EnterStepMode", fmi3EnterStepMode(f.c));
    expect_error!(f, "fmi3EnterEventMode", fmi3EnterEventMode(f.c));
    let n = f.log().len();
    let (st, _, _) = f.step(0.0, H);
    assert_eq!(
        st,
        OK,
        "refused calls leave Step Mode usable: {:?}",
        &f.log()[n..]
    );
    assert!(
        f.log()[n - 4].2.contains("not allowed in state StepMode"),
        "the FMI 3.0 name of the state: {:?}",
        f.log()[n - 4]
    );
    // Terminated
    assert_eq!(fmi3Terminate(f.c), OK);
    expect_error!(f, "fmi3DoStep", f.step(H, H).0);
    expect_error!(f, "fmi3Terminate", fmi3Terminate(f.c));
    expect_error!(f, "fmi3SetFloat64", fmi3SetFloat64(f.c, &vr, 1, &0.1, 1));
    // the FMU state functions and reset remain
    assert_eq!(fmi3GetFMUState(f.c, &mut s), OK);
    assert_eq!(fmi3FreeFMUState(f.c, &mut s), OK);
    assert_eq!(fmi3Reset(f.c), OK);
}

#[test]
fn a_failed_step_leaves_error_state_until_reset() {
    let f = Fmu3::new(Variant::ProjectionFlexionTorsion);
    f.init();
    // fold the shafts back: flexion α → π is singular
    let q = [0.0, 1.0, 0.0, 0.0];
    for (c, x) in ["w", "x", "y", "z"].iter().zip(q) {
        f.set_real_if(&format!("b.q.{c}"), x);
    }
    let n = f.log().len();
    let (s, flags, last) = f.step(0.0, H);
    assert_error_logged(&f, n, s, "fmi3DoStep");
    assert!(
        f.log()[n].2.contains("fmi3Reset or fmi3SetFMUState"),
        "{:?}",
        f.log()[n]
    );
    assert_eq!(flags, [0, 0, 0]);
    assert_eq!(last, 0.0, "lastSuccessfulTime: the state at t is kept");
    expect_error!(f, "fmi3DoStep", f.step(0.0, H).0);
    assert_eq!(fmi3Reset(f.c), OK);
    f.init();
    assert_eq!(f.step(0.0, H).0, OK);
}

// ------------------------------------------------------------------ bad input

#[test]
fn null_arrays_with_counts_are_refused() {
    let f = Fmu3::new(Variant::Bushing);
    f.init();
    let vr = f.vr("a.f[1]");
    let input = f.vr("b.r[1]");
    let (mut x, mut i, mut b) = (0.0, 0i32, 0u8);
    expect_error!(
        f,
        "fmi3GetFloat64",
        fmi3GetFloat64(f.c, null(), 1, &mut x, 1)
    );
    expect_error!(
        f,
        "fmi3GetFloat64",
        fmi3GetFloat64(f.c, &vr, 1, null_mut(), 1)
    );
    expect_error!(
        f,
        "fmi3SetFloat64",
        fmi3SetFloat64(f.c, &input, 1, null(), 1)
    );
    expect_error!(f, "fmi3GetInt32", fmi3GetInt32(f.c, null(), 1, &mut i, 1));
    expect_error!(f, "fmi3SetInt32", fmi3SetInt32(f.c, null(), 2, null(), 2));
    expect_error!(
        f,
        "fmi3GetBoolean",
        fmi3GetBoolean(f.c, null(), 1, &mut b, 1)
    );
    expect_error!(f, "fmi3SetBoolean", fmi3SetBoolean(f.c, &vr, 1, null(), 1));
    expect_error!(
        f,
        "fmi3GetDirectionalDerivative",
        fmi3GetDirectionalDerivative(f.c, &vr, 1, null(), 1, &1.0, 1, &mut x, 1)
    );
    expect_error!(
        f,
        "fmi3GetAdjointDerivative",
        fmi3GetAdjointDerivative(f.c, &vr, 1, &input, 1, &1.0, 1, null_mut(), 1)
    );
    expect_error!(
        f,
        "fmi3GetVariableDependencies",
        fmi3GetVariableDependencies(f.c, vr, null_mut(), null_mut(), null_mut(), null_mut(), 3)
    );
    expect_error!(
        f,
        "fmi3GetNumberOfVariableDependencies",
        fmi3GetNumberOfVariableDependencies(f.c, vr, null_mut())
    );
    let (mut e, mut t, mut er, mut last) = (0u8, 0u8, 0u8, 0.0);
    expect_error!(
        f,
        "fmi3DoStep",
        fmi3DoStep(f.c, 0.0, H, 0, null_mut(), &mut t, &mut er, &mut last)
    );
    expect_error!(
        f,
        "fmi3DoStep",
        fmi3DoStep(f.c, 0.0, H, 0, &mut e, &mut t, &mut er, null_mut())
    );
    let mut s = null_mut::<c_void>();
    assert_eq!(fmi3GetFMUState(f.c, &mut s), OK);
    expect_error!(
        f,
        "fmi3SerializeFMUState",
        fmi3SerializeFMUState(f.c, s, null_mut(), 10)
    );
    expect_error!(
        f,
        "fmi3DeserializeFMUState",
        fmi3DeserializeFMUState(f.c, null(), 10, &mut s)
    );
    expect_error!(f, "fmi3SetFMUState", fmi3SetFMUState(f.c, null_mut()));
    assert_eq!(fmi3FreeFMUState(f.c, &mut s), OK);
    assert!(s.is_null());
    // NULL instance: fmi3Error, nothing to log through, no crash
    assert_eq!(
        fmi3DoStep(null_mut(), 0.0, H, 0, &mut e, &mut t, &mut er, &mut last),
        ERR
    );
    assert_eq!(fmi3GetFloat64(null_mut(), null(), 0, null_mut(), 0), ERR);
    fmi3FreeInstance(null_mut());
    // the instance still steps
    assert_eq!(f.step(0.0, H).0, OK, "{:?}", f.log());
}

#[test]
fn counts_must_match_for_scalar_variables() {
    let f = Fmu3::new(Variant::Planar);
    f.init();
    let vrs = [f.vr("a.f[1]"), f.vr("a.f[2]")];
    let mut out = [0.0; 3];
    expect_error!(
        f,
        "fmi3GetFloat64",
        fmi3GetFloat64(f.c, vrs.as_ptr(), 2, out.as_mut_ptr(), 3)
    );
    assert!(f.log().last().unwrap().2.contains("nValues = 3"));
    let k = f.vr("b.r[1]");
    expect_error!(
        f,
        "fmi3GetDirectionalDerivative",
        fmi3GetDirectionalDerivative(f.c, vrs.as_ptr(), 2, &k, 1, &1.0, 1, out.as_mut_ptr(), 1)
    );
    expect_error!(
        f,
        "fmi3GetAdjointDerivative",
        fmi3GetAdjointDerivative(
            f.c,
            vrs.as_ptr(),
            2,
            &k,
            1,
            out.as_ptr(),
            1,
            out.as_mut_ptr(),
            1
        )
    );
}

#[test]
fn unknown_references_wrong_types_and_nan_are_refused_and_change_nothing() {
    let f = Fmu3::new(Variant::Planar);
    f.set_real_if("friction.muStatic", 0.3);
    f.init();
    let input = f.vr("b.r[1]");
    let status = f.vr("friction.status");
    let before = f.get_reals(&[input]);
    let (mut x, mut i) = (0.0, 0i32);
    expect_error!(
        f,
        "fmi3GetFloat64",
        fmi3GetFloat64(f.c, &9999, 1, &mut x, 1)
    );
    assert!(f
        .log()
        .last()
        .unwrap()
        .2
        .contains("unknown value reference 9999"));
    expect_error!(
        f,
        "fmi3GetFloat64",
        fmi3GetFloat64(f.c, &status, 1, &mut x, 1)
    );
    assert!(
        f.log()
            .last()
            .unwrap()
            .2
            .contains("of type Int32, not Float64"),
        "{:?}",
        f.log().last()
    );
    expect_error!(f, "fmi3GetInt32", fmi3GetInt32(f.c, &input, 1, &mut i, 1));
    assert!(f
        .log()
        .last()
        .unwrap()
        .2
        .contains("of type Float64, not Int32"));
    expect_error!(
        f,
        "fmi3SetFloat64",
        fmi3SetFloat64(f.c, &input, 1, &f64::NAN, 1)
    );
    expect_error!(
        f,
        "fmi3SetFloat64",
        fmi3SetFloat64(f.c, [input, 9999].as_ptr(), 2, [0.5, 0.5].as_ptr(), 2)
    );
    expect_error!(f, "fmi3SetFloat64", fmi3SetFloat64(f.c, &0, 1, &1.0, 1));
    assert!(f.log().last().unwrap().2.contains("independent variable"));
    let out = f.vr("a.f[1]");
    expect_error!(f, "fmi3SetFloat64", fmi3SetFloat64(f.c, &out, 1, &1.0, 1));
    assert_eq!(f.get_reals(&[input]), before, "all or nothing");
}

#[test]
fn types_without_variables_refuse_any_request_but_accept_empty_ones() {
    let f = Fmu3::new(Variant::Bushing);
    f.init();
    let real = f.vr("a.f[1]");
    let c = f.c;
    macro_rules! other {
        ($get:ident, $set:ident, $t:ty, $name:expr) => {{
            let mut v: [$t; 1] = Default::default();
            assert_eq!($get(c, null(), 0, null_mut(), 0), OK);
            assert_eq!($set(c, null(), 0, null(), 0), OK);
            expect_error!(f, stringify!($get), $get(c, &real, 1, v.as_mut_ptr(), 1));
            let m = f.log().last().unwrap().2.clone();
            assert!(m.contains(&format!("not {}", $name)), "{m}");
            expect_error!(f, stringify!($set), $set(c, &777, 1, v.as_ptr(), 1));
            assert!(f
                .log()
                .last()
                .unwrap()
                .2
                .contains("unknown value reference 777"));
        }};
    }
    other!(fmi3GetFloat32, fmi3SetFloat32, f32, "Float32");
    other!(fmi3GetInt8, fmi3SetInt8, i8, "Int8");
    other!(fmi3GetUInt8, fmi3SetUInt8, u8, "UInt8");
    other!(fmi3GetInt16, fmi3SetInt16, i16, "Int16");
    other!(fmi3GetUInt16, fmi3SetUInt16, u16, "UInt16");
    other!(fmi3GetUInt32, fmi3SetUInt32, u32, "UInt32");
    other!(fmi3GetInt64, fmi3SetInt64, i64, "Int64");
    other!(fmi3GetUInt64, fmi3SetUInt64, u64, "UInt64");
    let mut s: fmi3String = null();
    assert_eq!(fmi3GetString(c, null(), 0, null_mut(), 0), OK);
    expect_error!(f, "fmi3GetString", fmi3GetString(c, &real, 1, &mut s, 1));
    expect_error!(f, "fmi3SetString", fmi3SetString(c, &real, 1, &s, 1));
    let (mut size, mut bin): (usize, fmi3Binary) = (0, null());
    assert_eq!(fmi3GetBinary(c, null(), 0, null_mut(), null_mut(), 0), OK);
    expect_error!(
        f,
        "fmi3GetBinary",
        fmi3GetBinary(c, &real, 1, &mut size, &mut bin, 1)
    );
    expect_error!(
        f,
        "fmi3SetBinary",
        fmi3SetBinary(c, &real, 1, &size, &bin, 1)
    );
    let mut clock = 0u8;
    assert_eq!(fmi3GetClock(c, null(), 0, null_mut()), OK);
    assert_eq!(fmi3SetClock(c, null(), 0, null()), OK);
    expect_error!(f, "fmi3GetClock", fmi3GetClock(c, &real, 1, &mut clock));
    expect_error!(f, "fmi3SetClock", fmi3SetClock(c, &real, 1, &clock));
    // empty output-derivative requests are fine, others are not
    let mut y = 0.0;
    assert_eq!(
        fmi3GetOutputDerivatives(c, null(), 0, null(), null_mut(), 0),
        OK
    );
    expect_error!(
        f,
        "fmi3GetOutputDerivatives",
        fmi3GetOutputDerivatives(c, &real, 1, &1, &mut y, 1)
    );
}

#[test]
fn unsupported_functions_answer_error_with_one_message() {
    let f = Fmu3::new(Variant::RadialThrust);
    f.init();
    let c = f.c;
    let (mut b, mut x, mut n) = (0u8, 0.0, 0usize);
    let (mut u, mut q) = (0u64, 0 as fmi3IntervalQualifier);
    let vr = 1u32;
    type Call<'a> = (&'a str, Box<dyn Fn() -> fmi3Status + 'a>);
    let calls: Vec<Call> = vec![
        ("fmi3EnterEventMode", Box::new(|| fmi3EnterEventMode(c))),
        ("fmi3EnterStepMode", Box::new(|| fmi3EnterStepMode(c))),
        (
            "fmi3EnterConfigurationMode",
            Box::new(|| fmi3EnterConfigurationMode(c)),
        ),
        (
            "fmi3ExitConfigurationMode",
            Box::new(|| fmi3ExitConfigurationMode(c)),
        ),
        (
            "fmi3EvaluateDiscreteStates",
            Box::new(|| fmi3EvaluateDiscreteStates(c)),
        ),
        (
            "fmi3EnterContinuousTimeMode",
            Box::new(|| fmi3EnterContinuousTimeMode(c)),
        ),
        ("fmi3SetTime", Box::new(|| fmi3SetTime(c, 1.0))),
        (
            "fmi3SetContinuousStates",
            Box::new(|| fmi3SetContinuousStates(c, null(), 0)),
        ),
        (
            "fmi3ActivateModelPartition",
            Box::new(|| fmi3ActivateModelPartition(c, 1, 0.0)),
        ),
        (
            "fmi3SetIntervalDecimal",
            Box::new(move || fmi3SetIntervalDecimal(c, &vr, 1, &1.0)),
        ),
        (
            "fmi3SetShiftDecimal",
            Box::new(move || fmi3SetShiftDecimal(c, &vr, 1, &1.0)),
        ),
        (
            "fmi3SetIntervalFraction",
            Box::new(move || fmi3SetIntervalFraction(c, &vr, 1, &1, &1)),
        ),
        (
            "fmi3SetShiftFraction",
            Box::new(move || fmi3SetShiftFraction(c, &vr, 1, &1, &1)),
        ),
    ];
    for (name, call) in &calls {
        expect_error!(f, name, call());
    }
    expect_error!(
        f,
        "fmi3GetIntervalDecimal",
        fmi3GetIntervalDecimal(c, &vr, 1, &mut x, &mut q)
    );
    expect_error!(
        f,
        "fmi3GetIntervalFraction",
        fmi3GetIntervalFraction(c, &vr, 1, &mut u, &mut u.clone(), &mut q)
    );
    expect_error!(
        f,
        "fmi3GetShiftDecimal",
        fmi3GetShiftDecimal(c, &vr, 1, &mut x)
    );
    expect_error!(
        f,
        "fmi3GetShiftFraction",
        fmi3GetShiftFraction(c, &vr, 1, &mut u, &mut u.clone())
    );
    expect_error!(
        f,
        "fmi3UpdateDiscreteStates",
        fmi3UpdateDiscreteStates(
            c,
            &mut b,
            &mut b.clone(),
            &mut b.clone(),
            &mut b.clone(),
            &mut b.clone(),
            &mut x
        )
    );
    expect_error!(
        f,
        "fmi3CompletedIntegratorStep",
        fmi3CompletedIntegratorStep(c, 0, &mut b, &mut b.clone())
    );
    expect_error!(
        f,
        "fmi3GetContinuousStateDerivatives",
        fmi3GetContinuousStateDerivatives(c, &mut x, 1)
    );
    expect_error!(
        f,
        "fmi3GetEventIndicators",
        fmi3GetEventIndicators(c, &mut x, 1)
    );
    expect_error!(
        f,
        "fmi3GetContinuousStates",
        fmi3GetContinuousStates(c, &mut x, 1)
    );
    expect_error!(
        f,
        "fmi3GetNominalsOfContinuousStates",
        fmi3GetNominalsOfContinuousStates(c, &mut x, 1)
    );
    expect_error!(
        f,
        "fmi3GetNumberOfEventIndicators",
        fmi3GetNumberOfEventIndicators(c, &mut n)
    );
    expect_error!(
        f,
        "fmi3GetNumberOfContinuousStates",
        fmi3GetNumberOfContinuousStates(c, &mut n)
    );
    // none of them changed anything: the instance is still in Step Mode
    assert_eq!(f.step(0.0, H).0, OK, "{:?}", f.log());
}

#[test]
fn instantiation_refusals_are_null_and_logged() {
    let env = new_env();
    assert!(instantiate("{not-a-token}", false, env).is_null());
    let log = log_of(env);
    assert_eq!(log.len(), 1, "{log:?}");
    assert!(
        log[0]
            .2
            .starts_with("fmi3InstantiateCoSimulation: instantiationToken"),
        "{log:?}"
    );

    let env = new_env();
    assert!(instantiate(&table(Variant::Planar).guid, true, env).is_null());
    assert!(
        log_of(env)[0].2.contains("eventModeUsed"),
        "{:?}",
        log_of(env)
    );

    let env = new_env();
    let name = CString::new("x").unwrap();
    let token = CString::new(table(Variant::Planar).guid.clone()).unwrap();
    let me = fmi3InstantiateModelExchange(
        name.as_ptr(),
        token.as_ptr(),
        null(),
        0,
        0,
        env as *mut c_void,
        Some(logger),
    );
    assert!(me.is_null());
    let se = fmi3InstantiateScheduledExecution(
        name.as_ptr(),
        token.as_ptr(),
        null(),
        0,
        0,
        env as *mut c_void,
        Some(logger),
        None,
        None,
        None,
    );
    assert!(se.is_null());
    let log = log_of(env);
    assert_eq!(log.len(), 2, "{log:?}");
    assert!(log[0]
        .2
        .starts_with("fmi3InstantiateModelExchange: Model Exchange is not supported"));
    assert!(log[1]
        .2
        .starts_with("fmi3InstantiateScheduledExecution: Scheduled Execution"));
    // without a logger: NULL, no crash
    assert!(fmi3InstantiateModelExchange(null(), null(), null(), 0, 0, null_mut(), None).is_null());

    // empty name, NULL token, NULL required-intermediate array with a count
    let env = new_env();
    let empty = CString::new("").unwrap();
    let c = fmi3InstantiateCoSimulation(
        empty.as_ptr(),
        token.as_ptr(),
        null(),
        0,
        0,
        0,
        0,
        null(),
        0,
        env as *mut c_void,
        Some(logger),
        None,
    );
    assert!(c.is_null());
    let c = fmi3InstantiateCoSimulation(
        name.as_ptr(),
        null(),
        null(),
        0,
        0,
        0,
        0,
        null(),
        0,
        env as *mut c_void,
        Some(logger),
        None,
    );
    assert!(c.is_null());
    let c = fmi3InstantiateCoSimulation(
        name.as_ptr(),
        token.as_ptr(),
        null(),
        0,
        0,
        0,
        0,
        null(),
        2,
        env as *mut c_void,
        Some(logger),
        None,
    );
    assert!(c.is_null());
    assert_eq!(log_of(env).len(), 3, "{:?}", log_of(env));

    // a NULL logMessage is allowed (FMI 3.0): the instance works, silently
    let c = fmi3InstantiateCoSimulation(
        name.as_ptr(),
        token.as_ptr(),
        null(),
        0,
        1,
        0,
        1,
        null(),
        0,
        null_mut(),
        None,
        None,
    );
    assert!(!c.is_null());
    assert_eq!(fmi3EnterInitializationMode(c, 0, 0.0, 0.0, 0, 0.0), OK);
    assert_eq!(fmi3ExitInitializationMode(c), OK);
    assert_eq!(fmi3EnterEventMode(c), ERR);
    fmi3FreeInstance(c);
}

#[test]
fn debug_logging_categories() {
    let f = Fmu3::new(Variant::Bushing);
    let cats = [CString::new("logAll").unwrap()];
    let ptrs: Vec<fmi3String> = cats.iter().map(|c| c.as_ptr()).collect();
    assert_eq!(fmi3SetDebugLogging(f.c, 1, 1, ptrs.as_ptr()), OK);
    f.init();
    let log = f.log();
    assert!(
        log.iter()
            .any(|l| l.1 == "logAll" && l.2 == "fmi3ExitInitializationMode"),
        "{log:?}"
    );
    assert_eq!(
        fmi3SetDebugLogging(f.c, 0, 0, null()),
        OK,
        "(NULL, 0): all categories"
    );
    let bad = [CString::new("logNothing").unwrap()];
    let ptrs: Vec<fmi3String> = bad.iter().map(|c| c.as_ptr()).collect();
    expect_error!(
        f,
        "fmi3SetDebugLogging",
        fmi3SetDebugLogging(f.c, 1, 1, ptrs.as_ptr())
    );
    expect_error!(
        f,
        "fmi3SetDebugLogging",
        fmi3SetDebugLogging(f.c, 1, 1, null())
    );
}

// ------------------------------------------------------------------ dependencies

/// The FMI 2.0 description's ModelStructure as value references: (Outputs, InitialUnknowns),
/// each a list of (unknown vr, dependency vrs).
type Structure = Vec<(u32, Vec<u32>)>;

fn fmi2_structure(v: Variant) -> (Structure, Structure) {
    let id = v.spec().model_identifier;
    let path = format!("{}/modelDescription/{id}.xml", env!("CARGO_MANIFEST_DIR"));
    let xml = std::fs::read_to_string(path).unwrap();
    let mut reader = Reader::from_str(&xml);
    let mut vrs = Vec::new();
    let (mut outputs, mut initial) = (Vec::new(), Vec::new());
    let mut section = 0;
    loop {
        match reader.read_event().unwrap() {
            Event::Eof => break,
            Event::Start(e) | Event::Empty(e) => {
                let attr = |name: &[u8]| {
                    e.attributes()
                        .flatten()
                        .find(|a| a.key.as_ref() == name)
                        .map(|a| String::from_utf8_lossy(&a.value).into_owned())
                };
                match e.name().as_ref() {
                    b"ScalarVariable" => {
                        vrs.push(attr(b"valueReference").unwrap().parse::<u32>().unwrap())
                    }
                    b"Outputs" => section = 1,
                    b"InitialUnknowns" => section = 2,
                    b"Unknown" => {
                        let index: usize = attr(b"index").unwrap().parse().unwrap();
                        let deps: Vec<u32> = attr(b"dependencies")
                            .unwrap()
                            .split_whitespace()
                            .map(|i| vrs[i.parse::<usize>().unwrap() - 1])
                            .collect();
                        let entry = (vrs[index - 1], deps);
                        if section == 1 {
                            outputs.push(entry)
                        } else {
                            initial.push(entry)
                        }
                    }
                    _ => {}
                }
            }
            _ => {}
        }
    }
    (outputs, initial)
}

fn runtime_dependencies(f: &Fmu3, vr: u32) -> Vec<u32> {
    let mut n = usize::MAX;
    assert_eq!(
        fmi3GetNumberOfVariableDependencies(f.c, vr, &mut n),
        OK,
        "{:?}",
        f.log()
    );
    let (mut e_dep, mut indep, mut e_indep) = (vec![9; n], vec![0u32; n], vec![9; n]);
    let mut kinds = vec![fmi3DependencyKind::Independent; n];
    let s = fmi3GetVariableDependencies(
        f.c,
        vr,
        e_dep.as_mut_ptr(),
        indep.as_mut_ptr(),
        e_indep.as_mut_ptr(),
        kinds.as_mut_ptr(),
        n,
    );
    assert_eq!(s, OK, "{:?}", f.log());
    assert!(e_dep.iter().chain(&e_indep).all(|&i| i == 0), "scalars");
    assert!(kinds.iter().all(|&k| k == fmi3DependencyKind::Dependent));
    indep
}

#[test]
fn variable_dependencies_follow_the_fmi2_model_structure() {
    for spec in VARIANTS {
        let (outputs, initial) = fmi2_structure(spec.variant);
        let f = Fmu3::new(spec.variant);
        f.enter_init();
        for (vr, deps) in &initial {
            let mut want = deps.clone();
            want.sort_unstable();
            assert_eq!(
                runtime_dependencies(&f, *vr),
                want,
                "{:?} vr {vr}",
                spec.variant
            );
        }
        f.exit_init();
        for (vr, deps) in &outputs {
            let mut want = deps.clone();
            want.sort_unstable();
            assert_eq!(
                runtime_dependencies(&f, *vr),
                want,
                "{:?} vr {vr}",
                spec.variant
            );
        }
        let input = table(spec.variant)
            .vars
            .iter()
            .find(|x| x.causality == Causality::Input)
            .unwrap()
            .vr;
        let mut n = 0;
        expect_error!(
            f,
            "fmi3GetNumberOfVariableDependencies",
            fmi3GetNumberOfVariableDependencies(f.c, input, &mut n)
        );
        let out = outputs[0].0;
        let mut k = vec![fmi3DependencyKind::Independent; 1];
        let (mut a, mut b, mut c) = ([0usize; 1], [0u32; 1], [0usize; 1]);
        if outputs[0].1.len() != 1 {
            expect_error!(
                f,
                "fmi3GetVariableDependencies",
                fmi3GetVariableDependencies(
                    f.c,
                    out,
                    a.as_mut_ptr(),
                    b.as_mut_ptr(),
                    c.as_mut_ptr(),
                    k.as_mut_ptr(),
                    1
                )
            );
        }
    }
}

// ------------------------------------------------------------------ the FMI 2.0 twin

/// Sets a named parameter or input on both twins.
type SetBoth<'a> = &'a dyn Fn(&str, f64);
/// The set-up of a twin run: the parameters and initial inputs, through a `SetBoth`.
type Setup<'a> = &'a dyn Fn(SetBoth);

/// An FMI 2.0 instance of the same variant (through the fmi2* exports).
struct Fmu2(common::Fmu);

fn drive(v: Variant, setup: Setup) -> (Fmu2, Fmu3) {
    let f2i = Fmu2(common::Fmu::new(v));
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

/// Steps both twins along the same input path and compares every output bit for bit.
fn compare_twins(v: Variant, setup: Setup, path: &dyn Fn(f64) -> [f64; 6]) {
    let (a, b) = drive(v, setup);
    let (reals, ints) = (outputs(v, false), outputs(v, true));
    let names = ["b.r[1]", "b.r[2]", "b.v[1]", "b.v[2]", "b.w[3]", "b.r[3]"];
    let mut t = 0.0;
    let mut seen = std::collections::BTreeSet::<Vec<i32>>::new();
    for k in 0..400 {
        let u = path(t);
        for (n, x) in names.iter().zip(u) {
            a.0.set_real_if(n, x);
            b.set_real_if(n, x);
        }
        // a variable step: the FMUs declare canHandleVariableCommunicationStepSize
        let h = if k % 3 == 0 { 2e-3 } else { 1e-3 };
        assert_eq!(a.0.step(t, h), fmi2Status::OK, "{:?}", a.0.log());
        let (s, _, last) = b.step(t, h);
        assert_eq!(s, OK, "{:?}", b.log());
        t += h;
        assert_eq!(last, t);
        let (y2, y3) = (a.0.get_reals(&reals), b.get_reals(&reals));
        for ((vr, p), q) in reals.iter().zip(&y2).zip(&y3) {
            assert_eq!(
                p.to_bits(),
                q.to_bits(),
                "{v:?} vr {vr} at t = {t}: {p} vs {q}"
            );
        }
        let i3 = b.get_ints(&ints);
        assert_eq!(a.0.get_integers(&ints), i3, "{v:?} at t = {t}");
        seen.insert(i3);
    }
    // the path changed the discrete state (stops engage, friction sticks and slips)
    assert!(
        seen.len() >= 2,
        "{v:?}: discrete outputs took only {seen:?}"
    );
}

#[test]
fn fmi3_outputs_equal_fmi2_outputs_bit_for_bit() {
    let friction_and_stops = |set: &dyn Fn(&str, f64)| {
        for k in 1..=6 {
            set(&format!("elasticity.k{k}"), 2e3);
            set(&format!("damping.c{k}"), 5.0);
            set(&format!("stop.lower{k}"), -0.01);
            set(&format!("stop.upper{k}"), 0.01);
        }
        set("friction.muStatic", 0.3);
        set("friction.muKinetic", 0.2);
        set("friction.Fint", 20.0);
    };
    // a shaking path that reaches the stops and makes the friction stick and slip
    let path = |t: f64| {
        let w = 2.0 * std::f64::consts::PI * 5.0;
        let a = 0.02;
        [
            a * (w * t).sin(),
            0.5 * a * (2.0 * w * t).sin(),
            a * w * (w * t).cos(),
            a * w * (2.0 * w * t).cos(),
            (w * t).cos(),
            0.005 * (w * t).sin(),
        ]
    };
    for spec in VARIANTS {
        compare_twins(spec.variant, &friction_and_stops, &path);
    }
}

#[test]
fn directional_derivatives_equal_fmi2_and_adjoints_are_their_transpose() {
    for spec in VARIANTS {
        let v = spec.variant;
        let (a, b) = drive(v, &|set| {
            for k in 1..=6 {
                set(&format!("elasticity.k{k}"), 1e3 * k as f64);
                set(&format!("damping.c{k}"), 2.0);
            }
            set("friction.muStatic", 0.3);
            set("friction.Fint", 5.0);
            set("b.r[1]", 0.01);
            set("b.r[2]", -0.004);
            set("b.v[1]", 0.2);
        });
        let unknowns: Vec<u32> = table(v)
            .vars
            .iter()
            .filter(|x| {
                x.causality == Causality::Output && x.variability == Variability::Continuous
            })
            .filter(|x| matches!(x.start, Start::Real(_)))
            .map(|x| x.vr)
            .collect();
        let knowns: Vec<u32> = table(v)
            .vars
            .iter()
            .filter(|x| x.causality == Causality::Input)
            .map(|x| x.vr)
            .collect();
        let (nu, nk) = (unknowns.len(), knowns.len());
        // J column by column through both versions: bit for bit equal
        let mut jac = vec![vec![0.0; nk]; nu];
        for (j, &k) in knowns.iter().enumerate() {
            let (mut d2, mut d3) = (vec![0.0; nu], vec![0.0; nu]);
            let s2 = f2::fmi2GetDirectionalDerivative(
                a.0.c,
                unknowns.as_ptr(),
                nu,
                &k,
                1,
                &1.0,
                d2.as_mut_ptr(),
            );
            assert_eq!(s2, fmi2Status::OK);
            let s3 = fmi3GetDirectionalDerivative(
                b.c,
                unknowns.as_ptr(),
                nu,
                &k,
                1,
                &1.0,
                1,
                d3.as_mut_ptr(),
                nu,
            );
            assert_eq!(s3, OK, "{:?}", b.log());
            for i in 0..nu {
                assert_eq!(
                    d2[i].to_bits(),
                    d3[i].to_bits(),
                    "{v:?} ∂{}/∂{k}",
                    unknowns[i]
                );
                jac[i][j] = d3[i];
            }
        }
        // a seed direction with all entries non-zero
        let seed: Vec<f64> = (0..nu)
            .map(|i| 1.0 + 0.37 * i as f64 * if i % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let mut adj = vec![f64::NAN; nk];
        let s = fmi3GetAdjointDerivative(
            b.c,
            unknowns.as_ptr(),
            nu,
            knowns.as_ptr(),
            nk,
            seed.as_ptr(),
            nu,
            adj.as_mut_ptr(),
            nk,
        );
        assert_eq!(s, OK, "{:?}", b.log());
        let mut checked = 0;
        for j in 0..nk {
            let want: f64 = (0..nu).map(|i| jac[i][j] * seed[i]).sum();
            let scale: f64 = (0..nu).map(|i| (jac[i][j] * seed[i]).abs()).sum();
            assert!(
                (adj[j] - want).abs() <= 1e-12 * scale,
                "{v:?} known {}: adjoint {} vs Jᵀv {want}",
                knowns[j],
                adj[j]
            );
            checked += usize::from(want != 0.0);
        }
        assert!(checked > 0, "{v:?}: a non-trivial Jacobian");
    }
}

// ------------------------------------------------------------------ FMU state

#[test]
fn fmu_state_round_trips_bit_for_bit_and_across_versions() {
    let v = Variant::Planar;
    let (a, b) = drive(v, &|set| {
        set("friction.muStatic", 0.3);
        set("friction.Fint", 10.0);
        set("elasticity.k2", 1e3);
        set("stop.upper2", 0.003);
    });
    let reals = outputs(v, false);
    for k in 0..50 {
        b.set_real_if("b.v[2]", 0.3);
        b.set_real_if("b.r[2]", 3e-4 * k as f64);
        assert_eq!(b.step(k as f64 * H, H).0, OK);
    }
    let t = 50.0 * H;
    let mut s = null_mut::<c_void>();
    assert_eq!(fmi3GetFMUState(b.c, &mut s), OK);
    let y0 = b.get_reals(&reals);
    let mut size = 0usize;
    assert_eq!(fmi3SerializedFMUStateSize(b.c, s, &mut size), OK);
    let mut bytes = vec![0u8; size];
    assert_eq!(fmi3SerializeFMUState(b.c, s, bytes.as_mut_ptr(), size), OK);
    expect_error!(
        b,
        "fmi3SerializeFMUState",
        fmi3SerializeFMUState(b.c, s, bytes.as_mut_ptr(), size - 1)
    );
    // go on, then restore
    let mut path = Vec::new();
    for k in 0..20 {
        b.set_real_if("b.r[2]", 0.015 - 3e-4 * k as f64);
        assert_eq!(b.step(t + k as f64 * H, H).0, OK);
        path.push(b.get_reals(&reals));
    }
    assert_eq!(fmi3SetFMUState(b.c, s), OK);
    assert_eq!(b.get_reals(&reals), y0, "outputs at the restored state");
    let mut d = null_mut::<c_void>();
    assert_eq!(
        fmi3DeserializeFMUState(b.c, bytes.as_ptr(), size, &mut d),
        OK
    );
    assert_eq!(fmi3SetFMUState(b.c, d), OK);
    let y1 = b.get_reals(&reals);
    assert_eq!(
        y0.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        y1.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
    // the same future from the de-serialized state
    for (k, want) in path.iter().enumerate() {
        b.set_real_if("b.r[2]", 0.015 - 3e-4 * k as f64);
        assert_eq!(b.step(t + k as f64 * H, H).0, OK);
        let got = b.get_reals(&reals);
        assert!(got
            .iter()
            .zip(want)
            .all(|(p, q)| p.to_bits() == q.to_bits()));
    }
    // one state format: the FMI 2.0 twin restores the FMI 3.0 bytes
    let mut s2 = null_mut::<c_void>();
    let st = f2::fmi2DeSerializeFMUstate(a.0.c, bytes.as_ptr().cast(), size, &mut s2);
    assert_eq!(st, fmi2Status::OK, "{:?}", a.0.log());
    assert_eq!(f2::fmi2SetFMUstate(a.0.c, s2), fmi2Status::OK);
    assert_eq!(a.0.get_reals(&reals), y0);
    assert_eq!(f2::fmi2FreeFMUstate(a.0.c, &mut s2), fmi2Status::OK);
    // garbage is refused
    let mut g = null_mut::<c_void>();
    expect_error!(
        b,
        "fmi3DeserializeFMUState",
        fmi3DeserializeFMUState(b.c, bytes.as_ptr(), size / 2, &mut g)
    );
    assert!(g.is_null());
    assert_eq!(fmi3FreeFMUState(b.c, &mut s), OK);
    assert_eq!(fmi3FreeFMUState(b.c, &mut d), OK);
    assert_eq!(fmi3FreeFMUState(b.c, null_mut()), OK);
}

#[test]
fn booleans_read_as_bytes() {
    let v = VARIANTS.iter().map(|s| s.variant).find(|&v| {
        table(v)
            .vars
            .iter()
            .any(|x| matches!(x.start, Start::Boolean(_)))
    });
    let Some(v) = v else {
        return; // no variant has a Boolean parameter
    };
    let f = Fmu3::new(v);
    let vr = table(v)
        .vars
        .iter()
        .find(|x| matches!(x.start, Start::Boolean(_)))
        .unwrap()
        .vr;
    // any non-zero byte is true, and the FMU writes 1
    assert_eq!(fmi3SetBoolean(f.c, &vr, 1, &7u8, 1), OK, "{:?}", f.log());
    f.enter_init();
    let mut b = 9u8;
    assert_eq!(fmi3GetBoolean(f.c, &vr, 1, &mut b, 1), OK);
    assert_eq!(b, 1);
    assert_eq!(fmi3SetBoolean(f.c, &vr, 1, &0u8, 1), OK);
    assert_eq!(fmi3GetBoolean(f.c, &vr, 1, &mut b, 1), OK);
    assert_eq!(b, 0);
}

// ------------------------------------------------------------------ early return at events

/// Whether a located event time lies where the FMU puts it: at most 1e-10 of the step `h` past
/// the exact time (the far end of the bracket), with an ulp of slack for the time sum.
fn just_past(located: f64, exact: f64, h: f64) -> bool {
    (exact - 1e-17..=exact + 1e-10 * h + 1e-17).contains(&located)
}

/// ProjectionCartesian with an upper stop on u1 at 0.01 m; b set at x = x0 moving at `v`.
fn stop_scene(f: &Fmu3, x0: f64, v: f64) {
    f.enter_init();
    f.set_real_if("stop.upper1", 0.01);
    f.set_real_if("stop.stiffness", 1e4);
    f.set_real_if("b.v[1]", v);
    f.exit_init();
    f.set_real_if("b.r[1]", x0);
}

#[test]
fn do_step_returns_early_at_a_stop_contact_and_continues_from_there() {
    let v = Variant::ProjectionCartesian;
    let f = Fmu3::with_early_return(v, true);
    stop_scene(&f, 0.0, 1.0);
    let ev = [f.vr("event.time")];
    let (count, cslst) = (f.vr("event.count"), f.vr("CSLST1"));
    // 0 → 4 ms → 8 ms: no event; 8 ms + 4 ms: contact at x = 0.01, i.e. t = 10 ms
    let mut t = 0.0;
    for _ in 0..2 {
        let (s, [e, term, early], last) = f.step(t, 0.004);
        assert_eq!((s, e, term, early), (OK, 0, 0, 0), "{:?}", f.log());
        assert_eq!(last, t + 0.004);
        assert_eq!(
            f.get_reals(&ev)[0],
            last,
            "event.time = t + h without events"
        );
        assert_eq!(f.get_ints(&[count, cslst]), vec![0, 0]);
        t = last;
    }
    let (s, [e, term, early], last) = f.step(t, 0.004);
    assert_eq!((s, e, term, early), (OK, 0, 0, 1), "{:?}", f.log());
    // the located time is the bracket's far end, within 1e-10 of the step past the contact
    assert!(just_past(last, 0.01, 0.004), "{last}");
    assert_eq!(f.get_reals(&ev)[0], last, "event.time = lastSuccessfulTime");
    assert_eq!(
        f.get_ints(&[count, cslst]),
        vec![1, 1],
        "engaged at the event"
    );
    // the FMU's time is the event's: a step from the old end is refused, from the event runs
    let before = f.log().len();
    let (s, _, _) = f.step(t + 0.004, 0.004);
    assert_error_logged(&f, before, s, "fmi3DoStep");
    let g = Fmu3::with_early_return(v, true);
    stop_scene(&g, 0.0, 1.0);
    for (i, tk) in [0.0, 0.004, 0.008].iter().enumerate() {
        let (s, [.., early], _) = g.step(*tk, 0.004);
        assert_eq!((s, early), (OK, u8::from(i == 2)));
    }
    let (s, [.., early], next) = g.step(last, 0.004);
    assert_eq!((s, early), (OK, 0), "{:?}", g.log());
    assert_eq!(next, last + 0.004);
}

#[test]
fn without_early_return_the_step_runs_through_and_reports_the_event() {
    let v = Variant::ProjectionCartesian;
    let f = Fmu3::new(v);
    stop_scene(&f, 0.008, 1.0);
    let (s, [.., early], last) = f.step(0.0, 0.004);
    assert_eq!((s, early), (OK, 0));
    assert_eq!(last, 0.004);
    let t_event = f.get_reals(&[f.vr("event.time")])[0];
    assert!(just_past(t_event, 0.002, 0.004), "{t_event}");
    assert_eq!(f.get_ints(&[f.vr("event.count")]), vec![1]);
}

#[test]
fn an_early_return_repeats_bit_for_bit_from_a_restored_state() {
    let v = Variant::Planar;
    let f = Fmu3::with_early_return(v, true);
    f.enter_init();
    f.set_real_if("friction.muStatic", 0.5);
    f.set_real_if("friction.Fint", 20.0);
    f.set_real_if("friction.stickStiffness", 1e4);
    f.set_real_if("b.v[2]", 0.1);
    f.exit_init();
    let reals = outputs(v, false);
    let mut s0 = null_mut::<c_void>();
    assert_eq!(fmi3GetFMUState(f.c, &mut s0), OK);
    // breakaway where the stick spring reaches μN: t0 = 0.5·20/(1e4·0.1) = 10 ms
    let (s, [.., early], last) = f.step(0.0, 0.016);
    assert_eq!((s, early), (OK, 1), "{:?}", f.log());
    assert!(just_past(last, 0.01, 0.016), "{last}");
    let y1 = f.get_reals(&reals);
    assert_eq!(fmi3SetFMUState(f.c, s0), OK);
    let (s, [.., early], again) = f.step(0.0, 0.016);
    assert_eq!((s, early, again.to_bits()), (OK, 1, last.to_bits()));
    let y2 = f.get_reals(&reals);
    assert!(y1.iter().zip(&y2).all(|(p, q)| p.to_bits() == q.to_bits()));
    assert_eq!(fmi3FreeFMUState(f.c, &mut s0), OK);
}
