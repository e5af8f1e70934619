//! Regression 002 (found by the `fmi_calls` fuzz target): fmi2ExitInitializationMode refused a
//! degenerate orientation (here a.q = (−5e-324, 0, 0, 0)) with the message "orientation a.q =
//! (…) is not a rotation…", the only refusal whose message did not name the FMI function that
//! returned the error (fmi2DoStep wraps the same check with its name); and it printed the
//! components with `{}`, so −5e-324 became a 330-character decimal. Fixed: the message is
//! "fmi2ExitInitializationMode: orientation a.q = (-5e-324, 0.0, 0.0, 0.0) is not a rotation…"
//! (components in shortest round-trip form, `{:?}`).

mod common;

use common::*;
use connector_fmu::fmi2::exports::*;
use connector_fmu::variables::VARIANTS;

#[test]
fn exit_initialization_names_itself_and_the_orientation() {
    for spec in VARIANTS {
        let f = Fmu::new(spec.variant);
        f.enter_init();
        let node = if f.has("a.q.w") { "a" } else { "b" };
        for (c, x) in ["w", "x", "y", "z"].iter().zip([-5e-324, 0.0, 0.0, 0.0]) {
            f.set_real_if(&format!("{node}.q.{c}"), x);
        }
        let n = f.log_len();
        let status = fmi2ExitInitializationMode(f.c);
        assert_error_logged(&f, n, status, "fmi2ExitInitializationMode");
        let message = &f.log()[n].message;
        assert!(message.contains(&format!("{node}.q")), "{message}");
        assert!(
            message.contains("-5e-324") && message.len() < 200,
            "{message}"
        );
        // nothing was lost: fixing the orientation lets initialization finish
        f.set_real_if(&format!("{node}.q.w"), 1.0);
        f.exit_init();
    }
}
