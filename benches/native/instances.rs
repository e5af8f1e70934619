//! Instances of the two FMUs on a variant's path: `Inst` (its value references and path, freed
//! on drop), `real_instance` (parameters set, inputs at t = 0, initialized), `empty_instance`
//! (the empty FMU with the same numbers of values and the same path), and `ok`, the status
//! check that shows what the instance logged. Uses `fmus`, `scenes`, `empty` (the empty FMU's
//! GUID and sizes) and the test support module.

use crate::fmus::empty_fmu;
use crate::scenes::{interface, name_of, path_of};
use crate::{empty, support};
use connector_fmu::fmi2::exports as fmi;
use connector_fmu::fmi2::types::{fmi2CallbackFunctions, fmi2Component, fmi2False, fmi2Status};
use connector_fmu::variables::Variant;
use std::ffi::CString;

/// An initialized instance with its value references and its precomputed input path.
pub struct Inst {
    pub c: fmi2Component,
    pub vin: Vec<u32>,
    pub vout: Vec<u32>,
    /// PERIOD rows of vin.len() values.
    pub path: Vec<f64>,
    /// Steps taken (the next step starts at step·H).
    pub step: usize,
    pub empty: bool,
    /// The componentEnvironment key its messages are logged under (tests/common).
    pub env: usize,
}

impl Drop for Inst {
    fn drop(&mut self) {
        if self.empty {
            (empty_fmu().free_instance)(self.c);
        } else {
            fmi::fmi2FreeInstance(self.c);
        }
        support::forget_log(self.env);
    }
}

/// Asserts OK; on failure shows what the instance logged under `env`.
#[track_caller]
pub fn ok(env: usize, s: fmi2Status, what: &str) {
    assert_eq!(s, fmi2Status::OK, "{what}: {:?}", support::log_of(env));
}

/// An instance of the real FMU, parameters set, inputs at t = 0, initialized.
pub fn real_instance(v: Variant, params: &[(String, f64)]) -> Inst {
    real_instance_with(v, params, &[])
}

/// `real_instance` with Integer parameters too (`ints`, values given as f64).
pub fn real_instance_with(v: Variant, params: &[(String, f64)], ints: &[(String, f64)]) -> Inst {
    let (vin, sel, vout) = interface(v);
    let path = path_of(v, &sel);
    let env = support::new_env();
    let cb = support::callbacks(env);
    let c = support::instantiate_raw(
        Some("bench"),
        support::CO_SIMULATION,
        Some(&support::guid(v)),
        Some(&cb),
        false,
    );
    assert!(
        !c.is_null(),
        "fmi2Instantiate refused {}: {:?}",
        name_of(v),
        support::log_of(env)
    );
    let inst = Inst {
        c,
        vin,
        vout,
        path,
        step: 0,
        empty: false,
        env,
    };
    for (n, x) in params {
        ok(env, fmi::fmi2SetReal(c, &support::vr(v, n), 1, x), n);
    }
    for (n, x) in ints {
        let i = *x as i32;
        ok(env, fmi::fmi2SetInteger(c, &support::vr(v, n), 1, &i), n);
    }
    ok(
        env,
        fmi::fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0),
        "setup",
    );
    ok(env, fmi::fmi2EnterInitializationMode(c), "enter init");
    ok(
        env,
        fmi::fmi2SetReal(c, inst.vin.as_ptr(), inst.vin.len(), inst.path.as_ptr()),
        "inputs at 0",
    );
    ok(env, fmi::fmi2ExitInitializationMode(c), "exit init");
    inst
}

/// An instance of the empty FMU with the same numbers of inputs and outputs and the same path.
pub fn empty_instance(like: &Inst) -> Inst {
    let name = CString::new("empty").unwrap();
    let guid = CString::new(empty::GUID).unwrap();
    let env = support::new_env();
    let cb = support::callbacks(env);
    let e = empty_fmu();
    let c = (e.instantiate)(
        name.as_ptr(),
        1,
        guid.as_ptr(),
        c"".as_ptr(),
        (&cb as *const fmi2CallbackFunctions).cast(),
        0,
        0,
    );
    assert!(!c.is_null());
    let n_in = like.vin.len() as u32;
    let n_out = like.vout.len() as u32;
    assert!(n_in <= empty::N_IN && n_out <= empty::N_OUT);
    let inst = Inst {
        c,
        vin: (1..=n_in).collect(),
        vout: (empty::N_IN + 1..=empty::N_IN + n_out).collect(),
        path: like.path.clone(),
        step: 0,
        empty: true,
        env,
    };
    assert_eq!((e.setup_experiment)(c, 0, 0.0, 0.0, 0, 0.0), empty::OK);
    assert_eq!((e.enter_initialization_mode)(c), empty::OK);
    assert_eq!((e.exit_initialization_mode)(c), empty::OK);
    inst
}
