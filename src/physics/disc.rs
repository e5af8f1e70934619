//! Friction of a uniformly loaded disc that slides and spins at once (Contensou 1963; Farkas,
//! Bartels, Unger, Wolf, PRL 90, 248302, 2003), used by `friction.coupling = 1` for the
//! direction of the coupled friction force (the puck scene in docs/cosim.md).
//!
//! A disc of radius R pressed by N with Coulomb μ, its centre sliding at v and spinning at ω:
//! every contact point slips at v + ω × r and carries μN/(πR²) against that direction. The
//! resultants depend only on ε = v/(Rω):
//!
//! - force along −v:  F = μN F̂(ε), moment against ω: M = μNR M̂(ε);
//! - ε ≤ 1 (k = ε):   F̂ = 4/(3πε)·[(1 + ε²)E(k) − (1 − ε²)K(k)],
//!   M̂ = 4/(9π)·[(4 − 2ε²)E(k) + (ε² − 1)K(k)];
//! - ε ≥ 1 (k = 1/ε): F̂ = 4/(3π)·[(ε² + 1)E(k) − (ε² − 1)K(k)],
//!   M̂ = 4/(9πε)·[(2ε⁴ − 5ε² + 3)K(k) + (4ε² − 2ε⁴)E(k)];
//!
//! with K, E the complete elliptic integrals of modulus k. (Derivation: about the instantaneous
//! centre of rotation, at distance ε from the centre, the friction direction depends only on the
//! polar angle, and the integrals over the radius are elementary.) F̂(0) = 0, M̂(0) = 2/3,
//! F̂(1) = 8/(3π), M̂(1) = 8/(9π), F̂(∞) = 1, M̂(∞) = 0. A disc whose mass is m and moment of
//! inertia mR²/2 keeps ε where F̂(ε) = 2ε M̂(ε): ε* = 0.6527, the ratio both motions approach
//! as they stop together.
//!
//! Here the formulas are written with K and D = (K − E)/k², which avoids the cancellations of
//! small k ((1 + k²)E − (1 − k²)K = k²(2K − (1 + k²)D)).

use super::math::{Real, Scalar};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// K(k) and D(k) = (K − E)/k² for 0 ≤ k < 1 by the arithmetic–geometric mean
/// (E = K(1 − Σ 2ⁿ⁻¹ cₙ²), c₀ = k, so D = K Σ 2ⁿ⁻¹ (cₙ/k)², a sum of positive terms).
/// With a `Dual` k the iteration carries the derivatives along; they converge with it.
fn elliptic_k_d<T: Scalar>(k: T) -> (T, T) {
    if k.re() == 0.0 {
        // K and D are even in k: no derivative at 0
        return (T::cst(FRAC_PI_2), T::cst(FRAC_PI_4));
    }
    let kp = ((-k + 1.0) * (k + 1.0)).sqrt();
    let (mut a, mut b) = (T::one(), kp);
    let mut sum = T::cst(0.5); // 2⁻¹ (c₀/k)²
    let mut c_k = k / ((kp + 1.0) * 2.0); // c₁/k = (1 − k')/(2k)
    let mut w: Real = 1.0; // 2ⁿ⁻¹ for n = 1
    for _ in 0..40 {
        sum += c_k * w * c_k;
        let a_next = (a + b) * 0.5;
        b = (a * b).sqrt();
        a = a_next;
        if (a - b).re() <= 1e-16 * a.re() {
            break;
        }
        c_k = (a - b) * 0.5 / k;
        w *= 2.0;
    }
    let kk = T::cst(PI) / (a + b); // π/(2 AGM)
    (kk, kk * sum)
}

/// (F̂, M̂) of the disc at slip ratio ε = v/(Rω) given as ε = c/s with c, s ≥ 0 not both 0
/// (c = cos χ, s = sin χ of the slip direction in (v, Rω), so that ε = ∞ is s = 0).
pub fn disc_law<T: Scalar>(c: T, s: T) -> (T, T) {
    if c.re() <= s.re() {
        // ε ≤ 1
        let k = c / s;
        if k.re() == 1.0 {
            return (T::cst(8.0 / (3.0 * PI)), T::cst(8.0 / (9.0 * PI)));
        }
        let (kk, d) = elliptic_k_d(k);
        let k2 = k * k;
        let f = k * 4.0 / (3.0 * PI) * (kk * 2.0 - (k2 + 1.0) * d);
        let m = ((-k2 + 3.0) * kk - (-(k2 * 2.0) + 4.0) * k2 * d) * (4.0 / (9.0 * PI));
        (f, m)
    } else {
        // ε > 1, k = 1/ε < 1
        let k = s / c;
        let (kk, d) = elliptic_k_d(k);
        let k2 = k * k;
        let f = (kk * 2.0 - (k2 + 1.0) * d) * (4.0 / (3.0 * PI));
        // M̂ = 4/(9πk)·[(3k² − 1)K − (4k² − 2)D] cancels to O(k) as k → 0: the series
        // k/4 + k³/48 + 3k⁵/512 (from the integral (4k/3π)∫cos⁴u/√(1 − k² sin²u) du)
        // is exact to 1e-14 there
        let m = if k.re() <= 1e-2 {
            k * (k2 * (k2 * 3.0 / 512.0 + 1.0 / 48.0) + 0.25)
        } else {
            T::cst(4.0) / (k * (9.0 * PI)) * ((k2 * 3.0 - 1.0) * kk - (k2 * 4.0 - 2.0) * d)
        };
        (f, m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law(eps: Real) -> (Real, Real) {
        if eps.is_infinite() {
            disc_law(1.0, 0.0)
        } else {
            disc_law(eps, 1.0)
        }
    }

    /// K and E against tabulated values (Abramowitz & Stegun 17.3, m = k² = 0.5 and 0.9).
    #[test]
    fn elliptic_integrals_match_tables() {
        for (m, k_ref, e_ref) in [
            (0.5, 1.854_074_677_301_372, 1.350_643_881_047_675),
            (0.9, 2.578_092_113_348_173, 1.104_774_732_704_073),
        ] {
            let k = Real::sqrt(m);
            let (kk, d) = elliptic_k_d(k);
            let e = kk - m * d;
            assert!((kk - k_ref).abs() < 4e-15, "K({m}) = {kk}");
            assert!((e - e_ref).abs() < 4e-15, "E({m}) = {e}");
        }
    }

    #[test]
    fn limits_and_the_rim_value() {
        let (f0, m0) = law(0.0);
        assert_eq!(f0, 0.0);
        assert!((m0 - 2.0 / 3.0).abs() < 1e-15);
        let (fi, mi) = law(Real::INFINITY);
        assert!((fi - 1.0).abs() < 1e-15 && mi == 0.0);
        // ε → 1 from both sides meets the closed values at 1
        let (f1, m1) = law(1.0);
        for eps in [1.0 - 1e-9, 1.0 + 1e-9] {
            let (f, m) = law(eps);
            assert!(
                (f - f1).abs() < 1e-7 && (m - m1).abs() < 1e-7,
                "{eps}: {f} {m}"
            );
        }
        // small ε: F̂ = ε(1 − ε²/8 + …) (from the ε ≤ 1 form's series), large ε: M̂ = 1/(4ε)
        let (f, _) = law(1e-6);
        assert!((f / 1e-6 - 1.0).abs() < 1e-12);
        let (_, m) = law(1e6);
        assert!((m * 4e6 - 1.0).abs() < 1e-12);
    }

    /// The two forms of M̂ for ε > 1 (series below k = 0.01, closed form above) join smoothly.
    #[test]
    fn series_and_closed_form_join() {
        let below = disc_law(1.0, 0.01 * (1.0 - 1e-12)).1;
        let above = disc_law(1.0, 0.01 * (1.0 + 1e-12)).1;
        assert!((below - above).abs() < 1e-14, "{below} {above}");
    }

    /// The disc dissipates μN Φ(ε)·Rω with Φ = F̂ε + M̂ the mean slip speed over the disc
    /// (in units of Rω), and F̂ = dΦ/dε: checked by central differences.
    #[test]
    fn force_is_the_derivative_of_the_dissipation() {
        let phi = |e: Real| {
            let (f, m) = law(e);
            f * e + m
        };
        for eps in [0.05, 0.3, 0.653, 0.9, 1.3, 3.0, 30.0] {
            let h = 1e-5 * eps;
            let dphi = (phi(eps + h) - phi(eps - h)) / (2.0 * h);
            assert!((dphi - law(eps).0).abs() < 1e-8, "{eps}: {dphi}");
        }
    }

    /// A uniform disc (J = mR²/2) keeps the ratio where F̂ = 2ε M̂: 0.653 (Farkas et al. 2003).
    #[test]
    fn stationary_ratio_is_0653() {
        let g = |e: Real| {
            let (f, m) = law(e);
            f - 2.0 * e * m
        };
        let (mut lo, mut hi) = (0.5, 0.8);
        assert!(g(lo) < 0.0 && g(hi) > 0.0);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if g(mid) < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        assert!((lo - 0.653).abs() < 5e-4, "ε* = {lo}");
    }
}
