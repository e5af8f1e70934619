//! FMU states through the C functions of both versions: get/set and serialize/deserialize
//! round trips repeat a step bit for bit (in the instance that saved the state, in a fresh one,
//! and across FMI versions), a state saved in Initialization Mode restores that mode, and
//! corrupt, truncated or foreign bytes and short buffers are refused with the instance
//! unchanged. Uses `common` and the crate's exports.

mod common;

use body_fmu::fmi2::exports::*;
use body_fmu::fmi2::types::*;
use body_fmu::fmi3::exports::*;
use body_fmu::fmi3::types::*;
use common::*;
use std::ffi::c_void;
use std::ptr::null_mut;

/// A spinning, falling rigid body under a force and a moment, after a few steps.
fn rigid2() -> Fmu2 {
    let mut f = Fmu2::new();
    f.enter();
    assert_eq!(f.set_int("model", 1), fmi2Status::OK);
    for (n, x) in [
        ("mass", 2.5),
        ("inertia[1]", 0.3),
        ("inertia[2]", 0.5),
        ("inertia[3]", 0.7),
        ("gravity[3]", -9.81),
        ("start.w[1]", 3.0),
        ("start.w[2]", -1.0),
        ("start.w[3]", 7.0),
        ("f[1]", 1.5),
        ("m[2]", 0.25),
    ] {
        assert_eq!(f.set(n, x), fmi2Status::OK, "{n}");
    }
    assert_eq!(fmi2ExitInitializationMode(f.c), fmi2Status::OK);
    for _ in 0..3 {
        f.step(0.01);
    }
    f
}

fn bits(x: [f64; 15]) -> [u64; 15] {
    x.map(f64::to_bits)
}

#[test]
fn get_set_and_serialized_states_repeat_a_step_bit_for_bit() {
    let mut f = rigid2();
    let mut s: fmi2FMUstate = null_mut();
    assert_eq!(fmi2GetFMUstate(f.c, &mut s), fmi2Status::OK);
    let t0 = f.t;
    f.step(0.02);
    let first = bits(f.outputs());
    // restore and repeat
    assert_eq!(fmi2SetFMUstate(f.c, s), fmi2Status::OK);
    f.t = t0;
    f.step(0.02);
    assert_eq!(bits(f.outputs()), first);
    // serialize, deserialize into a fresh instance, repeat there
    let mut n = 0usize;
    assert_eq!(fmi2SerializedFMUstateSize(f.c, s, &mut n), fmi2Status::OK);
    let mut bytes = vec![0 as fmi2Byte; n];
    assert_eq!(
        fmi2SerializeFMUstate(f.c, s, bytes.as_mut_ptr(), n),
        fmi2Status::OK
    );
    let mut g = Fmu2::new();
    let mut s2: fmi2FMUstate = null_mut();
    assert_eq!(
        fmi2DeSerializeFMUstate(g.c, bytes.as_ptr(), n, &mut s2),
        fmi2Status::OK
    );
    assert_eq!(fmi2SetFMUstate(g.c, s2), fmi2Status::OK);
    g.t = t0;
    g.step(0.02);
    assert_eq!(bits(g.outputs()), first);
    // across versions: the FMI 2.0 bytes restore in an FMI 3.0 instance
    let mut h = Fmu3::new();
    let mut s3: fmi3FMUState = null_mut();
    let bytes3: Vec<u8> = bytes.iter().map(|&b| b as u8).collect();
    assert_eq!(
        fmi3DeserializeFMUState(h.c, bytes3.as_ptr(), n, &mut s3),
        fmi3Status::OK
    );
    assert_eq!(fmi3SetFMUState(h.c, s3), fmi3Status::OK);
    h.t = t0;
    h.step(0.02);
    assert_eq!(bits(h.outputs()), first);
    // a state handle is overwritten in place when passed back
    assert_eq!(fmi2GetFMUstate(f.c, &mut s), fmi2Status::OK);
    for (c, st) in [(f.c, &mut s), (g.c, &mut s2)] {
        assert_eq!(fmi2FreeFMUstate(c, st), fmi2Status::OK);
        assert!(st.is_null());
    }
    assert_eq!(fmi3FreeFMUState(h.c, &mut s3), fmi3Status::OK);
    assert_eq!(fmi2FreeFMUstate(f.c, null_mut()), fmi2Status::OK);
    assert!(log_of(f.env).is_empty() && log_of(g.env).is_empty());
}

#[test]
fn a_state_saved_in_initialization_mode_restores_that_mode() {
    let f = Fmu2::new();
    f.enter();
    assert_eq!(f.set("start.r[2]", 4.0), fmi2Status::OK);
    let mut s: fmi2FMUstate = null_mut();
    assert_eq!(fmi2GetFMUstate(f.c, &mut s), fmi2Status::OK);
    assert_eq!(fmi2ExitInitializationMode(f.c), fmi2Status::OK);
    assert_eq!(fmi2SetFMUstate(f.c, s), fmi2Status::OK);
    // in Initialization Mode again: parameters may be set, ExitInitializationMode works
    assert_eq!(f.set("start.r[2]", 5.0), fmi2Status::OK);
    assert_eq!(fmi2ExitInitializationMode(f.c), fmi2Status::OK);
    assert_eq!(f.get("r[2]"), 5.0);
    assert_eq!(fmi2FreeFMUstate(f.c, &mut s), fmi2Status::OK);
}

#[test]
fn corrupt_foreign_or_short_bytes_are_refused_and_change_nothing() {
    let f = rigid2();
    let mut s: fmi2FMUstate = null_mut();
    assert_eq!(fmi2GetFMUstate(f.c, &mut s), fmi2Status::OK);
    let mut n = 0usize;
    assert_eq!(fmi2SerializedFMUstateSize(f.c, s, &mut n), fmi2Status::OK);
    let mut bytes = vec![0 as fmi2Byte; n];
    assert_eq!(
        fmi2SerializeFMUstate(f.c, s, bytes.as_mut_ptr(), n - 1),
        fmi2Status::Error
    );
    assert_eq!(
        fmi2SerializeFMUstate(f.c, s, bytes.as_mut_ptr(), n),
        fmi2Status::OK
    );
    let before = bits(f.outputs());
    let mut out: fmi2FMUstate = null_mut();
    let mut tries = 0;
    for i in (0..n).step_by(7) {
        let mut bad = bytes.clone();
        bad[i] ^= 0x5a;
        let st = fmi2DeSerializeFMUstate(f.c, bad.as_ptr(), n, &mut out);
        assert_eq!(st, fmi2Status::Error, "byte {i}");
        assert!(out.is_null());
        tries += 1;
    }
    assert_eq!(
        fmi2DeSerializeFMUstate(f.c, bytes.as_ptr(), n - 3, &mut out),
        fmi2Status::Error
    );
    let foreign = vec![1 as fmi2Byte; n];
    assert_eq!(
        fmi2DeSerializeFMUstate(f.c, foreign.as_ptr(), n, &mut out),
        fmi2Status::Error
    );
    assert_eq!(bits(f.outputs()), before);
    let log = log_of(f.env);
    assert_eq!(log.len(), tries + 3, "one message per refusal");
    assert!(log[0].message.contains("smaller than the serialized state"));
    assert!(log
        .iter()
        .skip(1)
        .all(|l| l.message.starts_with("fmi2DeSerializeFMUstate: ")));
    assert!(log.iter().any(|l| l.message.contains("checksum")));
    assert!(log.iter().any(|l| l.message.contains("wrong magic")));
    assert_eq!(fmi2FreeFMUstate(f.c, &mut s), fmi2Status::OK);
}

#[test]
fn fmi3_states_round_trip_too() {
    let mut f = Fmu3::new();
    f.enter();
    for (n, x) in [
        ("gravity[1]", 1.0),
        ("spring.k[1]", 100.0),
        ("start.r[1]", 0.1),
    ] {
        assert_eq!(f.set(n, x), fmi3Status::OK);
    }
    assert_eq!(fmi3ExitInitializationMode(f.c), fmi3Status::OK);
    f.step(0.01);
    let mut s: fmi3FMUState = null_mut();
    assert_eq!(fmi3GetFMUState(f.c, &mut s), fmi3Status::OK);
    let mut n = 0usize;
    assert_eq!(fmi3SerializedFMUStateSize(f.c, s, &mut n), fmi3Status::OK);
    let mut bytes = vec![0u8; n];
    assert_eq!(
        fmi3SerializeFMUState(f.c, s, bytes.as_mut_ptr(), n),
        fmi3Status::OK
    );
    f.step(0.03);
    let first = bits(f.outputs());
    let mut s2: fmi3FMUState = null_mut();
    assert_eq!(
        fmi3DeserializeFMUState(f.c, bytes.as_ptr(), n, &mut s2),
        fmi3Status::OK
    );
    assert_eq!(fmi3SetFMUState(f.c, s2), fmi3Status::OK);
    f.t = 0.01;
    f.step(0.03);
    assert_eq!(bits(f.outputs()), first);
    // the FMI 3.0 bytes restore in an FMI 2.0 instance
    let mut g = Fmu2::new();
    let mut s3: fmi2FMUstate = null_mut();
    let p = bytes.as_ptr().cast::<fmi2Byte>();
    assert_eq!(fmi2DeSerializeFMUstate(g.c, p, n, &mut s3), fmi2Status::OK);
    assert_eq!(fmi2SetFMUstate(g.c, s3), fmi2Status::OK);
    g.t = 0.01;
    g.step(0.03);
    assert_eq!(bits(g.outputs()), first);
    for st in [&mut s, &mut s2] {
        assert_eq!(fmi3FreeFMUState(f.c, st), fmi3Status::OK);
    }
    assert_eq!(fmi2FreeFMUstate(g.c, &mut s3), fmi2Status::OK);
    assert_eq!(
        fmi3SetFMUState(f.c, null_mut::<c_void>()),
        fmi3Status::Error
    );
}
