//! A short deterministic replay of the `fmi_calls` fuzz harness inside `cargo test`: the same
//! program interpreter and invariants as the libFuzzer target (`fuzz/harness/`), run on
//!
//! - every committed seed in `fuzz/seeds/fmi_calls/` (lifecycle skeletons and the inputs of the
//!   findings fixed so far, `regression_<NNN>_*`), and
//! - a fixed set of pseudo-random programs (LCG, fixed seed), FMI 2.0 and FMI 3.0 alike, half
//!   of them behind a prefix that initialises a connector with every parameter set and runs
//!   steps, so the kernel is reached (FMI 3.0: with earlyReturnAllowed on and off).
//!
//! The long, coverage-guided run is `scripts/fuzz` (not CI). `FMI_FUZZ_TRACE=1` prints what
//! each program does.

#[path = "../fuzz/harness/mod.rs"]
mod harness;

use connector_fmu::variables::{table, Causality, Start, VARIANTS};
use std::time::Instant;

/// Number of pseudo-random programs (debug build: fewer, same generator).
const PROGRAMS: usize = if cfg!(debug_assertions) { 300 } else { 3000 };

struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        self.0 >> 33
    }
    fn byte(&mut self) -> u8 {
        self.next() as u8
    }
}

/// Which interface a program drives.
#[derive(Clone, Copy, Debug)]
enum Mode {
    Fmi2,
    /// FMI 3.0 with earlyReturnAllowed as given.
    Fmi3 {
        early_return: bool,
    },
}

/// The motion a prefix sets.
#[derive(Clone, Copy, Debug)]
enum Motion {
    /// Plausible random node inputs at scale 0.1 (the stops are near).
    Random,
    /// Node a at rest at the origin, node b leaving the origin at 0.5 m/s along W's x (scale 1),
    /// both unrotated: it meets the upper stop of CP1 (within 1.6 mm) in the first steps.
    TowardsStop,
}

/// Header + ops that instantiate variant `v`, enter initialization, set every parameter to a
/// plausible value (the byte layout follows the harness decoder exactly, from the variable
/// table), set a motion, and leave initialization. The program continues at random.
fn prefix(v: usize, mode: Mode, motion: Motion, rng: &mut Lcg) -> Vec<u8> {
    let variant = VARIANTS[v].variant;
    let t = table(variant);
    let mut p = match mode {
        // header: variant selector, flags (valid name and type, logging off), logger present
        Mode::Fmi2 => vec![v as u8, 0, 0],
        // mode byte, variant selector, flags (valid name, eventModeUsed = false, logging off),
        // options (earlyReturnAllowed, no required intermediate variables, logger present)
        Mode::Fmi3 { early_return } => vec![harness::FMI3_MODE, v as u8, 0, u8::from(early_return)],
    };
    p.extend([0, 9]); // instance 0: Enter Initialization Mode (op codes equal in both versions)
    p.extend([0, 6]); // instance 0: parameter set
    for var in t
        .vars
        .iter()
        .filter(|x| x.causality == Causality::Parameter)
    {
        p.push(200); // selected
        match var.start {
            // value kind "plausible" (≠ 0 mod 8), then a u16 for the value; stops within
            // ±1.6 mm of the start (u16 < 256), so that the motion meets them and steps return
            // early at their events
            Start::Real(_) if var.name.starts_with("stop.") && var.name.as_bytes()[5] != b's' => {
                p.extend([1 + rng.byte() % 7, rng.byte(), 0])
            }
            Start::Real(_) => p.extend([1 + rng.byte() % 7, rng.byte(), rng.byte()]),
            // the extrapolation linear or second order (with hold nothing moves inside a step,
            // and no event happens there); 0 for the others (friction.coupling)
            Start::Integer(_) if var.name == "cosim.extrapolation" => p.push(1 + rng.byte() % 2),
            Start::Integer(_) => p.push(0),
            Start::Boolean(_) => {}
        }
    }
    match motion {
        Motion::Random => {
            p.extend([0, 7, (rng.byte() & !3) | 1]); // motion, scale 0.1 (the stops are near)
            for node in ["a", "b"] {
                // quaternion kind 11 (axis-angle): angle u16 + turn byte, axis 3 × u16
                p.push(11);
                p.extend((0..9).map(|_| rng.byte()));
                let plain = t
                    .vars
                    .iter()
                    .filter(|x| x.causality == Causality::Input && x.name.starts_with(node))
                    .filter(|x| !x.name[2..].starts_with("q."))
                    .count();
                p.extend((0..2 * plain).map(|_| rng.byte()));
            }
        }
        Motion::TowardsStop => {
            p.extend([0, 7, 2]); // motion, scale 1
            for node in ["a", "b"] {
                p.push(11); // axis-angle with angle 0: no rotation
                p.extend([0; 9]);
                for x in t
                    .vars
                    .iter()
                    .filter(|x| x.causality == Causality::Input && x.name.starts_with(node))
                    .filter(|x| !x.name[2..].starts_with("q."))
                {
                    // a u16 (i16 / 32768 × scale): 0, or 0.5 for b.v[1]
                    let u: u16 = if x.name == "b.v[1]" { 0x4000 } else { 0 };
                    p.extend(u.to_le_bytes());
                }
            }
        }
    }
    p.extend([0, 10]); // Exit Initialization Mode
    for _ in 0..3 {
        // a run of four steps: h = 1e-3·(1 + 4·byte/255), t = the FMU's time
        p.extend([0, 31, 3]);
        for _ in 0..4 {
            p.extend([10, rng.byte(), 1]);
        }
    }
    p
}

#[test]
fn committed_seeds_replay_clean() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/fuzz/seeds/fmi_calls");
    let mut n = 0;
    let mut paths: Vec<_> = std::fs::read_dir(dir)
        .expect("fuzz/seeds/fmi_calls")
        .map(|e| e.expect("entry").path())
        .collect();
    paths.sort();
    for path in paths {
        let data = std::fs::read(&path).expect("seed");
        let r = std::panic::catch_unwind(|| harness::run(&data));
        assert!(r.is_ok(), "seed {} violates an invariant", path.display());
        n += 1;
    }
    assert!(n >= 2, "expected the committed seeds, found {n}");
}

#[test]
fn pseudo_random_programs_keep_the_invariants() {
    let started = Instant::now();
    let mut rng = Lcg(0x5eed_f00d);
    let mut early = 0;
    let mut count = [0usize; 2];
    for i in 0..PROGRAMS {
        let len = 16 + (rng.next() % 600) as usize;
        // i mod 4: FMI 2.0 / FMI 3.0 behind a prefix, FMI 2.0 / FMI 3.0 from scratch
        let fmi3 = i % 2 == 1;
        let mode = if fmi3 {
            Mode::Fmi3 {
                early_return: i % 8 < 4,
            }
        } else {
            Mode::Fmi2
        };
        let mut data = if i % 4 < 2 {
            prefix(i / 4 % 5, mode, Motion::Random, &mut rng)
        } else if fmi3 {
            vec![harness::FMI3_MODE | rng.byte()]
        } else {
            vec![rng.byte() % harness::FMI3_MODE]
        };
        data.extend((0..len).map(|_| rng.byte()));
        count[usize::from(fmi3)] += 1;
        let r = std::panic::catch_unwind(|| harness::run(&data));
        match r {
            Ok(n) => early += n,
            Err(_) => panic!("program {i} ({mode:?}) violates an invariant; bytes: {data:?}"),
        }
    }
    println!(
        "{PROGRAMS} programs ({} FMI 2.0, {} FMI 3.0) in {:.2} s, {early} early returns",
        count[0],
        count[1],
        started.elapsed().as_secs_f64()
    );
}

/// The early-return invariants are exercised, not only compiled: a program whose node b runs
/// into a stop in its first steps returns early there, for every seed of the rest of the program.
#[test]
fn a_program_running_into_a_stop_returns_early() {
    let v = VARIANTS
        .iter()
        .position(|s| s.model_identifier == "ProjectionCartesian")
        .expect("the variant");
    let mut rng = Lcg(7);
    for k in 0..8 {
        let mut data = prefix(
            v,
            Mode::Fmi3 { early_return: true },
            Motion::TowardsStop,
            &mut rng,
        );
        data.extend((0..200).map(|_| rng.byte()));
        let n = std::panic::catch_unwind(|| harness::run(&data))
            .unwrap_or_else(|_| panic!("program {k} violates an invariant; bytes: {data:?}"));
        assert!(n >= 1, "program {k}: no early return; bytes: {data:?}");
    }
}
