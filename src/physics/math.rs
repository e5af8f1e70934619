//! Small math prelude for the kernel: static nalgebra types only (no heap).

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};

/// Scalar type of the kernel.
pub type Real = f64;
/// A 3-vector in some frame (the name of the variable says which).
pub type Vec3<T = Real> = Vector3<T>;
/// A 3×3 matrix; as a rotation its columns are the frame's unit axes in W.
pub type Mat3<T = Real> = Matrix3<T>;
/// Unit quaternion, scalar first, mapping node-local coordinates to W.
pub type Quat = UnitQuaternion<Real>;

/// The kernel's scalar: `Real` for the step and the reads, `Dual` for the consistent tangent
/// (the same formulas, differentiated exactly along one input direction). Branches of the
/// formulas (stops, friction status, series near 0, angle branches) are decided on the value
/// alone (`re`), so a `Dual` evaluation takes the branches of the `Real` one at the same point.
pub trait Scalar:
    nalgebra::Scalar
    + Copy
    + Default
    + PartialOrd
    + num_traits::Zero
    + num_traits::One
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + Add<Real, Output = Self>
    + Sub<Real, Output = Self>
    + Mul<Real, Output = Self>
    + Div<Real, Output = Self>
{
    /// Whether this scalar carries a derivative (code only the tangent needs is left out of
    /// the `Real` copies).
    const DUAL: bool;
    /// The value.
    fn re(self) -> Real;
    /// A constant (no derivative).
    fn cst(x: Real) -> Self;
    /// √x; its derivative at 0 is taken as 0 (the central difference of |·| at 0).
    fn sqrt(self) -> Self;
    /// (sin x, cos x).
    fn sin_cos(self) -> (Self, Self);
    /// sin x.
    fn sin(self) -> Self;
    /// cos x.
    fn cos(self) -> Self;
    /// eˣ.
    fn exp(self) -> Self;
    /// atan2(self, x).
    fn atan2(self, x: Self) -> Self;
    /// `atan2(self, x)` where its value is known (`value`: `f64::atan2` of the values, taken
    /// elsewhere at the same point): the same result, the value not computed again.
    fn atan2_valued(self, x: Self, value: Real) -> Self;
    /// `sin_cos` where its values are known (`f64::sin_cos` of the value, taken elsewhere):
    /// the same result, the values not computed again.
    fn sin_cos_valued(self, value: (Real, Real)) -> (Self, Self);
    /// |x| (derivative 0 at 0, as the central difference).
    fn abs(self) -> Self;
    /// The larger by value (`f64::max`: a NaN loses).
    fn max(self, other: Self) -> Self;
    /// The smaller by value (`f64::min`: a NaN loses).
    fn min(self, other: Self) -> Self;
    /// |self| with the sign of `sign`'s value.
    fn copysign(self, sign: Self) -> Self;
    /// libm's hypot.
    fn hypot(self, y: Self) -> Self;
    /// Replaces the derivative (a `Real` ignores it).
    fn with_eps(self, eps: Real) -> Self;
    /// The derivative (0 for a `Real`).
    fn eps(self) -> Real;
}

impl Scalar for Real {
    const DUAL: bool = false;
    #[inline(always)]
    fn re(self) -> Real {
        self
    }
    #[inline(always)]
    fn cst(x: Real) -> Self {
        x
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        f64::sin_cos(self)
    }
    #[inline(always)]
    fn sin(self) -> Self {
        f64::sin(self)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        f64::cos(self)
    }
    #[inline(always)]
    fn exp(self) -> Self {
        f64::exp(self)
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        f64::atan2(self, x)
    }
    #[inline(always)]
    fn atan2_valued(self, _: Self, value: Real) -> Self {
        value
    }
    #[inline(always)]
    fn sin_cos_valued(self, value: (Real, Real)) -> (Self, Self) {
        value
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64::abs(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f64::max(self, other)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        f64::min(self, other)
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        f64::copysign(self, sign)
    }
    #[inline(always)]
    fn hypot(self, y: Self) -> Self {
        f64::hypot(self, y)
    }
    #[inline(always)]
    fn with_eps(self, _eps: Real) -> Self {
        self
    }
    #[inline(always)]
    fn eps(self) -> Real {
        0.0
    }
}

/// A dual number re + eps·ε (ε² = 0): evaluating a formula on it gives the value and the
/// exact derivative along the direction the inputs' `eps` were seeded with (forward-mode
/// differentiation; no step size, no truncation). Compared by value alone.
#[derive(Clone, Copy, Debug, Default)]
pub struct Dual {
    /// The value.
    pub re: Real,
    /// The derivative along the seeded direction.
    pub eps: Real,
}

impl Dual {
    /// re + eps·ε.
    #[inline(always)]
    pub const fn new(re: Real, eps: Real) -> Dual {
        Dual { re, eps }
    }
    /// f(re) with derivative f'(re)·eps.
    #[inline(always)]
    fn chain(self, f: Real, df: Real) -> Dual {
        Dual::new(f, df * self.eps)
    }
}

impl PartialEq for Dual {
    #[inline(always)]
    fn eq(&self, other: &Self) -> bool {
        self.re == other.re
    }
}

impl PartialOrd for Dual {
    #[inline(always)]
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl num_traits::Zero for Dual {
    #[inline(always)]
    fn zero() -> Self {
        Dual::new(0.0, 0.0)
    }
    #[inline(always)]
    fn is_zero(&self) -> bool {
        self.re == 0.0 && self.eps == 0.0
    }
}

impl num_traits::One for Dual {
    #[inline(always)]
    fn one() -> Self {
        Dual::new(1.0, 0.0)
    }
}

impl Add for Dual {
    type Output = Dual;
    #[inline(always)]
    fn add(self, o: Dual) -> Dual {
        Dual::new(self.re + o.re, self.eps + o.eps)
    }
}
impl Sub for Dual {
    type Output = Dual;
    #[inline(always)]
    fn sub(self, o: Dual) -> Dual {
        Dual::new(self.re - o.re, self.eps - o.eps)
    }
}
impl Mul for Dual {
    type Output = Dual;
    #[inline(always)]
    fn mul(self, o: Dual) -> Dual {
        Dual::new(self.re * o.re, self.eps * o.re + self.re * o.eps)
    }
}
impl Div for Dual {
    type Output = Dual;
    #[inline(always)]
    fn div(self, o: Dual) -> Dual {
        let q = self.re / o.re;
        Dual::new(q, (self.eps - q * o.eps) / o.re)
    }
}
impl Neg for Dual {
    type Output = Dual;
    #[inline(always)]
    fn neg(self) -> Dual {
        Dual::new(-self.re, -self.eps)
    }
}
impl Add<Real> for Dual {
    type Output = Dual;
    #[inline(always)]
    fn add(self, o: Real) -> Dual {
        Dual::new(self.re + o, self.eps)
    }
}
impl Sub<Real> for Dual {
    type Output = Dual;
    #[inline(always)]
    fn sub(self, o: Real) -> Dual {
        Dual::new(self.re - o, self.eps)
    }
}
impl Mul<Real> for Dual {
    type Output = Dual;
    #[inline(always)]
    fn mul(self, o: Real) -> Dual {
        Dual::new(self.re * o, self.eps * o)
    }
}
impl Div<Real> for Dual {
    type Output = Dual;
    #[inline(always)]
    fn div(self, o: Real) -> Dual {
        Dual::new(self.re / o, self.eps / o)
    }
}
macro_rules! dual_assign {
    ($($tr:ident $f:ident $op:tt),*) => {$(
        impl $tr for Dual {
            #[inline(always)]
            fn $f(&mut self, o: Dual) {
                *self = *self $op o;
            }
        }
    )*};
}
dual_assign!(AddAssign add_assign +, SubAssign sub_assign -, MulAssign mul_assign *, DivAssign div_assign /);

impl Scalar for Dual {
    const DUAL: bool = true;
    #[inline(always)]
    fn re(self) -> Real {
        self.re
    }
    #[inline(always)]
    fn cst(x: Real) -> Self {
        Dual::new(x, 0.0)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        let r = self.re.sqrt();
        Dual::new(r, if r == 0.0 { 0.0 } else { 0.5 * self.eps / r })
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        self.sin_cos_valued(self.re.sin_cos())
    }
    #[inline(always)]
    fn sin(self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(s, c)
    }
    #[inline(always)]
    fn cos(self) -> Self {
        let (s, c) = self.re.sin_cos();
        self.chain(c, -s)
    }
    #[inline(always)]
    fn exp(self) -> Self {
        let e = self.re.exp();
        self.chain(e, e)
    }
    #[inline(always)]
    fn atan2(self, x: Self) -> Self {
        self.atan2_valued(x, self.re.atan2(x.re))
    }
    #[inline(always)]
    fn atan2_valued(self, x: Self, value: Real) -> Self {
        let (y, r2) = (self, x.re * x.re + self.re * self.re);
        let d = if r2 == 0.0 {
            0.0
        } else {
            (x.re * y.eps - y.re * x.eps) / r2
        };
        Dual::new(value, d)
    }
    #[inline(always)]
    fn sin_cos_valued(self, (s, c): (Real, Real)) -> (Self, Self) {
        (self.chain(s, c), self.chain(c, -s))
    }
    #[inline(always)]
    fn abs(self) -> Self {
        if self.re > 0.0 {
            self
        } else if self.re < 0.0 {
            -self
        } else {
            Dual::new(self.re.abs(), 0.0)
        }
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        if other.re > self.re || self.re.is_nan() {
            other
        } else {
            self
        }
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        if other.re < self.re || self.re.is_nan() {
            other
        } else {
            self
        }
    }
    #[inline(always)]
    fn copysign(self, sign: Self) -> Self {
        let r = self.re.copysign(sign.re);
        if (r > 0.0) == (self.re > 0.0) {
            Dual::new(r, self.eps)
        } else {
            Dual::new(r, -self.eps)
        }
    }
    #[inline(always)]
    fn hypot(self, y: Self) -> Self {
        let h = self.re.hypot(y.re);
        let d = if h == 0.0 {
            0.0
        } else {
            (self.re * self.eps + y.re * y.eps) / h
        };
        Dual::new(h, d)
    }
    #[inline(always)]
    fn with_eps(self, eps: Real) -> Self {
        Dual::new(self.re, eps)
    }
    #[inline(always)]
    fn eps(self) -> Real {
        self.eps
    }
}

/// Whether every value is finite: x·0 is ±0 for a finite x and NaN for ±∞ and NaN, summed in
/// four lanes without early exit, which the compiler vectorises (the per-step path's set, the
/// directional derivatives).
#[inline]
pub fn all_finite(values: &[Real]) -> bool {
    let mut lanes = [0.0; 4];
    let chunks = values.chunks_exact(4);
    let rest = chunks.remainder();
    for c in chunks {
        for (l, x) in lanes.iter_mut().zip(c) {
            *l += x * 0.0;
        }
    }
    for (l, x) in lanes.iter_mut().zip(rest) {
        *l += x * 0.0;
    }
    lanes.iter().sum::<Real>() == 0.0
}

/// A `Real` array lifted to constants of `T`.
#[inline(always)]
pub fn lift<T: Scalar, const N: usize>(x: [Real; N]) -> [T; N] {
    x.map(T::cst)
}

/// A `Real` vector lifted to constants of `T`.
#[inline(always)]
pub fn lift3<T: Scalar>(v: &Vec3) -> Vec3<T> {
    Vec3::new(T::cst(v.x), T::cst(v.y), T::cst(v.z))
}

/// |v| as √(v·v) (nalgebra's `norm` needs a complex field).
#[inline(always)]
pub fn norm3<T: Scalar>(v: &Vec3<T>) -> T {
    v.dot(v).sqrt()
}

/// Rotation matrix of the rotation vector `phi` (exponential map), smooth at 0.
#[inline]
pub fn exp_so3(phi: &Vec3) -> Mat3 {
    Rotation3::from_scaled_axis(*phi).into_inner()
}

/// Unit quaternion of the rotation vector `phi` (exponential map): the same value, bit for
/// bit, as nalgebra's `UnitQuaternion::from_scaled_axis` (identity below |φ/2|² ≤ ε², else
/// (cos|φ/2|, sin|φ/2|·(φ/2)/|φ/2|)), without its exp(0) = 1 of the zero scalar part.
#[inline]
pub fn quat_exp(phi: &Vec3) -> Quat {
    let v = phi / 2.0;
    let nn = v.norm_squared();
    if nn <= Real::EPSILON * Real::EPSILON {
        return Quat::identity();
    }
    let n = nn.sqrt();
    let (sin, cos) = n.sin_cos();
    UnitQuaternion::new_unchecked(nalgebra::Quaternion::from_parts(cos, v * (sin / n)))
}

/// |(x, y)|: √(x² + y²) where the squares neither overflow nor lose precision to
/// underflow (1e-150 ≤ |(x, y)| ≤ 1e150), else libm's `hypot`, which is several times
/// slower and sits on the per-step path of friction and RADIAL-THRUST.
#[inline]
pub fn norm2<T: Scalar>(x: T, y: T) -> T {
    let n = (x * x + y * y).sqrt();
    if (1e-150..=1e150).contains(&n.re()) {
        n
    } else if x.re() == 0.0 && y.re() == 0.0 {
        T::zero()
    } else {
        x.hypot(y)
    }
}

/// Rotation about the local 3-axis by `angle` (radians).
#[inline]
pub fn rot_z(angle: Real) -> Mat3 {
    let (s, c) = angle.sin_cos();
    Mat3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Wraps an angle difference into (−π, π].
#[inline]
pub fn wrap_pi(x: Real) -> Real {
    let two_pi = 2.0 * std::f64::consts::PI;
    let mut y = x % two_pi;
    if y > std::f64::consts::PI {
        y -= two_pi;
    } else if y <= -std::f64::consts::PI {
        y += two_pi;
    }
    y
}

/// The continuous branch of an angle: the value of `raw + 2πm` nearest to `prev`.
///
/// Why: atan2 jumps by 2π; connector angles (β, PLANAR's α) accumulate turns.
#[inline]
pub fn continue_branch<T: Scalar>(raw: T, prev: Real) -> T {
    // raw + 2πm (not prev + wrap(raw − prev)): applied again to its own result it returns the
    // same bits, so re-evaluating where a step ended reproduces that step's angles exactly
    let two_pi = 2.0 * std::f64::consts::PI;
    raw + two_pi * ((prev - raw.re()) / two_pi).round()
}

/// `x / sin x`, smooth through 0 (series below 1e-4, where the error is below 1e-17).
#[inline]
pub fn x_over_sin(x: Real) -> Real {
    if x.abs() < 1e-4 {
        1.0 + x * x / 6.0
    } else {
        x / x.sin()
    }
}

/// `sin x / x`, smooth through 0.
#[inline]
pub fn sinc(x: Real) -> Real {
    if x.abs() < 1e-4 {
        1.0 - x * x / 6.0
    } else {
        x.sin() / x
    }
}

/// `(1 − cos x) / x²`, smooth through 0.
#[inline]
pub fn one_minus_cos_over_sq(x: Real) -> Real {
    if x.abs() < 1e-4 {
        0.5 - x * x / 24.0
    } else {
        (1.0 - x.cos()) / (x * x)
    }
}

/// An angle with its sine and cosine, for several of the smooth ratios of one angle at the
/// cost of one sin_cos: the formulas of the free functions, so the same values bit for bit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SinCos<T = Real> {
    /// The angle x (rad).
    pub x: T,
    /// sin x.
    pub sin: T,
    /// cos x.
    pub cos: T,
}

impl<T: Scalar> SinCos<T> {
    /// x with sin x and cos x.
    #[inline]
    pub fn of(x: T) -> SinCos<T> {
        let (sin, cos) = x.sin_cos();
        SinCos { x, sin, cos }
    }

    /// `x / sin x`, smooth through 0 (series below 1e-4, where the error is below 1e-17).
    #[inline]
    pub fn x_over_sin(&self) -> T {
        let x = self.x;
        if x.re().abs() < 1e-4 {
            x * x / 6.0 + 1.0
        } else {
            x / self.sin
        }
    }

    /// `sin x / x`, smooth through 0.
    #[inline]
    pub fn sinc(&self) -> T {
        let x = self.x;
        if x.re().abs() < 1e-4 {
            -(x * x / 6.0) + 1.0
        } else {
            self.sin / x
        }
    }

    /// `(1 − cos x) / x²`, smooth through 0.
    #[inline]
    pub fn one_minus_cos_over_sq(&self) -> T {
        let x = self.x;
        if x.re().abs() < 1e-4 {
            -(x * x / 24.0) + 0.5
        } else {
            (-self.cos + 1.0) / (x * x)
        }
    }
}

/// The rotation matrix of a unit quaternion (w, i, j, k): nalgebra's
/// `UnitQuaternion::to_rotation_matrix` written for any scalar (the same products and sums,
/// so the same bits for `Real`).
#[inline]
pub fn rotation_of<T: Scalar>(w: T, i: T, j: T, k: T) -> Mat3<T> {
    let (ww, ii, jj, kk) = (w * w, i * i, j * j, k * k);
    let ij = i * j * 2.0;
    let wk = w * k * 2.0;
    let wj = w * j * 2.0;
    let ik = i * k * 2.0;
    let jk = j * k * 2.0;
    let wi = w * i * 2.0;
    Mat3::new(
        ww + ii - jj - kk,
        ij - wk,
        wj + ik,
        wk + ij,
        ww - ii + jj - kk,
        jk - wi,
        ik - wj,
        wi + jk,
        ww - ii - jj + kk,
    )
}

/// Unit quaternion from scalar-first components, normalised.
///
/// Returns `None` when a component is not finite or the norm is below 1e-6
/// (such a quaternion is refused, never silently "fixed").
pub fn quat_from_wxyz(w: Real, x: Real, y: Real, z: Real) -> Option<Quat> {
    let q = nalgebra::Quaternion::new(w, x, y, z);
    let n = q.norm();
    if !n.is_finite() || n < 1e-6 {
        return None;
    }
    // A quaternion already unit to round-off is taken as it is: the FMU writes its own
    // extrapolated orientations back into the inputs, and reading them back must give the
    // same bits (dividing by a norm of 1 ± ε would not).
    if (n - 1.0).abs() <= 4.0 * Real::EPSILON {
        return Some(UnitQuaternion::new_unchecked(q));
    }
    Some(UnitQuaternion::new_unchecked(q / n))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_and_branch() {
        let pi = std::f64::consts::PI;
        assert!((wrap_pi(3.0 * pi) - pi).abs() < 1e-12);
        assert!((wrap_pi(-0.5) + 0.5).abs() < 1e-15);
        // crossing +π from below continues past π instead of jumping to −π
        let b = continue_branch(-pi + 0.1, pi - 0.1);
        assert!((b - (pi + 0.1)).abs() < 1e-12);
    }

    #[test]
    fn series_match_closed_forms_at_switch() {
        for x in [0.99e-4, 1.01e-4] {
            assert!((x_over_sin(x) - x / x.sin()).abs() < 1e-15);
            assert!((sinc(x) - x.sin() / x).abs() < 1e-15);
            assert!((one_minus_cos_over_sq(x) - 0.5).abs() < 1e-8);
        }
    }

    #[test]
    fn sin_cos_ratios_are_the_free_functions() {
        for x in [0.0, 1e-9, 0.99e-4, 1e-4, 1.01e-4, 0.3, 1.2, -0.7, 2.9] {
            let t = SinCos::of(x);
            assert_eq!(t.x_over_sin().to_bits(), x_over_sin(x).to_bits());
            assert_eq!(t.sinc().to_bits(), sinc(x).to_bits());
            assert_eq!(
                t.one_minus_cos_over_sq().to_bits(),
                one_minus_cos_over_sq(x).to_bits()
            );
            assert_eq!(t.cos.to_bits(), x.cos().to_bits());
        }
    }

    #[test]
    fn quaternion_exp_is_nalgebras() {
        for phi in [
            Vec3::zeros(),
            Vec3::new(1e-17, 0.0, -1e-17),
            Vec3::new(1e-3, -2e-4, 5e-4),
            Vec3::new(0.3, 1.1, -0.4),
            Vec3::new(-3.0, 2.0, 7.0),
        ] {
            let (a, b) = (quat_exp(&phi), Quat::from_scaled_axis(phi));
            let (a, b) = (a.quaternion().coords, b.quaternion().coords);
            for i in 0..4 {
                assert_eq!(a[i].to_bits(), b[i].to_bits(), "{phi:?}");
            }
        }
    }

    #[test]
    fn norm2_is_hypot_to_round_off_at_every_scale() {
        for (x, y) in [
            (3.0, 4.0),
            (0.0, 0.0),
            (-0.0, 0.0),
            (1e-160, -2e-160),
            (0.0, 1e-200),
            (1e160, 1e160),
            (f64::MAX, 1.0),
            (-1e-3, 2.5e5),
            (f64::INFINITY, 1.0),
        ] {
            let (a, b) = (norm2(x, y), x.hypot(y));
            assert!(
                a == b || (a - b).abs() <= 2.0 * f64::EPSILON * b,
                "{x} {y}: {a} {b}"
            );
        }
        assert!(norm2(f64::NAN, 1.0).is_nan());
    }

    #[test]
    fn quaternion_refusal() {
        assert!(quat_from_wxyz(0.0, 0.0, 0.0, 0.0).is_none());
        assert!(quat_from_wxyz(f64::NAN, 0.0, 0.0, 1.0).is_none());
        assert!(quat_from_wxyz(1e-7, 0.0, 0.0, 0.0).is_none());
        let q = quat_from_wxyz(2.0, 0.0, 0.0, 0.0).expect("valid");
        assert!((q.w - 1.0).abs() < 1e-15);
    }
}
