//! REVOLUTE, the rotational part of PLANAR (docs/physics.md, "PLANAR"): the rotation α about
//! e1a on its continuous branch and the constraint rotations φ2, φ3 that keep e1b along e1a,
//! with their Jacobian K (`Revolute`, `revolute`). Its translational part, SLIDE-PLANE, is the
//! projection x_i = e_i·d on node a's frame, which the dispatch writes (`geometry_into`). Uses
//! `math` and `geometry`'s `Singular` only.

use super::geometry::Singular;
use crate::physics::math::{continue_branch, lift, Mat3, Real, Scalar, Vec3};

/// REVOLUTE's rotational components (slots 4–6) and their gradients: the angle α about e1
/// and the two constraint rotations φ2, φ3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Revolute<T: Scalar = Real> {
    /// (α, φ2, φ3), α on its continuous branch.
    pub pos: [T; 3],
    /// K = ∂(α, φ2, φ3)/∂θ_b (rows); ∂/∂θ_a = −K (each depends on the relative rotation
    /// only), ∂/∂x_a = ∂/∂x_b = 0.
    pub k: Mat3<T>,
}

impl Revolute<Real> {
    /// The same components in any scalar, as constants (no derivative).
    #[inline(always)]
    pub fn lift<T: Scalar>(&self) -> Revolute<T> {
        Revolute {
            pos: lift(self.pos),
            k: self.k.map(T::cst),
        }
    }
}

/// `Revolute` for frames `ra`, `rb`, α continued from `alpha_prev`.
#[inline(always)]
pub fn revolute<T: Scalar>(
    ra: &Mat3<T>,
    rb: &Mat3<T>,
    alpha_prev: Real,
) -> Result<Revolute<T>, Singular> {
    let (e2a, e3a): (Vec3<T>, Vec3<T>) = (ra.column(1).into(), ra.column(2).into());
    let (e1b, e3b): (Vec3<T>, Vec3<T>) = (rb.column(0).into(), rb.column(2).into());
    // α = −atan((e2a·e3b)/(e3a·e3b)) = atan2(Y, X), Y = −e2a·e3b, X = e3a·e3b
    let y = -e2a.dot(&e3b);
    let x = e3a.dot(&e3b);
    let rr = x * x + y * y;
    if rr.re().is_nan() || rr.re() <= 1e-12 {
        return Err(if rr.re().is_finite() {
            Singular::RevoluteUndefined
        } else {
            Singular::NotFinite
        });
    }
    let alpha = continue_branch(y.atan2(x), alpha_prev);
    // δ(e_ia·e_jb) = δθ_b·(e_jb × e_ia) + δθ_a·(e_ia × e_jb): the θ_a part is the θ_b part's
    // negative
    let dy_tb = -e3b.cross(&e2a);
    let dx_tb = e3b.cross(&e3a);
    Ok(Revolute {
        // constraint rotations: φ2 = −e3a·e1b, φ3 = e2a·e1b (both 0 when e1b ∥ e1a)
        pos: [alpha, -e3a.dot(&e1b), e2a.dot(&e1b)],
        k: Mat3::from_rows(&[
            ((dy_tb * x - dx_tb * y) / rr).transpose(),
            (-e1b.cross(&e3a)).transpose(),
            e1b.cross(&e2a).transpose(),
        ]),
    })
}
