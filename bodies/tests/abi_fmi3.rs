//! The FMI 3.0 functions of the Body FMU called as an importer calls them: the lifecycle and
//! `time`, variable dependencies, refused instantiations, every function of what the FMU does
//! not have answering fmi3Error with one message, and the FMI 3.0 outputs equal to the FMI 2.0
//! ones bit for bit over random loads and steps in both models (the own loads and two ports'
//! at random offsets; the ports' outputs too). Uses `common` and the crate's
//! exports.

mod common;

use body_fmu::fmi2::types::fmi2Status;
use body_fmu::fmi3::exports::*;
use body_fmu::fmi3::refused::*;
use body_fmu::fmi3::types::*;
use common::*;
use std::ffi::c_void;
use std::ptr::{null, null_mut};

#[test]
fn lifecycle_time_and_dependencies() {
    let mut f = Fmu3::new();
    let n_params = body_fmu::variables::VARS
        .iter()
        .filter(|v| v.causality == body_fmu::variables::Causality::Parameter)
        .count();
    let deps = |f: &Fmu3, v: u32| {
        let mut n = 99usize;
        let st = fmi3GetNumberOfVariableDependencies(f.c, v, &mut n);
        (st, n)
    };
    assert_eq!(deps(&f, vr("r[1]")), (fmi3Status::OK, n_params));
    assert_eq!(deps(&f, vr("mass")).0, fmi3Status::Error);
    let mut indep = vec![0u32; n_params];
    let (mut e1, mut e2) = (vec![9usize; n_params], vec![9usize; n_params]);
    let mut kinds = vec![fmi3DependencyKind::Constant; n_params];
    let st = fmi3GetVariableDependencies(
        f.c,
        vr("q.w"),
        e1.as_mut_ptr(),
        indep.as_mut_ptr(),
        e2.as_mut_ptr(),
        kinds.as_mut_ptr(),
        n_params,
    );
    assert_eq!(st, fmi3Status::OK);
    assert!(
        indep.contains(&vr("mass")) && kinds.iter().all(|&k| k == fmi3DependencyKind::Dependent)
    );
    assert!(e1.iter().chain(&e2).all(|&e| e == 0));
    f.enter();
    assert_eq!(f.set("start.v[2]", 3.0), fmi3Status::OK);
    assert_eq!(f.get("v[2]"), 3.0);
    assert_eq!(fmi3ExitInitializationMode(f.c), fmi3Status::OK);
    assert_eq!(deps(&f, vr("r[1]")), (fmi3Status::OK, 0)); // no direct feedthrough
    f.step(0.5);
    f.step(0.25);
    assert_eq!(f.get("r[2]"), 2.25);
    let mut t = 0.0;
    assert_eq!(fmi3GetFloat64(f.c, &0, 1, &mut t, 1), fmi3Status::OK);
    assert_eq!(t, 0.75);
    assert_eq!(fmi3SetFloat64(f.c, &0, 1, &1.0, 1), fmi3Status::Error);
    assert_eq!(
        fmi3GetFloat64(f.c, &vr("r[1]"), 1, &mut t, 2),
        fmi3Status::Error
    ); // nValues
    assert_eq!(fmi3Terminate(f.c), fmi3Status::OK);
    assert_eq!(f.get("r[2]"), 2.25); // still readable
    assert_eq!(fmi3Reset(f.c), fmi3Status::OK);
    let m: Vec<String> = log_of(f.env).into_iter().map(|l| l.message).collect();
    assert_eq!(m.len(), 3, "{m:?}");
    assert!(m[0].contains("vr 501 is not an output"));
    assert!(m[1].contains("time (vr 0) is the independent variable"));
    assert!(m[2].contains("nValues = 2 differs from nValueReferences = 1"));
}

#[test]
fn instantiation_is_refused_with_a_reason_and_a_null_logger_is_allowed() {
    let env = new_env();
    let good = cs(body_fmu::variables::guid());
    let (name, wrong) = (cs("b"), cs("{nope}"));
    let inst = |token: &std::ffi::CString, event_mode: u8, n_req: usize, log: bool| {
        fmi3InstantiateCoSimulation(
            name.as_ptr(),
            token.as_ptr(),
            null(),
            0,
            0,
            event_mode,
            1,
            null(),
            n_req,
            env as *mut c_void,
            if log { logger3_fn() } else { None },
            None,
        )
    };
    assert!(inst(&wrong, 0, 0, true).is_null());
    assert!(inst(&good, 1, 0, true).is_null());
    assert!(inst(&good, 0, 2, true).is_null());
    assert!(fmi3InstantiateModelExchange(
        name.as_ptr(),
        good.as_ptr(),
        null(),
        0,
        0,
        env as *mut c_void,
        logger3_fn()
    )
    .is_null());
    let se = fmi3InstantiateScheduledExecution(
        name.as_ptr(),
        good.as_ptr(),
        null(),
        0,
        0,
        env as *mut c_void,
        logger3_fn(),
        None,
        None,
        None,
    );
    assert!(se.is_null());
    let m: Vec<String> = log_of(env).into_iter().map(|l| l.message).collect();
    assert_eq!(m.len(), 5, "{m:?}");
    assert!(m[0].contains("instantiationToken \"{nope}\""));
    assert!(m[1].contains("eventModeUsed"));
    assert!(m[2].contains("requiredIntermediateVariables[]"));
    assert!(m[3].contains("Model Exchange") && m[4].contains("Scheduled Execution"));
    // no logger: an instance that works silently
    let c = inst(&good, 0, 0, false);
    assert!(!c.is_null());
    assert_eq!(
        fmi3DoStep(c, 0.0, 1.0, 0, &mut 0, &mut 0, &mut 0, &mut 0.0),
        fmi3Status::Error
    );
    fmi3FreeInstance(c);
}

#[test]
fn everything_the_fmu_does_not_have_answers_error_with_one_message() {
    let f = Fmu3::new();
    f.init();
    let c = f.c;
    let v = vr("r[1]");
    let (mut x, mut b, mut n) = (0.0, 0u8, 0usize);
    let calls: Vec<(&str, fmi3Status)> = vec![
        ("fmi3EnterEventMode", fmi3EnterEventMode(c)),
        ("fmi3GetFloat32", fmi3GetFloat32(c, &v, 1, &mut 0.0, 1)),
        ("fmi3GetInt8", fmi3GetInt8(c, &v, 1, &mut 0, 1)),
        ("fmi3GetUInt64", fmi3GetUInt64(c, &v, 1, &mut 0, 1)),
        ("fmi3GetBoolean", fmi3GetBoolean(c, &v, 1, &mut b, 1)),
        ("fmi3GetString", fmi3GetString(c, &v, 1, &mut null(), 1)),
        (
            "fmi3GetBinary",
            fmi3GetBinary(c, &v, 1, &mut n, &mut null(), 1),
        ),
        ("fmi3GetClock", fmi3GetClock(c, &v, 1, &mut b)),
        ("fmi3SetInt16", fmi3SetInt16(c, &v, 1, &1, 1)),
        ("fmi3SetBoolean", fmi3SetBoolean(c, &v, 1, &1, 1)),
        ("fmi3SetBinary", fmi3SetBinary(c, &v, 1, &1, &null(), 1)),
        ("fmi3SetClock", fmi3SetClock(c, &v, 1, &1)),
        (
            "fmi3GetDirectionalDerivative",
            fmi3GetDirectionalDerivative(c, &v, 1, &v, 1, &1.0, 1, &mut x, 1),
        ),
        (
            "fmi3GetAdjointDerivative",
            fmi3GetAdjointDerivative(c, &v, 1, &v, 1, &1.0, 1, &mut x, 1),
        ),
        ("fmi3EnterConfigurationMode", fmi3EnterConfigurationMode(c)),
        ("fmi3ExitConfigurationMode", fmi3ExitConfigurationMode(c)),
        (
            "fmi3GetIntervalDecimal",
            fmi3GetIntervalDecimal(c, &v, 1, &mut x, &mut 0),
        ),
        (
            "fmi3SetShiftFraction",
            fmi3SetShiftFraction(c, &v, 1, &1, &1),
        ),
        ("fmi3EvaluateDiscreteStates", fmi3EvaluateDiscreteStates(c)),
        (
            "fmi3UpdateDiscreteStates",
            fmi3UpdateDiscreteStates(c, &mut b, &mut b, &mut b, &mut b, &mut b, &mut x),
        ),
        (
            "fmi3EnterContinuousTimeMode",
            fmi3EnterContinuousTimeMode(c),
        ),
        ("fmi3SetTime", fmi3SetTime(c, 1.0)),
        (
            "fmi3GetNumberOfContinuousStates",
            fmi3GetNumberOfContinuousStates(c, &mut n),
        ),
        ("fmi3EnterStepMode", fmi3EnterStepMode(c)),
        (
            "fmi3GetOutputDerivatives",
            fmi3GetOutputDerivatives(c, &v, 1, &1, &mut x, 1),
        ),
        (
            "fmi3ActivateModelPartition",
            fmi3ActivateModelPartition(c, 1, 0.0),
        ),
    ];
    let log = log_of(f.env);
    assert_eq!(log.len(), calls.len(), "{log:?}");
    for ((name, st), line) in calls.iter().zip(&log) {
        assert_eq!(*st, fmi3Status::Error, "{name}");
        assert!(
            line.message.starts_with(&format!("{name}: ")),
            "{name}: {}",
            line.message
        );
        assert_eq!((line.status, line.category.as_str()), (3, "logStatusError"));
    }
    // empty requests of types without variables are fine
    assert_eq!(fmi3GetInt8(c, null(), 0, null_mut(), 0), fmi3Status::OK);
    assert_eq!(fmi3SetString(c, null(), 0, null(), 0), fmi3Status::OK);
    assert_eq!(fmi3GetClock(c, null(), 0, null_mut()), fmi3Status::OK);
}

/// Drives an FMI 2.0 and an FMI 3.0 instance with the same parameters, loads and steps and
/// returns whether every output after every step had the same bits.
fn twins(model: i32, seed: u64) -> usize {
    let (mut f2, mut f3) = (Fmu2::new(), Fmu3::new());
    f2.enter();
    f3.enter();
    let mut rng = Lcg(seed);
    let ints = [("model", model), ("dof.w[3]", 1), ("dof.r[2]", 2)];
    let reals = [
        ("mass", rng.range(0.5, 3.0)),
        ("inertia[1]", rng.range(0.1, 1.0)),
        ("inertia[2]", rng.range(0.1, 1.0)),
        ("inertia[3]", rng.range(0.1, 1.0)),
        ("gravity[3]", -9.81),
        ("start.v[2]", rng.range(-1.0, 1.0)),
        ("start.w[3]", rng.range(-5.0, 5.0)),
        ("start.w[1]", if model == 1 { 2.0 } else { 0.0 }),
    ];
    for (n, x) in ints {
        assert_eq!(
            (f2.set_int(n, x), f3.set_int(n, x)),
            (fmi2Status::OK, fmi3Status::OK)
        );
    }
    for (n, x) in reals {
        assert_eq!(
            (f2.set(n, x), f3.set(n, x)),
            (fmi2Status::OK, fmi3Status::OK),
            "{n}"
        );
    }
    // ports 1 and 3 at random offsets and frames, loaded every step below
    for k in [1, 3] {
        let offsets = ["r[1]", "r[2]", "r[3]", "q.w", "q.x", "q.y", "q.z"];
        for o in offsets {
            let n = format!("port[{k}].offset.{o}");
            let x = rng.range(-0.5, 0.5) + if o == "q.w" { 1.0 } else { 0.0 };
            assert_eq!(
                (f2.set(&n, x), f3.set(&n, x)),
                (fmi2Status::OK, fmi3Status::OK)
            );
        }
    }
    let port_outputs = |get: &dyn Fn(&str) -> f64| -> Vec<u64> {
        let mut out = Vec::new();
        for k in 1..=4 {
            for o in PORT_OUTPUTS {
                out.push(get(&format!("port[{k}].{o}")).to_bits());
            }
        }
        out
    };
    assert_eq!(
        f2.outputs().map(f64::to_bits),
        f3.outputs().map(f64::to_bits)
    );
    assert_eq!(port_outputs(&|n| f2.get(n)), port_outputs(&|n| f3.get(n)));
    let exit2 = body_fmu::fmi2::exports::fmi2ExitInitializationMode(f2.c);
    assert_eq!(
        (exit2, fmi3ExitInitializationMode(f3.c)),
        (fmi2Status::OK, fmi3Status::OK)
    );
    let mut steps = 0;
    for _ in 0..200 {
        for n in ["f[1]", "f[2]", "f[3]", "m[1]", "m[2]", "m[3]"] {
            let x = rng.range(-2.0, 2.0);
            assert_eq!(
                (f2.set(n, x), f3.set(n, x)),
                (fmi2Status::OK, fmi3Status::OK)
            );
        }
        for k in [1, 3] {
            for l in ["f[1]", "f[2]", "f[3]", "m[1]", "m[2]", "m[3]"] {
                let n = format!("port[{k}].{l}");
                let x = rng.range(-2.0, 2.0);
                assert_eq!(
                    (f2.set(&n, x), f3.set(&n, x)),
                    (fmi2Status::OK, fmi3Status::OK)
                );
            }
        }
        let h = rng.range(1e-4, 2e-2);
        f2.step(h);
        f3.step(h);
        assert_eq!(
            f2.outputs().map(f64::to_bits),
            f3.outputs().map(f64::to_bits)
        );
        assert_eq!(port_outputs(&|n| f2.get(n)), port_outputs(&|n| f3.get(n)));
        steps += 1;
    }
    steps
}

/// The outputs of each port, behind `port[k].`.
const PORT_OUTPUTS: [&str; 13] = [
    "r[1]", "r[2]", "r[3]", "q.w", "q.x", "q.y", "q.z", "v[1]", "v[2]", "v[3]", "w[1]", "w[2]",
    "w[3]",
];

#[test]
fn fmi3_outputs_equal_fmi2_outputs_bit_for_bit() {
    assert_eq!(twins(0, 1), 200);
    assert_eq!(twins(1, 2), 200);
}
