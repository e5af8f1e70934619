//! The lifecycle of an FMI 3.0 Co-Simulation instance, called as an importer calls the exported
//! fmi3* functions: the version, instantiate → initialize → step → terminate → reset for every
//! variant, the start time, the state machine (illegal calls per state, each an fmi3Error with
//! one message), the error state after a failed step, and the debug-logging categories.
//!
//! Uses `tests/common/fmi3.rs` (`Fmu3`, `expect_error!`, `outputs`).

mod common;

use common::fmi3::*;
use connector_fmu::fmi3::exports::*;
use connector_fmu::fmi3::types::*;
use connector_fmu::variables::{Variant, VARIANTS};
use std::ffi::{c_void, CStr, CString};
use std::ptr::{null, null_mut};

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

// ------------------------------------------------------------------ debug logging

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
