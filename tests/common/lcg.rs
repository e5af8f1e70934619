//! The tests' pseudo-random numbers: a 64-bit LCG (Knuth's MMIX constants), fixed seeds, so that
//! every run draws the same cases. Included with `#[path = "common/lcg.rs"] mod lcg;` by the tests
//! that draw poses, statuses or parameters; each adds the draws it needs in an `impl Lcg` of its
//! own.

/// The generator's state.
pub struct Lcg(pub u64);

impl Lcg {
    /// The next value, uniform in [−1, 1).
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}
