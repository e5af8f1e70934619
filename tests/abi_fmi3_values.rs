//! Getting and setting values through the exported FMI 3.0 functions: counts that must match for
//! scalar variables, unknown value references, wrong types and NaN refused all or nothing, the
//! types without variables (any request refused, empty ones accepted), Booleans as bytes, and the
//! outputs of the FMI 2.0 twin: the same variant driven through fmi2* and fmi3* along the same
//! inputs and variable steps gives the same outputs bit for bit.
//!
//! Uses `tests/common/fmi3.rs` (`Fmu3`, `expect_error!`, `outputs`, `drive` of the FMI 2.0 twin).

mod common;

use common::fmi3::*;
use connector_fmu::fmi2::types::fmi2Status;
use connector_fmu::fmi3::exports::*;
use connector_fmu::fmi3::types::*;
use connector_fmu::variables::{table, Start, Variant, VARIANTS};
use std::ptr::{null, null_mut};

// ------------------------------------------------------------------ refused requests

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

/// Every variant has Boolean parameters (`reference.given<k>`, SPEC §3): the first of each reads
/// back as a byte. A variant without one fails the test rather than skipping it.
#[test]
fn booleans_read_as_bytes() {
    for v in VARIANTS.iter().map(|s| s.variant) {
        let vr = table(v)
            .vars
            .iter()
            .find(|x| matches!(x.start, Start::Boolean(_)))
            .unwrap_or_else(|| panic!("{v:?} has no Boolean parameter (reference.given<k>)"))
            .vr;
        let f = Fmu3::new(v);
        // any non-zero byte is true, and the FMU writes 1
        assert_eq!(fmi3SetBoolean(f.c, &vr, 1, &7u8, 1), OK, "{:?}", f.log());
        f.enter_init();
        let mut b = 9u8;
        assert_eq!(fmi3GetBoolean(f.c, &vr, 1, &mut b, 1), OK);
        assert_eq!(b, 1, "{v:?}");
        assert_eq!(fmi3SetBoolean(f.c, &vr, 1, &0u8, 1), OK);
        assert_eq!(fmi3GetBoolean(f.c, &vr, 1, &mut b, 1), OK);
        assert_eq!(b, 0, "{v:?}");
    }
}

// ------------------------------------------------------------------ the FMI 2.0 twin

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
