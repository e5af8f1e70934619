//! Tests of the friction law: the return map per effect and coupled (stick, slip, breakaway at
//! μ_s, the decay), the stick dampers (parallel to the spring, the elastic slip integrated exactly
//! while slipping), the event functions against what the return map decides, and the energy
//! balance along paths of substeps. Uses the module above (`super`) and the math.

use super::*;

fn params() -> FrictionParams {
    FrictionParams {
        mu_static: 0.5,
        mu_kinetic: 0.3,
        decay: 0.0,
        radius: 0.1,
        k_stick: 1e4,
        k_stick_r1: 1e2,
        ..FrictionParams::default()
    }
}

#[test]
fn normal_loads_follow_the_seed() {
    let p = params();
    let (f, m) = normal_loads(&p, -10.0, 0.3, 0.4);
    assert!((f - (10.0 + 0.5 / 0.1)).abs() < 1e-12);
    assert!((m - (2.0 / 3.0 * 0.1 * 10.0 + 0.5)).abs() < 1e-12);
    let p0 = FrictionParams { radius: 0.0, ..p };
    let (f, m) = normal_loads(&p0, -10.0, 0.3, 0.4);
    assert_eq!(f, 10.0);
    assert!((m - 0.5).abs() < 1e-12);
}

#[test]
fn stick_then_slip_saturates_at_mu_fn() {
    let p = params();
    let st = FrictionState::default();
    let r = update(
        &p,
        &st,
        [-10.0, 0.0, 0.0],
        [1e-4, 0.0, 0.0],
        [0.0; 3],
        Eval::Step(1e-3),
    );
    assert_eq!(r.out.status, Status::Stick);
    assert!((r.force[0] - 1.0).abs() < 1e-12);
    let r = update(
        &p,
        &r.state,
        [-10.0, 0.0, 0.0],
        [1e-2, 0.0, 0.0],
        [0.0; 3],
        Eval::Step(1e-3),
    );
    assert_eq!(r.out.status, Status::Slip);
    assert!((r.out.csfc - 0.5 * 10.0).abs() < 1e-12);
    // plastic slip: 1e-2 − 5/1e4
    assert!((r.state.slip_plastic[0] - (1e-2 - 5e-4)).abs() < 1e-15);
    assert!(r.state.dissipated > 0.0);
}

#[test]
fn coupled_limit_is_an_ellipsoid() {
    let p = FrictionParams {
        coupling: 1,
        ..params()
    };
    let r = update(
        &p,
        &FrictionState::default(),
        [-10.0, 0.0, 0.0],
        [1.0, 0.0, 1.0],
        [0.0; 3],
        Eval::Step(1e-3),
    );
    let rho = 2.0 / 3.0 * 0.1;
    let lhs = (r.force[0].powi(2) + r.force[1].powi(2) + (r.force[2] / rho).powi(2)).sqrt();
    assert!((lhs - 5.0).abs() < 1e-12);
    assert_eq!(r.out.status, Status::Slip);
    assert_eq!(r.out.status_r1, Status::Slip);
}

/// The disc's flow on the ellipsoid with unequal stick stiffnesses: the returned force is on
/// the surface, the plastic slip increments (Δs, Δθ) are along (f_tr, m_tr)'s signs, and
/// their ratio ε = |Δs|/(R|Δθ|) is the disc's for the returned direction:
/// |m|/|f| = R M̂(ε)/F̂(ε).
#[test]
fn coupled_return_follows_the_disc() {
    for (k_r, pos) in [
        (7.0, [0.3, -0.2, 2.0]),
        (1e3, [1e-3, 2e-3, -0.05]),
        (44.4, [-0.5, 0.0, 1e-3]),
    ] {
        let p = FrictionParams {
            coupling: 1,
            k_stick: 1e4,
            k_stick_r1: k_r,
            ..params()
        };
        let rho = 2.0 / 3.0 * 0.1;
        let r = update(
            &p,
            &FrictionState::default(),
            [-10.0, 0.0, 0.0],
            pos,
            [0.0; 3],
            Eval::Step(1e-3),
        );
        let (f, m) = ([r.force[0], r.force[1]], r.force[2]);
        let on = (f[0] * f[0] + f[1] * f[1] + (m / rho).powi(2)).sqrt();
        assert!((on - 5.0).abs() < 1e-12, "on the ellipsoid: {on}");
        let ds = r.state.slip_plastic;
        let ds_r = r.state.slip_plastic_r1;
        // sliding increment along the trial force, spin increment with the trial's sign
        assert!((ds[0] * pos[1] - ds[1] * pos[0]).abs() < 1e-15);
        assert!(ds[0] * pos[0] + ds[1] * pos[1] > 0.0 && ds_r * pos[2] > 0.0);
        let (f_hat, m_hat) = disc_law(ds[0].hypot(ds[1]), 0.1 * ds_r.abs());
        let want = 0.1 * m_hat / f_hat;
        let got = m.abs() / f[0].hypot(f[1]);
        assert!((got / want - 1.0).abs() < 1e-12, "{got} vs {want}");
    }
}

/// The tangent evaluation of a slipping effect stays on the slip branch: just inside the
/// limit it still returns the limit force (central differences see the slip tangent).
#[test]
fn tangent_mode_keeps_a_slipping_effect_on_its_limit() {
    let p = params();
    let slipped = update(
        &p,
        &FrictionState::default(),
        [-10.0, 0.0, 0.0],
        [1e-2, 0.0, 0.0],
        [0.0; 3],
        Eval::Step(1e-3),
    );
    assert_eq!(slipped.state.status, Status::Slip);
    let inside = [1e-2 - 1e-6, 0.0, 0.0];
    let read = update(
        &p,
        &slipped.state,
        [-10.0, 0.0, 0.0],
        inside,
        [0.0; 3],
        Eval::Read,
    );
    let tangent = update(
        &p,
        &slipped.state,
        [-10.0, 0.0, 0.0],
        inside,
        [0.0; 3],
        Eval::Tangent([Status::Slip, Status::Stick]),
    );
    assert!(read.force[0] < 5.0 - 1e-3, "read: elastic unloading");
    assert!(
        (tangent.force[0] - 5.0).abs() < 1e-12,
        "tangent: on the limit"
    );
}

/// Stick dampers: in stick f = k e + c·rate; a slipping substep returns with k + c/h
/// (backward Euler on the plastic slip), and reading again where it ended gives its bits.
#[test]
fn stick_damper_is_parallel_to_the_stick_spring() {
    let p = FrictionParams {
        c_stick: 50.0,
        c_stick_r1: 0.5,
        ..params()
    };
    let h = 1e-3;
    let n = [-10.0, 0.0, 0.0];
    let st = FrictionState::default();
    let r = update(
        &p,
        &st,
        n,
        [1e-4, 0.0, 0.0],
        [0.02, 0.0, 0.0],
        Eval::Step(h),
    );
    assert_eq!(r.out.status, Status::Stick);
    assert!((r.force[0] - (1e4 * 1e-4 + 50.0 * 0.02)).abs() < 1e-12);
    // the damper stores nothing
    assert!((r.stored - 0.5 * 1e4 * 1e-8).abs() < 1e-18);
    // breakaway: trial 1e4·1e-3 + 50·0.1 = 15 > μN = 5
    let (pos, rate) = ([1e-3, 0.0, 0.0], [0.1, 0.0, 0.0]);
    let s = update(&p, &r.state, n, pos, rate, Eval::Step(h));
    assert_eq!(s.out.status, Status::Slip);
    assert!((s.force[0] - 5.0).abs() < 1e-12);
    // the elastic slip follows c ė + k e = f(τ), f ramping from the stick force 2 N to the
    // limit 5 N over the substep, from e0 = 1e-4: e = A + Bτ + (e0 − A) exp(−kτ/c) with
    // B = (df/dτ)/k, A = f0/k − (df/dτ) c/k²; the plastic slip is the rest of the motion
    let (k, c, e0, f0, f1) = (1e4, 50.0, 1e-4, 2.0, 5.0);
    let slope = (f1 - f0) / h;
    let (b, a) = (slope / k, f0 / k - slope * c / (k * k));
    let e1 = a + b * h + (e0 - a) * (-k * h / c).exp();
    assert!((s.state.slip_plastic[0] - (1e-3 - e1)).abs() < 1e-15);
    // the force at the end is spring plus damper at the elastic rate ė = (f1 − k e1)/c
    assert!((s.state.slip_rate[0] - (0.1 - (f1 - k * e1) / c)).abs() < 1e-9);
    let again = update(&p, &s.state, n, pos, rate, Eval::Read);
    assert_eq!(again.force, s.force);
    assert_eq!(again.out.status, Status::Slip);
}

/// A damped stick spring relaxing while the contact slips on a constant limit: the elastic
/// slip is integrated exactly, so one substep and ten substeps of a tenth give the same
/// elastic slip (backward Euler would not: e1 = (e0 + h f/c)/(1 + kh/c) per substep).
#[test]
fn damped_elastic_slip_is_exact_for_a_constant_limit() {
    let p = FrictionParams {
        c_stick: 50.0,
        ..params()
    };
    let (n, h, v) = ([-10.0, 0.0, 0.0], 2e-3, 0.1);
    // slipping at 0.1 m/s on the limit μN = 5 N, the spring stretched to 6e-4 (6 N)
    let st = FrictionState {
        status: Status::Slip,
        elastic: [6e-4, 0.0, 0.0],
        force: [5.0, 0.0, 0.0],
        slip_rate: [v - (5.0 - 6.0) / 50.0, 0.0, 0.0],
        ..FrictionState::default()
    };
    let path = |s: &FrictionState, t: Real| {
        let pos = [s.slip_plastic[0] + 6e-4 + v * t, 0.0, 0.0];
        (pos, [v, 0.0, 0.0])
    };
    let (pos, rate) = path(&st, h);
    let one = update(&p, &st, n, pos, rate, Eval::Step(h));
    let mut s = st;
    for i in 1..=10 {
        let (pos, rate) = path(&st, h * i as Real / 10.0);
        s = update(&p, &s, n, pos, rate, Eval::Step(h / 10.0)).state;
    }
    let exact = 5e-4 + (6e-4 - 5e-4) * (-1e4 * h / 50.0).exp();
    assert_eq!(one.out.status, Status::Slip);
    assert!(
        (one.state.elastic[0] - exact).abs() < 1e-16,
        "{:e}",
        one.state.elastic[0]
    );
    assert!((s.elastic[0] - exact).abs() < 1e-16, "{:e}", s.elastic[0]);
}

/// Along any path of substeps, the trapezoidal work of the friction force equals the change
/// of the stick springs' energy plus the dissipation (plastic slip and stick dampers).
#[test]
fn friction_energy_balances_with_stick_dampers() {
    for coupling in [0, 1] {
        let p = FrictionParams {
            c_stick: 30.0,
            c_stick_r1: 0.3,
            coupling,
            ..params()
        };
        let n = [-10.0, 0.0, 0.0];
        let h = 2e-3;
        let path = |t: Real| {
            [
                [
                    0.02 * (7.0 * t).sin(),
                    0.01 * (3.0 * t).cos() - 0.01,
                    0.3 * (5.0 * t).sin(),
                ],
                [
                    0.14 * (7.0 * t).cos(),
                    -0.03 * (3.0 * t).sin(),
                    1.5 * (5.0 * t).cos(),
                ],
            ]
        };
        let mut st = FrictionState::default();
        // from rest: no force, nothing stored
        let (mut work, mut slips) = (0.0, 0);
        let mut pos0 = path(0.0)[0];
        for i in 1..=2000 {
            let [pos, rate] = path(i as Real * h);
            let r = update(&p, &st, n, pos, rate, Eval::Step(h));
            for k in 0..3 {
                work += 0.5 * (st.force[k] + r.force[k]) * (pos[k] - pos0[k]);
            }
            slips += (r.out.status == Status::Slip) as i32;
            st = r.state;
            pos0 = pos;
            let balance = work - r.stored - st.dissipated;
            assert!(
                balance.abs() <= 1e-12 * st.dissipated.max(1.0),
                "{coupling} {i}: {balance}"
            );
        }
        assert!(
            slips > 200 && st.dissipated > 0.1,
            "{coupling}: {slips} {}",
            st.dissipated
        );
    }
}

#[test]
fn refusals_name_the_parameters() {
    let bad = FrictionParams {
        mu_kinetic: 0.6,
        ..params()
    };
    assert_eq!(bad.check(), Err("friction.muKinetic > friction.muStatic"));
    let bad = FrictionParams {
        coupling: 1,
        radius: 0.0,
        ..params()
    };
    assert_eq!(
        bad.check(),
        Err("friction.coupling = 1 needs friction.R > 0")
    );
    assert_eq!(params().check(), Ok(()));
}
