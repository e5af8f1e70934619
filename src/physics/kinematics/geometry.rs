//! What an evaluation of the kinematics gives, shared by every connection type: the component
//! positions with their gradients kept factored (`Geometry`), from which the component rates
//! and the node loads follow (`Geometry::rates`, `Geometry::loads`), a gradient written out
//! (`Grad`), RADIAL-THRUST's own gradients (`Radial`, a field of `Geometry`), the angle
//! branches and remembered directions kept between evaluations (`Branches`) and the
//! configurations that cannot be measured (`Singular`). Uses `math`, `connection` and `pose`;
//! the per-type parts write into it.

use super::connection::{ConnectionType, Role, Rotational, Translational};
use super::pose::Pose;
use crate::physics::math::{Mat3, Real, Scalar, Vec3};

/// Gradient of one component with respect to the node motions (all in W).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grad<T: Scalar = Real> {
    /// ∂c/∂x_a
    pub xa: Vec3<T>,
    /// ∂c/∂θ_a
    pub ta: Vec3<T>,
    /// ∂c/∂x_b
    pub xb: Vec3<T>,
    /// ∂c/∂θ_b
    pub tb: Vec3<T>,
}

impl Grad {
    /// A component that does not depend on the node motions.
    pub const ZERO: Grad = Grad {
        xa: Vec3::new(0.0, 0.0, 0.0),
        ta: Vec3::new(0.0, 0.0, 0.0),
        xb: Vec3::new(0.0, 0.0, 0.0),
        tb: Vec3::new(0.0, 0.0, 0.0),
    };
}

impl Default for Grad {
    fn default() -> Self {
        Grad::ZERO
    }
}

impl<T: Scalar> Grad<T> {
    /// A component that does not depend on the node motions.
    #[inline(always)]
    pub fn zero() -> Grad<T> {
        Grad {
            xa: Vec3::zeros(),
            ta: Vec3::zeros(),
            xb: Vec3::zeros(),
            tb: Vec3::zeros(),
        }
    }

    /// Rate of the component for the node twists: ċ = ∇c · (v_a, ω_a, v_b, ω_b), written
    /// with ∂c/∂x_a = −∂c/∂x_b (every component depends on the positions through
    /// d = x_b − x_a only).
    #[inline]
    pub fn rate(&self, p: &Pose<T>) -> T {
        self.xb.dot(&p.dv) + self.ta.dot(&p.wa) + self.tb.dot(&p.wb)
    }
}

/// The gradient of a RADIAL-THRUST component (r or l): it depends on the positions through d
/// alone (∂c/∂x_a = −∂c/∂x_b) and on node a's rotation, not on node b's (∂c/∂θ_b = 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Radial<T: Scalar = Real> {
    /// ∂c/∂x_b
    pub xb: Vec3<T>,
    /// ∂c/∂θ_a
    pub ta: Vec3<T>,
}

/// The slots of RADIAL-THRUST's r and l (components 1 and 3), in `Geometry::radial`'s order.
const RADIAL_SLOTS: [usize; 2] = [0, 2];

/// Angle branches and remembered directions: kinematic state kept between evaluations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Branches {
    /// Torsion β of PROJECTION FLEXION-TORSION (continuous, rad).
    pub beta: Real,
    /// Rotation α of PLANAR's REVOLUTE part (continuous, rad).
    pub alpha: Real,
    /// RADIAL-THRUST radial direction e_r in node-a coordinates, kept while r is tiny.
    pub e_r_local: Vec3,
}

impl Default for Branches {
    fn default() -> Self {
        Branches {
            beta: 0.0,
            alpha: 0.0,
            e_r_local: Vec3::x(),
        }
    }
}

/// A configuration the kinematics cannot measure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Singular {
    /// PROJECTION FLEXION-TORSION with the shafts folded back (α → π).
    FlexionNearPi(Real),
    /// PLANAR with e3b perpendicular to the 2–3 plane of a (rotation α undefined).
    RevoluteUndefined,
    /// A value that is not finite appeared (non-finite input reached the kinematics).
    NotFinite,
}

/// Component positions, their gradients and the local directions.
///
/// The gradients of the projection components are kept factored, as they arise:
/// - translations x_i = e_i·d (PROJECTION CARTESIAN, SLIDE-PLANE): ∂x_i/∂x_b = e_i,
///   ∂x_i/∂θ_a = Aᵀ(e_i × d), ∂x_i/∂θ_b = Bᵀ(e_i × d), with A = ∂ψ/∂θ_a (`tri_a`) and
///   B = I − A for the centred triad, B = 0 when the triad is node a's frame (A = I);
/// - flexion–torsion angles (α1, α2, β): ∂/∂θ_b = K (`k`, rows), ∂/∂θ_a = −K;
/// - REVOLUTE's α, φ2, φ3, which depend on the relative rotation only: ∂/∂θ_b = K (`k`, rows),
///   ∂/∂θ_a = −K, ∂/∂x = 0.
///
/// So the rates and the node loads need no per-component gradient (`rates`, `loads`). The
/// other components (RADIAL-THRUST's r and l) carry theirs in `radial`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Geometry<T: Scalar = Real> {
    /// Position c_k of every component (slot k−1); 0 for absent slots.
    pub pos: [T; 6],
    /// The gradients of RADIAL-THRUST's r and l (slots 1 and 3), the components that are not
    /// projections (see above); None for the other types.
    pub radial: Option<[Radial<T>; 2]>,
    /// Local connector directions {e1, e2, e3} as columns (in W).
    pub triad: Mat3<T>,
    /// A = ∂ψ/∂θ_a of the centred triad, its rotation for a rotation of node a (zero, and not
    /// read, when the triad is node a's frame: there A = I).
    pub tri_a: Mat3<T>,
    /// K = ∂(α1, α2, β)/∂θ_b (rows) of FLEXION-TORSION, ∂(α, φ2, φ3)/∂θ_b of REVOLUTE (zero
    /// for other types).
    pub k: Mat3<T>,
    /// Updated branches (committed by the caller only when the step is accepted).
    pub branches: Branches,
}

impl<T: Scalar> Geometry<T> {
    /// All zero (triad and e_r_local included, so not a valid geometry): the cheapest value
    /// to evaluate into with `geometry_into`, which overwrites every field.
    #[inline(always)]
    pub fn blank() -> Geometry<T> {
        Geometry {
            pos: [T::zero(); 6],
            radial: None,
            triad: Mat3::zeros(),
            tri_a: Mat3::zeros(),
            k: Mat3::zeros(),
            branches: Branches {
                beta: 0.0,
                alpha: 0.0,
                e_r_local: Vec3::zeros(),
            },
        }
    }

    /// Whether slots 0..3 are projections x_i = e_i·d on the triad.
    #[inline(always)]
    fn projected_translations(ct: ConnectionType) -> bool {
        matches!(
            ct.trans,
            Translational::ProjectionCartesian | Translational::SlidePlane
        )
    }

    /// The triad's angular velocity ψ̇ = A ω_a + B ω_b (B = I − A centred, 0 otherwise).
    #[inline(always)]
    fn triad_rate(&self, ct: ConnectionType, p: &Pose<T>) -> Vec3<T> {
        if ct.centred() {
            p.wb + self.tri_a * (p.wa - p.wb)
        } else {
            p.wa
        }
    }

    /// Component rates ċ_k = ∇c_k · (v_a, ω_a, v_b, ω_b) for the twists of `p` (0 for absent
    /// slots): translations e_i·(Δv + d × ψ̇), flexion–torsion angles K(ω_b − ω_a), the others
    /// from their gradients.
    #[inline(always)]
    pub fn rates(&self, ct: ConnectionType, p: &Pose<T>) -> [T; 6] {
        let mut v = [T::zero(); 6];
        if Self::projected_translations(ct) {
            let u = p.dv + p.d.cross(&self.triad_rate(ct, p));
            for (i, vi) in v.iter_mut().enumerate().take(3) {
                *vi = self.triad.column(i).dot(&u);
            }
        }
        if ct.rot == Rotational::ProjectionFlexionTorsion {
            let w = self.k * (p.wb - p.wa);
            v[3..].copy_from_slice(w.as_slice());
        }
        if ct.rot == Rotational::Revolute {
            // K ω_b − K ω_a, row by row (the gradient's own sum: ∂/∂x·Δv is 0)
            for (i, vi) in v[3..].iter_mut().enumerate() {
                let row: Vec3<T> = self.k.row(i).transpose();
                *vi = row.dot(&p.wb) - row.dot(&p.wa);
            }
        }
        if let Some(own) = &self.radial {
            for (gr, k) in own.iter().zip(RADIAL_SLOTS) {
                v[k] = gr.xb.dot(&p.dv) + gr.ta.dot(&p.wa);
            }
        }
        v
    }

    /// Whether component k's gradient is kept factored (a projection, or a REVOLUTE rotation:
    /// `k`).
    #[inline(always)]
    fn factored(ct: ConnectionType, k: usize) -> bool {
        if k < 3 {
            Self::projected_translations(ct)
        } else {
            matches!(
                ct.rot,
                Rotational::ProjectionFlexionTorsion | Rotational::Revolute
            )
        }
    }

    /// Node loads by virtual work for component forces `f`: (m_a, f_b, m_b) = −Σ f_k (∂c_k/∂θ_a,
    /// ∂c_k/∂x_b, ∂c_k/∂θ_b); f_a = −f_b. For the translations with F = Σ f_i e_i:
    /// Σ f_i (e_i × d) = F × d, so the moments are Aᵀ(F × d) and Bᵀ(F × d); for the
    /// flexion–torsion angles ±Kᵀ(f4, f5, f6); for REVOLUTE's rotations the same, slot by slot.
    #[inline(always)]
    pub fn loads(
        &self,
        ct: ConnectionType,
        p: &Pose<T>,
        f: &[T; 6],
    ) -> (Vec3<T>, Vec3<T>, Vec3<T>) {
        let (mut ma, mut fb, mut mb) = (Vec3::zeros(), Vec3::zeros(), Vec3::zeros());
        if Self::projected_translations(ct) {
            let force = self.triad * Vec3::new(f[0], f[1], f[2]);
            let fxd = force.cross(&p.d);
            fb -= force;
            if ct.centred() {
                let on_a = self.tri_a.transpose() * fxd;
                ma -= on_a;
                mb -= fxd - on_a;
            } else {
                ma -= fxd;
            }
        }
        if ct.rot == Rotational::ProjectionFlexionTorsion {
            let m = self.k.transpose() * Vec3::new(f[3], f[4], f[5]);
            ma += m;
            mb -= m;
        }
        if let Some(own) = &self.radial {
            for (gr, k) in own.iter().zip(RADIAL_SLOTS) {
                let fk = f[k];
                if fk.re() != 0.0 || fk.eps() != 0.0 {
                    ma -= gr.ta * fk;
                    fb -= gr.xb * fk;
                }
            }
        }
        if ct.rot == Rotational::Revolute {
            // −f_k (∂c_k/∂θ_a, ∂c_k/∂θ_b) = f_k (K_k, −K_k), slot by slot as a gradient's own
            for (i, &fk) in f[3..].iter().enumerate() {
                if fk.re() != 0.0 || fk.eps() != 0.0 {
                    let row: Vec3<T> = self.k.row(i).transpose();
                    ma += row * fk;
                    mb -= row * fk;
                }
            }
        }
        (ma, fb, mb)
    }

    /// The gradient of component k written out (d = x_b − x_a of the pose it was computed at):
    /// what `rates` and `loads` use, for tests and inspection.
    pub fn gradient(&self, ct: ConnectionType, k: usize, d: &Vec3<T>) -> Grad<T> {
        if ct.roles()[k] == Role::Absent || !Self::factored(ct, k) {
            let own = RADIAL_SLOTS.iter().position(|&s| s == k);
            return match (&self.radial, own) {
                (Some(radial), Some(i)) => Grad {
                    xa: -radial[i].xb,
                    ta: radial[i].ta,
                    xb: radial[i].xb,
                    tb: Vec3::zeros(),
                },
                _ => Grad::zero(),
            };
        }
        if k < 3 {
            let e: Vec3<T> = self.triad.column(k).into();
            let exd = e.cross(d);
            let (ta, tb) = if ct.centred() {
                let ta = self.tri_a.transpose() * exd;
                (ta, exd - ta)
            } else {
                (exd, Vec3::zeros())
            };
            return Grad {
                xa: -e,
                ta,
                xb: e,
                tb,
            };
        }
        let row: Vec3<T> = self.k.row(k - 3).transpose();
        Grad {
            xa: Vec3::zeros(),
            ta: -row,
            xb: Vec3::zeros(),
            tb: row,
        }
    }
}
