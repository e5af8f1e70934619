//! Small math prelude for the kernel: static nalgebra types only (no heap).

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// Scalar type of the kernel.
pub type Real = f64;
/// A 3-vector in some frame (the name of the variable says which).
pub type Vec3 = Vector3<Real>;
/// A 3×3 matrix; as a rotation its columns are the frame's unit axes in W.
pub type Mat3 = Matrix3<Real>;
/// Unit quaternion, scalar first, mapping node-local coordinates to W.
pub type Quat = UnitQuaternion<Real>;

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
pub fn norm2(x: Real, y: Real) -> Real {
    let n = (x * x + y * y).sqrt();
    if (1e-150..=1e150).contains(&n) {
        n
    } else if x == 0.0 && y == 0.0 {
        0.0
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
pub fn continue_branch(raw: Real, prev: Real) -> Real {
    // raw + 2πm (not prev + wrap(raw − prev)): applied again to its own result it returns the
    // same bits, so re-evaluating where a step ended reproduces that step's angles exactly
    let two_pi = 2.0 * std::f64::consts::PI;
    raw + two_pi * ((prev - raw) / two_pi).round()
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
pub struct SinCos {
    /// The angle x (rad).
    pub x: Real,
    /// sin x.
    pub sin: Real,
    /// cos x.
    pub cos: Real,
}

impl SinCos {
    /// x with sin x and cos x.
    #[inline]
    pub fn of(x: Real) -> SinCos {
        let (sin, cos) = x.sin_cos();
        SinCos { x, sin, cos }
    }

    /// `x / sin x`, smooth through 0 (series below 1e-4, where the error is below 1e-17).
    #[inline]
    pub fn x_over_sin(&self) -> Real {
        let x = self.x;
        if x.abs() < 1e-4 {
            1.0 + x * x / 6.0
        } else {
            x / self.sin
        }
    }

    /// `sin x / x`, smooth through 0.
    #[inline]
    pub fn sinc(&self) -> Real {
        let x = self.x;
        if x.abs() < 1e-4 {
            1.0 - x * x / 6.0
        } else {
            self.sin / x
        }
    }

    /// `(1 − cos x) / x²`, smooth through 0.
    #[inline]
    pub fn one_minus_cos_over_sq(&self) -> Real {
        let x = self.x;
        if x.abs() < 1e-4 {
            0.5 - x * x / 24.0
        } else {
            (1.0 - self.cos) / (x * x)
        }
    }
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
