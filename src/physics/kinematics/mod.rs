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
//! each other, only `source` uses two of them). The rest of
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
//!   triad, on node a's frame);
//! - `tests`: the tests of all of them (they go through the dispatch, so they sit above it).

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
mod tests;
