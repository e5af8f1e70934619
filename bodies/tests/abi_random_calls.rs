//! A panic-free sweep of random call orders through both FMI versions' C functions: random
//! lifecycle calls, good and bad values (NaN, out of range, wrong type, unknown value
//! references, NULL arrays with and without counts), steps at the right and wrong times, FMU
//! states saved, restored and serialized. Every call must answer OK or Error (never Fatal: no
//! panic reached the boundary), every Error must come with exactly one log message, and
//! whatever the order, the outputs must stay readable and finite once initialized. Cheap
//! (a few thousand calls, well under a second). Uses `common` and the crate's exports.

mod common;

use body_fmu::fmi2::exports::*;
use body_fmu::fmi2::types::*;
use body_fmu::fmi3::exports::*;
use body_fmu::fmi3::types::*;
use common::*;
use std::ptr::{null, null_mut};

/// Real variables to set: inputs, parameters and one output.
const REALS: [&str; 12] = [
    "f[1]",
    "f[3]",
    "m[2]",
    "mass",
    "inertia[2]",
    "gravity[3]",
    "spring.k[1]",
    "start.q.w",
    "start.q.z",
    "start.w[3]",
    "rigid.maxTurn",
    "r[1]",
];
const INTS: [&str; 4] = ["model", "dof.r[1]", "dof.w[3]", "dof.w[1]"];

fn value(rng: &mut Lcg) -> f64 {
    match (rng.next() * 8.0) as u32 {
        0 => f64::NAN,
        1 => -1.0,
        2 => 0.0,
        3 => 1e6,
        _ => rng.range(-3.0, 3.0),
    }
}

/// One random FMI 2.0 call; returns its status.
fn call2(f: &mut Fmu2, rng: &mut Lcg, saved: &mut fmi2FMUstate) -> fmi2Status {
    let pick = |rng: &mut Lcg, n: usize| ((rng.next() * n as f64) as usize).min(n - 1);
    match pick(rng, 14) {
        0 => fmi2SetupExperiment(f.c, 0, 0.0, 0.0, 0, 0.0),
        1 => fmi2EnterInitializationMode(f.c),
        2 | 3 => fmi2ExitInitializationMode(f.c),
        4 => {
            let n = REALS[pick(rng, REALS.len())];
            f.set(n, value(rng))
        }
        5 => {
            let n = INTS[pick(rng, INTS.len())];
            f.set_int(n, pick(rng, 4) as i32 - 1)
        }
        6..=8 => {
            let mut t = 0.0;
            fmi2GetRealStatus(f.c, 2, &mut t);
            let t = if rng.next() < 0.9 { t } else { t + 1.0 };
            fmi2DoStep(f.c, t, rng.range(-0.01, 0.05), 1)
        }
        9 => fmi2GetFMUstate(f.c, saved),
        10 => fmi2SetFMUstate(f.c, *saved),
        11 => {
            let mut n = 0usize;
            let st = fmi2SerializedFMUstateSize(f.c, *saved, &mut n);
            if st != fmi2Status::OK {
                return st;
            }
            let mut b = vec![0 as fmi2Byte; n];
            fmi2SerializeFMUstate(f.c, *saved, b.as_mut_ptr(), n);
            let k = pick(rng, n);
            b[k] = b[k].wrapping_add((rng.next() < 0.5) as fmi2Byte);
            let mut s: fmi2FMUstate = null_mut();
            let st = fmi2DeSerializeFMUstate(f.c, b.as_ptr(), n, &mut s);
            fmi2FreeFMUstate(f.c, &mut s);
            st
        }
        12 => match pick(rng, 3) {
            0 => fmi2Terminate(f.c),
            1 => fmi2Reset(f.c),
            _ => fmi2GetReal(f.c, null(), 2, null_mut()),
        },
        _ => {
            let mut x = [0.0; 2];
            let vrs = [vr(OUTPUTS[pick(rng, 15)]), pick(rng, 600) as u32];
            fmi2GetReal(f.c, vrs.as_ptr(), 1 + pick(rng, 2), x.as_mut_ptr())
        }
    }
}

/// One random FMI 3.0 call (`t`: the FMU's time, or 0 when it cannot be read); returns its
/// status.
fn call3(f: &mut Fmu3, rng: &mut Lcg, t: f64) -> fmi3Status {
    let pick = |rng: &mut Lcg, n: usize| ((rng.next() * n as f64) as usize).min(n - 1);
    match pick(rng, 8) {
        0 => fmi3EnterInitializationMode(f.c, 0, 0.0, 0.0, 0, 0.0),
        1 => fmi3ExitInitializationMode(f.c),
        2 => f.set(REALS[pick(rng, REALS.len())], value(rng)),
        3 => f.set_int(INTS[pick(rng, INTS.len())], pick(rng, 4) as i32 - 1),
        4 | 5 => {
            let (mut a, mut b, mut c, mut last) = (0, 0, 0, 0.0);
            fmi3DoStep(
                f.c,
                t,
                rng.range(-0.01, 0.05),
                1,
                &mut a,
                &mut b,
                &mut c,
                &mut last,
            )
        }
        6 => match pick(rng, 3) {
            0 => fmi3Terminate(f.c),
            1 => fmi3Reset(f.c),
            _ => fmi3SetFloat64(f.c, null(), 1, null(), 1),
        },
        _ => {
            let mut x = 0.0;
            fmi3GetFloat64(f.c, &vr(OUTPUTS[pick(rng, 15)]), 1, &mut x, 1)
        }
    }
}

#[test]
fn random_call_orders_never_panic_and_explain_every_error() {
    let mut rng = Lcg(2026);
    let mut errors = 0;
    for _ in 0..60 {
        let mut f = Fmu2::new();
        let mut saved: fmi2FMUstate = null_mut();
        for _ in 0..60 {
            let before = f.log_len();
            let st = call2(&mut f, &mut rng, &mut saved);
            assert!(matches!(st, fmi2Status::OK | fmi2Status::Error), "{st:?}");
            let logged = f.log_len() - before;
            assert_eq!(
                logged,
                usize::from(st == fmi2Status::Error),
                "{:?}",
                log_of(f.env)
            );
            errors += usize::from(st == fmi2Status::Error);
            let mut out = [0.0; 15];
            let vrs = OUTPUTS.map(vr);
            if fmi2GetReal(f.c, vrs.as_ptr(), 15, out.as_mut_ptr()) == fmi2Status::OK {
                assert!(out.iter().all(|x| x.is_finite()), "{out:?}");
            }
        }
        fmi2FreeFMUstate(f.c, &mut saved);
        let mut g = Fmu3::new();
        for _ in 0..60 {
            let mut t = 0.0;
            fmi3GetFloat64(g.c, &0, 1, &mut t, 1);
            let before = g.log_len();
            let st = call3(&mut g, &mut rng, t);
            assert!(matches!(st, fmi3Status::OK | fmi3Status::Error), "{st:?}");
            assert_eq!(g.log_len() - before, usize::from(st == fmi3Status::Error));
        }
    }
    assert!(
        errors > 100,
        "the sweep should provoke refusals, got {errors}"
    );
}
