//! A refused step or read whose outputs would not be finite names the output and the input
//! that made it so (the input of largest magnitude), through the C ABI.

mod common;
use common::{assert_error_logged, Fmu};
use connector_fmu::fmi2::exports::fmi2GetReal;
use connector_fmu::variables::Variant;

fn last_message(f: &Fmu) -> String {
    f.log()
        .last()
        .map(|l| l.message.clone())
        .unwrap_or_default()
}

#[test]
fn a_huge_position_names_the_stored_energy_and_the_position() {
    let f = Fmu::new(Variant::Bushing);
    f.set_real_if("elasticity.k1", 1.0);
    f.init();
    // ½·k·u² overflows for u = 1e308 (the force k·u does not)
    f.set_real_if("b.r[1]", 1e308);
    let before = f.log_len();
    let status = f.step(0.0, 1e-3);
    assert_error_logged(&f, before, status, "fmi2DoStep");
    let m = last_message(&f);
    assert!(
        m.contains("output energy.stored would be inf, not finite"),
        "{m}"
    );
    assert!(m.contains("largest input: b.r[1] = 1e308"), "{m}");
}

#[test]
fn a_held_huge_velocity_names_the_damping_energy_and_the_velocity() {
    let f = Fmu::new(Variant::ProjectionCartesian);
    f.set_real_if("damping.c2", 1.0);
    f.init();
    // the damper force c·v is finite, its power c·v² is not
    f.set_real_if("b.v[2]", 1e200);
    let before = f.log_len();
    let status = f.step(0.0, 1e-3);
    assert_error_logged(&f, before, status, "fmi2DoStep");
    let m = last_message(&f);
    assert!(
        m.contains("output energy.damping would be inf, not finite"),
        "{m}"
    );
    assert!(m.contains("largest input: b.v[2] = 1e200"), "{m}");
}

#[test]
fn a_read_at_inputs_that_overflow_names_the_output_and_the_input() {
    let f = Fmu::new(Variant::ProjectionCartesian);
    f.set_real_if("elasticity.k3", 1e10);
    f.init();
    f.set_real_if("a.r[3]", -1e300);
    let vr = f.vr("energy.stored");
    let mut x = 0.0;
    let before = f.log_len();
    let status = fmi2GetReal(f.c, &vr, 1, &mut x);
    assert_error_logged(&f, before, status, "fmi2GetReal");
    let m = last_message(&f);
    // k·u overflows: the first output in the table that is not finite is named
    assert!(
        m.contains("at these inputs output a.f[1] would be NaN, not finite"),
        "{m}"
    );
    assert!(m.contains("largest input: a.r[3] = -1e300"), "{m}");
    assert_eq!(x, 0.0, "the value is not written on error");
}
