//! What a run prints and writes: `table_text` (the table of the rounds, and of the rounds
//! against the floor written directly), `csv_text` (out/bench_native.csv) and `scene_json` (one
//! "on" scene for scripts/bench_fmpy.py, in out/bench_scenes.json). Formatting only: uses
//! `measure` (its rows and settings), `scenes`, `timing::median` and `direct::DIRECT_TARGET`.

use crate::direct::DIRECT_TARGET;
use crate::measure::{Row, Settings};
use crate::scenes::{interface, name_of, path_of, H};
use crate::timing::median;
use connector_fmu::variables::{table, Variant};
use std::fmt::Write as _;

pub fn table_text(rows: &[Row], s: &Settings) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "native benchmark: release build, through the exported C functions; h = {H} s, default substepping; \
         median of {} batches x {} steps; round = set(in node inputs) + doStep + get(out node loads)",
        s.batches, s.steps
    );
    let mut b: Vec<f64> = rows.iter().map(|r| r.bracket).collect();
    let _ = writeln!(
        t,
        "(Instant bracket measured in every batch and subtracted from ns_doStep: median {:.1} ns; \
         ratio = ns_round / floor_round, ratio_min = the same from the fastest batches)",
        if b.is_empty() { 0.0 } else { median(&mut b) }
    );
    let _ = writeln!(
        t,
        "{:<25} {:>13} {:>6} {:>10} {:>9} {:>11} {:>10} {:>6} {:>9} {:>9} {:>7}  target",
        "variant",
        "beh",
        "in/out",
        "ns_doStep",
        "ns_round",
        "floor_round",
        "floor_step",
        "ratio",
        "ratio_min",
        "allocs/st",
        "state_B"
    );
    for r in rows {
        let ratio = r.ns_round / r.floor_round;
        let target = match r.target {
            Some(x) if ratio <= x => format!("<= {x}x: met"),
            Some(x) => format!("<= {x}x: MISSED"),
            None => String::new(),
        };
        let _ = writeln!(
            t,
            "{:<25} {:>13} {:>6} {:>10.1} {:>9.1} {:>11.1} {:>10.1} {:>6.1} {:>9.1} {:>9} {:>7}  {}",
            r.variant,
            r.label,
            format!("{}/{}", r.n_in, r.n_out),
            r.ns_do_step,
            r.ns_round,
            r.floor_round,
            r.floor_do_step,
            ratio,
            r.ratio_min,
            r.allocs as f64 / r.alloc_steps as f64,
            r.state_bytes,
            target
        );
    }
    let direct: Vec<&Row> = rows.iter().filter(|r| r.direct_round.is_some()).collect();
    if !direct.is_empty() {
        let _ = writeln!(
            t,
            "\nfloor: the same physics written directly (benches/native/floor.rs), rounds interleaved with the FMU's and the empty FMU's\n\
             {:<25} {:>13} {:>9} {:>12} {:>11} {:>15} {:>15}  target",
            "variant", "beh", "ns_round", "floor_direct", "floor_round", "round/direct", "direct/empty"
        );
        for r in direct {
            let dr = r.direct_round.unwrap_or(f64::NAN);
            // issue 15's target for the "on" rounds (without stops the FMU tracks no event)
            let target = if r.label == "on" {
                let met = if r.ns_round / dr <= DIRECT_TARGET {
                    "met"
                } else {
                    "MISSED"
                };
                format!("<= {DIRECT_TARGET}x: {met}")
            } else {
                String::new()
            };
            let _ = writeln!(
                t,
                "{:<25} {:>13} {:>9.1} {:>12.1} {:>11.1} {:>15.2} {:>15.2}  {target}",
                r.variant,
                r.label,
                r.ns_round,
                dr,
                r.floor_round,
                r.ns_round / dr,
                dr / r.floor_round
            );
        }
    }
    t
}

pub fn csv_text(rows: &[Row]) -> String {
    let mut t = String::from(
        "variant,behaviours,ns_doStep_median,ns_round_median,floor_ns_round_median,ratio,allocs_per_step,state_bytes,floor_ns_doStep_median,n_inputs,n_outputs,target_ratio,ratio_min,direct_ns_round_median,ratio_to_direct\n",
    );
    for r in rows {
        let _ = writeln!(
            t,
            "{},{},{:.2},{:.2},{:.2},{:.3},{},{},{:.2},{},{},{},{:.3},{},{}",
            r.variant,
            r.label,
            r.ns_do_step,
            r.ns_round,
            r.floor_round,
            r.ns_round / r.floor_round,
            r.allocs as f64 / r.alloc_steps as f64,
            r.state_bytes,
            r.floor_do_step,
            r.n_in,
            r.n_out,
            r.target.map_or(String::new(), |x| x.to_string()),
            r.ratio_min,
            r.direct_round.map_or(String::new(), |x| format!("{x:.2}")),
            r.direct_round
                .map_or(String::new(), |x| format!("{:.3}", r.ns_round / x))
        );
    }
    t
}

/// The scene of one case as JSON, for scripts/bench_fmpy.py.
pub fn scene_json(v: Variant, params: &[(String, f64)]) -> String {
    let t = table(v);
    let (vin, sel, vout) = interface(v);
    let path = path_of(v, &sel);
    let name = |vr: &u32| format!("\"{}\"", t.get(*vr).unwrap().name);
    let list = |vrs: &[u32]| vrs.iter().map(name).collect::<Vec<_>>().join(", ");
    let mut j = String::new();
    let _ = write!(
        j,
        "{{\"variant\": \"{}\", \"behaviours\": \"on\",\n  \"params\": {{",
        name_of(v)
    );
    let ps: Vec<String> = params
        .iter()
        .map(|(n, x)| format!("\"{n}\": {x:?}"))
        .collect();
    let _ = write!(
        j,
        "{}}},\n  \"inputs\": [{}],\n  \"outputs\": [{}],\n  \"path\": [\n",
        ps.join(", "),
        list(&vin),
        list(&vout)
    );
    let rows: Vec<String> = path
        .chunks(vin.len())
        .map(|r| {
            format!(
                "    [{}]",
                r.iter()
                    .map(|x| format!("{x:?}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })
        .collect();
    let _ = write!(j, "{}\n  ]}}", rows.join(",\n"));
    j
}
