//! Singular and near-singular configurations through the C ABI: each gives defined, finite
//! outputs or a clear fmi2Error (one message naming the function and the cause), never NaN, and
//! nothing is lost — the state before the error stays and fmi2Reset / fmi2SetFMUstate recover.
//!
//! - flexion α → π (ProjectionFlexionTorsion, Bushing): exactly π and paths through π are
//!   refused; α = π − 1e-3 (the edge of the refused band, README) and π − 2e-3 give finite
//!   outputs;
//! - r → 0 in RadialThrust: node b passes through the axis; the radial direction is kept;
//! - coincident nodes (x_a = x_b) for every variant with positions;
//! - 10^6 full turns of torsion (ProjectionFlexionTorsion, linear extrapolation over big steps;
//!   10^4 turns in a debug build): CPR3 tracks 2π·turns.

mod common;

use common::*;
use connector_fmu::fmi2::exports::*;
use connector_fmu::fmi2::types::*;
use connector_fmu::variables::{table, Variant};
use std::f64::consts::PI;
use std::ptr::null_mut;
use std::time::Instant;

const OK: fmi2Status = fmi2Status::OK;

/// (w, x, y, z) of a rotation by `angle` about a unit axis.
fn quat(angle: f64, axis: [f64; 3]) -> [f64; 4] {
    let (s, c) = (0.5 * angle).sin_cos();
    [c, s * axis[0], s * axis[1], s * axis[2]]
}

fn set_quat(f: &Fmu, node: &str, q: [f64; 4]) {
    for (c, x) in ["w", "x", "y", "z"].iter().zip(q) {
        assert_eq!(f.set_real(&format!("{node}.q.{c}"), x), OK, "{:?}", f.log());
    }
}

fn set_vec(f: &Fmu, name: &str, x: [f64; 3]) {
    for (i, xi) in x.iter().enumerate() {
        f.set_real_if(&format!("{name}[{}]", i + 1), *xi);
    }
}

/// Every Real output, asserting OK and finite.
#[track_caller]
fn finite_outputs(f: &Fmu) -> Vec<f64> {
    let vrs = f.outputs(false);
    let y = f.get_reals(&vrs);
    for (vr, x) in vrs.iter().zip(&y) {
        assert!(
            x.is_finite(),
            "{:?}: {} = {x}",
            f.variant,
            table(f.variant).get(*vr).unwrap().name
        );
    }
    y
}

/// fmi2GetReal of every Real output: either OK with finite values or fmi2Error with one
/// message; never a non-finite value with OK.
#[track_caller]
fn outputs_or_error(f: &Fmu) -> fmi2Status {
    let vrs = f.outputs(false);
    let mut y = vec![0.0; vrs.len()];
    let n = f.log_len();
    let s = fmi2GetReal(f.c, vrs.as_ptr(), vrs.len(), y.as_mut_ptr());
    match s {
        OK => assert!(y.iter().all(|x| x.is_finite()), "{y:?}"),
        _ => assert_error_logged(f, n, s, "fmi2GetReal"),
    }
    s
}

/// The FMU state as serialized bytes with the mode byte blanked.
fn state_bytes(f: &Fmu) -> Vec<u8> {
    let mut s: fmi2FMUstate = null_mut();
    assert_eq!(fmi2GetFMUstate(f.c, &mut s), OK);
    let mut n = 0usize;
    assert_eq!(fmi2SerializedFMUstateSize(f.c, s, &mut n), OK);
    let mut b = vec![0u8; n];
    assert_eq!(fmi2SerializeFMUstate(f.c, s, b.as_mut_ptr().cast(), n), OK);
    assert_eq!(fmi2FreeFMUstate(f.c, &mut s), OK);
    let mode = 7 + table(f.variant).spec.model_identifier.len();
    b[mode] = 0;
    let len = b.len();
    b[len - 8..].fill(0);
    b
}

/// A flexion connector with springs and dampers on every rotational component, initialised
/// at identity orientations (and b at (0.1, 0, 0) when the variant has positions).
fn flexion_fmu(v: Variant) -> Fmu {
    let f = Fmu::new(v);
    f.enter_init();
    for k in 1..=6 {
        f.set_real_if(&format!("elasticity.k{k}"), 50.0);
        f.set_real_if(&format!("damping.c{k}"), 0.5);
    }
    set_vec(&f, "b.r", [0.1, 0.0, 0.0]);
    f.exit_init();
    f
}

// ------------------------------------------------------------------ α → π

#[test]
fn flexion_exactly_pi_is_a_clear_error_and_recoverable() {
    for v in [Variant::ProjectionFlexionTorsion, Variant::Bushing] {
        let f = flexion_fmu(v);
        let reference = flexion_fmu(v);
        // a regular step with a small bend
        let bend = quat(0.3, [1.0, 0.0, 0.0]);
        for g in [&f, &reference] {
            set_quat(g, "b", bend);
            assert_eq!(g.step(0.0, 1e-3), OK);
        }
        let mut saved: fmi2FMUstate = null_mut();
        assert_eq!(fmi2GetFMUstate(f.c, &mut saved), OK);
        let kept = state_bytes(&f);

        // shafts folded back exactly: b rotated by π about e1 (e3b = −e3a)
        set_quat(&f, "b", [0.0, 1.0, 0.0, 0.0]);
        let after_set = state_bytes(&f);
        // outputs at the folded configuration: a clear error, not NaN
        assert_eq!(outputs_or_error(&f), fmi2Status::Error, "{v:?}");
        assert!(
            f.log().last().unwrap().message.contains("α → π"),
            "{:?}",
            f.log()
        );
        let n = f.log_len();
        let s = f.step(1e-3, 1e-3);
        assert_error_logged(&f, n, s, "fmi2DoStep");
        let msg = &f.log()[n].message;
        assert!(msg.contains("α → π") && msg.contains("kept"), "{msg}");
        // the last good state stays (only the mode changed to Error)
        assert_eq!(
            state_bytes(&f),
            after_set,
            "{v:?}: state changed by the failed step"
        );
        // (the time is part of those bytes; fmi2GetRealStatus is not allowed in the Error
        // state, FMI 2.0 §4.2.4)

        // recover by fmi2SetFMUstate: the run continues bit-identical to a clean reference
        assert_eq!(fmi2SetFMUstate(f.c, saved), OK, "{:?}", f.log());
        assert_eq!(state_bytes(&f), kept);
        for g in [&f, &reference] {
            set_quat(g, "b", quat(0.35, [1.0, 0.0, 0.0]));
            assert_eq!(g.step(1e-3, 1e-3), OK, "{:?}", g.log());
        }
        let (y, yr) = (finite_outputs(&f), finite_outputs(&reference));
        assert!(
            y.iter().zip(&yr).all(|(a, b)| a.to_bits() == b.to_bits()),
            "{v:?}: restored run differs"
        );
        assert_eq!(fmi2FreeFMUstate(f.c, &mut saved), OK);

        // fold again, then recover by fmi2Reset and a new initialization
        set_quat(&f, "b", [0.0, 1.0, 0.0, 0.0]);
        assert_eq!(f.step(2e-3, 1e-3), fmi2Status::Error);
        assert_eq!(fmi2Reset(f.c), OK, "{:?}", f.log());
        f.init();
        finite_outputs(&f);
        assert_eq!(f.step(0.0, 1e-3), OK);

        // initialization at the folded configuration is refused, and fixing it recovers
        assert_eq!(fmi2Reset(f.c), OK);
        f.enter_init();
        set_quat(&f, "b", [0.0, 1.0, 0.0, 0.0]);
        assert_eq!(outputs_or_error(&f), fmi2Status::Error);
        let n = f.log_len();
        let s = fmi2ExitInitializationMode(f.c);
        assert_error_logged(&f, n, s, "fmi2ExitInitializationMode");
        set_quat(&f, "b", bend);
        f.exit_init();
        finite_outputs(&f);
    }
}

#[test]
fn a_path_through_pi_within_one_step_is_refused() {
    for v in [Variant::ProjectionFlexionTorsion, Variant::Bushing] {
        let f = flexion_fmu(v);
        // α = 3.0, turning at 1 rad/s about e1: π is crossed 0.14 s into a 0.5 s step,
        // while both ends (α = 3.0 and 2π − 3.5 = 2.78) are regular
        set_quat(&f, "b", quat(3.0, [1.0, 0.0, 0.0]));
        set_vec(&f, "b.w", [1.0, 0.0, 0.0]);
        let before = state_bytes(&f);
        let n = f.log_len();
        let s = f.step(0.0, 0.5);
        assert_error_logged(&f, n, s, "fmi2DoStep");
        assert!(f.log()[n].message.contains("α → π"), "{:?}", f.log()[n]);
        assert_eq!(state_bytes(&f), before);
        // outputs at the (regular) start of the step are still defined
        finite_outputs(&f);
    }
}

#[test]
fn flexion_near_pi_gives_finite_outputs() {
    for v in [Variant::ProjectionFlexionTorsion, Variant::Bushing] {
        // π − 1e-3 is the edge of the refused band (README): accepted while at rest there;
        // π − 2e-3 also while turning away from π
        for (gap, w) in [(1e-3, 0.0), (2e-3, -0.5)] {
            let f = flexion_fmu(v);
            set_quat(&f, "b", quat(PI - gap, [1.0, 0.0, 0.0]));
            set_vec(&f, "b.w", [w, 0.0, 0.0]);
            let y0 = finite_outputs(&f);
            let mut t = 0.0;
            for _ in 0..10 {
                assert_eq!(f.step(t, 1e-3), OK, "{v:?} gap {gap}: {:?}", f.log());
                t += 1e-3;
                finite_outputs(&f);
            }
            let alpha = f.get_real("CPR1").hypot(f.get_real("CPR2"));
            assert!(
                (alpha - (PI - gap - w.abs() * t)).abs() < 1e-9,
                "{v:?}: α = {alpha}"
            );
            // the large but finite loads near the fold
            assert!(y0.iter().any(|x| x.abs() > 1.0));
            // directional derivative there: finite (or a clear error)
            let (unk, kn) = (f.vr("b.m[1]"), f.vr("b.q.x"));
            let mut d = f64::NAN;
            let n = f.log_len();
            let s = fmi2GetDirectionalDerivative(f.c, &unk, 1, &kn, 1, &1.0, &mut d);
            if s == OK {
                assert!(d.is_finite(), "{d}");
            } else {
                assert_error_logged(&f, n, s, "fmi2GetDirectionalDerivative");
            }
        }
    }
}

// ------------------------------------------------------------------ r → 0

#[test]
fn radial_thrust_through_the_axis_keeps_the_direction() {
    let f = Fmu::new(Variant::RadialThrust);
    f.enter_init();
    f.set_real_if("elasticity.k1", 100.0);
    f.set_real_if("elasticity.k3", 100.0);
    f.set_real_if("damping.c1", 1.0);
    f.set_real_if("stop.lower1", 0.0);
    f.set_real_if("stop.upper1", 0.15);
    set_vec(&f, "b.r", [0.1, 0.0, 0.5]);
    f.exit_init();
    // b moves along −x at 1 m/s: on the axis (exactly) at t = 0.1, out on the other side after
    let h = 1e-3;
    set_vec(&f, "b.v", [-1.0, 0.0, 0.0]);
    let mut last_dir = [1.0, 0.0, 0.0];
    let mut t = 0.0;
    for k in 0..200 {
        // the positions the master prescribes (the same line, exact at the axis crossing)
        let x = 0.1 - k as f64 * h;
        set_vec(&f, "b.r", [if k == 100 { 0.0 } else { x }, 0.0, 0.5]);
        let y = finite_outputs(&f);
        let r = f.get_real("CP1");
        assert!(r >= 0.0 && r.is_finite());
        let fb = [
            f.get_real("b.f[1]"),
            f.get_real("b.f[2]"),
            f.get_real("b.f[3]"),
        ];
        assert!(fb.iter().all(|x| x.is_finite()), "{fb:?}");
        // the radial force lies along ±(kept e_r): never a NaN direction, never off the line
        assert!(fb[1].abs() < 1e-9, "{fb:?}");
        if k == 100 {
            assert_eq!(r, 0.0);
            // on the axis e_r is the last well-defined direction (+x, b came from +x): the
            // spring, compressed to r = 0, pushes b along +e_r
            assert_eq!(last_dir, [1.0, 0.0, 0.0]);
            assert!(fb[0] > 0.0, "{fb:?}");
        }
        if r > 1e-6 {
            last_dir = [x.signum(), 0.0, 0.0];
        }
        let _ = y;
        assert_eq!(f.step(t, h), OK, "step {k}: {:?}", f.log());
        t += h;
    }
    // tiny radii below and above the 1e-9 threshold
    for x in [1e-12, -1e-12, 2e-9, 1e-300, 5e-324] {
        set_vec(&f, "b.r", [x, 0.0, 0.5]);
        finite_outputs(&f);
        assert_eq!(f.step(t, h), OK, "{:?}", f.log());
        t += h;
        finite_outputs(&f);
    }
    // directional derivative on the axis
    set_vec(&f, "b.r", [0.0, 0.0, 0.5]);
    let unk = [f.vr("b.f[1]"), f.vr("b.f[2]"), f.vr("CTF1")];
    let kn = [f.vr("b.r[1]"), f.vr("b.r[2]")];
    let mut d = [f64::NAN; 3];
    assert_eq!(
        fmi2GetDirectionalDerivative(
            f.c,
            unk.as_ptr(),
            3,
            kn.as_ptr(),
            2,
            [1.0, 0.5].as_ptr(),
            d.as_mut_ptr()
        ),
        OK
    );
    assert!(d.iter().all(|x| x.is_finite()), "{d:?}");
}

// ------------------------------------------------------------------ coincident nodes

#[test]
fn coincident_nodes_give_finite_outputs() {
    for v in [
        Variant::Bushing,
        Variant::ProjectionCartesian,
        Variant::RadialThrust,
        Variant::Planar,
    ] {
        let f = Fmu::new(v);
        f.enter_init();
        for k in 1..=6 {
            f.set_real_if(&format!("elasticity.k{k}"), 100.0);
            f.set_real_if(&format!("damping.c{k}"), 1.0);
        }
        f.set_real_if("friction.muStatic", 0.3);
        f.set_real_if("friction.R", 0.01);
        let p = [0.3, -0.2, 0.7];
        set_vec(&f, "a.r", p);
        set_vec(&f, "b.r", p);
        // in initialization the outputs follow the inputs
        finite_outputs(&f);
        f.exit_init();
        finite_outputs(&f);
        // move b away and back through a: coincident again at k = 10
        let mut t = 0.0;
        for k in 0..=20 {
            let s = (10 - k) as f64 * 1e-3;
            set_vec(&f, "b.r", [p[0] + s, p[1] + 0.5 * s, p[2]]);
            set_vec(&f, "b.v", [-1.0, -0.5, 0.0]);
            set_vec(&f, "b.w", [0.0, 0.0, 0.2]);
            finite_outputs(&f);
            assert_eq!(f.step(t, 1e-3), OK, "{v:?} step {k}: {:?}", f.log());
            t += 1e-3;
            finite_outputs(&f);
        }
        // coincident with a rotated a and b
        set_vec(&f, "b.r", p);
        set_vec(&f, "b.v", [0.0; 3]);
        set_quat(&f, "a", quat(0.4, [0.0, 1.0, 0.0]));
        if f.has("b.q.w") {
            set_quat(&f, "b", quat(0.5, [0.0, 1.0, 0.0]));
        }
        assert_eq!(f.step(t, 1e-3), OK, "{v:?}: {:?}", f.log());
        finite_outputs(&f);
        assert!(f.log().is_empty(), "{v:?}: {:?}", f.log());
    }
}

// ------------------------------------------------------------------ 10^6 turns of torsion

/// Tolerance of CPR3 against the prescribed total torsion, relative (round-off of millions of
/// branch continuations and exponential-map substeps; measured ~1e-16).
const TORSION_TOL: f64 = 1e-9;

/// A ProjectionFlexionTorsion instance with torsion spring and damper and a constant 0.1 rad
/// bend of node a about its e2 (so the flexion components are non-trivial); returns it with
/// a's e3 in W.
fn torsion_fmu(extrapolation: i32) -> (Fmu, [f64; 3]) {
    let f = Fmu::new(Variant::ProjectionFlexionTorsion);
    f.enter_init();
    f.set_real_if("elasticity.k6", 1.0);
    f.set_real_if("damping.c6", 1e-3);
    f.set_real_if("elasticity.k4", 10.0);
    f.set_real_if("elasticity.k5", 10.0);
    let ext = f.vr("cosim.extrapolation");
    assert_eq!(fmi2SetInteger(f.c, &ext, 1, &extrapolation), OK);
    set_quat(&f, "a", quat(0.1, [0.0, 1.0, 0.0]));
    f.exit_init();
    (f, [(0.1f64).sin(), 0.0, (0.1f64).cos()])
}

/// Checks CPR3 against the prescribed torsion and the flexion against the constant bend.
fn check_torsion(f: &Fmu, what: &str, turns: f64, secs: f64, steps: u64, worst: f64) {
    let beta = f.get_real("CPR3");
    let want = 2.0 * PI * turns;
    let rel = (beta - want).abs() / want;
    println!(
        "torsion ({what}): {turns:e} turns in {steps} steps ({secs:.2} s): CPR3 = {beta:.9} rad, \
         2π·turns = {want:.9} rad, relative error {rel:.3e} (worst along the run {worst:.3e}); \
         CEM3 = {:.6e} N·m",
        f.get_real("CEM3")
    );
    assert!(
        rel < TORSION_TOL && worst < TORSION_TOL,
        "relative error {rel} (worst {worst})"
    );
    let alpha = f.get_real("CPR1").hypot(f.get_real("CPR2"));
    assert!((alpha - 0.1).abs() < 1e-6, "α = {alpha}");
    finite_outputs(f);
    assert!(f.log().is_empty(), "{:?}", f.log());
}

/// b spins about a's e3 at ω; the master sets only the angular velocity and the FMU
/// extrapolates the orientation linearly (exponential map) over big steps of 1000 turns,
/// in substeps of at most 0.25 rad.
fn spin_with_linear_extrapolation(turns_total: u64) {
    let turns_per_step = 1000.0;
    let h = 1.0;
    let omega = 2.0 * PI * turns_per_step / h;
    let steps = (turns_total as f64 / turns_per_step) as u64;
    let (f, e3a) = torsion_fmu(1);
    set_vec(&f, "b.w", e3a.map(|x| x * omega));
    let started = Instant::now();
    let mut t = 0.0;
    let mut worst: f64 = 0.0;
    for k in 1..=steps {
        assert_eq!(f.step(t, h), OK, "step {k}: {:?}", f.log());
        t += h;
        let beta = f.get_real("CPR3");
        worst = worst.max((beta - omega * t).abs() / (omega * t));
        if k % 100 == 0 {
            finite_outputs(&f);
        }
    }
    let secs = started.elapsed().as_secs_f64();
    check_torsion(
        &f,
        "linear extrapolation",
        turns_total as f64,
        secs,
        steps,
        worst,
    );
}

/// 10^5 turns (10^3 in a debug build) with linear extrapolation over big steps.
#[test]
fn torsion_turns_with_linear_extrapolation_over_big_steps() {
    spin_with_linear_extrapolation(if cfg!(debug_assertions) {
        1_000
    } else {
        100_000
    });
}

/// 10^6 turns with linear extrapolation: 2.5e7 substeps, 10–30 s in release (the FMU limits
/// the rotation per substep); the default test below covers 10^6 turns faster.
#[test]
#[ignore = "slow: 2.5e7 substeps"]
fn a_million_turns_with_linear_extrapolation() {
    spin_with_linear_extrapolation(1_000_000);
}

/// 10^6 full turns (10^4 in a debug build): the master sets b's orientation every
/// communication point, 3.1 rad further each time (just under π, the largest increment the
/// torsion branch can follow), with hold extrapolation; CPR3 tracks the total angle.
#[test]
fn a_million_turns_of_torsion_track_two_pi_turns() {
    let turns: f64 = if cfg!(debug_assertions) { 1e4 } else { 1e6 };
    let inc = 3.1;
    let steps = (2.0 * PI * turns / inc).ceil() as u64;
    let total = steps as f64 * inc; // radians actually turned (≥ 2π·turns)
    let h = 1e-3;
    let (f, e3a) = torsion_fmu(0);
    set_vec(&f, "b.w", e3a.map(|x| x * inc / h));
    let q_vrs = ["w", "x", "y", "z"].map(|c| f.vr(&format!("b.q.{c}")));
    let four_pi = 4.0 * PI;
    let started = Instant::now();
    let mut worst: f64 = 0.0;
    for k in 1..=steps {
        // the angle modulo 4π (the quaternion's period) from the exact integer count
        let theta = (k as f64 * inc) % four_pi;
        let q = quat(theta, e3a);
        assert_eq!(fmi2SetReal(f.c, q_vrs.as_ptr(), 4, q.as_ptr()), OK);
        assert_eq!(f.step((k - 1) as f64 * h, h), OK, "step {k}: {:?}", f.log());
        if k % 4096 == 0 || k == steps {
            let beta = f.get_real("CPR3");
            let want = k as f64 * inc;
            worst = worst.max((beta - want).abs() / want);
            finite_outputs(&f);
        }
    }
    let secs = started.elapsed().as_secs_f64();
    check_torsion(
        &f,
        "orientation set every 3.1 rad",
        total / (2.0 * PI),
        secs,
        steps,
        worst,
    );
}
