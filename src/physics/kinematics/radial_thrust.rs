//! RADIAL-THRUST (docs/physics.md, "RADIAL-THRUST"): the radial distance r from node a's axis
//! e3a and the distance l along it (components 1 and 3), with their gradients (`Radial`), and
//! the radial direction e_r kept while r is tiny (`R_MIN`, `Branches::e_r_local`). Uses `math`
//! and `geometry` only.

use super::geometry::{Branches, Geometry, Radial};
use crate::physics::math::{lift3, norm2, Mat3, Real, Scalar, Vec3};

/// Below this radius (m) RADIAL-THRUST keeps its last radial direction.
pub const R_MIN: Real = 1e-9;

/// RADIAL-THRUST's r and l (slots 1 and 3) at node a's frame `ra` and d = x_b − x_a, written
/// into `g` with their gradients (`g.radial`) and, where r is not tiny, e_r
/// (`g.branches.e_r_local`); on the axis e_r is `prev`'s. The translational arm of
/// `geometry_into`, which writes the rest of `g`.
#[inline(always)]
pub(super) fn radial_thrust_into<T: Scalar>(
    ra: &Mat3<T>,
    d: &Vec3<T>,
    prev: &Branches,
    g: &mut Geometry<T>,
) {
    let e3a: Vec3<T> = ra.column(2).into();
    let d_loc = ra.transpose() * d;
    let r = norm2(d_loc.x, d_loc.y);
    let l = d_loc.z;
    // Why: e_r = d⊥/r is undefined on the axis; keep the last well-defined direction.
    let e_r_local = if r.re() > R_MIN {
        let e = Vec3::new(d_loc.x / r, d_loc.y / r, T::zero());
        g.branches.e_r_local = e.map(|x| x.re());
        e
    } else {
        lift3(&prev.e_r_local)
    };
    let e_r = ra * e_r_local;
    g.pos[0] = r;
    g.pos[2] = l;
    g.radial = Some([
        Radial {
            xb: e_r,
            ta: -e3a.cross(&e_r) * l,
        },
        Radial {
            xb: e3a,
            ta: e3a.cross(d),
        },
    ]);
}
