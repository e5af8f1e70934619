//! One case measured: `run_case` warms the FMU, the empty FMU and the floor up (checking that
//! an "on" scene hits each of its stops), runs the BENCH_PROFILE rounds in main.rs's `profiled*`
//! functions, times the interleaved batches (rounds of each, doStep alone, the Instant bracket),
//! then counts the allocations of the rounds after warm-up and sizes the serialized state, into
//! a `Row`; `Settings` are the batch sizes. Uses `allocs`, `fmus`, `scenes`, `instances`,
//! `timing`, `cases`, `direct`, and from main.rs the profiling entry and `env_usize`.

use crate::allocs::ALLOCS;
use crate::cases::{stop_status_vrs, Case};
use crate::direct::{direct_instance, direct_rounds};
use crate::fmus::{empty_fmu, REAL};
use crate::instances::{empty_instance, ok, real_instance};
use crate::scenes::{name_of, PERIOD};
use crate::timing::{bracket_ns, do_steps, median, rounds};
use crate::{env_usize, profiled, profiled_direct, profiled_empty};
use connector_fmu::fmi2::exports as fmi;
use connector_fmu::fmi2::types::fmi2FMUstate;
use connector_fmu::variables::Variant;
use std::sync::atomic::Ordering;
use std::time::Duration;

pub struct Row {
    pub variant: &'static str,
    pub ns_do_step: f64,
    pub ns_round: f64,
    pub floor_round: f64,
    pub floor_do_step: f64,
    pub allocs: usize,
    pub alloc_steps: usize,
    pub state_bytes: usize,
    pub n_in: usize,
    pub n_out: usize,
    pub target: Option<f64>,
    /// min(ns_round) / min(floor_ns_round): the least disturbed batches (busy machines).
    pub ratio_min: f64,
    /// Median cost of the Instant bracket subtracted from ns_doStep.
    pub bracket: f64,
    /// ns per round of the floor (`floor.rs`, same physics written directly), when it has one.
    pub direct_round: Option<f64>,
    /// The label of the case (e.g. "on", "on, no stops").
    pub label: &'static str,
}

pub struct Settings {
    pub batches: usize,
    pub steps: usize,
    pub alloc_steps: usize,
}

pub fn run_case(case: &Case, params: &[(String, f64)], s: &Settings) -> Row {
    let v = case.variant;
    let mut f = real_instance(v, params);
    let mut e = empty_instance(&f);
    let mut d = case.direct.then(|| direct_instance(v, params));

    // warm-up (also checks that the "on" scene really engages its stops)
    rounds(&REAL, &mut f, PERIOD);
    rounds(&empty_fmu().api, &mut e, PERIOD);
    if let Some(d) = d.as_mut() {
        direct_rounds(d, PERIOD);
    }
    let has_stops = params.iter().any(|(n, _)| n.starts_with("stop.upper"));
    if case.on && has_stops {
        let vrs = stop_status_vrs(v);
        let mut hit = vec![false; vrs.len()];
        let mut st = vec![0; vrs.len()];
        for _ in 0..PERIOD {
            rounds(&REAL, &mut f, 1);
            ok(
                f.env,
                fmi::fmi2GetInteger(f.c, vrs.as_ptr(), vrs.len(), st.as_mut_ptr()),
                "CSLST",
            );
            for (h, x) in hit.iter_mut().zip(&st) {
                *h |= *x != 0;
            }
        }
        assert!(
            hit.iter().all(|&h| h),
            "{}: a stop is never hit",
            name_of(v)
        );
    }

    if let Some(n) = env_usize("BENCH_PROFILE") {
        // only steady-state rounds, for `valgrind --tool=callgrind --toggle-collect=native::profiled`
        profiled(&mut f, n);
        profiled_empty(&mut e, n);
        if let Some(d) = d.as_mut() {
            profiled_direct(d, n);
        }
    }
    let (mut fr, mut vr, mut fd, mut vd, mut br) = (vec![], vec![], vec![], vec![], vec![]);
    let mut dr = vec![];
    let per = |d: Duration| d.as_nanos() as f64 / s.steps as f64;
    for _ in 0..s.batches {
        fr.push(per(rounds(&empty_fmu().api, &mut e, s.steps)));
        vr.push(per(rounds(&REAL, &mut f, s.steps)));
        if let Some(d) = d.as_mut() {
            dr.push(per(direct_rounds(d, s.steps)));
        }
        let b = bracket_ns(s.steps);
        br.push(b);
        fd.push(per(do_steps(&empty_fmu().api, &mut e, s.steps)) - b);
        vd.push(per(do_steps(&REAL, &mut f, s.steps)) - b);
    }

    let before = ALLOCS.load(Ordering::SeqCst);
    rounds(&REAL, &mut f, s.alloc_steps);
    let allocs = ALLOCS.load(Ordering::SeqCst) - before;

    let mut state: fmi2FMUstate = std::ptr::null_mut();
    ok(
        f.env,
        fmi::fmi2GetFMUstate(f.c, &mut state),
        "fmi2GetFMUstate",
    );
    let mut state_bytes = 0usize;
    ok(
        f.env,
        fmi::fmi2SerializedFMUstateSize(f.c, state, &mut state_bytes),
        "fmi2SerializedFMUstateSize",
    );
    ok(
        f.env,
        fmi::fmi2FreeFMUstate(f.c, &mut state),
        "fmi2FreeFMUstate",
    );

    let target = match (v, case.label == "on") {
        (Variant::Bushing, true) => Some(40.0),
        (Variant::Planar, true) => Some(25.0),
        _ => None,
    };
    Row {
        variant: name_of(v),
        ns_do_step: median(&mut vd),
        ns_round: median(&mut vr),
        floor_round: median(&mut fr),
        floor_do_step: median(&mut fd),
        ratio_min: vr[0] / fr[0], // sorted by median()
        bracket: median(&mut br),
        direct_round: (!dr.is_empty()).then(|| median(&mut dr)),
        label: case.label,
        allocs,
        alloc_steps: s.alloc_steps,
        state_bytes,
        n_in: f.vin.len(),
        n_out: f.vout.len(),
        target,
    }
}
