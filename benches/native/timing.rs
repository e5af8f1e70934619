//! The timed loops over an instance's path: `rounds` (set + doStep + get, the whole loop
//! timed), `do_steps` (the same rounds, doStep alone timed, each call bracketed by
//! `Instant::now`), `bracket_ns` (the bracket's own cost, subtracted), and `median`. Generic over
//! the FMU's `Api`; uses `fmus`, `instances`, `scenes` and the test support module.

use crate::fmus::Api;
use crate::instances::Inst;
use crate::scenes::{H, PERIOD};
use crate::support;
use std::fmt::Debug;
use std::hint::black_box;
use std::time::{Duration, Instant};

#[cold]
#[inline(never)]
fn step_failed<R: Debug>(env: usize, step: usize, s: [R; 3]) -> ! {
    panic!(
        "round at step {step} failed: set/doStep/get returned {s:?}: {:?}",
        support::log_of(env)
    );
}

/// `n` rounds set + doStep + get; the wall time of the whole loop.
#[inline(never)]
pub fn rounds<R: Copy + PartialEq + Debug>(api: &Api<R>, f: &mut Inst, n: usize) -> Duration {
    let (set, step, get) = (
        black_box(api.set_real),
        black_box(api.do_step),
        black_box(api.get_real),
    );
    let (n_in, n_out) = (f.vin.len(), f.vout.len());
    let mut out = [0.0f64; 16];
    let start = Instant::now();
    for _ in 0..n {
        let k = f.step;
        let row = &f.path[(k % PERIOD) * n_in..][..n_in];
        let s1 = set(f.c, f.vin.as_ptr(), n_in, row.as_ptr());
        let s2 = step(f.c, k as f64 * H, H, 0);
        let s3 = get(f.c, f.vout.as_ptr(), n_out, out.as_mut_ptr());
        if s1 != api.ok || s2 != api.ok || s3 != api.ok {
            step_failed(f.env, k, [s1, s2, s3]);
        }
        black_box(&out);
        f.step = k + 1;
    }
    start.elapsed()
}

/// `n` rounds as above, timing only fmi2DoStep (each call bracketed by Instant::now).
#[inline(never)]
pub fn do_steps<R: Copy + PartialEq + Debug>(api: &Api<R>, f: &mut Inst, n: usize) -> Duration {
    let (set, step, get) = (
        black_box(api.set_real),
        black_box(api.do_step),
        black_box(api.get_real),
    );
    let (n_in, n_out) = (f.vin.len(), f.vout.len());
    let mut out = [0.0f64; 16];
    let mut acc = Duration::ZERO;
    for _ in 0..n {
        let k = f.step;
        let row = &f.path[(k % PERIOD) * n_in..][..n_in];
        let s1 = set(f.c, f.vin.as_ptr(), n_in, row.as_ptr());
        let t0 = Instant::now();
        let s2 = step(f.c, k as f64 * H, H, 0);
        acc += t0.elapsed();
        let s3 = get(f.c, f.vout.as_ptr(), n_out, out.as_mut_ptr());
        if s1 != api.ok || s2 != api.ok || s3 != api.ok {
            step_failed(f.env, k, [s1, s2, s3]);
        }
        black_box(&out);
        f.step = k + 1;
    }
    acc
}

/// ns of an empty `Instant::now()` … `elapsed()` bracket, over `n` brackets (measured in every
/// batch, next to the timed calls, and subtracted from `do_steps`).
#[inline(never)]
pub fn bracket_ns(n: usize) -> f64 {
    let mut acc = Duration::ZERO;
    for _ in 0..n {
        let t0 = Instant::now();
        acc += black_box(t0).elapsed();
    }
    acc.as_nanos() as f64 / n as f64
}

pub fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}
