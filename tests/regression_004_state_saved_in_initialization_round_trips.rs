//! Regression 004 (found by the `fmi_calls` fuzz target): an FMU state taken before
//! fmi2ExitInitializationMode could hold a parameter combination that only initialization
//! refuses (here friction.coupling = 1 with friction.R = 0; also stop.lower > stop.upper or
//! μ_k > μ_s): the setters accept each value on its own and the cross-parameter rules are
//! checked at fmi2ExitInitializationMode (docs/fmi.md, "Bad input"). fmi2SerializeFMUstate wrote such a state,
//! but fmi2DeSerializeFMUstate ran the cross-parameter check on every state and refused the
//! bytes ("invalid parameter friction.coupling = 1 needs friction.R > 0") — a state this FMU
//! had written could not be read back. Fixed: de-serialization applies the cross-parameter
//! check only to states past initialization (where the setters enforce it); per-value checks
//! apply always. Initialization still refuses the combination.

mod common;

use common::*;
use connector_fmu::fmi2::exports::*;
use connector_fmu::fmi2::types::*;
use connector_fmu::variables::Variant;
use std::ptr::null_mut;

const OK: fmi2Status = fmi2Status::OK;

#[test]
fn a_state_with_pending_cross_parameter_rules_round_trips() {
    for (setup, name) in [
        (&[("friction.muStatic", 0.3)][..], "friction.coupling"),
        (
            &[("stop.lower2", 0.1), ("stop.upper2", -0.1)][..],
            "stop.lower2",
        ),
        (
            &[("friction.muStatic", 0.2), ("friction.muKinetic", 0.3)][..],
            "friction.muKinetic",
        ),
    ] {
        for in_init in [false, true] {
            let f = Fmu::new(Variant::Planar);
            if in_init {
                f.enter_init();
            }
            for (p, x) in setup {
                assert_eq!(f.set_real(p, *x), OK);
            }
            if name == "friction.coupling" {
                let vr = f.vr("friction.coupling");
                assert_eq!(fmi2SetInteger(f.c, &vr, 1, &1), OK);
            }
            let mut s = f.round_trip_state();
            assert_eq!(fmi2SetFMUstate(f.c, s), OK, "{:?}", f.log());
            assert_eq!(fmi2FreeFMUstate(f.c, &mut s), OK);
            // initialization still refuses the combination, naming the parameter
            if !in_init {
                f.enter_init();
            }
            let n = f.log_len();
            let status = fmi2ExitInitializationMode(f.c);
            assert_error_logged(&f, n, status, "fmi2ExitInitializationMode");
            assert!(f.log()[n].message.contains(name), "{:?}", f.log()[n]);
        }
    }
}

#[test]
fn corrupt_cross_parameters_after_initialization_are_still_refused() {
    // a state past initialization with stop.lower2 > stop.upper2 (bytes patched, checksum
    // fixed) is refused: there the setters enforce the rule, so such bytes are corrupt
    let f = Fmu::new(Variant::Planar);
    f.enter_init();
    assert_eq!(f.set_real("stop.lower2", -0.5), OK);
    assert_eq!(f.set_real("stop.upper2", 0.5), OK);
    f.exit_init();
    let mut s: fmi2FMUstate = null_mut();
    assert_eq!(fmi2GetFMUstate(f.c, &mut s), OK);
    let mut n = 0usize;
    assert_eq!(fmi2SerializedFMUstateSize(f.c, s, &mut n), OK);
    let mut bytes = vec![0u8; n];
    assert_eq!(
        fmi2SerializeFMUstate(f.c, s, bytes.as_mut_ptr().cast(), n),
        OK
    );
    assert_eq!(fmi2FreeFMUstate(f.c, &mut s), OK);
    // swap the two stop values (−0.5 and 0.5 appear once each as f64)
    let find = |x: f64| {
        let b = x.to_le_bytes();
        bytes
            .windows(8)
            .position(|w| w == b)
            .expect("value present")
    };
    let (lo, hi) = (find(-0.5), find(0.5));
    bytes[lo..lo + 8].copy_from_slice(&0.5f64.to_le_bytes());
    bytes[hi..hi + 8].copy_from_slice(&(-0.5f64).to_le_bytes());
    let body = n - 8;
    let sum = common::fnv1a(&bytes[..body]);
    bytes[body..].copy_from_slice(&sum.to_le_bytes());
    let mut back: fmi2FMUstate = null_mut();
    let before = f.log_len();
    let status = fmi2DeSerializeFMUstate(f.c, bytes.as_ptr().cast(), n, &mut back);
    assert_error_logged(&f, before, status, "fmi2DeSerializeFMUstate");
    assert!(
        f.log()[before].message.contains("stop.lower2"),
        "{:?}",
        f.log()[before]
    );
    assert!(back.is_null());
}
