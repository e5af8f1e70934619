//! A short deterministic replay of the archive reader's fuzz harness (fuzz/archive_harness.rs,
//! the libFuzzer target fuzz/fuzz_targets/ssp_archive.rs) inside `cargo test`: every committed
//! seed in fuzz/seeds/ssp_archive/ (the findings' inputs are added there as `regression_*`), and
//! pseudo-random mutations of them (LCG, fixed seed: byte flips, insertions, truncations). The
//! harness panics on what must never happen; reaching the end is the test.

#[path = "../../fuzz/archive_harness.rs"]
mod archive_harness;

use std::path::Path;

struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() as usize) % n.max(1)
    }
}

fn seeds() -> Vec<Vec<u8>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/seeds/ssp_archive");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("fuzz/seeds/ssp_archive exists")
        .flatten()
        .map(|e| e.path())
        .collect();
    files.sort();
    files.iter().map(|p| std::fs::read(p).unwrap()).collect()
}

#[test]
fn seeds_and_their_mutations_never_panic() {
    let seeds = seeds();
    assert!(seeds.len() >= 4);
    for s in &seeds {
        archive_harness::run(s);
    }
    let mut rng = Lcg(0x005e_ed40);
    for round in 0..600 {
        let mut data = seeds[round % seeds.len()].clone();
        for _ in 0..1 + rng.below(4) {
            match rng.below(3) {
                0 if data.len() > 1 => {
                    let i = 1 + rng.below(data.len() - 1);
                    data[i] ^= 1 << rng.below(8);
                }
                1 => {
                    let i = 1 + rng.below(data.len().saturating_sub(1));
                    let b = b"<>/=\"'&;:. \x00\xff"[rng.below(13)];
                    data.insert(i.min(data.len()), b);
                }
                _ => {
                    let n = 1 + rng.below(data.len().saturating_sub(1));
                    data.truncate(n);
                }
            }
        }
        archive_harness::run(&data);
    }
}
