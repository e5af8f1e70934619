//! Regression 005 (found by the `fmi_calls` fuzz target on e2e21fe; the cause is older):
//! fmi2ExitInitializationMode accepted velocity inputs so large that the connector's outputs
//! or its dissipation power were not finite (a.w[1] = f64::MAX: CV = ±INF and a power of
//! 0·INF = NaN; b.v = 1e200 on a damped component: finite outputs but c·v² = +INF). The non-finite
//! power was committed into the connector state: the first fmi2DoStep could only fail, and a
//! state taken then was written by fmi2SerializeFMUstate but refused by fmi2DeSerializeFMUstate
//! ("energy is not finite"). Fixed: initialization is refused with fmi2Error and one message;
//! the instance stays in Initialization Mode, so correcting the input and calling
//! fmi2ExitInitializationMode again succeeds.

mod common;

use common::*;
use connector_fmu::fmi2::exports::*;
use connector_fmu::fmi2::types::*;
use connector_fmu::variables::VARIANTS;

const OK: fmi2Status = fmi2Status::OK;

#[test]
fn initialization_with_overflowing_velocities_is_refused_and_recoverable() {
    for spec in VARIANTS {
        // all three components, so that a damped component is always among them
        for (input, x) in [("a.w", f64::MAX), ("b.v", 1e200), ("b.w", 1e200)] {
            let f = Fmu::new(spec.variant);
            if !f.has(&format!("{input}[1]")) {
                continue;
            }
            let set = |x: f64| {
                for i in 1..=3 {
                    assert_eq!(f.set_real(&format!("{input}[{i}]"), x), OK);
                }
            };
            f.enter_init();
            for k in 1..=6 {
                f.set_real_if(&format!("damping.c{k}"), 1.0);
                f.set_real_if(&format!("elasticity.k{k}"), 10.0);
            }
            f.set_real_if("b.r[1]", 0.1);
            f.set_real_if("b.r[3]", 0.05);
            set(x);
            let n = f.log_len();
            let status = fmi2ExitInitializationMode(f.c);
            assert_error_logged(&f, n, status, "fmi2ExitInitializationMode");
            assert!(
                f.log()[n].message.contains("not finite"),
                "{:?} {input}: {:?}",
                spec.variant,
                f.log()[n]
            );
            // still in Initialization Mode: fix the input and initialize
            set(0.5);
            f.exit_init();
            assert_eq!(f.step(0.0, 1e-3), OK, "{:?}", f.log());
            // the state round-trips through its bytes
            let mut back = f.round_trip_state();
            assert_eq!(fmi2FreeFMUstate(f.c, &mut back), OK);
        }
    }
}
