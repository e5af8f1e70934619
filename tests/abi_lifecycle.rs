//! The exported FMI 2.0 Co-Simulation functions, called as an importer calls them: lifecycle,
//! the state table, NULL arguments, bad values, instantiation refusals, independent instances
//! and threads, FMU state round trips.

mod common;

use common::*;
use connector_fmu::fmi2::exports::*;
use connector_fmu::fmi2::types::*;
use connector_fmu::variables::{table, Variant, VARIANTS};
use std::ffi::{c_int, CStr, CString};
use std::ptr::{null, null_mut};

const OK: fmi2Status = fmi2Status::OK;

/// Evaluates one call and asserts fmi2Error with exactly one logged message naming `$name`.
macro_rules! expect_error {
    ($f:expr, $name:expr, $call:expr) => {{
        let n = $f.log_len();
        let s = $call;
        assert_error_logged(&$f, n, s, $name);
    }};
}
const H: f64 = 1e-3;

// ------------------------------------------------------------------ 1. lifecycle

#[test]
fn version_and_types_platform() {
    // SAFETY: both return static NUL-terminated strings.
    let (v, p) = unsafe {
        (
            CStr::from_ptr(fmi2GetVersion()),
            CStr::from_ptr(fmi2GetTypesPlatform()),
        )
    };
    assert_eq!(v.to_str().unwrap(), "2.0");
    assert_eq!(p.to_str().unwrap(), "default");
}

/// A small rotation as (w, x, y, z) about a unit axis.
fn quat(angle: f64, axis: [f64; 3]) -> [f64; 4] {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let s = (angle / 2.0).sin() / n;
    [(angle / 2.0).cos(), s * axis[0], s * axis[1], s * axis[2]]
}

fn set_quat(f: &Fmu, node: &str, q: [f64; 4]) {
    for (c, x) in ["w", "x", "y", "z"].iter().zip(q) {
        f.set_real_if(&format!("{node}.q.{c}"), x);
    }
}

#[test]
fn full_cs_lifecycle_every_variant() {
    for spec in VARIANTS {
        let f = Fmu::new(spec.variant);
        f.enter_init();
        for k in 1..=6 {
            f.set_real_if(&format!("elasticity.k{k}"), 100.0);
            f.set_real_if(&format!("damping.c{k}"), 1.0);
        }
        for (i, x) in [0.02, 0.01, 0.1].into_iter().enumerate() {
            f.set_real_if(&format!("b.r[{}]", i + 1), x);
        }
        set_quat(&f, "b", quat(0.05, [1.0, 1.0, 0.0]));
        f.exit_init();

        f.set_real_if("b.v[1]", 0.1);
        f.set_real_if("b.w[3]", 0.5);
        let (real_out, int_out) = (f.outputs(false), f.outputs(true));
        let mut t = 0.0;
        for _ in 0..20 {
            assert_eq!(f.step(t, H), OK, "{:?}: {:?}", spec.variant, f.log());
            t += H;
            let y = f.get_reals(&real_out);
            assert!(y.iter().all(|x| x.is_finite()), "{:?}: {y:?}", spec.variant);
            f.get_integers(&int_out);
        }
        let mut last = f64::NAN;
        assert_eq!(fmi2GetRealStatus(f.c, 2, &mut last), OK);
        assert!((last - 0.02).abs() < 1e-12, "{last}");
        let mut terminated = fmi2True;
        assert_eq!(fmi2GetBooleanStatus(f.c, 3, &mut terminated), OK);
        assert_eq!(terminated, fmi2False);
        assert_eq!(fmi2Terminate(f.c), OK, "{:?}", f.log());
        // outputs stay readable after terminate
        assert!(f.get_reals(&real_out).iter().all(|x| x.is_finite()));
        assert!(
            f.log().is_empty(),
            "a clean run logs nothing: {:?}",
            f.log()
        );
    }
}

#[test]
fn stretched_bushing_spring_pulls_node_b_back() {
    let f = Fmu::new(Variant::Bushing);
    f.enter_init();
    assert_eq!(f.set_real("elasticity.k1", 100.0), OK);
    f.exit_init();
    // identity orientations: the triad's 1 axis is world x
    assert_eq!(f.set_real("b.r[1]", 0.01), OK);
    assert_eq!(f.step(0.0, H), OK, "{:?}", f.log());
    assert!(
        (f.get_real("CEF1") - 1.0).abs() < 1e-9,
        "CEF1 = {}",
        f.get_real("CEF1")
    );
    assert!((f.get_real("CTF1") - 1.0).abs() < 1e-9);
    let bf = [
        f.get_real("b.f[1]"),
        f.get_real("b.f[2]"),
        f.get_real("b.f[3]"),
    ];
    let af = [
        f.get_real("a.f[1]"),
        f.get_real("a.f[2]"),
        f.get_real("a.f[3]"),
    ];
    // b sits at +x of a: the force on b points back toward a, the force on a toward b
    assert!(
        (bf[0] + 1.0).abs() < 1e-9 && bf[1].abs() < 1e-12 && bf[2].abs() < 1e-12,
        "{bf:?}"
    );
    assert!((af[0] - 1.0).abs() < 1e-9, "{af:?}");
}

#[test]
fn log_all_traces_every_call_and_percent_is_doubled() {
    let f = Fmu::with_logging(Variant::Bushing, true);
    let all = CString::new("logAll").unwrap();
    assert_eq!(fmi2SetDebugLogging(f.c, fmi2True, 1, &all.as_ptr()), OK);
    let n = f.log_len();
    f.init();
    let names: Vec<String> = f.log()[n..]
        .iter()
        .filter(|l| l.category == "logAll")
        .map(|l| l.message.clone())
        .collect();
    assert_eq!(
        names,
        [
            "fmi2SetupExperiment",
            "fmi2EnterInitializationMode",
            "fmi2ExitInitializationMode"
        ]
    );
    assert!(f.log()[n..]
        .iter()
        .all(|l| l.status == OK as c_int && l.instance == "test instance"));

    // logAll off: nothing is traced; an unknown category is refused, its '%' reaches the
    // importer doubled (the message is a printf format there)
    assert_eq!(fmi2SetDebugLogging(f.c, fmi2False, 0, null()), OK);
    let n = f.log_len();
    let bad = CString::new("100%").unwrap();
    let s = fmi2SetDebugLogging(f.c, fmi2True, 1, &bad.as_ptr());
    assert_error_logged(&f, n, s, "fmi2SetDebugLogging");
    assert!(f.log()[n].message.contains("\"100%%\""), "{:?}", f.log()[n]);
}

// ------------------------------------------------------------------ 2. the state table

#[test]
fn illegal_calls_in_instantiated_state() {
    let f = Fmu::new(Variant::Bushing);
    let (vr_out, vr_int, vr_bool) = (f.vr("a.f[1]"), f.vr("CSLST1"), f.vr("reference.given1"));
    let (mut x, mut i, mut b, mut s, mut st) = (0.0, 0, 0, null(), OK);
    let order = 1;
    expect_error!(f, "fmi2DoStep", f.step(0.0, H));
    expect_error!(
        f,
        "fmi2ExitInitializationMode",
        fmi2ExitInitializationMode(f.c)
    );
    expect_error!(f, "fmi2Terminate", fmi2Terminate(f.c));
    expect_error!(f, "fmi2GetReal", fmi2GetReal(f.c, &vr_out, 1, &mut x));
    expect_error!(f, "fmi2GetInteger", fmi2GetInteger(f.c, &vr_int, 1, &mut i));
    expect_error!(
        f,
        "fmi2GetBoolean",
        fmi2GetBoolean(f.c, &vr_bool, 1, &mut b)
    );
    expect_error!(f, "fmi2GetString", fmi2GetString(f.c, null(), 0, &mut s));
    expect_error!(
        f,
        "fmi2GetRealOutputDerivatives",
        fmi2GetRealOutputDerivatives(f.c, &vr_out, 1, &order, &mut x)
    );
    expect_error!(
        f,
        "fmi2GetDirectionalDerivative",
        fmi2GetDirectionalDerivative(f.c, null(), 0, null(), 0, null(), null_mut())
    );
    expect_error!(f, "fmi2GetStatus", fmi2GetStatus(f.c, 0, &mut st));
    expect_error!(f, "fmi2GetRealStatus", fmi2GetRealStatus(f.c, 2, &mut x));
    expect_error!(
        f,
        "fmi2GetIntegerStatus",
        fmi2GetIntegerStatus(f.c, 0, &mut i)
    );
    expect_error!(
        f,
        "fmi2GetBooleanStatus",
        fmi2GetBooleanStatus(f.c, 3, &mut b)
    );
    expect_error!(
        f,
        "fmi2GetStringStatus",
        fmi2GetStringStatus(f.c, 0, &mut s)
    );
    expect_error!(f, "fmi2CancelStep", fmi2CancelStep(f.c));
    // the instance is still usable
    f.init();
}

#[test]
fn illegal_calls_in_initialization_mode() {
    let f = Fmu::new(Variant::Bushing);
    f.enter_init();
    let mut x = 0.0;
    expect_error!(f, "fmi2SetupExperiment", f.setup());
    expect_error!(
        f,
        "fmi2EnterInitializationMode",
        fmi2EnterInitializationMode(f.c)
    );
    expect_error!(f, "fmi2DoStep", f.step(0.0, H));
    expect_error!(f, "fmi2Terminate", fmi2Terminate(f.c));
    expect_error!(f, "fmi2GetRealStatus", fmi2GetRealStatus(f.c, 2, &mut x));
    expect_error!(f, "fmi2CancelStep", fmi2CancelStep(f.c));
    f.exit_init();
}

#[test]
fn illegal_calls_in_step_complete() {
    let f = Fmu::new(Variant::Planar);
    f.init();
    let coupling = f.vr("friction.coupling");
    let given = f.vr("reference.given4");
    let out = f.vr("CP2");
    let mut x = 0.0;
    let order = 1;
    expect_error!(f, "fmi2SetupExperiment", f.setup());
    expect_error!(
        f,
        "fmi2EnterInitializationMode",
        fmi2EnterInitializationMode(f.c)
    );
    expect_error!(
        f,
        "fmi2ExitInitializationMode",
        fmi2ExitInitializationMode(f.c)
    );
    expect_error!(f, "fmi2SetReal", f.set_real("reference.value4", 0.1));
    expect_error!(f, "fmi2SetInteger", fmi2SetInteger(f.c, &coupling, 1, &1));
    expect_error!(
        f,
        "fmi2SetBoolean",
        fmi2SetBoolean(f.c, &given, 1, &fmi2True)
    );
    expect_error!(f, "fmi2SetReal", fmi2SetReal(f.c, &out, 1, &0.5));
    expect_error!(f, "fmi2CancelStep", fmi2CancelStep(f.c));
    expect_error!(
        f,
        "fmi2GetRealOutputDerivatives",
        fmi2GetRealOutputDerivatives(f.c, &out, 1, &order, &mut x)
    );
    let msgs: Vec<String> = f.log().into_iter().map(|l| l.message).collect();
    assert!(
        msgs[3].contains("reference.value4") && msgs[6].contains("CP2"),
        "{msgs:?}"
    );
    assert!(msgs[8].contains("MaxOutputDerivativeOrder = 0"), "{msgs:?}");
    // an empty request for output derivatives asks for nothing
    assert_eq!(
        fmi2GetRealOutputDerivatives(f.c, null(), 0, null(), null_mut()),
        OK
    );
    // status kinds that are not provided: fmi2Discard with a message naming the kind
    let mut st = OK;
    let n = f.log_len();
    assert_eq!(fmi2GetStatus(f.c, 0, &mut st), fmi2Status::Discard);
    assert!(
        f.log()[n].message.contains("fmi2DoStepStatus"),
        "{:?}",
        f.log()[n]
    );
    assert_eq!(fmi2GetRealStatus(f.c, 0, &mut x), fmi2Status::Discard);
    let mut i = 0;
    assert_eq!(fmi2GetIntegerStatus(f.c, 1, &mut i), fmi2Status::Discard);
    assert_eq!(fmi2GetStatus(f.c, 42, &mut st), fmi2Status::Error);
    assert!(f.log().last().unwrap().message.contains("42"));
    // still stepping
    assert_eq!(f.step(0.0, H), OK, "{:?}", f.log());
}

#[test]
fn illegal_calls_after_terminate_and_reset_recovers() {
    let f = Fmu::new(Variant::Bushing);
    f.init();
    assert_eq!(f.step(0.0, H), OK);
    assert_eq!(fmi2Terminate(f.c), OK);
    let order = 1;
    let vr = f.vr("b.r[1]");
    expect_error!(f, "fmi2Terminate", fmi2Terminate(f.c));
    expect_error!(f, "fmi2DoStep", f.step(H, H));
    expect_error!(f, "fmi2SetReal", f.set_real("b.r[1]", 0.1));
    expect_error!(
        f,
        "fmi2SetRealInputDerivatives",
        fmi2SetRealInputDerivatives(f.c, &vr, 1, &order, &1.0)
    );
    expect_error!(f, "fmi2SetupExperiment", f.setup());
    expect_error!(
        f,
        "fmi2EnterInitializationMode",
        fmi2EnterInitializationMode(f.c)
    );
    expect_error!(
        f,
        "fmi2ExitInitializationMode",
        fmi2ExitInitializationMode(f.c)
    );
    // getters stay allowed, reset goes back to Instantiated with start values
    assert!(f.get_real("CTF1").is_finite());
    assert_eq!(fmi2Reset(f.c), OK);
    assert_eq!(f.get_real_in_instantiated_fails(), fmi2Status::Error);
    f.init();
    assert_eq!(f.step(0.0, H), OK);
}

trait InstantiatedProbe {
    fn get_real_in_instantiated_fails(&self) -> fmi2Status;
}

impl InstantiatedProbe for Fmu {
    fn get_real_in_instantiated_fails(&self) -> fmi2Status {
        let mut x = 0.0;
        fmi2GetReal(self.c, &self.vr("CTF1"), 1, &mut x)
    }
}

#[test]
fn failed_step_enters_error_state_and_set_fmu_state_recovers() {
    let f = Fmu::new(Variant::ProjectionFlexionTorsion);
    f.init();
    let mut saved: fmi2FMUstate = null_mut();
    assert_eq!(fmi2GetFMUstate(f.c, &mut saved), OK);
    // fold the shafts back: flexion α = π is singular
    set_quat(&f, "b", [0.0, 1.0, 0.0, 0.0]);
    let n = f.log_len();
    assert_error_logged(&f, n, f.step(0.0, H), "fmi2DoStep");
    // in the error state: no step, no set, no terminate; parameters stay readable
    expect_error!(f, "fmi2DoStep", f.step(0.0, H));
    expect_error!(f, "fmi2SetReal", f.set_real("b.q.w", 1.0));
    expect_error!(f, "fmi2Terminate", fmi2Terminate(f.c));
    assert_eq!(f.get_real("elasticity.k4"), 0.0);
    assert_eq!(fmi2SetFMUstate(f.c, saved), OK, "{:?}", f.log());
    assert_eq!(f.step(0.0, H), OK, "{:?}", f.log());
    assert_eq!(fmi2FreeFMUstate(f.c, &mut saved), OK);
}

// ------------------------------------------------------------------ 3. NULL arguments

#[test]
fn null_zero_arrays_are_legal() {
    let f = Fmu::new(Variant::Bushing);
    f.init();
    assert_eq!(fmi2GetReal(f.c, null(), 0, null_mut()), OK);
    assert_eq!(fmi2GetInteger(f.c, null(), 0, null_mut()), OK);
    assert_eq!(fmi2GetBoolean(f.c, null(), 0, null_mut()), OK);
    assert_eq!(fmi2GetString(f.c, null(), 0, null_mut()), OK);
    assert_eq!(fmi2SetReal(f.c, null(), 0, null()), OK);
    assert_eq!(fmi2SetInteger(f.c, null(), 0, null()), OK);
    assert_eq!(fmi2SetBoolean(f.c, null(), 0, null()), OK);
    assert_eq!(fmi2SetString(f.c, null(), 0, null()), OK);
    assert_eq!(
        fmi2SetRealInputDerivatives(f.c, null(), 0, null(), null()),
        OK
    );
    assert_eq!(
        fmi2GetDirectionalDerivative(f.c, null(), 0, null(), 0, null(), null_mut()),
        OK
    );
    assert_eq!(fmi2SetDebugLogging(f.c, fmi2False, 0, null()), OK);
    assert!(f.log().is_empty(), "{:?}", f.log());
}

#[test]
fn null_arrays_with_a_count_are_refused_and_named() {
    let f = Fmu::new(Variant::Bushing);
    f.init();
    let vr = f.vr("elasticity.k1");
    let vri = f.vr("cosim.extrapolation");
    let vrb = f.vr("reference.given1");
    let (mut x, mut i, mut b) = (7.0, 7, 7);
    let order = 1;
    let cases: Vec<(&str, &str, fmi2Status)> = vec![
        ("fmi2GetReal", "vr[]", fmi2GetReal(f.c, null(), 1, &mut x)),
        (
            "fmi2GetReal",
            "value[]",
            fmi2GetReal(f.c, &vr, 1, null_mut()),
        ),
        (
            "fmi2GetInteger",
            "vr[]",
            fmi2GetInteger(f.c, null(), 1, &mut i),
        ),
        (
            "fmi2GetInteger",
            "value[]",
            fmi2GetInteger(f.c, &vri, 1, null_mut()),
        ),
        (
            "fmi2GetBoolean",
            "vr[]",
            fmi2GetBoolean(f.c, null(), 1, &mut b),
        ),
        (
            "fmi2GetBoolean",
            "value[]",
            fmi2GetBoolean(f.c, &vrb, 1, null_mut()),
        ),
        (
            "fmi2GetString",
            "value[]",
            fmi2GetString(f.c, &vr, 1, null_mut()),
        ),
        ("fmi2SetReal", "vr[]", fmi2SetReal(f.c, null(), 1, &1.0)),
        ("fmi2SetReal", "value[]", fmi2SetReal(f.c, &vr, 1, null())),
        (
            "fmi2SetInteger",
            "value[]",
            fmi2SetInteger(f.c, &vri, 1, null()),
        ),
        (
            "fmi2SetBoolean",
            "value[]",
            fmi2SetBoolean(f.c, &vrb, 1, null()),
        ),
        (
            "fmi2SetString",
            "value[]",
            fmi2SetString(f.c, &vr, 1, null()),
        ),
        (
            "fmi2SetRealInputDerivatives",
            "order[]",
            fmi2SetRealInputDerivatives(f.c, &vr, 1, null(), &1.0),
        ),
        (
            "fmi2SetRealInputDerivatives",
            "value[]",
            fmi2SetRealInputDerivatives(f.c, &vr, 1, &order, null()),
        ),
        (
            "fmi2GetDirectionalDerivative",
            "dvUnknown[]",
            fmi2GetDirectionalDerivative(f.c, &vr, 1, &vr, 1, &1.0, null_mut()),
        ),
        (
            "fmi2SetDebugLogging",
            "categories",
            fmi2SetDebugLogging(f.c, fmi2True, 2, null()),
        ),
        (
            "fmi2GetRealStatus",
            "value",
            fmi2GetRealStatus(f.c, 2, null_mut()),
        ),
        (
            "fmi2GetFMUstate",
            "FMUstate",
            fmi2GetFMUstate(f.c, null_mut()),
        ),
        (
            "fmi2SetFMUstate",
            "FMUstate",
            fmi2SetFMUstate(f.c, null_mut()),
        ),
        (
            "fmi2SerializedFMUstateSize",
            "FMUstate",
            fmi2SerializedFMUstateSize(f.c, null_mut(), &mut 0),
        ),
        (
            "fmi2DeSerializeFMUstate",
            "serializedState",
            fmi2DeSerializeFMUstate(f.c, null(), 8, &mut null_mut()),
        ),
    ];
    let log = f.log();
    assert_eq!(
        log.len(),
        cases.len(),
        "one message per refused call: {log:?}"
    );
    for ((fname, arg, s), line) in cases.iter().zip(&log) {
        assert_eq!(*s, fmi2Status::Error, "{fname} {arg}");
        assert!(
            line.message.contains(fname) && line.message.contains(arg),
            "{fname} {arg}: {line:?}"
        );
    }
    // nothing was written through the good pointers
    assert_eq!((x, i, b), (7.0, 7, 7));
}

#[test]
fn null_instance_is_an_error_everywhere() {
    let c: fmi2Component = null_mut();
    let e = fmi2Status::Error;
    let (mut x, mut i, mut st, mut s, mut p, mut n) = (0.0, 0, OK, null(), null_mut(), 0usize);
    fmi2FreeInstance(c);
    assert_eq!(fmi2SetDebugLogging(c, fmi2True, 0, null()), e);
    assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), e);
    assert_eq!(fmi2EnterInitializationMode(c), e);
    assert_eq!(fmi2ExitInitializationMode(c), e);
    assert_eq!(fmi2Terminate(c), e);
    assert_eq!(fmi2Reset(c), e);
    assert_eq!(fmi2GetReal(c, null(), 0, null_mut()), e);
    assert_eq!(fmi2GetInteger(c, null(), 0, null_mut()), e);
    assert_eq!(fmi2GetBoolean(c, null(), 0, null_mut()), e);
    assert_eq!(fmi2GetString(c, null(), 0, null_mut()), e);
    assert_eq!(fmi2SetReal(c, null(), 0, null()), e);
    assert_eq!(fmi2SetInteger(c, null(), 0, null()), e);
    assert_eq!(fmi2SetBoolean(c, null(), 0, null()), e);
    assert_eq!(fmi2SetString(c, null(), 0, null()), e);
    assert_eq!(fmi2GetFMUstate(c, &mut p), e);
    assert_eq!(fmi2SetFMUstate(c, p), e);
    assert_eq!(fmi2FreeFMUstate(c, &mut p), e);
    assert_eq!(fmi2SerializedFMUstateSize(c, p, &mut n), e);
    assert_eq!(fmi2SerializeFMUstate(c, p, null_mut(), 0), e);
    assert_eq!(fmi2DeSerializeFMUstate(c, null(), 0, &mut p), e);
    assert_eq!(
        fmi2GetDirectionalDerivative(c, null(), 0, null(), 0, null(), null_mut()),
        e
    );
    assert_eq!(fmi2SetRealInputDerivatives(c, null(), 0, null(), null()), e);
    assert_eq!(
        fmi2GetRealOutputDerivatives(c, null(), 0, null(), null_mut()),
        e
    );
    assert_eq!(fmi2DoStep(c, 0.0, H, 0), e);
    assert_eq!(fmi2CancelStep(c), e);
    assert_eq!(fmi2GetStatus(c, 0, &mut st), e);
    assert_eq!(fmi2GetRealStatus(c, 2, &mut x), e);
    assert_eq!(fmi2GetIntegerStatus(c, 0, &mut i), e);
    assert_eq!(fmi2GetBooleanStatus(c, 3, &mut i), e);
    assert_eq!(fmi2GetStringStatus(c, 0, &mut s), e);
}

// ------------------------------------------------------------------ 4. bad values

#[test]
fn unknown_vr_wrong_type_nan_and_negative_stiffness_are_refused() {
    let f = Fmu::new(Variant::Bushing);
    f.enter_init();
    assert_eq!(f.set_real("elasticity.k1", 100.0), OK);
    f.exit_init();
    let k1 = f.vr("elasticity.k1");
    let (mut x, mut i) = (-1.0, -1);

    let n = f.log_len();
    assert_error_logged(&f, n, fmi2GetReal(f.c, &99999, 1, &mut x), "fmi2GetReal");
    assert!(f.log()[n].message.contains("99999"), "{:?}", f.log()[n]);
    assert_eq!(x, -1.0, "nothing written on error");

    // a good VR before the bad one: still nothing written
    let mut two = [-1.0, -1.0];
    let n = f.log_len();
    assert_error_logged(
        &f,
        n,
        fmi2GetReal(f.c, [k1, 99999].as_ptr(), 2, two.as_mut_ptr()),
        "fmi2GetReal",
    );
    assert_eq!(two, [-1.0, -1.0]);

    let n = f.log_len();
    assert_error_logged(&f, n, fmi2SetReal(f.c, &99999, 1, &1.0), "fmi2SetReal");
    assert!(f.log()[n].message.contains("99999"));

    let n = f.log_len();
    assert_error_logged(&f, n, fmi2GetInteger(f.c, &k1, 1, &mut i), "fmi2GetInteger");
    assert!(
        f.log()[n].message.contains("elasticity.k1"),
        "{:?}",
        f.log()[n]
    );
    assert_eq!(i, -1);

    for bad in [f64::NAN, f64::INFINITY, -5.0] {
        let n = f.log_len();
        assert_error_logged(&f, n, f.set_real("elasticity.k1", bad), "fmi2SetReal");
        assert!(
            f.log()[n].message.contains("elasticity.k1"),
            "{:?}",
            f.log()[n]
        );
        assert_eq!(
            f.get_real("elasticity.k1"),
            100.0,
            "value unchanged after {bad}"
        );
    }
    // a batch with one bad value sets nothing
    let k2 = f.vr("elasticity.k2");
    let n = f.log_len();
    assert_error_logged(
        &f,
        n,
        fmi2SetReal(f.c, [k1, k2].as_ptr(), 2, [5.0, f64::NAN].as_ptr()),
        "fmi2SetReal",
    );
    assert_eq!(f.get_real("elasticity.k1"), 100.0);
    // NaN input: refused, unchanged
    let n = f.log_len();
    assert_error_logged(&f, n, f.set_real("b.r[2]", f64::NAN), "fmi2SetReal");
    assert_eq!(f.get_real("b.r[2]"), 0.0);
}

// ------------------------------------------------------------------ 5. fmi2Instantiate refusals

#[test]
fn instantiate_refuses_bad_arguments_after_logging() {
    let g = guid(Variant::Planar);
    let refused = |name: Option<&str>, ty: c_int, guid: Option<&str>, expect: &str| {
        let env = new_env();
        let cb = callbacks(env);
        let c = instantiate_raw(name, ty, guid, Some(&cb), true);
        assert!(c.is_null(), "{expect}");
        let log = log_of(env);
        assert_eq!(log.len(), 1, "{log:?}");
        assert_eq!(log[0].status, fmi2Status::Error as c_int);
        assert!(
            log[0].message.contains("fmi2Instantiate") && log[0].message.contains(expect),
            "{:?}",
            log[0]
        );
    };
    refused(
        Some("x"),
        CO_SIMULATION,
        Some("{not-a-guid}"),
        "{not-a-guid}",
    );
    refused(Some("x"), CO_SIMULATION, None, "fmuGUID");
    refused(Some("x"), 0, Some(&g), "fmi2ModelExchange");
    refused(Some("x"), 7, Some(&g), "invalid fmuType 7");
    refused(Some(""), CO_SIMULATION, Some(&g), "instanceName");
    refused(None, CO_SIMULATION, Some(&g), "instanceName");

    // no callbacks, or no logger: NULL, nothing to log through
    assert!(instantiate_raw(Some("x"), CO_SIMULATION, Some(&g), None, false).is_null());
    let mut cb = callbacks(new_env());
    cb.logger = None;
    assert!(instantiate_raw(Some("x"), CO_SIMULATION, Some(&g), Some(&cb), false).is_null());
}

#[test]
fn every_variant_guid_selects_its_variant() {
    for spec in VARIANTS {
        let f = Fmu::new(spec.variant);
        // a variable only this variant's table has the same VR for
        let first = &table(spec.variant).vars[0];
        assert_eq!(f.vr(&first.name), first.vr);
        f.init();
    }
}

// ------------------------------------------------------------------ 6. independence, threads

/// Drives a Bushing with stiffness k along a prescribed motion; returns all Real outputs per step.
fn bushing_run(f: &Fmu, k: f64, steps: usize, interleave: Option<&dyn Fn(usize)>) -> Vec<Vec<u64>> {
    f.enter_init();
    assert_eq!(f.set_real("elasticity.k1", k), OK);
    assert_eq!(f.set_real("elasticity.k5", k / 10.0), OK);
    assert_eq!(f.set_real("damping.c2", 0.5), OK);
    f.exit_init();
    let out = f.outputs(false);
    let mut res = Vec::new();
    for n in 0..steps {
        let t = n as f64 * H;
        let w = 2.0 * std::f64::consts::PI;
        assert_eq!(f.set_real("b.r[1]", 0.01 * (w * t).sin()), OK);
        assert_eq!(f.set_real("b.v[1]", 0.01 * w * (w * t).cos()), OK);
        assert_eq!(f.set_real("b.r[2]", 0.002 * t), OK);
        assert_eq!(f.set_real("b.v[2]", 0.002), OK);
        assert_eq!(f.set_real("b.w[2]", 0.3), OK);
        assert_eq!(f.step(t, H), OK, "{:?}", f.log());
        res.push(f.get_reals(&out).into_iter().map(f64::to_bits).collect());
        if let Some(g) = interleave {
            g(n);
        }
    }
    res
}

/// The same run, one step at a time (to interleave two instances).
struct Stepper<'a> {
    f: &'a Fmu,
    out: Vec<u32>,
}

impl<'a> Stepper<'a> {
    fn new(f: &'a Fmu, k: f64) -> Self {
        f.enter_init();
        assert_eq!(f.set_real("elasticity.k1", k), OK);
        assert_eq!(f.set_real("elasticity.k5", k / 10.0), OK);
        assert_eq!(f.set_real("damping.c2", 0.5), OK);
        f.exit_init();
        Stepper {
            f,
            out: f.outputs(false),
        }
    }

    fn step(&self, n: usize) -> Vec<u64> {
        let (f, t, w) = (self.f, n as f64 * H, 2.0 * std::f64::consts::PI);
        f.set_real("b.r[1]", 0.01 * (w * t).sin());
        f.set_real("b.v[1]", 0.01 * w * (w * t).cos());
        f.set_real("b.r[2]", 0.002 * t);
        f.set_real("b.v[2]", 0.002);
        f.set_real("b.w[2]", 0.3);
        assert_eq!(f.step(t, H), OK, "{:?}", f.log());
        f.get_reals(&self.out)
            .into_iter()
            .map(f64::to_bits)
            .collect()
    }
}

const STEPS: usize = 200;

#[test]
fn two_instances_in_one_process_are_independent() {
    let alone_a = bushing_run(&Fmu::new(Variant::Bushing), 100.0, STEPS, None);
    let alone_b = bushing_run(&Fmu::new(Variant::Bushing), 250.0, STEPS, None);
    assert_ne!(
        alone_a, alone_b,
        "different parameters must give different results"
    );

    let (fa, fb) = (Fmu::new(Variant::Bushing), Fmu::new(Variant::Bushing));
    let (sa, sb) = (Stepper::new(&fa, 100.0), Stepper::new(&fb, 250.0));
    let mut ra = Vec::new();
    let mut rb = Vec::new();
    for n in 0..STEPS {
        ra.push(sa.step(n));
        rb.push(sb.step(n));
    }
    assert_eq!(ra, alone_a);
    assert_eq!(rb, alone_b);
    // a third instance of another variant alive at the same time does not disturb them
    let other = Fmu::new(Variant::Planar);
    other.init();
    assert_eq!(
        bushing_run(
            &Fmu::new(Variant::Bushing),
            100.0,
            STEPS,
            Some(&|n| {
                assert_eq!(other.step(n as f64 * H, H), OK);
            })
        ),
        alone_a
    );
}

#[test]
fn instances_on_threads_match_single_thread_results() {
    let ks = [50.0, 100.0, 250.0, 400.0];
    let single: Vec<_> = ks
        .iter()
        .map(|&k| bushing_run(&Fmu::new(Variant::Bushing), k, STEPS, None))
        .collect();
    let threads: Vec<_> = ks
        .iter()
        .map(|&k| {
            std::thread::spawn(move || bushing_run(&Fmu::new(Variant::Bushing), k, STEPS, None))
        })
        .collect();
    for (h, s) in threads.into_iter().zip(&single) {
        assert_eq!(&h.join().unwrap(), s);
    }
}

// ------------------------------------------------------------------ 7. FMU state

/// Planar with friction: normal load from the penalty constraint, sliding in the 2–3 plane.
fn planar_with_friction() -> Fmu {
    let f = Fmu::new(Variant::Planar);
    f.enter_init();
    for (name, x) in [
        ("friction.muStatic", 0.3),
        ("friction.muKinetic", 0.2),
        ("elasticity.k2", 50.0),
        ("stop.upper3", 0.001),
    ] {
        assert_eq!(f.set_real(name, x), OK, "{name}: {:?}", f.log());
    }
    f.exit_init();
    f
}

/// Steps n times from step index `from` along a prescribed sliding motion; returns every
/// output (Real and Integer) as bits, per step.
fn planar_steps(f: &Fmu, from: usize, n: usize) -> Vec<Vec<u64>> {
    let (ro, io) = (f.outputs(false), f.outputs(true));
    (from..from + n)
        .map(|k| {
            let t = k as f64 * H;
            assert_eq!(f.set_real("b.r[1]", -1e-4), OK);
            assert_eq!(f.set_real("b.r[2]", 0.05 * t), OK);
            assert_eq!(f.set_real("b.v[2]", 0.05), OK);
            assert_eq!(f.set_real("b.r[3]", 0.02 * t), OK);
            assert_eq!(f.set_real("b.v[3]", 0.02), OK);
            assert_eq!(f.step(t, H), OK, "{:?}", f.log());
            let mut v: Vec<u64> = f.get_reals(&ro).into_iter().map(f64::to_bits).collect();
            v.extend(f.get_integers(&io).into_iter().map(|i| i as u64));
            v
        })
        .collect()
}

#[test]
fn fmu_state_round_trip_is_bit_identical() {
    let f = planar_with_friction();
    planar_steps(&f, 0, 10);
    let mut s: fmi2FMUstate = null_mut();
    assert_eq!(fmi2GetFMUstate(f.c, &mut s), OK);
    assert!(!s.is_null());
    let first = planar_steps(&f, 10, 40);
    assert!(
        f.get_real("friction.slip") > 0.0,
        "the run must exercise friction state"
    );

    assert_eq!(fmi2SetFMUstate(f.c, s), OK, "{:?}", f.log());
    assert_eq!(planar_steps(&f, 10, 40), first);

    // a second get into the same handle overwrites it in place
    let before = s;
    assert_eq!(fmi2GetFMUstate(f.c, &mut s), OK);
    assert_eq!(s, before);
    let later = planar_steps(&f, 50, 5);
    assert_eq!(fmi2SetFMUstate(f.c, s), OK);
    assert_eq!(planar_steps(&f, 50, 5), later);

    assert_eq!(fmi2FreeFMUstate(f.c, &mut s), OK);
    assert!(s.is_null());
    assert_eq!(
        fmi2FreeFMUstate(f.c, &mut s),
        OK,
        "freeing *NULL is a no-op"
    );
    assert_eq!(
        fmi2FreeFMUstate(f.c, null_mut()),
        OK,
        "freeing NULL is a no-op"
    );
}

#[test]
fn serialized_fmu_state_round_trip_is_bit_identical() {
    let f = planar_with_friction();
    planar_steps(&f, 0, 10);
    let mut s: fmi2FMUstate = null_mut();
    assert_eq!(fmi2GetFMUstate(f.c, &mut s), OK);
    let mut size = 0usize;
    assert_eq!(
        fmi2SerializedFMUstateSize(f.c, s, &mut size),
        OK,
        "{:?}",
        f.log()
    );
    assert!(size > 0);
    let mut bytes = vec![0 as fmi2Byte; size];
    assert_eq!(
        fmi2SerializeFMUstate(f.c, s, bytes.as_mut_ptr(), size),
        OK,
        "{:?}",
        f.log()
    );
    assert_eq!(fmi2FreeFMUstate(f.c, &mut s), OK);

    let first = planar_steps(&f, 10, 30);
    let mut restored: fmi2FMUstate = null_mut();
    assert_eq!(
        fmi2DeSerializeFMUstate(f.c, bytes.as_ptr(), size, &mut restored),
        OK,
        "{:?}",
        f.log()
    );
    assert!(!restored.is_null());
    assert_eq!(fmi2SetFMUstate(f.c, restored), OK);
    assert_eq!(planar_steps(&f, 10, 30), first);

    // too small a buffer: refused, named
    let n = f.log_len();
    let mut small = vec![0 as fmi2Byte; size - 1];
    assert_error_logged(
        &f,
        n,
        fmi2SerializeFMUstate(f.c, restored, small.as_mut_ptr(), size - 1),
        "fmi2SerializeFMUstate",
    );
    assert_eq!(fmi2FreeFMUstate(f.c, &mut restored), OK);
}

#[test]
fn corrupt_serialized_state_is_refused_and_nothing_changes() {
    let f = planar_with_friction();
    let expected = {
        let g = planar_with_friction();
        planar_steps(&g, 0, 10)
    };
    let garbage: Vec<fmi2Byte> = (0..64).map(|i| (i * 37 % 251) as u8 as fmi2Byte).collect();
    let mut s: fmi2FMUstate = null_mut();
    let n = f.log_len();
    let status = fmi2DeSerializeFMUstate(f.c, garbage.as_ptr(), garbage.len(), &mut s);
    assert_error_logged(&f, n, status, "fmi2DeSerializeFMUstate");
    assert!(s.is_null(), "no state is made from bad bytes");
    assert_eq!(
        planar_steps(&f, 0, 10),
        expected,
        "the instance is unchanged"
    );
}
