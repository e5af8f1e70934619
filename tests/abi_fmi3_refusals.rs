//! What the exported FMI 3.0 functions refuse, each with fmi3Error and one message naming the
//! function: NULL arrays with non-zero counts (and a NULL instance: no crash), the functions this
//! Co-Simulation FMU does not support (Model Exchange, Scheduled Execution, clocks, event mode),
//! and the refused instantiations (bad token, eventModeUsed, other interface types, empty name,
//! NULL token or array). A refused call leaves the instance as it was: it still steps.
//!
//! Uses `tests/common/fmi3.rs` (`Fmu3`, `expect_error!`, its logger and `instantiate`).

mod common;

use common::fmi3::*;
use common::new_env;
use connector_fmu::fmi3::exports::*;
use connector_fmu::fmi3::types::*;
use connector_fmu::variables::{table, Variant};
use std::ffi::{c_void, CString};
use std::ptr::{null, null_mut};

// ------------------------------------------------------------------ NULL arguments

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

// ------------------------------------------------------------------ unsupported functions

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

// ------------------------------------------------------------------ instantiation

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
