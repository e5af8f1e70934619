//! Regression 003 (found by the fuzz harness replay, `tests/fuzz_smoke.rs`): fmi2GetDirectional
//! Derivative returned fmi2OK with −inf for a seed of 1e308 (Planar, dvKnown = [−0.37, 1e308]).
//! The central difference used ε = 1e-6·scale/max|dvKnown|: for huge seeds ε became denormal
//! and the quotient overflowed; for denormal seeds (5e-324) ε overflowed to +INF and the call
//! failed with a misleading "outputs are not finite". Fixed: the difference is taken along the
//! seed scaled to max-norm 1 and the result scaled back (the same perturbation for ordinary
//! seeds), and a derivative that is not finite (J·dvKnown beyond the f64 range) is refused
//! with fmi2Error naming the unknown.

mod common;

use common::*;
use connector_fmu::fmi2::exports::*;
use connector_fmu::fmi2::types::*;
use connector_fmu::variables::Variant;

fn bushing() -> Fmu {
    let f = Fmu::new(Variant::Bushing);
    f.enter_init();
    assert_eq!(f.set_real("elasticity.k1", 100.0), fmi2Status::OK);
    f.exit_init();
    assert_eq!(f.set_real("b.r[1]", 0.01), fmi2Status::OK);
    f
}

fn derivative(f: &Fmu, seed: f64) -> (fmi2Status, f64) {
    let (unk, kn) = (f.vr("b.f[1]"), f.vr("b.r[1]"));
    let mut d = f64::NAN;
    let s = fmi2GetDirectionalDerivative(f.c, &unk, 1, &kn, 1, &seed, &mut d);
    (s, d)
}

#[test]
fn huge_seeds_overflowing_the_derivative_are_refused() {
    let f = bushing();
    let n = f.log_len();
    let (s, _) = derivative(&f, 1e308);
    assert_error_logged(&f, n, s, "fmi2GetDirectionalDerivative");
    assert!(f.log()[n].message.contains("b.f[1]"), "{:?}", f.log()[n]);
    let n = f.log_len();
    let (s, _) = derivative(&f, -f64::MAX);
    assert_error_logged(&f, n, s, "fmi2GetDirectionalDerivative");
}

#[test]
fn huge_and_denormal_seeds_within_range_are_exact() {
    let f = bushing();
    // ∂(b.f[1])/∂(b.r[1]) = −k1 = −100
    for seed in [1.0, -3.0, 1e300, -1e306, 1e-300, 5e-324, -2.5e-320] {
        let (s, d) = derivative(&f, seed);
        assert_eq!(s, fmi2Status::OK, "seed {seed:e}: {:?}", f.log());
        let want = -100.0 * seed;
        assert!(d.is_finite(), "seed {seed:e}: {d:e}");
        // relative 1e-6 (central difference of a linear spring: round-off only); for
        // denormal results, the denormal spacing
        assert!(
            (d - want).abs() <= 1e-6 * want.abs() + 1e-321,
            "seed {seed:e}: {d:e} vs {want:e}"
        );
    }
    assert!(f.log().is_empty(), "{:?}", f.log());
}
