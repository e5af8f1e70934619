//! The Body's update (bodies/src/physics) against closed forms and the quaternion algebra's own
//! identities (mutants ./scripts/mutants found the ABI tests let pass):
//! - the quaternion product follows Hamilton's table (i j = k, j k = i, k i = j, i² = −1), is
//!   associative and multiplies norms; R(q) a is the sandwich q ⊗ (0, a) ⊗ q*, Rᵀ undoes it;
//!   a × b is orthogonal to both with |a × b|² = |a|²|b|² − (a·b)² and e1 × e2 = e3;
//! - model 0's axis under a held load: x + h u + ½ h² Q/m and u + h Q/m without a spring, the
//!   harmonic closed form with one;
//! - model 1 (RK4) under a held force and a moment about a principal axis: exact where the
//!   motion is polynomial of degree ≤ 2 (r, v) or linear (ω about the axis).

use body_fmu::physics::axes::advance;
use body_fmu::physics::quat::{cross, mat_t_vec, mat_vec, matrix, mul, Quat, Vec3};
use body_fmu::physics::rigid;
use body_fmu::physics::{Body, Load, Model, Params};

mod common;
use common::Lcg;

/// Draws in [−1, 1) from the tests' generator (`common::Lcg`).
trait Draws {
    fn vec(&mut self) -> Vec3;
    fn unit_quat(&mut self) -> Quat;
}

impl Draws for Lcg {
    fn vec(&mut self) -> Vec3 {
        [
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
            self.range(-1.0, 1.0),
        ]
    }
    fn unit_quat(&mut self) -> Quat {
        let q = [(); 4].map(|_| self.range(-1.0, 1.0));
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        q.map(|x| x / n)
    }
}

fn close(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tol)
}

#[test]
fn the_quaternion_product_is_hamiltons() {
    let (one, i, j, k) = (
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    );
    let neg = |q: Quat| q.map(|x| -x);
    assert_eq!(mul(&i, &j), k);
    assert_eq!(mul(&j, &k), i);
    assert_eq!(mul(&k, &i), j);
    assert_eq!(mul(&j, &i), neg(k));
    for e in [i, j, k] {
        assert_eq!(mul(&e, &e), neg(one));
        assert_eq!(mul(&one, &e), e);
    }
    let mut rng = Lcg(1);
    for _ in 0..200 {
        let (p, q, r) = (rng.unit_quat(), rng.unit_quat(), rng.unit_quat());
        // associativity and |p q| = |p||q| = 1, to round-off of O(1) sums
        assert!(close(&mul(&mul(&p, &q), &r), &mul(&p, &mul(&q, &r)), 8e-15));
        let n: f64 = mul(&p, &q).iter().map(|x| x * x).sum();
        assert!((n - 1.0).abs() < 8e-15);
    }
}

#[test]
fn the_rotation_matrix_is_the_quaternion_sandwich() {
    let mut rng = Lcg(2);
    for _ in 0..200 {
        let (q, a) = (rng.unit_quat(), rng.vec());
        let conj = [q[0], -q[1], -q[2], -q[3]];
        let s = mul(&mul(&q, &[0.0, a[0], a[1], a[2]]), &conj);
        let r = matrix(&q);
        let ra = mat_vec(&r, &a);
        assert!(close(&ra, &s[1..], 8e-15), "{ra:?} vs {s:?}");
        assert!(close(&mat_t_vec(&r, &ra), &a, 8e-15));
    }
}

#[test]
fn the_cross_product_is_orthogonal_with_lagranges_norm() {
    assert_eq!(cross(&[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
    assert_eq!(cross(&[0.0, 1.0, 0.0], &[0.0, 0.0, 1.0]), [1.0, 0.0, 0.0]);
    assert_eq!(cross(&[0.0, 0.0, 1.0], &[1.0, 0.0, 0.0]), [0.0, 1.0, 0.0]);
    let mut rng = Lcg(3);
    let dot = |a: &Vec3, b: &Vec3| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    for _ in 0..200 {
        let (a, b) = (rng.vec(), rng.vec());
        let c = cross(&a, &b);
        assert!(dot(&c, &a).abs() < 8e-15 && dot(&c, &b).abs() < 8e-15);
        let lagrange = dot(&a, &a) * dot(&b, &b) - dot(&a, &b).powi(2);
        assert!((dot(&c, &c) - lagrange).abs() < 1e-14);
    }
}

/// Model 0, one axis, Q = 3 N held on m = 2 kg over h = 0.1 s from x = 0.5 m, u = −1 m/s:
/// without a spring x + h u + ½ h² Q/m, u + h Q/m (both roundings of the master); with k = 50
/// N/m, ω = 5 rad/s, x = Q/k + (x0 − Q/k) cos ωh + (u0/ω) sin ωh and its derivative.
#[test]
fn an_axis_under_a_held_load_follows_the_closed_forms() {
    let (x0, u0, q, m, h) = (0.5, -1.0, 3.0, 2.0, 0.1);
    for grouped in [true, false] {
        let (x, u) = advance(x0, u0, q, m, 0.0, h, grouped);
        assert!(
            (x - (x0 + h * u0 + 0.5 * h * h * q / m)).abs() < 1e-15,
            "{grouped}: {x}"
        );
        assert!((u - (u0 + h * q / m)).abs() < 1e-15, "{grouped}: {u}");
    }
    let k = 50.0;
    let w = (k / m).sqrt();
    let (x, u) = advance(x0, u0, q, m, k, h, true);
    let a = x0 - q / k;
    let want_x = q / k + a * (w * h).cos() + u0 / w * (w * h).sin();
    let want_u = -a * w * (w * h).sin() + u0 * (w * h).cos();
    assert!(
        (x - want_x).abs() < 1e-15 && (u - want_u).abs() < 1e-15,
        "{x} {u}"
    );
}

/// Model 1: force f = (1, −2, 0.5) N with gravity g = (0, 0, −9.81) on m = 2 kg, a moment of
/// 0.3 N.m about body axis 3 (J3 = 0.2 kg.m², starting at rest): after h = 0.05 s,
/// r = r0 + v0 h + ½ a h², v = v0 + a h (RK4 is exact for them) and ω = (M/J3) h about
/// axis 3, to round-off.
#[test]
fn a_rigid_body_under_held_loads_moves_as_the_closed_forms() {
    let p = Params {
        mass: 2.0,
        inertia: [0.1, 0.15, 0.2],
        gravity: [0.0, 0.0, -9.81],
        model: Model::Rigid,
        max_turn: 0.05,
        start_q: [1.0, 0.0, 0.0, 0.0],
        ..Params::default()
    };
    let b = Body {
        r: [0.1, 0.2, 0.3],
        q: [1.0, 0.0, 0.0, 0.0],
        v: [0.5, 0.0, -0.2],
        w: [0.0; 3],
        angle: [0.0; 3],
    };
    let load = Load {
        f: [1.0, -2.0, 0.5],
        m: [0.0, 0.0, 0.3],
    };
    let h = 0.05;
    let n = rigid::step(&p, &b, &load, h).expect("a regular step");
    for i in 0..3 {
        let acc = load.f[i] / p.mass + p.gravity[i];
        let (r, v) = (b.r[i] + b.v[i] * h + 0.5 * acc * h * h, b.v[i] + acc * h);
        assert!(
            (n.r[i] - r).abs() < 1e-15 && (n.v[i] - v).abs() < 1e-14,
            "{i}: {n:?}"
        );
    }
    let w3 = 0.3 / 0.2 * h;
    assert!(close(&n.w, &[0.0, 0.0, w3], 1e-15), "{:?}", n.w);
}

/// Model 1 takes a step that needs exactly `MAX_SUBSTEPS` (10^6) RK4 substeps
/// (|ω| h / rigid.maxTurn = 5e5 · 1 / 0.5, exact in binary) and refuses one that needs more.
#[test]
fn a_step_of_exactly_the_most_substeps_is_taken() {
    let p = Params {
        mass: 1.0,
        inertia: [1.0, 1.0, 1.0],
        model: Model::Rigid,
        max_turn: 0.5,
        start_q: [1.0, 0.0, 0.0, 0.0],
        ..Params::default()
    };
    let spin = |w: f64| Body {
        q: [1.0, 0.0, 0.0, 0.0],
        w: [0.0, 0.0, w],
        ..Body::default()
    };
    assert!(rigid::step(&p, &spin(5e5), &Load::default(), 1.0).is_ok());
    let err = rigid::step(&p, &spin(5e5 + 1.0), &Load::default(), 1.0).unwrap_err();
    assert!(err.contains("RK4 substeps"), "{err}");
}
