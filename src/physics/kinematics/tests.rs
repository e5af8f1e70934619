//! Tests of the kinematics: the dispatch over every connection type (rigid motion, rates and
//! loads against finite differences, a↔b symmetry), the centred triad's properties (triad.rs)
//! and RADIAL-THRUST's radial direction on the axis (radial_thrust.rs). A file of its own: the
//! tests use the dispatch (mod.rs) and the parts it composes, which use nothing of this file.

use super::triad::*;
use super::*;
use crate::physics::math::{exp_so3, quat_from_wxyz, rot_z, x_over_sin, Quat, Real, Vec3};
use std::f64::consts::PI;

const ALL: [ConnectionType; 5] = [
    ConnectionType {
        trans: Translational::SlidePlane,
        rot: Rotational::Revolute,
    },
    ConnectionType {
        trans: Translational::ProjectionCartesian,
        rot: Rotational::None,
    },
    ConnectionType {
        trans: Translational::None,
        rot: Rotational::ProjectionFlexionTorsion,
    },
    ConnectionType {
        trans: Translational::ProjectionCartesian,
        rot: Rotational::ProjectionFlexionTorsion,
    },
    ConnectionType {
        trans: Translational::RadialThrust,
        rot: Rotational::None,
    },
];

/// Deterministic pseudo-random numbers in [−1, 1] (no extra crates).
struct Lcg(pub(super) u64);
impl Lcg {
    pub(super) fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
    pub(super) fn vec(&mut self, s: f64) -> Vec3 {
        Vec3::new(self.next() * s, self.next() * s, self.next() * s)
    }
    fn node(&mut self, rot: f64) -> Node {
        Node {
            r: self.vec(1.0),
            q: Quat::from_scaled_axis(self.vec(rot)),
            v: self.vec(1.0),
            w: self.vec(1.0),
        }
    }
}

fn moved(n: &Node, dx: Vec3, dth: Vec3) -> Node {
    Node {
        r: n.r + dx,
        q: Quat::from_scaled_axis(dth) * n.q,
        ..*n
    }
}

/// The factored rates and loads against the gradients written out (which the test below
/// holds to central differences): ċ_k = ∇c_k·(v_a, ω_a, v_b, ω_b) and (m_a, f_b, m_b) =
/// −Σ f_k ∇c_k, to 1e-13 of the largest term (the sums run in a different order).
#[test]
fn factored_rates_and_loads_match_the_gradients() {
    let mut rng = Lcg(11);
    for ct in ALL {
        for _ in 0..40 {
            let (a, b) = (rng.node(1.2), rng.node(1.2));
            let pose = Pose::of(&a, &b);
            let Ok(g) = geometry(ct, &a, &b, &Branches::default()) else {
                continue;
            };
            let f: [Real; 6] = std::array::from_fn(|_| rng.next() * 100.0);
            let rates = g.rates(ct, &pose);
            let (ma, fb, mb) = g.loads(ct, &pose, &f);
            let (mut ma_ref, mut fb_ref, mut mb_ref) =
                (Vec3::zeros(), Vec3::zeros(), Vec3::zeros());
            let mut scale: Real = 1.0;
            for k in 0..6 {
                let gr = g.gradient(ct, k, &pose.d);
                let rate_ref = gr.rate(&pose);
                assert!(
                    (rates[k] - rate_ref).abs() <= 1e-13 * (1.0 + rate_ref.abs()),
                    "{ct:?} rate {}: {} vs {rate_ref}",
                    k + 1,
                    rates[k]
                );
                if ct.roles()[k] == Role::Absent {
                    assert_eq!(rates[k], 0.0);
                    continue;
                }
                ma_ref -= gr.ta * f[k];
                fb_ref -= gr.xb * f[k];
                mb_ref -= gr.tb * f[k];
                scale = scale.max((gr.ta.norm() + gr.xb.norm() + gr.tb.norm()) * f[k].abs());
            }
            for (got, want) in [(ma, ma_ref), (fb, fb_ref), (mb, mb_ref)] {
                assert!(
                    (got - want).norm() <= 1e-13 * scale,
                    "{ct:?}: loads {got:?} vs {want:?}"
                );
            }
        }
    }
}

/// Central differences of every component along 12 node motions vs the analytic gradient.
/// Step 1e-6 gives truncation ~1e-12·c''' and round-off ~1e-10; tolerance 1e-7 absolute.
#[test]
fn gradients_match_central_differences() {
    let mut rng = Lcg(7);
    for ct in ALL {
        for _ in 0..40 {
            let a = rng.node(1.2);
            let b = rng.node(1.2);
            let br = Branches::default();
            let g = match geometry(ct, &a, &b, &br) {
                Ok(g) => g,
                Err(_) => continue,
            };
            let h = 1e-6;
            for dof in 0..12 {
                let mut e = Vec3::zeros();
                e[dof % 3] = h;
                let (ap, am, bp, bm) = match dof / 3 {
                    0 => (
                        moved(&a, e, Vec3::zeros()),
                        moved(&a, -e, Vec3::zeros()),
                        b,
                        b,
                    ),
                    1 => (
                        moved(&a, Vec3::zeros(), e),
                        moved(&a, Vec3::zeros(), -e),
                        b,
                        b,
                    ),
                    2 => (
                        a,
                        a,
                        moved(&b, e, Vec3::zeros()),
                        moved(&b, -e, Vec3::zeros()),
                    ),
                    _ => (
                        a,
                        a,
                        moved(&b, Vec3::zeros(), e),
                        moved(&b, Vec3::zeros(), -e),
                    ),
                };
                let gp = geometry(ct, &ap, &bp, &g.branches).expect("near a regular point");
                let gm = geometry(ct, &am, &bm, &g.branches).expect("near a regular point");
                for k in 0..6 {
                    let fd = (gp.pos[k] - gm.pos[k]) / (2.0 * h);
                    let gr = g.gradient(ct, k, &(b.r - a.r));
                    let an = [gr.xa, gr.ta, gr.xb, gr.tb][dof / 3][dof % 3];
                    assert!(
                        (fd - an).abs() < 1e-7 * (1.0 + an.abs()),
                        "{ct:?} comp {} dof {dof}: fd {fd} analytic {an}",
                        k + 1
                    );
                }
            }
        }
    }
}

#[test]
fn rigid_motion_leaves_positions_unchanged() {
    let mut rng = Lcg(5);
    for ct in ALL {
        for _ in 0..20 {
            let a = rng.node(1.0);
            let b = rng.node(1.0);
            let Ok(g0) = geometry(ct, &a, &b, &Branches::default()) else {
                continue;
            };
            let rig = Quat::from_scaled_axis(rng.vec(2.0));
            let shift = rng.vec(3.0);
            let tr = |n: &Node| Node {
                r: rig * n.r + shift,
                q: rig * n.q,
                ..*n
            };
            let g1 = geometry(ct, &tr(&a), &tr(&b), &g0.branches).expect("regular");
            for k in 0..6 {
                assert!(
                    (g1.pos[k] - g0.pos[k]).abs() < 1e-12,
                    "{ct:?} comp {}",
                    k + 1
                );
            }
        }
    }
}

// --- the centred triad (triad.rs) ---

#[test]
fn centred_triad_properties() {
    let mut rng = Lcg(11);
    for _ in 0..200 {
        let ra = *Quat::from_scaled_axis(rng.vec(2.0))
            .to_rotation_matrix()
            .matrix();
        let rb = *Quat::from_scaled_axis(rng.vec(2.0))
            .to_rotation_matrix()
            .matrix();
        let Ok(c) = centred(&ra, &rb, 0.0) else {
            continue;
        };
        let e3: Vec3 = c.triad.column(2).into();
        let bis = (ra.column(2) + rb.column(2)).normalize();
        assert!((e3 - bis).norm() < 1e-12, "e3 is the bisector");
        let (a1, a2) = (c.angles.x, c.angles.y);
        assert!((a1 * a1 + a2 * a2 - c.alpha * c.alpha).abs() < 1e-12);
        // e3 · q = 0
        let q = ra.column(2).cross(&rb.column(2));
        assert!(e3.dot(&q).abs() < 1e-12);
        // b' = Rot(e3, β)·a': frame b rotated back by α/2 equals frame a rotated on by α/2
        // and twisted by β about e3
        let phi = q * x_over_sin(c.alpha);
        let a_half = exp_so3(&(phi * 0.5)) * ra;
        let b_half = exp_so3(&(-phi * 0.5)) * rb;
        let diff = (a_half * rot_z(c.angles.z) - b_half).norm();
        assert!(diff < 1e-12, "torsion twist β reproduces frame b: {diff}");
        // a ↔ b swap: same triad, angles negated
        let s = centred(&rb, &ra, 0.0).expect("regular");
        assert!((s.triad - c.triad).norm() < 1e-12);
        assert!((s.angles + c.angles).norm() < 1e-12);
    }
}

/// The triad's own variation: δe_i = δψ × e_i with δψ = A δθ_a + B δθ_b.
#[test]
fn triad_variation_matches_differences() {
    let mut rng = Lcg(3);
    let h = 1e-6;
    for _ in 0..50 {
        let qa = Quat::from_scaled_axis(rng.vec(1.5));
        let qb = Quat::from_scaled_axis(rng.vec(1.5));
        let ra = *qa.to_rotation_matrix().matrix();
        let rb = *qb.to_rotation_matrix().matrix();
        let c = centred(&ra, &rb, 0.0).expect("regular");
        for j in 0..6 {
            let mut e = Vec3::zeros();
            e[j % 3] = h;
            let rot = |q: Quat, d: Vec3| {
                *(Quat::from_scaled_axis(d) * q)
                    .to_rotation_matrix()
                    .matrix()
            };
            let (p, m) = if j < 3 {
                (
                    centred(&rot(qa, e), &rb, c.angles.z),
                    centred(&rot(qa, -e), &rb, c.angles.z),
                )
            } else {
                (
                    centred(&ra, &rot(qb, e), c.angles.z),
                    centred(&ra, &rot(qb, -e), c.angles.z),
                )
            };
            let (p, m) = (p.expect("regular"), m.expect("regular"));
            let de = (p.triad - m.triad) / (2.0 * h);
            // ∂ψ/∂θ_a = A, ∂ψ/∂θ_b = I − A (a rigid rotation of both turns the triad)
            let b = Mat3::identity() - c.a;
            let dpsi = if j < 3 { c.a * e / h } else { b * e / h };
            for i in 0..3 {
                let pred = dpsi.cross(&c.triad.column(i));
                assert!((de.column(i) - pred).norm() < 1e-7, "triad variation");
            }
        }
    }
}

#[test]
fn torsion_through_four_pi_is_continuous() {
    let ct = ALL[2];
    let a = Node::default();
    let mut br = Branches::default();
    let n = 400;
    for i in 0..=n {
        let ang = 4.0 * PI * i as f64 / n as f64;
        let b = Node {
            q: Quat::from_scaled_axis(Vec3::new(0.0, 0.0, ang)),
            ..a
        };
        let g = geometry(ct, &a, &b, &br).expect("regular");
        assert!((g.pos[5] - ang).abs() < 1e-9, "β = {} at {ang}", g.pos[5]);
        br = g.branches;
    }
}

#[test]
fn folded_shafts_are_refused_not_nan() {
    let ct = ALL[2];
    let a = Node::default();
    let b = Node {
        q: Quat::from_scaled_axis(Vec3::new(PI, 0.0, 0.0)),
        ..a
    };
    assert!(matches!(
        geometry(ct, &a, &b, &Branches::default()),
        Err(Singular::FlexionNearPi(_))
    ));
    let q = quat_from_wxyz(1.0, 0.0, 0.0, 0.0).expect("unit");
    let b = Node { q, ..a };
    assert!(geometry(ct, &a, &b, &Branches::default()).is_ok());
}

// --- RADIAL-THRUST (radial_thrust.rs) ---

#[test]
fn radial_direction_kept_on_axis() {
    let ct = ALL[4];
    let a = Node::default();
    let b = Node {
        r: Vec3::new(0.0, 0.5, 1.0),
        ..a
    };
    let g = geometry(ct, &a, &b, &Branches::default()).expect("regular");
    assert!((g.branches.e_r_local - Vec3::y()).norm() < 1e-15);
    let on_axis = Node {
        r: Vec3::new(0.0, 0.0, 1.0),
        ..a
    };
    let g2 = geometry(ct, &a, &on_axis, &g.branches).expect("regular");
    assert_eq!(g2.pos[0], 0.0);
    assert!((g2.gradient(ct, 0, &Vec3::zeros()).xb - Vec3::y()).norm() < 1e-15);
}
