//! The FMU state through the exported FMI 3.0 functions: get, set, serialize and de-serialize
//! round trips bit for bit (the same future from a restored state), a too small buffer and
//! garbage bytes refused, and one state format: the FMI 2.0 twin restores the FMI 3.0 bytes.
//!
//! Uses `tests/common/fmi3.rs` (`Fmu3`, `expect_error!`, `outputs`, `drive` of the FMI 2.0 twin).

mod common;

use common::fmi3::*;
use connector_fmu::fmi2::exports as f2;
use connector_fmu::fmi2::types::fmi2Status;
use connector_fmu::fmi3::exports::*;
use connector_fmu::variables::Variant;
use std::ffi::c_void;
use std::ptr::null_mut;

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
