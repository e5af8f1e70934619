//! The centred projection triad of PROJECTION CARTESIAN and PROJECTION FLEXION-TORSION
//! (docs/physics.md, "Centred projection triad"): the local directions {e1, e2, e3} (along which
//! CARTESIAN's x, y, z are measured), FLEXION-TORSION's angles α1, α2, β with their Jacobian K,
//! and the triad's rotation A = ∂ψ/∂θ_a, all from one construction (`centred`, `centred_with`,
//! with its libm calls through `TriadLibm`); the total flexion α of the shafts and its limit
//! short of the folded configuration (`Shafts`, `ALPHA_MAX_GAP`). Uses `math` and `geometry`'s
//! `Singular` only.

use super::geometry::Singular;
use crate::physics::math::{continue_branch, norm3, Mat3, Quat, Real, Scalar, SinCos, Vec3};

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
