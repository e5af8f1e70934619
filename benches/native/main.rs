//! Native benchmark (docs/benchmarks.md): the cost of the exported FMI functions, release build, called as
//! an importer calls them (through `extern "C"` function pointers), against the floor of an
//! empty FMI round trip measured side by side in the same run.
//!
//! Per variant, behaviours off (defaults) and on, in a driven scene (node b on a smooth periodic
//! path with consistent velocities; h = 1 ms, default substepping):
//! - `ns_doStep_median`: ns per fmi2DoStep alone (each call bracketed by `Instant::now`, the
//!   bracket's own cost subtracted);
//! - `ns_round_median`: ns per round fmi2SetReal(node inputs) + fmi2DoStep + fmi2GetReal(node loads);
//! - `floor_ns_round_median`: the same round on the empty FMU (`empty_fmu/src/imp.rs`: set/get
//!   copy values into/out of an array, doStep advances the clock), with the same numbers of
//!   values, its batches interleaved with the variant's batches; the empty FMU is loaded from its
//!   own shared library (`target/empty_fmu/release/libempty_fmu.so`, or `BENCH_EMPTY_LIB`) so
//!   that its code placement does not change with the connector's;
//! - `ratio` = ns_round / floor_ns_round (targets: Bushing on ≤ 40, Planar on ≤ 25; figures,
//!   not a pass/fail test);
//! - `allocs_per_step`: heap allocations per round after warm-up, counted by a counting global
//!   allocator (must be 0: the run fails otherwise);
//! - `state_bytes`: fmi2SerializedFMUstateSize after the run (must be ≤ 1024: the run fails
//!   otherwise);
//! - for Bushing and Planar "on" (and Bushing "on" without its stops, "on-nostops": no event
//!   tracking), `floor_direct`: ns per round of the same physics written directly
//!   (`floor.rs`), interleaved in the same batches, after a check that it computes the FMU's
//!   node loads and CTF/CTM to 1e-12 relative over two periods (the run fails otherwise), and
//!   `round/direct` = ns_round / floor_direct (target for the "on" rounds: ≤ 1.3, issue 15).
//!
//! `cargo bench --bench native` runs the full benchmark, prints the table and writes
//! out/bench_native.csv and out/bench_scenes.json (the "on" scenes of Bushing and Planar, for
//! scripts/bench_fmpy.py). Without `--bench` (e.g. `cargo test --benches`) it runs a short smoke
//! pass and writes nothing. Environment: BENCH_BATCHES, BENCH_STEPS (per batch),
//! BENCH_ONLY=<Variant>[:on|:off] (then nothing is written either), BENCH_PROFILE=<n> (n more
//! rounds in `profiled` and `profiled_empty`, for
//! `valgrind --tool=callgrind --toggle-collect='native::profiled'`), BENCH_DUMP=<file> (no
//! timing: the bits of every output along every case's path, `dump_bits`), BENCH_TANGENT=1
//! (instead of the rounds: one directional derivative against one set + get per variant,
//! `tangent_cost`; BENCH_ONLY=<Variant> for one).
//!
//! The modules, each using only those listed before it, `support` (tests/common/mod.rs) and
//! `empty` (the empty FMU's bodies, empty_fmu/src/imp.rs):
//! - `allocs`: the counting global allocator;
//! - `fmus`: the two FMUs' functions (the connector's exports, the empty FMU's library);
//! - `scenes`: the variants, their paths, the parameter sets shared with tests/python;
//! - `instances`: the two FMUs' instances on a variant's path;
//! - `timing`: the timed loops and the median;
//! - `cases`: the behaviour sets (`params_on`, the stops);
//! - `floor`: the same physics written directly; `direct`: it on a case's path, checked
//!   against the FMU;
//! - `measure`: one case measured (`run_case`), with this file's profiling entry;
//! - `report`: the table, out/bench_native.csv and out/bench_scenes.json;
//! - `dump`: BENCH_DUMP; `tangent`: BENCH_TANGENT.
//!
//! This file: the environment, the loop over the cases, the checks that fail a run, and the
//! profiling entry (`profiled`, `profiled_empty`, `profiled_direct`), which stays in the crate
//! root so that its symbols stay `native::profiled*` for callgrind's `--toggle-collect`.
#![allow(clippy::not_unsafe_ptr_arg_deref)]

mod allocs;
mod cases;
mod direct;
mod dump;
#[path = "../../empty_fmu/src/imp.rs"]
mod empty;
// The same physics written directly: the floor a round is compared with.
mod floor;
mod fmus;
mod instances;
mod measure;
mod report;
mod scenes;
// The logger, callback struct and value lookups shared with the tests and the fuzz harness.
#[path = "../../tests/common/mod.rs"]
mod support;
mod tangent;
mod timing;

use cases::{params_on, Case};
use connector_fmu::variables::Variant;
use direct::{check_floor, direct_rounds, floor_kind, Direct};
use dump::dump_bits;
use fmus::{empty_fmu, REAL};
use instances::Inst;
use measure::{run_case, Settings};
use report::{csv_text, scene_json, table_text};
use scenes::{name_of, H, PERIOD, VARIANTS};
use tangent::tangent_cost;
use timing::rounds;

/// `n` rounds of the real FMU, alone in a function of its own (BENCH_PROFILE=n).
#[inline(never)]
fn profiled(f: &mut Inst, n: usize) {
    rounds(&REAL, f, n);
}

/// `n` rounds of the empty FMU, alone in a function of its own (BENCH_PROFILE=n).
#[inline(never)]
fn profiled_empty(f: &mut Inst, n: usize) {
    rounds(&empty_fmu().api, f, n);
}

/// `n` floor rounds, alone in a function of its own (BENCH_PROFILE=n).
#[inline(never)]
fn profiled_direct(d: &mut Direct, n: usize) {
    direct_rounds(d, n);
}

fn env_usize(name: &str) -> Option<usize> {
    std::env::var(name).ok().and_then(|s| s.parse().ok())
}

fn main() {
    let full = std::env::args().any(|a| a == "--bench");
    let only = std::env::var("BENCH_ONLY").ok();
    let (batches, steps) = if full { (20, 20_000) } else { (2, 1_000) };
    let s = Settings {
        batches: env_usize("BENCH_BATCHES").unwrap_or(batches),
        steps: env_usize("BENCH_STEPS").unwrap_or(steps),
        alloc_steps: if full { 10_000 } else { 1_000 },
    };
    if let Ok(path) = std::env::var("BENCH_DUMP") {
        dump_bits(&path);
        return;
    }
    if std::env::var("BENCH_TANGENT").is_ok() {
        tangent_cost(only.as_deref());
        return;
    }
    let write_files = full && only.is_none();
    if full && !empty_fmu().source.starts_with('/') {
        eprintln!(
            "error: the full benchmark measures the empty FMU from its own library; build it with\n  \
             cargo build --release --manifest-path empty_fmu/Cargo.toml --target-dir target/empty_fmu\n\
             (scripts/bench does) or set BENCH_EMPTY_LIB"
        );
        std::process::exit(2);
    }

    let variants = VARIANTS;
    let mut rows = vec![];
    let mut scenes = vec![];
    let mut deviations = vec![];
    for v in variants {
        // off, on, and for Bushing on without its stops (no event tracking: what tracking costs)
        let beh: &[(&str, bool)] = if v == Variant::Bushing {
            &[("off", false), ("on", true), ("on-nostops", true)]
        } else {
            &[("off", false), ("on", true)]
        };
        for &(what, on) in beh {
            let label = format!("{}:{what}", name_of(v));
            if let Some(o) = &only {
                if !(label == *o || name_of(v) == o) {
                    continue;
                }
            }
            let mut params = if on { params_on(v) } else { vec![] };
            if what == "on-nostops" {
                params.retain(|(n, _)| !n.starts_with("stop."));
            }
            let direct = on && floor_kind(v).is_some();
            if direct {
                // the floor computes the FMU's outputs (asserted), before it is timed
                let (vec, comp) = check_floor(v, &params);
                deviations.push((label.clone(), vec, comp));
            }
            eprintln!("  {label} ...");
            let case = Case {
                variant: v,
                on,
                direct,
                label: what,
            };
            rows.push(run_case(&case, &params, &s));
            if what == "on" && matches!(v, Variant::Bushing | Variant::Planar) {
                scenes.push(scene_json(v, &params));
            }
        }
    }

    let text = table_text(&rows, &s);
    print!("{text}");
    println!("empty FMU: {}", empty_fmu().source);
    for (label, vec, comp) in &deviations {
        println!(
            "floor = FMU, {label}: node loads and CTF/CTM agree to {vec:.1e} relative per 3-vector \
             (<= 1e-12 asserted), {comp:.1e} per component relative to its largest value, over {} rounds",
            2 * PERIOD
        );
    }
    let allocs: usize = rows.iter().map(|r| r.allocs).sum();
    println!(
        "heap allocations: {allocs} in {} rounds after warm-up ({} per case)",
        rows.len() * s.alloc_steps,
        s.alloc_steps
    );
    if write_files {
        let out = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("out");
        std::fs::create_dir_all(&out).expect("create out/");
        std::fs::write(out.join("bench_native.csv"), csv_text(&rows))
            .expect("write out/bench_native.csv");
        let json = format!(
            "{{\"h\": {H:?}, \"period\": {PERIOD},\n\"scenes\": [\n{}\n]}}\n",
            scenes.join(",\n")
        );
        std::fs::write(out.join("bench_scenes.json"), json).expect("write out/bench_scenes.json");
        println!("wrote out/bench_native.csv, out/bench_scenes.json");
    }
    let mut failed = false;
    for r in &rows {
        if r.allocs != 0 {
            eprintln!(
                "error: {} {}: {} heap allocations in {} rounds (must be 0)",
                r.variant, r.label, r.allocs, r.alloc_steps
            );
            failed = true;
        }
        if r.state_bytes > 1024 {
            eprintln!(
                "error: {} {}: serialized FMU state is {} bytes (must be <= 1024)",
                r.variant, r.label, r.state_bytes
            );
            failed = true;
        }
    }
    if failed {
        std::process::exit(1);
    }
}
