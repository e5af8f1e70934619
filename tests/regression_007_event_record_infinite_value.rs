//! Regression 007 (found by the `fmi_calls` fuzz target on the FMI 3.0 programs, introduced with
//! event location): the event-function record saved with the FMU state holds the functions'
//! values at the last step's end, and a function far from its event can overflow while every
//! output stays finite (a node at −1.7e308 below a stop at +1.7e308: penetration c − upper =
//! −INF). fmi2SerializeFMUstate wrote that value and fmi2DeSerializeFMUstate refused it ("event
//! function is not finite"): a state the FMU wrote could not be read back. Fixed: ±INF is a
//! value of the record (NaN alone marks a function not taking part, and is refused as a value).

mod common;

use common::*;
use connector_fmu::fmi2::exports::*;
use connector_fmu::fmi2::types::*;
use connector_fmu::variables::Variant;

const OK: fmi2Status = fmi2Status::OK;

#[test]
fn a_state_with_an_infinite_event_function_round_trips() {
    let f = Fmu::new(Variant::ProjectionCartesian);
    f.enter_init();
    f.set_real_if("stop.upper1", 1.7e308);
    f.exit_init();
    f.set_real_if("b.r[1]", -1.7e308);
    assert_eq!(f.step(0.0, 1e-3), OK, "{:?}", f.log());
    let reals = f.outputs(false);
    assert!(f.get_reals(&reals).iter().all(|x| x.is_finite()));
    // the record now holds −INF for the upper stop; the state round-trips through bytes
    let mut back = f.round_trip_state();
    // and steps from it as from the original
    assert_eq!(fmi2SetFMUstate(f.c, back), OK);
    assert_eq!(f.step(1e-3, 1e-3), OK, "{:?}", f.log());
    assert_eq!(fmi2FreeFMUstate(f.c, &mut back), OK);
}
