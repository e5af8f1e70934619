//! Connector kinematics: the component positions c_k of every connection type and their
//! gradients with respect to the node motions (the manual's connection types; docs/physics.md, "Kinematics").
//!
//! Components use the Abaqus numbering k = 1..6 (slot k−1): 1–3 translations, 4–6 rotations.
//! Node motions are δx (translation, W) and δθ (small rotation vector, W) per node; the
//! gradient `Grad` of a component holds ∂c/∂x_a, ∂c/∂θ_a, ∂c/∂x_b, ∂c/∂θ_b. Component
//! velocities and node loads (virtual work) both follow from these gradients, so the loads
//! are exactly in equilibrium and a purely elastic connector is exactly conservative. The
//! projection components and REVOLUTE's rotations keep their gradients factored (the triad, its
//! rotation ∂ψ/∂θ_a and the angles' Jacobian K, `Geometry::rates` and `Geometry::loads`);
//! RADIAL-THRUST's r and l carry the parts of theirs that are not zero (`Radial`);
//! `Geometry::gradient` writes any component's out.
//!
//! The parts, one per concern, each using only those before it in the order connection, pose;
//! geometry; triad, revolute, radial_thrust; source; this file (the per-type parts never use
//! each other, only `source` uses two of them; their tests go through `geometry`). The rest of
//! the crate names every item through this module (`crate::physics::kinematics::X`, re-exported
//! below):
//! - `connection`: the connection types and the roles of their component slots;
//! - `pose`: the two nodes as the kinematics reads them (`Node`, `Pose`);
//! - `geometry`: what an evaluation gives, for every type (`Geometry`, with its factored rates
//!   and loads; `Grad`, `Radial`, `Branches`, `Singular`);
//! - `triad`: the centred projection triad, PROJECTION CARTESIAN's directions and PROJECTION
//!   FLEXION-TORSION's angles α1, α2, β, with the flexion limit (`Centred`, `Shafts`);
//! - `revolute`: REVOLUTE's α, φ2, φ3 (PLANAR's rotational part);
//! - `radial_thrust`: RADIAL-THRUST's r and l;
//! - `source`: where the centred triad and REVOLUTE's rotations come from (`Triads`);
//! - this file: the dispatch over the connection type (`geometry`, `geometry_into`), with the
//!   projected translations x_i = e_i·d of PROJECTION CARTESIAN and SLIDE-PLANE (on the centred
//!   triad, on node a's frame), and the tests across the types.

mod connection;
mod geometry;
mod pose;
mod radial_thrust;
mod revolute;
mod source;
mod triad;

pub(crate) use connection::with_constant_type;
pub use connection::{ConnectionType, Role, Rotational, Translational};
pub use geometry::{Branches, Geometry, Grad, Radial, Singular};
pub use pose::{frame_of_raw, Node, NodeDual, Pose};
pub use radial_thrust::R_MIN;
pub use revolute::{revolute, Revolute};
pub use source::{constant, Computed, TriadSource, Triads};
pub use triad::{
    centred, centred_with, flexion, shaft, Calls, Centred, Shafts, TriadLibm, TriadTrig,
    ALPHA_MAX_GAP,
};

use crate::physics::math::{Mat3, Scalar};
use radial_thrust::radial_thrust_into;

/// Component positions and gradients of a connection type at nodes a, b.
///
/// `prev` holds the branches of the last accepted evaluation; the returned geometry carries
/// the updated ones. Absent slots stay zero.
pub fn geometry(
    ct: ConnectionType,
    a: &Node,
    b: &Node,
    prev: &Branches,
) -> Result<Geometry, Singular> {
    let mut g = Geometry::blank();
    geometry_into(ct, &Pose::of(a, b), prev, Computed, &mut g)?;
    Ok(g)
}

/// `geometry` at a pose, written into `g` (the per-step path, `connector::evaluate_into`: no
/// copy of the result). Every field of `g` is overwritten (`radial` None but for
/// RADIAL-THRUST; `tri_a` zero when the triad is node a's frame, `k` zero without
/// FLEXION-TORSION or REVOLUTE); on an error its contents are unspecified.
///
/// `triads`: how the centred triad of this pose's orientations at `prev.beta` is come by
/// (`Triads`).
///
/// A caller that starts from `Geometry::blank()` (all zero) lets the compiler drop that
/// zeroing where this function overwrites it: with the connection type a constant, every store
/// below is to a known place (a `Result<Geometry, _>` returned by value was copied instead, and
/// so was a start from a geometry with an identity triad, which is not zero bits).
#[inline(always)]
pub fn geometry_into<T: Scalar, S: Triads<T>>(
    ct: ConnectionType,
    pose: &Pose<T>,
    prev: &Branches,
    triads: S,
    g: &mut Geometry<T>,
) -> Result<(), Singular> {
    let (ra, rb, d) = (pose.ra, pose.rb, pose.d);
    // only the slots the connection type leaves absent are zeroed, the others are written
    // below; gradients of their own only where a component has one
    for (k, role) in ct.roles().iter().enumerate() {
        if *role == Role::Absent {
            g.pos[k] = T::zero();
        }
    }
    g.radial = None;
    g.triad = ra;
    g.branches = *prev;

    // Local directions and, for the centred triad, the rotational components and
    // A = ∂ψ/∂θ_a (∂ψ/∂θ_b = I − A: a rigid rotation of both nodes turns the centred triad with
    // them); `tri_a` and `k` are zero where they do not apply (see `Geometry`)
    g.tri_a = Mat3::zeros();
    g.k = Mat3::zeros();
    // a direction that leaves both orientations alone (a seed on positions or velocities)
    // leaves the centred triad alone, and REVOLUTE's rotations: the caller's or computed in
    // Real (the same values), lifted, instead of carrying zero derivatives through every
    // product
    let fixed = T::DUAL && constant(&ra) && constant(&rb);
    let rev = if ct.rot == Rotational::Revolute {
        Some(triads.revolute(&ra, &rb, prev.alpha, fixed)?)
    } else {
        None
    };
    if ct.centred() {
        let mut slot = None;
        let cen = triads.centred(&ra, &rb, prev.beta, fixed, &mut slot)?;
        g.triad = cen.triad;
        g.branches.beta = cen.angles.z.re();
        g.tri_a = cen.a;
        if ct.rot == Rotational::ProjectionFlexionTorsion {
            g.k = cen.k;
            for i in 0..3 {
                g.pos[3 + i] = cen.angles[i];
            }
        }
    }

    match ct.trans {
        Translational::None => {}
        Translational::ProjectionCartesian | Translational::SlidePlane => {
            // x_i = e_i·d; δx_i = e_i·(δx_b − δx_a) + δψ·(e_i × d) (gradient factored: see
            // `Geometry`)
            for i in 0..3 {
                g.pos[i] = g.triad.column(i).dot(&d);
            }
        }
        Translational::RadialThrust => radial_thrust_into(&ra, &d, prev, g),
    }

    if let Some(rev) = rev {
        g.branches.alpha = rev.pos[0].re();
        g.pos[3..].copy_from_slice(&rev.pos);
        g.k = rev.k;
    }

    if g.pos.iter().all(|p| p.re().is_finite()) {
        Ok(())
    } else {
        Err(Singular::NotFinite)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::math::{Quat, Real, Vec3};

    pub(super) const ALL: [ConnectionType; 5] = [
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
    pub(super) struct Lcg(pub(super) u64);
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
}
