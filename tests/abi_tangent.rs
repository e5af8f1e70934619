//! The consistent tangent where a slipping step ended: the directional derivative of the
//! friction force along the slip is the slip branch's (0 for a 1-D slide at constant μ), not
//! the average of the stick and slip sides of the kink (k_s/2); in stick it is k_s, also on the
//! limit at rest (the spring holds there until the motion loads it further).

mod common;
use common::Fmu;
use connector_fmu::fmi2::exports::fmi2GetDirectionalDerivative;
use connector_fmu::fmi2::types::fmi2Status;
use connector_fmu::variables::Variant;

fn slope(f: &Fmu, unknown: &str, known: &str) -> f64 {
    let (u, k) = (f.vr(unknown), f.vr(known));
    let (seed, mut out) = (1.0, f64::NAN);
    let s = fmi2GetDirectionalDerivative(f.c, &u, 1, &k, 1, &seed, &mut out);
    assert_eq!(s, fmi2Status::OK, "{:?}", f.log());
    out
}

#[test]
fn tangent_is_the_slip_branch_where_a_slipping_step_ended() {
    let k_s = 1e5;
    let f = Fmu::new(Variant::Planar);
    f.set_real_if("friction.muStatic", 0.4);
    f.set_real_if("friction.Fint", 10.0);
    f.set_real_if("friction.stickStiffness", k_s);
    f.init();
    // in stick: the stick spring
    assert!((slope(&f, "CSF2", "b.r[2]") - k_s).abs() < 1e-6 * k_s);
    // slide 1 mm along e2 in one step (elastic range μN/k_s = 40 µm): slipping
    f.set_real_if("b.v[2]", 1.0);
    assert_eq!(f.step(0.0, 1e-3), fmi2Status::OK);
    let status = f.get_integers(&[f.vr("friction.status")])[0];
    assert_eq!(status, 2, "slipping, the slide going on");
    let along = slope(&f, "CSF2", "b.r[2]");
    assert!(
        along.abs() < 1e-6 * k_s,
        "slip tangent along the slide: {along}"
    );
    // across the slide the radial return turns the force: k_s·L/|trial| (I − n nᵀ), and
    // where the step ended the trial is on the limit, L/|trial| = 1
    let across = slope(&f, "CSF3", "b.r[3]");
    assert!((across - k_s).abs() < 1e-6 * k_s, "across: {across}");
    // brought to rest there, the spring holds at the limit: stick from the first step at rest,
    // and its stiffness
    f.set_real_if("b.v[2]", 0.0);
    assert_eq!(f.step(1e-3, 1e-3), fmi2Status::OK);
    let status = f.get_integers(&[f.vr("friction.status")])[0];
    assert_eq!(status, 1, "at rest on the limit");
    let along = slope(&f, "CSF2", "b.r[2]");
    assert!(
        (along - k_s).abs() < 1e-6 * k_s,
        "stick tangent at rest: {along}"
    );
}
