//! The operations of FMI 3.0 only that `fmi3.rs` dispatches to: adjoint derivatives, Get/Set
//! of the types this FMU has no variables of, the refused functions of Event Mode, clocks,
//! configuration, Model Exchange and Scheduled Execution (invariant 9), variable dependencies,
//! and the other instantiation functions. Uses `api`, `program`, `ops` (derivative arguments),
//! `fmi3` (its logger) and `support` (log, GUIDs).

use super::api::{St, OK};
use super::fmi3::{logger3, Fmi3};
use super::program::Program;
use super::support;
use connector_fmu::fmi3::exports::*;
use connector_fmu::fmi3::types::*;
use connector_fmu::variables::{table, Variant};
use std::ffi::{c_int, c_void, CStr, CString};
use std::ptr::null;

/// fmi3GetAdjointDerivative (seed per unknown, sensitivity per known; sometimes a count off).
pub(super) fn adjoint(p: &mut Program<'_, Fmi3>, i: usize, v: Variant) {
    let a = p.der_args(v, true);
    let off = p.b.u8() % 8;
    let n_seed = a.seed.len() + usize::from(off == 0);
    let n_sens = a.knowns.len() + usize::from(off == 1);
    let seed = [a.seed.clone(), vec![1.0]].concat();
    let mut out = vec![f64::NAN; a.knowns.len() + 1];
    p.trace.push(format!(
        "adjoint[{i}] {:?} {:?} {:?} off {off}",
        a.unknowns, a.knowns, a.seed
    ));
    let s = p.call(i, "fmi3GetAdjointDerivative", |c| {
        fmi3GetAdjointDerivative(
            c,
            a.unknowns.as_ptr(),
            a.unknowns.len(),
            a.knowns.as_ptr(),
            a.knowns.len(),
            seed.as_ptr(),
            n_seed,
            out.as_mut_ptr(),
            n_sens,
        )
        .into()
    });
    if s == OK {
        if off < 2 {
            p.fail("fmi3GetAdjointDerivative accepted a wrong nSeed or nSensitivity".into());
        }
        if let Some(x) = out[..n_sens].iter().find(|x| !x.is_finite()) {
            p.fail(format!("fmi3GetAdjointDerivative OK with a value {x}"));
        }
    }
}

/// Get/Set of the types this FMU has no variables of (an empty request is OK, any value
/// reference an error), with nValues sometimes differing from nValueReferences.
pub(super) fn other_types(p: &mut Program<'_, Fmi3>, i: usize, v: Variant) {
    let which = p.b.u8() % 24;
    let n = p.b.u8() as usize % 3;
    let vrs: Vec<u32> = (0..n)
        .map(|_| {
            let ty = p.b.u8() % 3;
            p.vr(v, ty)
        })
        .collect();
    let nv = if p.b.u8().is_multiple_of(4) { n + 1 } else { n };
    p.trace
        .push(format!("otherType[{i}] {which} {vrs:?} nValues {nv}"));
    let vp = vrs.as_ptr();
    // room for nv values of any type (8 bytes each, aligned)
    let mut raw = [0u64; 4];
    let out = raw.as_mut_ptr();
    let mut sizes = [0usize; 4];
    let mut bins: [fmi3Binary; 4] = [null(); 4];
    let strs: [fmi3String; 4] = [c"x".as_ptr(); 4];
    macro_rules! pair {
        ($get:ident, $set:ident, $t:ty, $g:expr) => {{
            let s = if $g {
                p.call(i, stringify!($get), |c| {
                    $get(c, vp, n, out.cast::<$t>(), nv).into()
                })
            } else {
                p.call(i, stringify!($set), |c| {
                    $set(c, vp, n, out.cast::<$t>().cast_const(), nv).into()
                })
            };
            if s == OK && n > 0 {
                p.fail(format!(
                    "{} OK for a type this FMU has no variables of",
                    stringify!($get)
                ));
            }
        }};
    }
    let get = which.is_multiple_of(2);
    match which / 2 {
        0 => pair!(fmi3GetFloat32, fmi3SetFloat32, f32, get),
        1 => pair!(fmi3GetInt8, fmi3SetInt8, i8, get),
        2 => pair!(fmi3GetUInt8, fmi3SetUInt8, u8, get),
        3 => pair!(fmi3GetInt16, fmi3SetInt16, i16, get),
        4 => pair!(fmi3GetUInt16, fmi3SetUInt16, u16, get),
        5 => pair!(fmi3GetUInt32, fmi3SetUInt32, u32, get),
        6 => pair!(fmi3GetInt64, fmi3SetInt64, i64, get),
        7 => pair!(fmi3GetUInt64, fmi3SetUInt64, u64, get),
        8 => {
            if get {
                pair!(fmi3GetString, fmi3SetString, fmi3String, true);
            } else {
                let s = p.call(i, "fmi3SetString", |c| {
                    fmi3SetString(c, vp, n, strs.as_ptr(), nv).into()
                });
                if s == OK && n > 0 {
                    p.fail("fmi3SetString OK without String variables".into());
                }
            }
        }
        9 => {
            let s = if get {
                p.call(i, "fmi3GetBinary", |c| {
                    fmi3GetBinary(c, vp, n, sizes.as_mut_ptr(), bins.as_mut_ptr(), nv).into()
                })
            } else {
                p.call(i, "fmi3SetBinary", |c| {
                    fmi3SetBinary(c, vp, n, sizes.as_ptr(), bins.as_ptr(), nv).into()
                })
            };
            if s == OK && n > 0 {
                p.fail("fmi3Get/SetBinary OK without Binary variables".into());
            }
        }
        10 => {
            let s = if get {
                p.call(i, "fmi3GetClock", |c| {
                    fmi3GetClock(c, vp, n, out.cast()).into()
                })
            } else {
                p.call(i, "fmi3SetClock", |c| {
                    fmi3SetClock(c, vp, n, out.cast::<u8>().cast_const()).into()
                })
            };
            if s == OK && n > 0 {
                p.fail("fmi3Get/SetClock OK without clocks".into());
            }
        }
        _ => {
            // the supported types with a count off or Boolean bytes other than 0/1
            let mut b = [2u8, 255, 1, 0];
            let s = if get {
                p.call(i, "fmi3GetBoolean", |c| {
                    fmi3GetBoolean(c, vp, n, b.as_mut_ptr(), nv).into()
                })
            } else {
                p.call(i, "fmi3SetBoolean", |c| {
                    fmi3SetBoolean(c, vp, n, b.as_ptr(), nv).into()
                })
            };
            if s == OK && nv != n {
                p.fail("fmi3Get/SetBoolean OK with nValues != nValueReferences".into());
            }
        }
    }
}

/// The functions of Event Mode, clocks, configuration, Model Exchange and Scheduled Execution:
/// each answers fmi3Error (invariant 9), whatever the arguments.
pub(super) fn refused(p: &mut Program<'_, Fmi3>, i: usize, v: Variant) {
    let which = p.b.u8() % 22;
    let vr = p.vr(v, 0);
    let x = p.b.real();
    let n = p.b.u8() as usize % 3;
    p.trace
        .push(format!("refused[{i}] {which} vr {vr} x {x} n {n}"));
    let mut f = [0.0f64; 4];
    let mut u = [0u64; 4];
    let mut u2 = [0u64; 4];
    let mut q = [0 as fmi3IntervalQualifier; 4];
    let mut b = [0u8; 6];
    let mut z = 0usize;
    let vrs = [vr; 4];
    let fp = f.as_mut_ptr();
    let name = |k: u8| -> &'static str {
        [
            "fmi3EnterEventMode",
            "fmi3UpdateDiscreteStates",
            "fmi3EvaluateDiscreteStates",
            "fmi3EnterStepMode",
            "fmi3EnterConfigurationMode",
            "fmi3ExitConfigurationMode",
            "fmi3GetIntervalDecimal",
            "fmi3GetIntervalFraction",
            "fmi3GetShiftDecimal",
            "fmi3GetShiftFraction",
            "fmi3SetIntervalDecimal",
            "fmi3SetIntervalFraction",
            "fmi3SetShiftDecimal",
            "fmi3SetShiftFraction",
            "fmi3EnterContinuousTimeMode",
            "fmi3CompletedIntegratorStep",
            "fmi3SetTime",
            "fmi3SetContinuousStates",
            "fmi3GetContinuousStateDerivatives",
            "fmi3GetEventIndicators",
            "fmi3GetContinuousStates",
            "fmi3GetNominalsOfContinuousStates",
        ][k as usize]
    };
    let s = p.call(i, name(which), |c| {
        let bp = b.as_mut_ptr();
        let s = match which {
            0 => fmi3EnterEventMode(c),
            1 => fmi3UpdateDiscreteStates(
                c,
                bp,
                bp.wrapping_add(1),
                bp.wrapping_add(2),
                bp.wrapping_add(3),
                bp.wrapping_add(4),
                fp,
            ),
            2 => fmi3EvaluateDiscreteStates(c),
            3 => fmi3EnterStepMode(c),
            4 => fmi3EnterConfigurationMode(c),
            5 => fmi3ExitConfigurationMode(c),
            6 => fmi3GetIntervalDecimal(c, vrs.as_ptr(), n, fp, q.as_mut_ptr()),
            7 => fmi3GetIntervalFraction(
                c,
                vrs.as_ptr(),
                n,
                u.as_mut_ptr(),
                u2.as_mut_ptr(),
                q.as_mut_ptr(),
            ),
            8 => fmi3GetShiftDecimal(c, vrs.as_ptr(), n, fp),
            9 => fmi3GetShiftFraction(c, vrs.as_ptr(), n, u.as_mut_ptr(), u2.as_mut_ptr()),
            10 => fmi3SetIntervalDecimal(c, vrs.as_ptr(), n, fp),
            11 => fmi3SetIntervalFraction(c, vrs.as_ptr(), n, u.as_ptr(), u2.as_ptr()),
            12 => fmi3SetShiftDecimal(c, vrs.as_ptr(), n, fp),
            13 => fmi3SetShiftFraction(c, vrs.as_ptr(), n, u.as_ptr(), u2.as_ptr()),
            14 => fmi3EnterContinuousTimeMode(c),
            15 => fmi3CompletedIntegratorStep(c, fmi3False, bp, bp.wrapping_add(1)),
            16 => fmi3SetTime(c, x),
            17 => fmi3SetContinuousStates(c, fp, n),
            18 => fmi3GetContinuousStateDerivatives(c, fp, n),
            19 => fmi3GetEventIndicators(c, fp, n),
            20 => fmi3GetContinuousStates(c, fp, n),
            _ => fmi3GetNominalsOfContinuousStates(c, fp, n),
        };
        s.into()
    });
    if s != St::Error {
        p.fail(format!("{} answered {s:?}, not fmi3Error", name(which)));
    }
    let which2 = p.b.u8() % 3;
    let name2 = [
        "fmi3GetNumberOfEventIndicators",
        "fmi3GetNumberOfContinuousStates",
        "fmi3ActivateModelPartition",
    ][which2 as usize];
    let s = p.call(i, name2, |c| {
        match which2 {
            0 => fmi3GetNumberOfEventIndicators(c, &mut z),
            1 => fmi3GetNumberOfContinuousStates(c, &mut z),
            _ => fmi3ActivateModelPartition(c, vr, x),
        }
        .into()
    });
    if s != St::Error {
        p.fail(format!("{name2} answered {s:?}, not fmi3Error"));
    }
}

/// fmi3GetNumberOfVariableDependencies then fmi3GetVariableDependencies (sometimes with a
/// wrong count); an OK answer lists value references of the variant.
pub(super) fn dependencies(p: &mut Program<'_, Fmi3>, i: usize, v: Variant) {
    let ty = p.b.u8() % 3;
    let vr = p.vr(v, ty);
    let mut n = usize::MAX;
    p.trace.push(format!("dependencies[{i}] {vr}"));
    let s = p.call(i, "fmi3GetNumberOfVariableDependencies", |c| {
        fmi3GetNumberOfVariableDependencies(c, vr, &mut n).into()
    });
    let k = match (s, p.b.u8() % 4) {
        (OK, 0) => n + 1,
        (OK, _) => n,
        _ => p.b.u8() as usize % 3,
    };
    if k > table(v).vars.len() + 1 {
        p.fail(format!("fmi3GetNumberOfVariableDependencies OK with {n}"));
    }
    let mut e_dep = vec![usize::MAX; k];
    let mut indep = vec![u32::MAX; k];
    let mut e_indep = vec![usize::MAX; k];
    let mut kinds = vec![fmi3DependencyKind::Independent; k];
    let s2 = p.call(i, "fmi3GetVariableDependencies", |c| {
        fmi3GetVariableDependencies(
            c,
            vr,
            e_dep.as_mut_ptr(),
            indep.as_mut_ptr(),
            e_indep.as_mut_ptr(),
            kinds.as_mut_ptr(),
            k,
        )
        .into()
    });
    if s2 == OK {
        if s != OK || k != n {
            p.fail(format!(
                "fmi3GetVariableDependencies OK with nDependencies {k} (number: {s:?} {n})"
            ));
        }
        if indep.iter().any(|&x| table(v).get(x).is_none())
            || e_dep.iter().chain(&e_indep).any(|&e| e != 0)
        {
            p.fail(format!(
                "fmi3GetVariableDependencies OK with {indep:?} {e_dep:?} {e_indep:?}"
            ));
        }
    }
}

/// fmi3GetVersion, and the instantiation functions of the interfaces this FMU has not: NULL
/// and, with a logger, exactly one error naming the function.
pub(super) fn other_interfaces(p: &mut Program<'_, Fmi3>, i: usize) {
    // SAFETY: fmi3GetVersion returns a static NUL-terminated string.
    let version = unsafe { CStr::from_ptr(fmi3GetVersion()) };
    if version.to_bytes() != b"3.0" {
        p.fail(format!("fmi3GetVersion {version:?}"));
    }
    let which = p.b.u8() % 4;
    let logger = which < 2;
    let log = if logger {
        Some(logger3 as fmi3LogMessageCallback)
    } else {
        None
    };
    let env = p.env.0 as *mut c_void;
    let token = CString::new(support::guid(p.variant(i).expect("live"))).expect("no NUL");
    let n0 = support::log_len(p.env.0);
    p.trace.push(format!("otherInterface[{i}] {which}"));
    let (fname, c) = if which.is_multiple_of(2) {
        (
            "fmi3InstantiateModelExchange",
            fmi3InstantiateModelExchange(c"me".as_ptr(), token.as_ptr(), null(), 0, 0, env, log),
        )
    } else {
        (
            "fmi3InstantiateScheduledExecution",
            fmi3InstantiateScheduledExecution(
                c"se".as_ptr(),
                token.as_ptr(),
                null(),
                0,
                0,
                env,
                log,
                None,
                None,
                None,
            ),
        )
    };
    let lines = support::log_since(p.env.0, n0);
    if !c.is_null() {
        p.fail(format!("{fname} returned an instance"));
    }
    let want = usize::from(logger);
    if lines.len() != want
        || lines
            .iter()
            .any(|l| l.status != St::Error as c_int || !l.message.contains(fname))
    {
        p.fail(format!(
            "{fname} must log one error when it has a logger: {lines:?}"
        ));
    }
}
