//! The PLANAR friction law through the kernel's public API, against the seed's formulas and
//! closed forms (the mutants of src/physics/friction that the other tests let pass):
//! - the stick → slip event function is the trial force minus its limit, separately per effect
//!   and on the coupled ellipsoid |(f2, f3, m1/ρ)| ≤ μ F_NC (ρ = 2R/3), and its sign is the
//!   return map's stick/slip decision;
//! - the slip speeds μ is taken at: |(ẏ, ż)| for sliding, ρ|α̇| for spin (|α̇| when R = 0), both
//!   together when coupled; a slipping spin's moment is μ(ρ|α̇|)·M_NR1 with the seed's decay;
//! - a slipping effect with a stick damper: its elastic slip at the end of the substep solves
//!   c ė + k e = f(τ) under the force ramp, checked against RK4 with 20,000 steps;
//! - μ = 0 (both coefficients) turns friction off, μ_s > 0 alone turns it on.

use connector_fmu::physics::friction::{
    normal_loads, slip_speeds, stick_slip_function, update, Eval, FrictionParams, FrictionState,
    Status,
};

#[path = "common/lcg.rs"]
mod lcg;
use lcg::Lcg;

fn params(coupling: i32) -> FrictionParams {
    FrictionParams {
        mu_static: 0.5,
        mu_kinetic: 0.3,
        decay: 2.0,
        radius: 0.06,
        f_int: 20.0,
        m_int: 1.0,
        k_stick: 1e4,
        k_stick_r1: 1e2,
        coupling,
        ..FrictionParams::default()
    }
}

/// From a fresh state (no plastic slip) the trial is the stick springs' k·pos: the event
/// function is |(k y, k z)| − μ_s F_NC and |k_r1 α| − μ_s M_NR1 separately, and
/// |(k y, k z, k_r1 α / ρ)| − μ_s F_NC coupled (SPEC §5), to round-off; the return map slips
/// exactly where it is positive.
#[test]
fn the_stick_slip_event_function_is_the_trial_minus_the_limit() {
    let mut rng = Lcg(11);
    let (mut slips, mut sticks) = (0, 0);
    for coupling in [0, 1] {
        let p = params(coupling);
        let rho = 2.0 / 3.0 * p.radius;
        for _ in 0..400 {
            let reaction = [30.0 * rng.next(), 2.0 * rng.next(), 2.0 * rng.next()];
            let (f_nc, m_nr1) = normal_loads(&p, reaction[0], reaction[1], reaction[2]);
            let pos = [3e-3 * rng.next(), 3e-3 * rng.next(), 3e-2 * rng.next()];
            let (f2, f3, m1) = (
                p.k_stick * pos[0],
                p.k_stick * pos[1],
                p.k_stick_r1 * pos[2],
            );
            let phi =
                stick_slip_function(&p, &FrictionState::default(), pos, [0.0; 3], (f_nc, m_nr1));
            let want = if coupling == 1 {
                let v = ((f2 * f2 + f3 * f3) + (m1 / rho) * (m1 / rho)).sqrt() - 0.5 * f_nc;
                [v, v]
            } else {
                [
                    (f2 * f2 + f3 * f3).sqrt() - 0.5 * f_nc,
                    m1.abs() - 0.5 * m_nr1,
                ]
            };
            for i in 0..2 {
                // round-off of sums of O(100 N) terms
                assert!(
                    (phi[i] - want[i]).abs() < 1e-10,
                    "{coupling}: {phi:?} vs {want:?}"
                );
            }
            let r = update(
                &p,
                &FrictionState::default(),
                reaction,
                pos,
                [0.0; 3],
                Eval::Step(1e-3),
            );
            let statuses = [r.out.status, r.out.status_r1];
            for i in 0..2 {
                if phi[i].abs() < 1e-9 {
                    continue; // on the limit: either decision is the same force
                }
                let slipping = statuses[i] == Status::Slip;
                assert_eq!(
                    slipping,
                    phi[i] > 0.0,
                    "{coupling} effect {i}: {phi:?} {statuses:?}"
                );
                if slipping {
                    slips += 1;
                } else {
                    sticks += 1;
                }
            }
        }
    }
    assert!(
        slips > 200 && sticks > 200,
        "{slips} slips, {sticks} sticks"
    );
}

#[test]
fn slip_speeds_are_the_sliding_speed_and_the_spin_at_rho() {
    let rate = [0.3, -0.4, 2.0];
    let p = params(0);
    let rho = 2.0 / 3.0 * p.radius;
    let s = slip_speeds(&p, rate);
    assert!(
        (s[0] - 0.5).abs() < 1e-15 && (s[1] - 2.0 * rho).abs() < 1e-15,
        "{s:?}"
    );
    // R = 0: the spin rate itself (1 m)
    let p0 = FrictionParams { radius: 0.0, ..p };
    assert_eq!(slip_speeds(&p0, rate)[1], 2.0);
    // coupled: one speed, |(slide, ρ spin)|
    let s = slip_speeds(&params(1), rate);
    let v = (0.25f64 + (2.0 * rho) * (2.0 * rho)).sqrt();
    assert!((s[0] - v).abs() < 1e-15 && s[1] == s[0], "{s:?}");
}

/// A spin that slips at α̇ = 3 rad/s: its moment is μ(ρ α̇) M_NR1 with
/// μ(v) = μ_k + (μ_s − μ_k) exp(−d_c v) (the seed's decay), ρ = 2R/3.
#[test]
fn a_slipping_spin_takes_mu_at_rho_times_its_rate() {
    let p = params(0);
    let rho = 2.0 / 3.0 * p.radius;
    let reaction = [-10.0, 0.0, 0.0];
    let (_, m_nr1) = normal_loads(&p, reaction[0], reaction[1], reaction[2]);
    let h = 1e-3;
    let rate = [0.0, 0.0, 3.0];
    let first = update(
        &p,
        &FrictionState::default(),
        reaction,
        [0.0, 0.0, 0.5],
        rate,
        Eval::Step(h),
    );
    assert_eq!(first.out.status_r1, Status::Slip);
    let second = update(
        &p,
        &first.state,
        reaction,
        [0.0, 0.0, 0.5 + 3.0 * h],
        rate,
        Eval::Step(h),
    );
    assert_eq!(second.out.status_r1, Status::Slip);
    let mu = p.mu_kinetic + (p.mu_static - p.mu_kinetic) * (-p.decay * rho * 3.0).exp();
    let want = mu * m_nr1;
    assert!(
        (second.out.csmc1 - want).abs() < 1e-12 * want,
        "{} vs μ(ρα̇)·M_NR1 = {want}",
        second.out.csmc1
    );
}

/// c ė + k e = f0 + (f1 − f0) τ/h from e0, by classical RK4 in n steps.
fn rk4_damped(k: f64, c: f64, h: f64, e0: f64, f0: f64, f1: f64, n: usize) -> f64 {
    let f = |t: f64, e: f64| (f0 + (f1 - f0) * t / h - k * e) / c;
    let dt = h / n as f64;
    let mut e = e0;
    for i in 0..n {
        let t = i as f64 * dt;
        let k1 = f(t, e);
        let k2 = f(t + dt / 2.0, e + dt / 2.0 * k1);
        let k3 = f(t + dt / 2.0, e + dt / 2.0 * k2);
        let k4 = f(t + dt, e + dt * k3);
        e += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    e
}

/// A slipping spin with a stick damper, its moment ramping from the committed 0.6 N.m to the
/// new limit μ M_NR1 = 1.2 N.m: the elastic slip at the end of the substep is the damped
/// spring's exact solution, at kh/c = 0.2 (the exponential form) and 2e-4 (its series); RK4
/// with 20,000 steps has an error far below the 1e-12 relative asked.
#[test]
fn a_damped_stick_spring_follows_its_ode_while_slipping() {
    let p = FrictionParams {
        mu_static: 0.4,
        mu_kinetic: 0.4,
        m_int: 2.0,
        k_stick_r1: 100.0,
        c_stick_r1: 5.0,
        ..FrictionParams::default()
    };
    for h in [1e-2, 1e-5] {
        let st = FrictionState {
            status_r1: Status::Slip,
            force: [0.0, 0.0, 0.6],
            elastic: [0.0, 0.0, 0.005],
            slip_plastic_r1: 0.0,
            ..FrictionState::default()
        };
        // M_NR1 = M_int + |(m2, m3)| = 3 N.m (R = 0): the limit 1.2 N.m
        let r = update(
            &p,
            &st,
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 0.5],
            [0.0, 0.0, 1.0],
            Eval::Step(h),
        );
        assert_eq!(r.out.status_r1, Status::Slip);
        assert!((r.force[2] - 1.2).abs() < 1e-12, "{}", r.force[2]);
        let want = rk4_damped(100.0, 5.0, h, 0.005, 0.6, 1.2, 20_000);
        let got = r.state.elastic[2];
        assert!(
            (got - want).abs() < 1e-12 * want.abs(),
            "h {h}: {got} vs {want}"
        );
    }
}

/// μ_s = μ_k = 0: a pressed contact (F_int = 20 N) moved past any stick range reports no
/// friction (status 0, no force, no dissipation); μ_s = 0.3 with μ_k = 0 is friction (stick,
/// the spring's force k·y = 1 N inside μ_s F_NC = 6 N).
#[test]
fn friction_is_off_exactly_when_both_coefficients_are_zero() {
    let with = |mu_static: f64, mu_kinetic: f64| FrictionParams {
        mu_static,
        mu_kinetic,
        f_int: 20.0,
        k_stick: 1e4,
        ..FrictionParams::default()
    };
    let st = FrictionState::default();
    let r = update(
        &with(0.0, 0.0),
        &st,
        [0.0; 3],
        [1e-4, 0.0, 0.0],
        [0.0; 3],
        Eval::Step(1e-3),
    );
    assert_eq!(
        (r.out.status, r.out.status_r1),
        (Status::NoNormal, Status::NoNormal)
    );
    assert_eq!(
        (r.force, r.stored, r.state.dissipated),
        ([0.0; 3], 0.0, 0.0)
    );
    let r = update(
        &with(0.3, 0.0),
        &st,
        [0.0; 3],
        [1e-4, 0.0, 0.0],
        [0.0; 3],
        Eval::Step(1e-3),
    );
    assert_eq!(r.out.status, Status::Stick);
    assert!((r.force[0] - 1.0).abs() < 1e-12, "{:?}", r.force);
}

mod common;

/// Read past the end of a slipping step (the slide loaded 0.1 mm further, the spin sticking):
/// the directional derivative of energy.friction along b.r[2] is the central difference's
/// (h = 1e-8 m; the plastic work is smooth there, quadratic in the motion, so the difference's
/// error is round-off, ~1e-7 of the slope). Only where both effects sit on their kinks is the
/// slope halved (docs: the central difference's value at the kink of max(0, ·)).
#[test]
fn the_friction_energy_slope_past_a_slipping_step_is_the_central_difference() {
    use connector_fmu::fmi2::exports::fmi2GetDirectionalDerivative;
    use connector_fmu::fmi2::types::fmi2Status;
    use connector_fmu::variables::Variant;
    let f = common::Fmu::new(Variant::Planar);
    f.set_real_if("friction.muStatic", 0.4);
    f.set_real_if("friction.muKinetic", 0.4);
    f.set_real_if("friction.Fint", 10.0);
    f.set_real_if("friction.Mint", 1.0);
    f.set_real_if("friction.stickStiffness", 1e5);
    f.init();
    let y0 = f.get_real("b.r[2]");
    f.set_real_if("b.v[2]", 1.0);
    assert_eq!(f.step(0.0, 1e-3), fmi2Status::OK);
    let statuses = f.get_integers(&[f.vr("friction.status"), f.vr("friction.statusR1")]);
    assert_eq!(statuses, vec![2, 1], "sliding slips, the spin sticks");
    let y = y0 + 1e-3 + 1e-4;
    let energy_at = |y: f64| {
        f.set_real_if("b.r[2]", y);
        f.get_real("energy.friction")
    };
    let h = 1e-8;
    let fd = (energy_at(y + h) - energy_at(y - h)) / (2.0 * h);
    energy_at(y);
    let (u, k, seed, mut dd) = (f.vr("energy.friction"), f.vr("b.r[2]"), 1.0, f64::NAN);
    let s = fmi2GetDirectionalDerivative(f.c, &u, 1, &k, 1, &seed, &mut dd);
    assert_eq!(s, fmi2Status::OK, "{:?}", f.log());
    // the slope is μ F_NC = 4 N (the force on the limit doing work on the plastic slip)
    assert!(fd > 1.0, "the read slips further: {fd}");
    assert!(
        (dd - fd).abs() < 1e-5 * fd,
        "dd {dd} vs central difference {fd}"
    );
}
