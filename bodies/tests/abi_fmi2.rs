//! The FMI 2.0 functions of the Body FMU called as an importer calls them: the lifecycle, the
//! outputs in Initialization Mode, `(NULL, 0)` and NULL arrays, a NULL instance, refused
//! instantiations, values refused and left unchanged, parameters that do not fit together,
//! refused steps, the functions of what the FMU does not provide, and one log message per
//! non-OK status. Uses `common` and the crate's exports.

mod common;

use body_fmu::fmi2::exports::*;
use body_fmu::fmi2::types::*;
use common::*;
use std::ptr::{null, null_mut};

#[test]
fn lifecycle_free_fall_through_the_c_functions() {
    let mut f = Fmu2::new();
    f.enter();
    for (n, x) in [
        ("gravity[3]", -9.81),
        ("start.r[3]", 10.0),
        ("start.v[1]", 2.0),
    ] {
        assert_eq!(f.set(n, x), fmi2Status::OK);
    }
    // Initialization Mode: the outputs follow the start parameters at once
    assert_eq!(
        (f.get("r[3]"), f.get("v[1]"), f.get("q.w")),
        (10.0, 2.0, 1.0)
    );
    assert_eq!(f.get("energy.potential"), 9.81 * 10.0);
    assert_eq!(fmi2ExitInitializationMode(f.c), fmi2Status::OK);
    for _ in 0..100 {
        f.step(0.01);
    }
    // exact per step for a held load: r = r0 + v0 t - g t²/2 to round-off (100 steps, 1e-13)
    assert!((f.get("r[3]") - (10.0 - 0.5 * 9.81)).abs() < 1e-13);
    assert!((f.get("r[1]") - 2.0).abs() < 1e-14);
    assert!((f.get("v[3]") + 9.81).abs() < 1e-13);
    let mut t = 0.0;
    assert_eq!(fmi2GetRealStatus(f.c, 2, &mut t), fmi2Status::OK);
    assert!((t - 1.0).abs() < 1e-15);
    let mut term = 7;
    assert_eq!(fmi2GetBooleanStatus(f.c, 3, &mut term), fmi2Status::OK);
    assert_eq!(term, 0);
    assert_eq!(fmi2Terminate(f.c), fmi2Status::OK);
    assert_eq!(fmi2Reset(f.c), fmi2Status::OK);
    f.t = 0.0;
    f.init();
    assert_eq!(f.get("r[3]"), 0.0); // reset brought the start values back
    assert!(log_of(f.env).is_empty(), "{:?}", log_of(f.env));
}

#[test]
fn null_and_empty_arrays() {
    let f = Fmu2::new();
    f.init();
    assert_eq!(fmi2GetReal(f.c, null(), 0, null_mut()), fmi2Status::OK);
    assert_eq!(fmi2SetReal(f.c, null(), 0, null()), fmi2Status::OK);
    assert_eq!(fmi2GetInteger(f.c, null(), 0, null_mut()), fmi2Status::OK);
    assert_eq!(fmi2GetBoolean(f.c, null(), 0, null_mut()), fmi2Status::OK);
    assert_eq!(fmi2SetString(f.c, null(), 0, null()), fmi2Status::OK);
    assert_eq!(fmi2SetDebugLogging(f.c, 1, 0, null()), fmi2Status::OK);
    let mut x = 0.0;
    assert_eq!(fmi2GetReal(f.c, null(), 1, &mut x), fmi2Status::Error);
    assert_eq!(fmi2SetReal(f.c, &vr("f[1]"), 1, null()), fmi2Status::Error);
    let mut n = 0usize;
    assert_eq!(
        fmi2SerializedFMUstateSize(f.c, null_mut(), &mut n),
        fmi2Status::Error
    );
    assert_eq!(
        fmi2DeSerializeFMUstate(f.c, null(), 5, &mut null_mut()),
        fmi2Status::Error
    );
    let log = log_of(f.env);
    let errors: Vec<_> = log.iter().filter(|l| l.status == 3).collect();
    assert_eq!(errors.len(), 4, "{log:?}");
    assert!(errors[0].message.contains("vr[]") && errors[1].message.contains("value[]"));
    assert!(
        errors[2].message.contains("FMUstate") && errors[3].message.contains("serializedState")
    );
}

#[test]
fn a_null_instance_is_an_error_everywhere_and_free_ignores_it() {
    let c = null_mut();
    let mut x = 0.0;
    assert_eq!(fmi2GetReal(c, &vr("r[1]"), 1, &mut x), fmi2Status::Error);
    assert_eq!(fmi2DoStep(c, 0.0, 0.1, 1), fmi2Status::Error);
    assert_eq!(fmi2EnterInitializationMode(c), fmi2Status::Error);
    assert_eq!(fmi2Reset(c), fmi2Status::Error);
    assert_eq!(fmi2GetFMUstate(c, &mut null_mut()), fmi2Status::Error);
    fmi2FreeInstance(c);
}

#[test]
fn instantiation_is_refused_with_a_reason() {
    let env = new_env();
    let cb = callbacks(env);
    let (name, empty, wrong) = (
        cs("b"),
        cs(""),
        cs("{00000000-0000-0000-0000-000000000000}"),
    );
    let good = cs(body_fmu::variables::guid());
    let inst = |n: &std::ffi::CString, t, g: &std::ffi::CString| {
        fmi2Instantiate(n.as_ptr(), t, g.as_ptr(), null(), &cb, 0, 0)
    };
    assert!(inst(&name, 1, &wrong).is_null());
    assert!(inst(&name, 0, &good).is_null());
    assert!(inst(&name, 7, &good).is_null());
    assert!(inst(&empty, 1, &good).is_null());
    assert!(fmi2Instantiate(name.as_ptr(), 1, good.as_ptr(), null(), null(), 0, 0).is_null());
    let log = log_of(env);
    let msgs: Vec<&str> = log.iter().map(|l| l.message.as_str()).collect();
    assert_eq!(msgs.len(), 4, "{msgs:?}");
    assert!(msgs[0].contains("fmuGUID") && msgs[1].contains("ModelExchange"));
    assert!(msgs[2].contains("invalid fmuType 7") && msgs[3].contains("instanceName is empty"));
}

#[test]
fn bad_values_are_refused_named_and_change_nothing() {
    let f = Fmu2::new();
    f.enter();
    assert_eq!(f.set("mass", 2.0), fmi2Status::OK);
    let cases: [(&str, f64, &str); 6] = [
        ("f[1]", f64::NAN, "f[1] = NaN"),
        ("m[3]", f64::INFINITY, "m[3] = inf"),
        ("mass", 0.0, "mass = 0.0 is refused: it must be > 0"),
        ("inertia[2]", -1.0, "inertia[2] = -1.0"),
        (
            "spring.k[1]",
            -3.0,
            "spring.k[1] = -3.0 is refused: it must be >= 0.0",
        ),
        ("rigid.maxTurn", 0.0, "rigid.maxTurn = 0.0"),
    ];
    for (i, (name, x, what)) in cases.iter().enumerate() {
        let before = f.get(name);
        assert_eq!(f.set(name, *x), fmi2Status::Error, "{name}");
        assert_eq!(f.get(name).to_bits(), before.to_bits(), "{name} changed");
        let log = log_of(f.env);
        assert_eq!(log.len(), i + 1, "one message per refusal: {log:?}");
        assert!(log[i].message.contains(what), "{:?}", log[i].message);
        assert!(log[i].message.starts_with("fmi2SetReal: "));
    }
    // all or nothing: the good value of a refused call is not applied either
    let vrs = [vr("f[2]"), vr("mass")];
    assert_eq!(
        fmi2SetReal(f.c, vrs.as_ptr(), 2, [5.0, -1.0].as_ptr()),
        fmi2Status::Error
    );
    assert_eq!(f.get("f[2]"), 0.0);
    assert_eq!(f.set_int("dof.w[1]", 3), fmi2Status::Error);
    assert_eq!(f.set_int("model", -1), fmi2Status::Error);
    assert_eq!(fmi2SetInteger(f.c, &vr("mass"), 1, &1), fmi2Status::Error); // wrong type
    assert_eq!(f.set("r[1]", 1.0), fmi2Status::Error); // an output
    assert_eq!(fmi2SetReal(f.c, &999, 1, &1.0), fmi2Status::Error); // unknown
    assert_eq!(fmi2SetBoolean(f.c, &vr("mass"), 1, &1), fmi2Status::Error);
    let log = log_of(f.env);
    assert_eq!(log.len(), 13);
    assert!(log[7]
        .message
        .contains("dof.w[1] = 3 is refused: it must be <= 2"));
    assert!(log[9]
        .message
        .contains("vr 501 (mass) is not of type Integer"));
    assert!(log[10].message.contains("r[1] is an output"));
    assert!(log[11].message.contains("vr 999"));
    assert!(log[12].message.contains("no Boolean variables"));
    assert_eq!(fmi2ExitInitializationMode(f.c), fmi2Status::OK);
    // a fixed parameter after initialization
    assert_eq!(f.set("mass", 3.0), fmi2Status::Error);
    assert!(
        log_of(f.env)[13]
            .message
            .contains("mass is a fixed parameter"),
        "{:?}",
        log_of(f.env)
    );
    assert_eq!(f.get("mass"), 2.0);
}

#[test]
fn parameters_that_do_not_fit_together_are_refused_at_exit_and_can_be_fixed() {
    let f = Fmu2::new();
    f.enter();
    let exit = |f: &Fmu2| fmi2ExitInitializationMode(f.c);
    assert_eq!(f.set_int("dof.w[1]", 1), fmi2Status::OK);
    assert_eq!(f.set_int("dof.w[3]", 2), fmi2Status::OK);
    assert_eq!(exit(&f), fmi2Status::Error);
    assert_eq!(f.set_int("dof.w[1]", 0), fmi2Status::OK);
    assert_eq!(f.set("start.q.x", 0.5), fmi2Status::OK);
    assert_eq!(exit(&f), fmi2Status::Error);
    let mut x = 0.0;
    assert_eq!(fmi2GetReal(f.c, &vr("q.w"), 1, &mut x), fmi2Status::Error); // outputs too
    assert_eq!(f.set("start.q.x", 0.0), fmi2Status::OK);
    assert_eq!(f.set_int("model", 1), fmi2Status::OK);
    assert_eq!(f.set("spring.k[2]", 10.0), fmi2Status::OK);
    assert_eq!(exit(&f), fmi2Status::Error);
    assert_eq!(f.set("spring.k[2]", 0.0), fmi2Status::OK);
    for n in ["start.q.w", "start.q.x", "start.q.y", "start.q.z"] {
        assert_eq!(f.set(n, 0.0), fmi2Status::OK);
    }
    assert_eq!(exit(&f), fmi2Status::Error);
    let log = log_of(f.env);
    let m: Vec<&str> = log.iter().map(|l| l.message.as_str()).collect();
    assert_eq!(m.len(), 5, "{m:?}");
    assert!(
        m[0].starts_with("fmi2ExitInitializationMode: ") && m[0].contains("dof.w[1], dof.w[3]")
    );
    assert!(m[1].contains("start.q must be a rotation about world z, but start.q.x = 0.5"));
    assert!(m[2].starts_with("fmi2GetReal: the outputs follow the start parameters"));
    assert!(m[3].contains("spring.k[2] = 10.0, but springs act in model 0 only"));
    assert!(m[4].contains("start.q has norm"));
    assert_eq!(f.set("start.q.w", 2.0), fmi2Status::OK); // normalised
    assert_eq!(exit(&f), fmi2Status::OK);
    assert_eq!(f.get("q.w"), 1.0);
}

#[test]
fn refused_steps_and_calls_out_of_order_change_nothing() {
    let mut f = Fmu2::new();
    assert_eq!(fmi2DoStep(f.c, 0.0, 0.1, 1), fmi2Status::Error); // before initialization
    let mut x = 0.0;
    assert_eq!(fmi2GetReal(f.c, &vr("r[1]"), 1, &mut x), fmi2Status::Error);
    f.init();
    assert_eq!(f.set("f[1]", 1.0), fmi2Status::OK);
    f.step(0.5);
    let before = f.outputs();
    assert_eq!(fmi2DoStep(f.c, 0.5, 0.0, 1), fmi2Status::Error);
    assert_eq!(fmi2DoStep(f.c, 0.5, -1.0, 1), fmi2Status::Error);
    assert_eq!(fmi2DoStep(f.c, 0.7, 0.1, 1), fmi2Status::Error); // not the FMU time
    assert_eq!(fmi2DoStep(f.c, 0.5, f64::MAX, 1), fmi2Status::Error); // r = inf
    assert_eq!(f.outputs(), before);
    assert_eq!(fmi2DoStep(f.c, 0.5, 1e10, 1), fmi2Status::OK);
    assert_ne!(f.outputs(), before);
    assert_eq!(fmi2EnterInitializationMode(f.c), fmi2Status::Error);
    let m: Vec<String> = log_of(f.env).into_iter().map(|l| l.message).collect();
    assert_eq!(m.len(), 7, "{m:?}");
    assert!(m[0].contains("not allowed in the Instantiated state"));
    assert!(m[2].contains("communicationStepSize 0.0 must be finite and > 0"));
    assert!(m[4].contains("currentCommunicationPoint 0.7 does not match the FMU time 0.5"));
    assert!(m[5].contains("that are not finite"), "{}", m[5]);
    assert!(m[6].contains("not allowed in Step Mode"));
}

#[test]
fn what_the_fmu_does_not_provide_answers_error_with_a_message() {
    let f = Fmu2::new();
    f.init();
    let (v, mut x, mut s) = (vr("r[1]"), 0.0, fmi2Status::OK);
    let st = [
        fmi2GetDirectionalDerivative(f.c, &v, 1, &vr("f[1]"), 1, &1.0, &mut x),
        fmi2SetRealInputDerivatives(f.c, &vr("f[1]"), 1, &1, &1.0),
        fmi2GetRealOutputDerivatives(f.c, &v, 1, &1, &mut x),
        fmi2CancelStep(f.c),
        fmi2GetStatus(f.c, 0, &mut s),
        fmi2GetRealStatus(f.c, 0, &mut x),
        fmi2GetIntegerStatus(f.c, 2, &mut 0),
        fmi2GetStringStatus(f.c, 2, &mut null()),
    ];
    assert!(st.iter().all(|&s| s == fmi2Status::Error), "{st:?}");
    let log = log_of(f.env);
    assert_eq!(log.len(), st.len());
    assert!(log
        .iter()
        .all(|l| l.category == "logStatusError" && l.status == 3));
    assert!(log[0]
        .message
        .starts_with("fmi2GetDirectionalDerivative: no directional"));
    assert!(log[1].message.contains("canInterpolateInputs = false"));
    // versions and logging
    // SAFETY: the FMU returns static NUL-terminated strings.
    let version = unsafe { std::ffi::CStr::from_ptr(fmi2GetVersion()) };
    assert_eq!(version.to_str(), Ok("2.0"));
    let bad = [cs("logEvents")];
    let ptrs = [bad[0].as_ptr()];
    assert_eq!(
        fmi2SetDebugLogging(f.c, 1, 1, ptrs.as_ptr()),
        fmi2Status::Error
    );
    assert!(log_of(f.env)
        .last()
        .unwrap()
        .message
        .contains("unknown log category"));
}

#[test]
fn log_all_traces_every_call_and_percent_is_doubled() {
    let f = Fmu2::new();
    let all = [cs("logAll")];
    let ptrs = [all[0].as_ptr()];
    assert_eq!(
        fmi2SetDebugLogging(f.c, 1, 1, ptrs.as_ptr()),
        fmi2Status::OK
    );
    f.init();
    let log = log_of(f.env);
    assert!(log
        .iter()
        .any(|l| l.category == "logAll" && l.message == "fmi2ExitInitializationMode"));
    assert_eq!(fmi2SetDebugLogging(f.c, 0, 0, null()), fmi2Status::OK);
    let n = f.log_len();
    assert_eq!(f.set("f[1]", 1.0), fmi2Status::OK);
    assert_eq!(f.log_len(), n);
    // importers printf the message: a '%' reaches them doubled
    let pct = [cs("50%s")];
    let ptrs = [pct[0].as_ptr()];
    assert_eq!(
        fmi2SetDebugLogging(f.c, 1, 1, ptrs.as_ptr()),
        fmi2Status::Error
    );
    assert!(log_of(f.env)[n].message.contains("\"50%%s\""));
}
