//! The floor (`floor.rs`, the same physics written directly) on a case's path: `Direct`, its
//! timed `direct_rounds`, and `check_floor`, which runs it side by side with the FMU and asserts
//! that it computes the FMU's node loads and CTF/CTM to 1e-12 before it is timed;
//! `DIRECT_TARGET`, a round's target against it. Uses `floor`, `scenes`, `instances`, `fmus`,
//! `timing` and the test support module.

use crate::floor;
use crate::fmus::REAL;
use crate::instances::{ok, real_instance};
use crate::scenes::{interface, name_of, path_of, H, PERIOD};
use crate::support;
use crate::timing::rounds;
use connector_fmu::fmi2::exports as fmi;
use connector_fmu::variables::{table, Field, Variant};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// Target of a round against the floor written directly (issue 15: Bushing on and Planar on
/// within 1.3× of it).
pub const DIRECT_TARGET: f64 = 1.3;

/// The floor's kind of a variant (Bushing and Planar have one).
pub fn floor_kind(v: Variant) -> Option<floor::Kind> {
    match v {
        Variant::Bushing => Some(floor::Kind::Bushing),
        Variant::Planar => Some(floor::Kind::Planar),
        _ => None,
    }
}

/// The floor instance on a variant's path, with its own step counter.
pub struct Direct {
    fl: floor::Floor,
    path: Vec<f64>,
    n_in: usize,
    step: usize,
}

pub fn direct_instance(v: Variant, params: &[(String, f64)]) -> Direct {
    let (vin, sel, _) = interface(v);
    let path = path_of(v, &sel);
    let kind = floor_kind(v).expect("a variant with a floor");
    Direct {
        fl: floor::Floor::new(kind, params, &sel, &path[..vin.len()]),
        path,
        n_in: vin.len(),
        step: 0,
    }
}

/// `n` floor rounds set + step + get; the wall time of the whole loop.
#[inline(never)]
pub fn direct_rounds(d: &mut Direct, n: usize) -> Duration {
    let mut out = [0.0f64; 12];
    let n_in = d.n_in;
    let start = Instant::now();
    for _ in 0..n {
        let k = d.step;
        let row = &d.path[(k % PERIOD) * n_in..][..n_in];
        d.fl.set(black_box(row));
        d.fl.step(black_box(H));
        d.fl.get(&mut out);
        black_box(&out);
        d.step = k + 1;
    }
    start.elapsed()
}

/// Runs the FMU and the floor side by side over `steps` rounds of the path and returns the
/// largest relative difference of the node loads and of CTF/CTM, per 3-vector
/// (|Δ|∞ / |x_FMU|∞; a vector that is zero in the FMU must be zero in the floor), and the
/// largest per component relative to the largest value of that output over the run.
fn floor_deviation(v: Variant, params: &[(String, f64)], steps: usize) -> (f64, f64) {
    let mut f = real_instance(v, params);
    let mut d = direct_instance(v, params);
    let total: Vec<u32> = ["CTF1", "CTF2", "CTF3", "CTM1", "CTM2", "CTM3"]
        .iter()
        .map(|n| support::vr(v, n))
        .collect();
    // the FMU's loads in the floor's order fa, ma, fb, mb
    let loads: Vec<u32> = (0..4u8)
        .flat_map(|which| (0..3u8).map(move |i| (which, i)))
        .map(|(which, i)| {
            table(v)
                .vars
                .iter()
                .find(|x| x.field == Field::Load { which, i })
                .expect("node load")
                .vr
        })
        .collect();
    let (mut worst_vec, mut worst_comp) = (0.0f64, 0.0f64);
    let mut fmu = [0.0; 18];
    let mut direct = [0.0; 18];
    let mut diff_max = [0.0f64; 18];
    let mut scale = [0.0f64; 18];
    for _ in 0..steps {
        rounds(&REAL, &mut f, 1);
        let mut out = [0.0; 12];
        direct_rounds(&mut d, 1);
        d.fl.get(&mut out);
        direct[..12].copy_from_slice(&out);
        direct[12..].copy_from_slice(&d.fl.total());
        ok(
            f.env,
            fmi::fmi2GetReal(f.c, loads.as_ptr(), 12, fmu.as_mut_ptr()),
            "loads",
        );
        ok(
            f.env,
            fmi::fmi2GetReal(f.c, total.as_ptr(), 6, fmu[12..].as_mut_ptr()),
            "CTF/CTM",
        );
        for g in 0..6 {
            let r = g * 3..g * 3 + 3;
            let norm = fmu[r.clone()].iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let diff = fmu[r.clone()]
                .iter()
                .zip(&direct[r])
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            let rel = if norm > 0.0 {
                diff / norm
            } else if diff == 0.0 {
                0.0
            } else {
                f64::INFINITY
            };
            worst_vec = worst_vec.max(rel);
        }
        for i in 0..18 {
            diff_max[i] = diff_max[i].max((fmu[i] - direct[i]).abs());
            scale[i] = scale[i].max(fmu[i].abs());
        }
    }
    for i in 0..18 {
        if scale[i] > 0.0 {
            worst_comp = worst_comp.max(diff_max[i] / scale[i]);
        } else if diff_max[i] > 0.0 {
            worst_comp = f64::INFINITY;
        }
    }
    (worst_vec, worst_comp)
}

/// The floor computes what the FMU computes: node loads and CTF/CTM to 1e-12 relative per
/// 3-vector over two periods of the path (both see the stops and the stick–slip reversals).
/// The bound: both evaluate the same closed forms in a different order (sums of a few products
/// of O(1) numbers, a few ulp each), and the path-dependent state (angle branch, friction
/// state) is a function of values that agree to that; 1e-12 leaves three orders above that
/// and fails at once if a term or a state update were missing.
pub fn check_floor(v: Variant, params: &[(String, f64)]) -> (f64, f64) {
    let (vec, comp) = floor_deviation(v, params, 2 * PERIOD);
    assert!(
        vec <= 1e-12,
        "{}: the floor's node loads or CTF/CTM differ from the FMU's by {vec:e} relative (> 1e-12)",
        name_of(v)
    );
    (vec, comp)
}
