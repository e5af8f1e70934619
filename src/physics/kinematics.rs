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

use super::math::{
    continue_branch, lift, lift3, norm2, norm3, rotation_of, Mat3, Quat, Real, Scalar, SinCos, Vec3,
};

/// Pose and twist of one node, all in W.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// Position x (m).
    pub r: Vec3,
    /// Orientation: maps node-local coordinates to W.
    pub q: Quat,
    /// Velocity (m/s).
    pub v: Vec3,
    /// Angular velocity (rad/s).
    pub w: Vec3,
}

impl Default for Node {
    fn default() -> Self {
        Node {
            r: Vec3::zeros(),
            q: Quat::identity(),
            v: Vec3::zeros(),
            w: Vec3::zeros(),
        }
    }
}

/// Translational part of a connection type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Translational {
    /// No translational components.
    None,
    /// PROJECTION CARTESIAN: x, y, z along the centred projection triad.
    ProjectionCartesian,
    /// SLIDE-PLANE: y, z in the plane of normal e1a (available), x = e1a·d constrained.
    SlidePlane,
    /// RADIAL-THRUST: r (component 1) and l (component 3) about the axis e3a.
    RadialThrust,
}

/// Rotational part of a connection type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Rotational {
    /// No rotational components.
    None,
    /// PROJECTION FLEXION-TORSION: α1, α2, β on the centred triad.
    ProjectionFlexionTorsion,
    /// REVOLUTE: α about e1a (available), e1b kept along e1a by two constraint rotations.
    Revolute,
}

/// What a component slot is in a connection type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// Not part of the connection type.
    Absent,
    /// An available component: constitutive behaviour, stops, friction act on it.
    Available,
    /// A kinematic constraint, enforced by a penalty; its reaction is CRF/CRM.
    Constrained,
}

/// A connection type: translational part + rotational part (or an assembled type).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ConnectionType {
    /// Translational part.
    pub trans: Translational,
    /// Rotational part.
    pub rot: Rotational,
}

/// `$body` evaluated with `$c` a constant copy of the connection type `$ct`, one copy of the
/// body per connection type of the variants (the branches on the type and its roles fold
/// away in each); other pairings take the general copy, `$c` = `$ct`.
macro_rules! with_constant_type {
    ($ct:expr, |$c:ident| $body:expr) => {
        with_constant_type!(@types $ct, $c, $body;
            (SlidePlane, Revolute),
            (ProjectionCartesian, None),
            (None, ProjectionFlexionTorsion),
            (ProjectionCartesian, ProjectionFlexionTorsion),
            (RadialThrust, None))
    };
    (@types $ct:expr, $c:ident, $body:expr; $(($t:ident, $r:ident)),*) => {{
        use $crate::physics::kinematics::{
            ConnectionType as Ct, Rotational as R, Translational as T,
        };
        let ct: Ct = $ct;
        match (ct.trans, ct.rot) {
            $((T::$t, R::$r) => {
                const $c: Ct = Ct { trans: T::$t, rot: R::$r };
                $body
            })*
            _ => {
                #[allow(non_snake_case)]
                let $c = ct;
                $body
            }
        }
    }};
}
pub(crate) use with_constant_type;

impl ConnectionType {
    /// Role of every component slot (k = 1..6 at index k−1).
    #[inline(always)]
    pub fn roles(&self) -> [Role; 6] {
        use Role::*;
        let mut r = [Absent; 6];
        match self.trans {
            Translational::None => {}
            Translational::ProjectionCartesian => r[..3].copy_from_slice(&[Available; 3]),
            Translational::SlidePlane => {
                r[..3].copy_from_slice(&[Constrained, Available, Available])
            }
            Translational::RadialThrust => {
                r[0] = Available;
                r[2] = Available;
            }
        }
        match self.rot {
            Rotational::None => {}
            Rotational::ProjectionFlexionTorsion => r[3..].copy_from_slice(&[Available; 3]),
            Rotational::Revolute => r[3..].copy_from_slice(&[Available, Constrained, Constrained]),
        }
        r
    }

    /// Whether the local directions are the centred projection triad (else they follow node a).
    pub fn centred(&self) -> bool {
        self.trans == Translational::ProjectionCartesian
            || self.rot == Rotational::ProjectionFlexionTorsion
    }

    /// Whether node a's orientation matters (else it is not an input of the FMU).
    pub fn uses_orientation_a(&self) -> bool {
        self.centred() || self.trans != Translational::None || self.rot != Rotational::None
    }

    /// Whether node b's orientation matters (RADIAL-THRUST: "orientation at b: ignored").
    pub fn uses_orientation_b(&self) -> bool {
        self.centred() || self.rot != Rotational::None
    }

    /// Whether the node positions matter.
    pub fn uses_positions(&self) -> bool {
        self.trans != Translational::None
    }
}

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

/// The two nodes as the kinematics reads them: frames, relative position and twists (W).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose<T: Scalar = Real> {
    /// Node a's frame (columns e1a, e2a, e3a).
    pub ra: Mat3<T>,
    /// Node b's frame.
    pub rb: Mat3<T>,
    /// d = x_b − x_a.
    pub d: Vec3<T>,
    /// v_b − v_a.
    pub dv: Vec3<T>,
    /// ω_a.
    pub wa: Vec3<T>,
    /// ω_b.
    pub wb: Vec3<T>,
}

impl Pose {
    /// The pose of nodes a and b.
    #[inline(always)]
    pub fn of(a: &Node, b: &Node) -> Pose {
        Pose {
            ra: *a.q.to_rotation_matrix().matrix(),
            rb: *b.q.to_rotation_matrix().matrix(),
            d: b.r - a.r,
            dv: b.v - a.v,
            wa: a.w,
            wb: b.w,
        }
    }
}

/// A node's raw inputs (x, q as w, i, j, k, v, ω) with their derivatives along a direction.
pub type NodeDual = [super::math::Dual; 13];

impl Pose<super::math::Dual> {
    /// The pose of two nodes given as raw inputs with derivatives: the quaternions normalised
    /// as `math::quat_from_wxyz` does (its value; the derivative is that of q/|q|, which the
    /// inputs' round-off rule does not change), so the value is `Pose::of` of the same nodes
    /// bit for bit. `frames`: the frames of these orientation inputs in Real
    /// (`frame_of_raw` of each), which a node whose orientation the direction leaves alone
    /// takes as a constant.
    pub fn of_inputs(a: &NodeDual, b: &NodeDual, frames: &[Mat3; 2]) -> Self {
        use super::math::{quat_from_wxyz, Dual};
        let frame = |u: &NodeDual, known: &Mat3| {
            let q = [u[3], u[4], u[5], u[6]];
            if q.iter().all(|x| x.eps == 0.0) {
                // an orientation the direction leaves alone (every seed but its own): a
                // constant frame
                return known.map(|x| Dual::new(x, 0.0));
            }
            // the value as the Real path reads it; a refused quaternion never gets here (the
            // inputs were checked when set), and would give NaN, which the caller refuses
            let unit = quat_from_wxyz(q[0].re, q[1].re, q[2].re, q[3].re)
                .map_or([Real::NAN; 4], |x| [x.w, x.i, x.j, x.k]);
            let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
            let q: [Dual; 4] = std::array::from_fn(|i| Dual::new(unit[i], (q[i] / n).eps));
            rotation_of(q[0], q[1], q[2], q[3])
        };
        let v = |u: &NodeDual, i: usize| Vec3::new(u[i], u[i + 1], u[i + 2]);
        Pose {
            ra: frame(a, &frames[0]),
            rb: frame(b, &frames[1]),
            d: v(b, 0) - v(a, 0),
            dv: v(b, 7) - v(a, 7),
            wa: v(a, 10),
            wb: v(b, 10),
        }
    }
}

/// The frame of a node's raw orientation input (w, x, y, z), normalised as
/// `math::quat_from_wxyz` reads it (the same bits as `Pose::of`'s frame of that node); NaN
/// where it is no rotation (the setters refuse such an input).
pub fn frame_of_raw(q: &[Real; 4]) -> Mat3 {
    let unit = super::math::quat_from_wxyz(q[0], q[1], q[2], q[3])
        .map_or([Real::NAN; 4], |x| [x.w, x.i, x.j, x.k]);
    rotation_of(unit[0], unit[1], unit[2], unit[3])
}

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

/// Below this radius (m) RADIAL-THRUST keeps its last radial direction.
pub const R_MIN: Real = 1e-9;
/// Flexion angles closer than this to π (rad) are refused: near the folded configuration
/// the torsion β loses accuracy like ε/(1 + cos α) and the node moments grow like
/// 1/cos(α/2) (2e3 at this gap), so the connector stops being meaningful before it is NaN.
pub const ALPHA_MAX_GAP: Real = 1e-3;

/// Total flexion α = ∠(e3a, e3b) of two orientations.
#[inline]
pub fn flexion(qa: &Quat, qb: &Quat) -> Real {
    Shafts::of(qa, qb).flexion()
}

/// The shaft axes e3a, e3b of two orientations: their flexion α, or only cos α (no atan2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shafts {
    /// e3a (W).
    pub e3a: Vec3,
    /// e3b (W).
    pub e3b: Vec3,
}

impl Shafts {
    /// The shaft axes of orientations a and b.
    #[inline]
    pub fn of(qa: &Quat, qb: &Quat) -> Shafts {
        Shafts {
            e3a: shaft(qa),
            e3b: shaft(qb),
        }
    }

    /// cos α = e3a·e3b.
    #[inline]
    pub fn cos_flexion(&self) -> Real {
        self.e3a.dot(&self.e3b)
    }

    /// The total flexion α = atan2(|e3a × e3b|, e3a·e3b) ∈ [0, π].
    #[inline]
    pub fn flexion(&self) -> Real {
        self.e3a.cross(&self.e3b).norm().atan2(self.cos_flexion())
    }
}

/// q·e3, the rotated third axis: nalgebra's `q * Vector3::z()` (t = 2 u × e3,
/// e3 + w t + u × t, u = the vector part) without its products with the zeros of e3, which
/// change no value (a product with ±0 added to a non-zero term leaves it exact; only the sign
/// of an exact zero can differ, which no use of the axes can tell: they enter dot and cross
/// products and a comparison `> 0`).
#[inline]
pub fn shaft(q: &Quat) -> Vec3 {
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    let (tx, ty) = (y * 2.0, -x * 2.0);
    Vec3::new(tx * w - z * ty, ty * w + z * tx, (x * ty - y * tx) + 1.0)
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

/// The centred projection triad (docs/physics.md, "Centred projection triad") with the flexion–torsion angles and Jacobians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Centred<T: Scalar = Real> {
    /// {e1, e2, e3} as columns.
    pub triad: Mat3<T>,
    /// (α1, α2, β), β on its continuous branch.
    pub angles: Vec3<T>,
    /// Total flexion α.
    pub alpha: T,
    /// K = ∂(α1, α2, β)/∂θ_b (rows); ∂/∂θ_a = −K.
    pub k: Mat3<T>,
    /// A = ∂ψ/∂θ_a, the triad's rotation for a rotation of node a (W); ∂ψ/∂θ_b = I − A.
    pub a: Mat3<T>,
}

/// Whether a frame is a constant along the seeded direction (every derivative exactly 0).
#[inline]
pub fn constant<T: Scalar>(m: &Mat3<T>) -> bool {
    m.iter().all(|x| x.eps() == 0.0)
}

impl Centred {
    /// The same triad in any scalar, as a constant (no derivative).
    pub fn lift<T: Scalar>(&self) -> Centred<T> {
        let m = |x: &Mat3| x.map(T::cst);
        Centred {
            triad: m(&self.triad),
            angles: self.angles.map(T::cst),
            alpha: T::cst(self.alpha),
            k: m(&self.k),
            a: m(&self.a),
        }
    }
}

/// The centred triad and angles (the four construction steps in docs/physics.md), with exact
/// derivatives.
///
/// Parametrisation used for the derivatives: R_a = R_c·E(−v)·Z(−β/2), R_b = R_c·E(v)·Z(β/2),
/// v = (α1/2, α2/2, 0) in triad coordinates (E = exponential map, Z = rotation about 3).
pub fn centred<T: Scalar>(
    ra: &Mat3<T>,
    rb: &Mat3<T>,
    beta_prev: Real,
) -> Result<Centred<T>, Singular> {
    centred_with(ra, rb, beta_prev, Calls)
}

/// How `geometry_into` comes by the centred triad at a pose's orientations, and REVOLUTE's
/// rotations: `Computed` (the step), or as a `TriadSource` says (a read, whose triad
/// `instance::memo::PointMemo` computed and keeps; the directional derivatives, which all need
/// the same ones at a point). A type of its own for the step, so that its code has no branch
/// on it.
pub trait Triads<T: Scalar> {
    /// The centred triad at frames `ra`, `rb` and torsion branch `beta` (`fixed`: the frames
    /// are constants along the seeded direction); where one is computed, in `slot`.
    fn centred<'s>(
        self,
        ra: &Mat3<T>,
        rb: &Mat3<T>,
        beta: Real,
        fixed: bool,
        slot: &'s mut Option<Centred<T>>,
    ) -> Result<&'s Centred<T>, Singular>
    where
        Self: 's;

    /// REVOLUTE's rotations at frames `ra`, `rb` and branch `alpha` (`fixed`: the frames are
    /// constants along the seeded direction): computed, unless the source has them.
    #[inline(always)]
    fn revolute(
        &self,
        ra: &Mat3<T>,
        rb: &Mat3<T>,
        alpha: Real,
        fixed: bool,
    ) -> Result<Revolute<T>, Singular> {
        if fixed {
            Ok(revolute(&ra.map(|x| x.re()), &rb.map(|x| x.re()), alpha)?.lift())
        } else {
            revolute(ra, rb, alpha)
        }
    }
}

/// The centred triad computed (in Real and lifted where the frames are constants).
#[inline(always)]
fn computed<T: Scalar>(
    ra: &Mat3<T>,
    rb: &Mat3<T>,
    beta: Real,
    fixed: bool,
) -> Result<Centred<T>, Singular> {
    if fixed {
        Ok(centred(&ra.map(|x| x.re()), &rb.map(|x| x.re()), beta)?.lift())
    } else {
        centred(ra, rb, beta)
    }
}

/// Every triad computed: the step's evaluations.
pub struct Computed;

impl<T: Scalar> Triads<T> for Computed {
    #[inline(always)]
    fn centred<'s>(
        self,
        ra: &Mat3<T>,
        rb: &Mat3<T>,
        beta: Real,
        fixed: bool,
        slot: &'s mut Option<Centred<T>>,
    ) -> Result<&'s Centred<T>, Singular>
    where
        Self: 's,
    {
        Ok(slot.insert(computed(ra, rb, beta, fixed)?))
    }
}

impl<'a, T: Scalar> Triads<T> for TriadSource<'a, T> {
    #[inline(always)]
    fn centred<'s>(
        self,
        ra: &Mat3<T>,
        rb: &Mat3<T>,
        beta: Real,
        fixed: bool,
        slot: &'s mut Option<Centred<T>>,
    ) -> Result<&'s Centred<T>, Singular>
    where
        Self: 's,
    {
        match self {
            TriadSource::Given(c) if fixed || !T::DUAL => Ok(c),
            TriadSource::Trig(trig) if T::DUAL && !fixed => {
                Ok(slot.insert(centred_with(ra, rb, beta, trig)?))
            }
            TriadSource::RecordTrig(record) if T::DUAL && !fixed => {
                let mut trig = TriadTrig::default();
                let c = centred_with(ra, rb, beta, &mut trig)?;
                *record = Some(trig);
                Ok(slot.insert(c))
            }
            _ => Ok(slot.insert(computed(ra, rb, beta, fixed)?)),
        }
    }

    #[inline(always)]
    fn revolute(
        &self,
        ra: &Mat3<T>,
        rb: &Mat3<T>,
        alpha: Real,
        fixed: bool,
    ) -> Result<Revolute<T>, Singular> {
        match self {
            TriadSource::Revolute(rev) if fixed || !T::DUAL => Ok(rev.lift()),
            _ => Computed.revolute(ra, rb, alpha, fixed),
        }
    }
}

/// Where a read or a directional derivative takes the centred triad, or REVOLUTE's rotations,
/// from (`Triads`).
#[derive(Debug)]
pub enum TriadSource<'a, T: Scalar> {
    /// Computed.
    Compute,
    /// The caller has it, computed in Real at these frames and torsion branch: read in Real,
    /// and in `Dual` (as a constant) where the orientations are constants along the seeded
    /// direction (`constant`).
    Given(&'a Centred<T>),
    /// The caller has the values of its libm calls at these frames and branch.
    Trig(&'a TriadTrig),
    /// Computed, and the values of its libm calls handed to the caller.
    RecordTrig(&'a mut Option<TriadTrig>),
    /// No centred triad (REVOLUTE's frames are the nodes'): the caller has REVOLUTE's
    /// rotations, computed in Real at these frames and branch: read in Real, and in `Dual` (as
    /// constants) where the frames are constants along the seeded direction.
    Revolute(&'a Revolute),
}

/// The values of the centred triad's libm calls at one pose (`centred_with`): atan2 for α
/// and the raw torsion, sin_cos of α/2 and of β/2.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TriadTrig {
    /// atan2 values: α, the torsion before its branch is continued.
    pub atan2: [Real; 2],
    /// sin_cos values: of α/2, of β/2.
    pub sin_cos: [(Real, Real); 2],
}

/// Where `centred_with` takes the values of its libm calls from (call i of each kind, in
/// `TriadTrig`'s order).
pub trait TriadLibm {
    /// atan2(y, x).
    fn atan2<T: Scalar>(&mut self, i: usize, y: T, x: T) -> T;
    /// (sin x, cos x).
    fn sin_cos<T: Scalar>(&mut self, i: usize, x: T) -> (T, T);
}

/// The calls made (`centred`).
pub struct Calls;

impl TriadLibm for Calls {
    #[inline(always)]
    fn atan2<T: Scalar>(&mut self, _: usize, y: T, x: T) -> T {
        y.atan2(x)
    }
    #[inline(always)]
    fn sin_cos<T: Scalar>(&mut self, _: usize, x: T) -> (T, T) {
        x.sin_cos()
    }
}

/// The calls made and their values recorded.
impl TriadLibm for &mut TriadTrig {
    #[inline(always)]
    fn atan2<T: Scalar>(&mut self, i: usize, y: T, x: T) -> T {
        let v = y.atan2(x);
        self.atan2[i] = v.re();
        v
    }
    #[inline(always)]
    fn sin_cos<T: Scalar>(&mut self, i: usize, x: T) -> (T, T) {
        let v = x.sin_cos();
        self.sin_cos[i] = (v.0.re(), v.1.re());
        v
    }
}

/// The values known from the same pose's triad computed in Real (a directional derivative
/// along an orientation at a point whose triad was computed): not computed again, the same
/// results bit for bit.
impl TriadLibm for &TriadTrig {
    #[inline(always)]
    fn atan2<T: Scalar>(&mut self, i: usize, y: T, x: T) -> T {
        y.atan2_valued(x, self.atan2[i])
    }
    #[inline(always)]
    fn sin_cos<T: Scalar>(&mut self, i: usize, x: T) -> (T, T) {
        x.sin_cos_valued(self.sin_cos[i])
    }
}

/// `centred`, with its libm calls through `libm` (`TriadLibm`).
pub fn centred_with<T: Scalar, L: TriadLibm>(
    ra: &Mat3<T>,
    rb: &Mat3<T>,
    beta_prev: Real,
    mut libm: L,
) -> Result<Centred<T>, Singular> {
    let (e1a, e2a, e3a) = (ra.column(0), ra.column(1), ra.column(2));
    let (e1b, e2b, e3b) = (rb.column(0), rb.column(1), rb.column(2));
    // 1. total flexion α and α·q = (α / sin α)(e3a × e3b), smooth at α → 0
    let w = e3a.cross(&e3b);
    let s = norm3(&w);
    let c = e3a.dot(&e3b);
    let alpha = libm.atan2(0, s, c);
    if !alpha.re().is_finite() {
        return Err(Singular::NotFinite);
    }
    if alpha.re() > std::f64::consts::PI - ALPHA_MAX_GAP {
        return Err(Singular::FlexionNearPi(alpha.re()));
    }
    // s = |e3a × e3b| and c are sin α and cos α, so α/sin α needs no sine of its own
    let phi = w * SinCos {
        x: alpha,
        sin: s,
        cos: c,
    }
    .x_over_sin();
    // 2. frame a rotated by +α/2 about q: its third axis is the bisector e3 (Rodrigues, with
    //    the sine and cosine of α/2 that the Jacobians below need too)
    let x = alpha * 0.5;
    let (sin, cos) = libm.sin_cos(0, x);
    let th = SinCos { x, sin, cos };
    let ra_half = rotate_about(&w, s, &th, ra);
    // 3. torsion β (the manual's formula on the original frames), continued from the previous value
    let (y, x) = (e2a.dot(&e1b) - e1a.dot(&e2b), e1a.dot(&e1b) + e2a.dot(&e2b));
    let beta_raw = libm.atan2(1, y, x);
    let beta = continue_branch(beta_raw, beta_prev);
    // 4. {e1, e2, e3} = Rot(e3, β/2)·Rot(q, α/2)·{frame a}: ra_half·rot_z(β/2) column by
    //    column (the zeros of rot_z left out)
    let (sb, cb) = libm.sin_cos(1, beta * 0.5);
    let (h0, h1c) = (ra_half.column(0), ra_half.column(1));
    let triad = Mat3::from_columns(&[
        h0 * cb + h1c * sb,
        h0 * -sb + h1c * cb,
        ra_half.column(2).into(),
    ]);
    let a1 = triad.column(0).dot(&phi);
    let a2 = triad.column(1).dot(&phi);

    // Jacobian ∂Θ/∂θ_b = M⁻¹ R_cᵀ with M = Jb − Ja (triad coordinates):
    // in-plane block (θ/sin θ)(I − q̂q̂ᵀ) + q̂q̂ᵀ, torsion 1/cos θ, θ = α/2.
    let a_s = th.x_over_sin();
    // (1 − a_s)/α², smooth: a_s ≈ 1 + α²/24 → −1/24
    let coef = if alpha.re() < 1e-4 {
        T::cst(-1.0 / 24.0)
    } else {
        (-a_s + 1.0) / (alpha * alpha)
    };
    // M⁻¹ is symmetric with the in-plane block (m11 m12; m12 m22) and the torsion entry m33:
    // K = M⁻¹·triadᵀ, i.e. Kᵀ = triad·M⁻¹ column by column
    let (m11, m12, m22) = (a_s + coef * a1 * a1, coef * a1 * a2, a_s + coef * a2 * a2);
    let m33 = T::one() / th.cos;
    let (t0, t1, t2) = (triad.column(0), triad.column(1), triad.column(2));
    let k_t = Mat3::from_columns(&[t0 * m11 + t1 * m12, t0 * m12 + t1 * m22, t2 * m33]);
    let k = k_t.transpose();
    // Triad variation δψ = ½(δθ_a + δθ_b) − R_c·N·δΘ with N = ½(Ja + Jb):
    let h1 = th.one_minus_cos_over_sq();
    let h2 = th.sinc();
    // N = (0 0 n13; 0 0 n23; n31 n32 0), so N·K has rows n13 K₃, n23 K₃, n31 K₁ + n32 K₂
    let (n13, n23) = (h2 * a2 * 0.25, -h2 * a1 * 0.25);
    let (n31, n32) = (-h1 * a2 * 0.25, h1 * a1 * 0.25);
    let (k1, k2, k3) = (k_t.column(0), k_t.column(1), k_t.column(2));
    let nk = Mat3::from_columns(&[k3 * n13, k3 * n23, k1 * n31 + k2 * n32]).transpose();
    let rnk = triad * nk;
    let half = Mat3::<T>::identity() * T::cst(0.5);
    Ok(Centred {
        triad,
        angles: Vec3::new(a1, a2, beta),
        alpha,
        k,
        a: half + rnk,
    })
}

/// The columns of `m` rotated by the angle `th` about the unit axis w/|w| (|w| = `w_norm`):
/// v cos θ + (q × v) sin θ + q (q·v)(1 − cos θ). No rotation when w = 0.
///
/// Its derivative at w = 0 (shafts aligned, α = 0, θ = α/2): the rotation vector θ·w/|w| is
/// w/2 + O(|w|³), so the columns turn by δw/2 (the central difference there; the formula's
/// q = w/|w| has no derivative).
#[inline(always)]
fn rotate_about<T: Scalar>(w: &Vec3<T>, w_norm: T, th: &SinCos<T>, m: &Mat3<T>) -> Mat3<T> {
    if w_norm.re() == 0.0 {
        if T::DUAL {
            let half = w * T::cst(0.5);
            return Mat3::from_columns(&[
                m.column(0) + half.cross(&m.column(0)),
                m.column(1) + half.cross(&m.column(1)),
                m.column(2) + half.cross(&m.column(2)),
            ]);
        }
        return *m;
    }
    let q = w / w_norm;
    let mut out = *m;
    for j in 0..3 {
        let v: Vec3<T> = m.column(j).into();
        let r = v * th.cos + q.cross(&v) * th.sin + q * (q.dot(&v) * (-th.cos + 1.0));
        out.set_column(j, &r);
    }
    out
}

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
        Translational::RadialThrust => {
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
                    ta: e3a.cross(&d),
                },
            ]);
        }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::math::{exp_so3, quat_from_wxyz, rot_z, x_over_sin};
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
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        }
        fn vec(&mut self, s: f64) -> Vec3 {
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
}
