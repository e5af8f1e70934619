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
#![allow(clippy::not_unsafe_ptr_arg_deref)]

use connector_fmu::fmi2::exports as fmi;
use connector_fmu::fmi2::types::{
    fmi2CallbackFunctions, fmi2Component, fmi2FMUstate, fmi2False, fmi2Status,
};
use connector_fmu::variables::{table, Causality, Field, Variant};
use std::alloc::{GlobalAlloc, Layout, System};
use std::ffi::{c_char, c_double, c_int, c_uint, c_void, CStr, CString};
use std::fmt::Write as _;
use std::hint::black_box;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

#[path = "../../empty_fmu/src/imp.rs"]
mod empty;

// The same physics written directly: the floor a round is compared with.
mod floor;

// The logger, callback struct and value lookups shared with the tests and the fuzz harness.
#[path = "../../tests/common/mod.rs"]
mod support;

// ---------------------------------------------------------------- counting allocator

/// Every allocation (alloc, alloc_zeroed, realloc) of the process.
static ALLOCS: AtomicUsize = AtomicUsize::new(0);

struct Counting;

// SAFETY: forwards to System unchanged; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        System.alloc(l)
    }
    unsafe fn alloc_zeroed(&self, l: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        System.alloc_zeroed(l)
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, n: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        System.realloc(p, l, n)
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        System.dealloc(p, l)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

// ---------------------------------------------------------------- the two FMUs' functions

/// The three functions of a round, as C function pointers returning the status type `R`.
struct Api<R> {
    set_real: extern "C" fn(*mut c_void, *const c_uint, usize, *const c_double) -> R,
    do_step: extern "C" fn(*mut c_void, c_double, c_double, c_int) -> R,
    get_real: extern "C" fn(*mut c_void, *const c_uint, usize, *mut c_double) -> R,
    ok: R,
}

const REAL: Api<fmi2Status> = Api {
    set_real: fmi::fmi2SetReal,
    do_step: fmi::fmi2DoStep,
    get_real: fmi::fmi2GetReal,
    ok: fmi2Status::OK,
};

type Comp = *mut c_void;
type SetRealFn = extern "C" fn(Comp, *const c_uint, usize, *const c_double) -> c_int;
type DoStepFn = extern "C" fn(Comp, c_double, c_double, c_int) -> c_int;
type GetRealFn = extern "C" fn(Comp, *const c_uint, usize, *mut c_double) -> c_int;
type InstantiateFn = extern "C" fn(
    *const c_char,
    c_int,
    *const c_char,
    *const c_char,
    *const c_void,
    c_int,
    c_int,
) -> Comp;
type SetupFn = extern "C" fn(Comp, c_int, c_double, c_double, c_int, c_double) -> c_int;
type ModeFn = extern "C" fn(Comp) -> c_int;
type FreeFn = extern "C" fn(Comp);

/// The empty FMU: its round's functions and the life-cycle calls the benchmark makes.
struct EmptyFmu {
    api: Api<c_int>,
    instantiate: InstantiateFn,
    setup_experiment: SetupFn,
    enter_initialization_mode: ModeFn,
    exit_initialization_mode: ModeFn,
    free_instance: FreeFn,
    /// Where the functions come from (printed with the results).
    source: String,
}

/// The empty FMU's own shared library (`scripts/bench` builds it), or `BENCH_EMPTY_LIB`.
fn empty_lib_path() -> String {
    std::env::var("BENCH_EMPTY_LIB").unwrap_or_else(|_| {
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/target/empty_fmu/release/libempty_fmu.so"
        )
        .to_string()
    })
}

/// The empty FMU from its shared library, loaded as an importer loads an FMU: its code then
/// stays where it is whatever the connector's code does (compiled into this binary, the empty
/// round moved between 16 and 23 ns with the alignment the connector's code left it). Without
/// the library (the smoke pass of `cargo test --benches`) the same bodies compiled in.
fn empty_fmu() -> &'static EmptyFmu {
    static FMU: std::sync::OnceLock<EmptyFmu> = std::sync::OnceLock::new();
    FMU.get_or_init(|| {
        let path = empty_lib_path();
        load_empty(&path).unwrap_or_else(|| EmptyFmu {
            api: Api {
                set_real: empty::set_real,
                do_step: empty::do_step,
                get_real: empty::get_real,
                ok: empty::OK,
            },
            instantiate: empty::instantiate,
            setup_experiment: empty::setup_experiment,
            enter_initialization_mode: empty::enter_initialization_mode,
            exit_initialization_mode: empty::exit_initialization_mode,
            free_instance: empty::free_instance,
            source: format!("compiled into the benchmark ({path} not found)"),
        })
    })
}

/// dlopen + dlsym of the empty FMU's fmi2 functions; None when the library is not there.
fn load_empty(path: &str) -> Option<EmptyFmu> {
    let c_path = CString::new(path).ok()?;
    // SAFETY: dlopen of a library built from empty_fmu/ (plain Rust cdylib, no initialisers
    // with side effects); the handle is never closed, so the symbols stay valid.
    let lib = unsafe { libc::dlopen(c_path.as_ptr(), libc::RTLD_NOW | libc::RTLD_LOCAL) };
    if lib.is_null() {
        return None;
    }
    let sym = |name: &CStr| {
        // SAFETY: lib is a live handle; name is NUL-terminated.
        let p = unsafe { libc::dlsym(lib, name.as_ptr()) };
        assert!(!p.is_null(), "{path} does not export {name:?}");
        p
    };
    // SAFETY: each symbol is the `#[no_mangle] extern "C"` function of empty_fmu/src/lib.rs with
    // exactly the signature it is cast to (the fmi2 C signatures).
    unsafe {
        use std::mem::transmute as t;
        Some(EmptyFmu {
            api: Api {
                set_real: t::<*mut c_void, SetRealFn>(sym(c"fmi2SetReal")),
                do_step: t::<*mut c_void, DoStepFn>(sym(c"fmi2DoStep")),
                get_real: t::<*mut c_void, GetRealFn>(sym(c"fmi2GetReal")),
                ok: empty::OK,
            },
            instantiate: t::<*mut c_void, InstantiateFn>(sym(c"fmi2Instantiate")),
            setup_experiment: t::<*mut c_void, SetupFn>(sym(c"fmi2SetupExperiment")),
            enter_initialization_mode: t::<*mut c_void, ModeFn>(sym(
                c"fmi2EnterInitializationMode",
            )),
            exit_initialization_mode: t::<*mut c_void, ModeFn>(sym(c"fmi2ExitInitializationMode")),
            free_instance: t::<*mut c_void, FreeFn>(sym(c"fmi2FreeInstance")),
            source: path.to_string(),
        })
    }
}

// ---------------------------------------------------------------- scenes

/// Communication step (s).
const H: f64 = 1e-3;
/// Steps per period of every path (2 s).
const PERIOD: usize = 2000;
/// Node inputs per node: r(3), q w x y z (4), v(3), ω(3).
const PER_NODE: usize = 13;

/// Both nodes' 26 poses and twists at t, node a then node b, in the order of `Field::Input { node, idx }`.
type Pose = [f64; 2 * PER_NODE];

fn node_a_at_rest(p: &mut Pose) {
    p[..PER_NODE].copy_from_slice(&[
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
    ]);
}

/// Node a at rest at the origin; node b translates on a Lissajous path and rotates about the
/// fixed axis n = (2, 1, 2)/3 by φ = 0.3 sin ωt (so α1, α2 and β all vary), ω = 2π rad/s.
fn smooth(t: f64) -> Pose {
    let om = 2.0 * std::f64::consts::PI;
    let (s, c) = (om * t).sin_cos();
    let (s2, c2) = (2.0 * om * t).sin_cos();
    let phi = 0.3 * s;
    let dphi = 0.3 * om * c;
    let n = [2.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0];
    let (sh, ch) = (0.5 * phi).sin_cos();
    let mut p = [0.0; 26];
    node_a_at_rest(&mut p);
    let b = &mut p[PER_NODE..];
    b[0..3].copy_from_slice(&[0.05 + 0.01 * s, -0.03 + 0.008 * s2, 0.10 + 0.01 * c]);
    b[3..7].copy_from_slice(&[ch, sh * n[0], sh * n[1], sh * n[2]]);
    b[7..10].copy_from_slice(&[0.01 * om * c, 0.016 * om * c2, -0.01 * om * s]);
    b[10..13].copy_from_slice(&[dphi * n[0], dphi * n[1], dphi * n[2]]);
    p
}

/// The parameter sets and paths shared with tests/python (tests/data/parameter_sets.json).
#[derive(serde::Deserialize)]
struct Shared {
    spring_damper: SpringDamper,
    planar_friction: PlanarFriction,
    planar_slide: PlanarSlide,
}

#[derive(serde::Deserialize)]
struct SpringDamper {
    k_translational: [f64; 3],
    k_rotational: [f64; 3],
    c_translational: [f64; 3],
    c_rotational: [f64; 3],
}

#[derive(serde::Deserialize)]
struct PlanarFriction {
    values: Vec<(String, f64)>,
}

#[derive(serde::Deserialize)]
#[allow(non_snake_case)]
struct PlanarSlide {
    X0: f64,
    Y0: f64,
    Z0: f64,
    A: f64,
    B: f64,
    PSI0: f64,
    PS: f64,
}

fn shared() -> &'static Shared {
    static SHARED: std::sync::OnceLock<Shared> = std::sync::OnceLock::new();
    SHARED.get_or_init(|| {
        serde_json::from_str(include_str!("../../tests/data/parameter_sets.json"))
            .expect("tests/data/parameter_sets.json")
    })
}

/// PLANAR (`planar_slide` of tests/data/parameter_sets.json, as tests/python PlanarSlide): node
/// a at rest; node b slides in a's 2–3 plane along a parabolic arc b = (X0, Y0 + A s, Z0 + B s²),
/// s = sin ωt (the sliding direction turns, both rates vanish at the ends so the friction sticks
/// there) and spins about e1 by ψ = PSI0 + PS sin 1.5ωt.
fn planar(t: f64) -> Pose {
    let PlanarSlide {
        X0,
        Y0,
        Z0,
        A,
        B,
        PSI0,
        PS,
    } = shared().planar_slide;
    let om = 2.0 * std::f64::consts::PI;
    let (s, c) = (om * t).sin_cos();
    let ds = om * c;
    let psi = PSI0 + PS * (1.5 * om * t).sin();
    let dpsi = 1.5 * om * PS * (1.5 * om * t).cos();
    let (sh, ch) = (0.5 * psi).sin_cos();
    let mut p = [0.0; 26];
    node_a_at_rest(&mut p);
    let b = &mut p[PER_NODE..];
    b[0..3].copy_from_slice(&[X0, Y0 + A * s, Z0 + B * s * s]);
    b[3..7].copy_from_slice(&[ch, sh, 0.0, 0.0]);
    b[7..10].copy_from_slice(&[0.0, A * ds, 2.0 * B * s * ds]);
    b[10..13].copy_from_slice(&[dpsi, 0.0, 0.0]);
    p
}

/// One benchmark configuration.
struct Case {
    variant: Variant,
    on: bool,
    /// Compared with the floor (Bushing and Planar "on").
    direct: bool,
    label: &'static str,
}

/// Target of a round against the floor written directly (issue 15: Bushing on and Planar on
/// within 1.3× of it).
const DIRECT_TARGET: f64 = 1.3;

/// The floor's kind of a variant (Bushing and Planar have one).
fn floor_kind(v: Variant) -> Option<floor::Kind> {
    match v {
        Variant::Bushing => Some(floor::Kind::Bushing),
        Variant::Planar => Some(floor::Kind::Planar),
        _ => None,
    }
}

/// The floor instance on a variant's path, with its own step counter.
struct Direct {
    fl: floor::Floor,
    path: Vec<f64>,
    n_in: usize,
    step: usize,
}

fn direct_instance(v: Variant, params: &[(String, f64)]) -> Direct {
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
fn direct_rounds(d: &mut Direct, n: usize) -> Duration {
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

/// `n` floor rounds, alone in a function of its own (BENCH_PROFILE=n).
#[inline(never)]
fn profiled_direct(d: &mut Direct, n: usize) {
    direct_rounds(d, n);
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
fn check_floor(v: Variant, params: &[(String, f64)]) -> (f64, f64) {
    let (vec, comp) = floor_deviation(v, params, 2 * PERIOD);
    assert!(
        vec <= 1e-12,
        "{}: the floor's node loads or CTF/CTM differ from the FMU's by {vec:e} relative (> 1e-12)",
        name_of(v)
    );
    (vec, comp)
}

fn name_of(v: Variant) -> &'static str {
    v.spec().model_identifier
}

/// The Abaqus components (1..6) the variant makes available.
fn components(v: Variant) -> Vec<usize> {
    table(v)
        .vars
        .iter()
        .filter_map(|x| x.name.strip_prefix("elasticity.k"))
        .filter_map(|k| k.parse().ok())
        .collect()
}

/// Components that get a stop in the "on" configuration (hit twice per period).
fn stop_components(v: Variant) -> &'static [usize] {
    match v {
        Variant::Bushing => &[1, 4],
        Variant::Planar => &[2],
        Variant::ProjectionCartesian => &[1],
        Variant::ProjectionFlexionTorsion => &[4],
        Variant::RadialThrust => &[1],
    }
}

/// CP<i> / CPR<i> of Abaqus component k.
fn position_name(k: usize) -> String {
    if k <= 3 {
        format!("CP{k}")
    } else {
        format!("CPR{}", k - 3)
    }
}

// ---------------------------------------------------------------- instances

/// An initialized instance with its value references and its precomputed input path.
struct Inst {
    c: fmi2Component,
    vin: Vec<u32>,
    vout: Vec<u32>,
    /// PERIOD rows of vin.len() values.
    path: Vec<f64>,
    /// Steps taken (the next step starts at step·H).
    step: usize,
    empty: bool,
    /// The componentEnvironment key its messages are logged under (tests/common).
    env: usize,
}

impl Drop for Inst {
    fn drop(&mut self) {
        if self.empty {
            (empty_fmu().free_instance)(self.c);
        } else {
            fmi::fmi2FreeInstance(self.c);
        }
        support::forget_log(self.env);
    }
}

/// Asserts OK; on failure shows what the instance logged under `env`.
#[track_caller]
fn ok(env: usize, s: fmi2Status, what: &str) {
    assert_eq!(s, fmi2Status::OK, "{what}: {:?}", support::log_of(env));
}

/// Inputs (value references, index into Pose) and node-load outputs of a variant.
fn interface(v: Variant) -> (Vec<u32>, Vec<usize>, Vec<u32>) {
    let (mut vin, mut sel, mut vout) = (vec![], vec![], vec![]);
    for x in &table(v).vars {
        match x.field {
            // the poses and twists (the acceleration inputs only matter with extrapolation 3)
            Field::Input { node, idx } if (idx as usize) < PER_NODE => {
                vin.push(x.vr);
                sel.push(node as usize * PER_NODE + idx as usize);
            }
            Field::Load { .. } if x.causality == Causality::Output => vout.push(x.vr),
            _ => {}
        }
    }
    (vin, sel, vout)
}

fn path_of(v: Variant, sel: &[usize]) -> Vec<f64> {
    let pose = if v == Variant::Planar { planar } else { smooth };
    let mut path = Vec::with_capacity(PERIOD * sel.len());
    for i in 0..PERIOD {
        let p = pose(i as f64 * H);
        path.extend(sel.iter().map(|&j| p[j]));
    }
    path
}

/// An instance of the real FMU, parameters set, inputs at t = 0, initialized.
fn real_instance(v: Variant, params: &[(String, f64)]) -> Inst {
    real_instance_with(v, params, &[])
}

/// `real_instance` with Integer parameters too (`ints`, values given as f64).
fn real_instance_with(v: Variant, params: &[(String, f64)], ints: &[(String, f64)]) -> Inst {
    let (vin, sel, vout) = interface(v);
    let path = path_of(v, &sel);
    let env = support::new_env();
    let cb = support::callbacks(env);
    let c = support::instantiate_raw(
        Some("bench"),
        support::CO_SIMULATION,
        Some(&support::guid(v)),
        Some(&cb),
        false,
    );
    assert!(
        !c.is_null(),
        "fmi2Instantiate refused {}: {:?}",
        name_of(v),
        support::log_of(env)
    );
    let inst = Inst {
        c,
        vin,
        vout,
        path,
        step: 0,
        empty: false,
        env,
    };
    for (n, x) in params {
        ok(env, fmi::fmi2SetReal(c, &support::vr(v, n), 1, x), n);
    }
    for (n, x) in ints {
        let i = *x as i32;
        ok(env, fmi::fmi2SetInteger(c, &support::vr(v, n), 1, &i), n);
    }
    ok(
        env,
        fmi::fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0),
        "setup",
    );
    ok(env, fmi::fmi2EnterInitializationMode(c), "enter init");
    ok(
        env,
        fmi::fmi2SetReal(c, inst.vin.as_ptr(), inst.vin.len(), inst.path.as_ptr()),
        "inputs at 0",
    );
    ok(env, fmi::fmi2ExitInitializationMode(c), "exit init");
    inst
}

/// An instance of the empty FMU with the same numbers of inputs and outputs and the same path.
fn empty_instance(like: &Inst) -> Inst {
    let name = CString::new("empty").unwrap();
    let guid = CString::new(empty::GUID).unwrap();
    let env = support::new_env();
    let cb = support::callbacks(env);
    let e = empty_fmu();
    let c = (e.instantiate)(
        name.as_ptr(),
        1,
        guid.as_ptr(),
        c"".as_ptr(),
        (&cb as *const fmi2CallbackFunctions).cast(),
        0,
        0,
    );
    assert!(!c.is_null());
    let n_in = like.vin.len() as u32;
    let n_out = like.vout.len() as u32;
    assert!(n_in <= empty::N_IN && n_out <= empty::N_OUT);
    let inst = Inst {
        c,
        vin: (1..=n_in).collect(),
        vout: (empty::N_IN + 1..=empty::N_IN + n_out).collect(),
        path: like.path.clone(),
        step: 0,
        empty: true,
        env,
    };
    assert_eq!((e.setup_experiment)(c, 0, 0.0, 0.0, 0, 0.0), empty::OK);
    assert_eq!((e.enter_initialization_mode)(c), empty::OK);
    assert_eq!((e.exit_initialization_mode)(c), empty::OK);
    inst
}

// ---------------------------------------------------------------- timed loops

#[cold]
#[inline(never)]
fn step_failed<R: std::fmt::Debug>(env: usize, step: usize, s: [R; 3]) -> ! {
    panic!(
        "round at step {step} failed: set/doStep/get returned {s:?}: {:?}",
        support::log_of(env)
    );
}

/// `n` rounds set + doStep + get; the wall time of the whole loop.
#[inline(never)]
fn rounds<R: Copy + PartialEq + std::fmt::Debug>(api: &Api<R>, f: &mut Inst, n: usize) -> Duration {
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

/// `n` rounds as above, timing only fmi2DoStep (each call bracketed by Instant::now).
#[inline(never)]
fn do_steps<R: Copy + PartialEq + std::fmt::Debug>(
    api: &Api<R>,
    f: &mut Inst,
    n: usize,
) -> Duration {
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
fn bracket_ns(n: usize) -> f64 {
    let mut acc = Duration::ZERO;
    for _ in 0..n {
        let t0 = Instant::now();
        acc += black_box(t0).elapsed();
    }
    acc.as_nanos() as f64 / n as f64
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

// ---------------------------------------------------------------- one case

struct Row {
    variant: &'static str,
    ns_do_step: f64,
    ns_round: f64,
    floor_round: f64,
    floor_do_step: f64,
    allocs: usize,
    alloc_steps: usize,
    state_bytes: usize,
    n_in: usize,
    n_out: usize,
    target: Option<f64>,
    /// min(ns_round) / min(floor_ns_round): the least disturbed batches (busy machines).
    ratio_min: f64,
    /// Median cost of the Instant bracket subtracted from ns_doStep.
    bracket: f64,
    /// ns per round of the floor (`floor.rs`, same physics written directly), when it has one.
    direct_round: Option<f64>,
    /// The label of the case (e.g. "on", "on, no stops").
    label: &'static str,
}

struct Settings {
    batches: usize,
    steps: usize,
    alloc_steps: usize,
}

/// The "on" parameters of a variant (stops placed from a pre-pass over one period).
fn params_on(v: Variant) -> Vec<(String, f64)> {
    let mut p: Vec<(String, f64)> = vec![];
    if v == Variant::Planar {
        // `planar_friction` of tests/data/parameter_sets.json (tests/python PLANAR_FRICTION)
        p.extend(shared().planar_friction.values.iter().cloned());
    } else {
        // `spring_damper` of tests/data/parameter_sets.json (tests/python spring_damper_params)
        let sd = &shared().spring_damper;
        for k in components(v) {
            let (kk, cc) = if k <= 3 {
                (sd.k_translational[k - 1], sd.c_translational[k - 1])
            } else {
                (sd.k_rotational[k - 4], sd.c_rotational[k - 4])
            };
            p.push((format!("elasticity.k{k}"), kk));
            p.push((format!("damping.c{k}"), cc));
        }
    }
    // stops at 70 % of each component's excursion along the path (positions are kinematic, so
    // a pre-pass with the defaults gives them)
    let stops = stop_components(v);
    let mut pre = real_instance(v, &[]);
    let vrs: Vec<u32> = stops
        .iter()
        .map(|&k| support::vr(v, &position_name(k)))
        .collect();
    let mut lo = vec![f64::INFINITY; stops.len()];
    let mut hi = vec![f64::NEG_INFINITY; stops.len()];
    let mut x = vec![0.0; stops.len()];
    for _ in 0..PERIOD {
        rounds(&REAL, &mut pre, 1);
        ok(
            pre.env,
            fmi::fmi2GetReal(pre.c, vrs.as_ptr(), vrs.len(), x.as_mut_ptr()),
            "positions",
        );
        for i in 0..x.len() {
            lo[i] = lo[i].min(x[i]);
            hi[i] = hi[i].max(x[i]);
        }
    }
    for (i, &k) in stops.iter().enumerate() {
        p.push((format!("stop.upper{k}"), lo[i] + 0.7 * (hi[i] - lo[i])));
    }
    p.extend([
        ("stop.stiffness".into(), 1.0e5),
        ("stop.damping".into(), 10.0),
        ("stop.rotStiffness".into(), 500.0),
        ("stop.rotDamping".into(), 1.0),
    ]);
    p.retain(|(n, _)| table(v).vars.iter().any(|x| &x.name == n));
    p
}

fn stop_status_vrs(v: Variant) -> Vec<u32> {
    stop_components(v)
        .iter()
        .map(|k| support::vr(v, &format!("CSLST{k}")))
        .collect()
}

fn run_case(case: &Case, params: &[(String, f64)], s: &Settings) -> Row {
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

// ---------------------------------------------------------------- output

fn table_text(rows: &[Row], s: &Settings) -> String {
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

fn csv_text(rows: &[Row]) -> String {
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
fn scene_json(v: Variant, params: &[(String, f64)]) -> String {
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

/// BENCH_DUMP=<file>: the bits of every output after every round of every case (both
/// behaviour sets, linear and second-order extrapolation, two periods), and every 97th round
/// the directional derivatives of all Real outputs along each node input, written as hex lines
/// to <file> (nothing timed). Two builds that write the same file compute the same numbers bit
/// for bit on these paths (docs/benchmarks.md: how the per-step restructuring was checked).
fn dump_bits(path: &str) {
    let mut text = String::new();
    for v in VARIANTS {
        let t = table(v);
        let real_out: Vec<u32> = t
            .vars
            .iter()
            .filter(|x| x.causality == Causality::Output)
            .filter(|x| !matches!(x.start, connector_fmu::variables::Start::Integer(_)))
            .map(|x| x.vr)
            .collect();
        let cont_out = continuous_outputs(v);
        let int_out: Vec<u32> = t
            .vars
            .iter()
            .filter(|x| x.causality == Causality::Output)
            .filter(|x| matches!(x.start, connector_fmu::variables::Start::Integer(_)))
            .map(|x| x.vr)
            .collect();
        for on in [false, true] {
            for extrapolation in [1.0, 2.0] {
                let mut params = if on { params_on(v) } else { vec![] };
                if extrapolation != 1.0 {
                    // an Integer parameter: set below through fmi2SetInteger
                    params.push(("cosim.extrapolation".into(), extrapolation));
                }
                let (ints, reals): (Vec<_>, Vec<_>) = params
                    .into_iter()
                    .partition(|(n, _)| n == "cosim.extrapolation");
                let mut f = real_instance_with(v, &reals, &ints);
                let _ = writeln!(text, "{} on={on} extrapolation={extrapolation}", name_of(v));
                let mut r = vec![0.0; real_out.len()];
                let mut i = vec![0; int_out.len()];
                let mut dd = vec![0.0; cont_out.len()];
                for step in 0..2 * PERIOD {
                    rounds(&REAL, &mut f, 1);
                    ok(
                        f.env,
                        fmi::fmi2GetReal(f.c, real_out.as_ptr(), r.len(), r.as_mut_ptr()),
                        "outputs",
                    );
                    ok(
                        f.env,
                        fmi::fmi2GetInteger(f.c, int_out.as_ptr(), i.len(), i.as_mut_ptr()),
                        "integer outputs",
                    );
                    let _ = write!(text, "{step}:");
                    for x in &r {
                        let _ = write!(text, " {:016x}", x.to_bits());
                    }
                    for x in &i {
                        let _ = write!(text, " {x}");
                    }
                    text.push('\n');
                    if step % 97 == 0 {
                        for &known in &f.vin {
                            ok(
                                f.env,
                                fmi::fmi2GetDirectionalDerivative(
                                    f.c,
                                    cont_out.as_ptr(),
                                    cont_out.len(),
                                    &known,
                                    1,
                                    &1.0,
                                    dd.as_mut_ptr(),
                                ),
                                "directional derivative",
                            );
                            let _ = write!(text, "  d/d{known}:");
                            for x in &dd {
                                let _ = write!(text, " {:016x}", x.to_bits());
                            }
                            text.push('\n');
                        }
                    }
                }
            }
        }
    }
    std::fs::write(path, text).expect("write BENCH_DUMP file");
    println!("wrote {path}");
}

/// The VRs of a variant's continuous Real outputs (the unknowns of a directional derivative).
fn continuous_outputs(v: Variant) -> Vec<u32> {
    table(v)
        .vars
        .iter()
        .filter(|x| x.causality == Causality::Output)
        .filter(|x| x.variability == connector_fmu::variables::Variability::Continuous)
        .map(|x| x.vr)
        .collect()
}

/// BENCH_TANGENT=1: what a directional derivative costs against one kernel evaluation, on
/// every variant with its behaviours on, a quarter period into its path. Interleaved batches,
/// each call sequence at a new point (the seed's input and an orientation input set to other
/// values first: everything moves, as from one communication point to the next):
/// (e) fmi2SetReal of one input + fmi2GetReal of one output: one kernel evaluation at the new
///     inputs, plus the two calls;
/// (d) (e) + fmi2GetDirectionalDerivative of every continuous output along one node input
///     (b.r[2], b.r[1] or b.q.x where that is what there is): the first derivative at a point,
///     one evaluation in `Dual`;
/// (j) (e) + the n derivatives of every continuous output along each input of node b in
///     turn (n = 13; 7 or 6 where node b has an orientation or positions only), as a
///     linear-implicit master asks for its Jacobian: each one evaluation in `Dual`.
/// (dl), (jl) as (d), (j) with the node loads as the unknowns, which is what a linear-implicit
///     master asks for (scripts/cosim/master.py): the same kernel evaluation, fewer values to
///     hand back.
/// Printed: ns per (e), (d), (j), the first derivative's cost ((d) − (e)) / (e), and the cost
/// per derivative of the Jacobian ((j) − (e)) / n / (e), then the same two for the loads
/// ((dl), (jl)); medians of 15 batches of 1000.
/// BENCH_ONLY=<variant> measures that variant alone.
fn tangent_cost(only: Option<&str>) {
    println!(
        "variant, ns per set+get (e), set+get+derivative (d), set+get+n derivatives (j), n, first derivative / evaluation, Jacobian per derivative / evaluation, the same two for the node loads alone"
    );
    for v in VARIANTS {
        if only.is_some_and(|o| o != name_of(v)) {
            continue;
        }
        let mut f = real_instance(v, &params_on(v));
        rounds(&REAL, &mut f, PERIOD / 4);
        let t = table(v);
        let cont = continuous_outputs(v);
        let loads: Vec<u32> = t
            .vars
            .iter()
            .filter(|x| matches!(x.field, Field::Load { .. }))
            .map(|x| x.vr)
            .collect();
        let vr_of = |n: &str| t.vars.iter().find(|x| x.name == n).map(|x| x.vr);
        let seed = ["b.r[2]", "b.r[1]", "b.q.x"]
            .iter()
            .find_map(|n| vr_of(n))
            .expect("a node input");
        let node_b: Vec<u32> = t
            .vars
            .iter()
            .filter(
                |x| matches!(x.field, Field::Input { node: 1, idx } if (idx as usize) < PER_NODE),
            )
            .map(|x| x.vr)
            .collect();
        // the point moves along the seed's input and an orientation (as in a co-simulation,
        // where everything moves from one point to the next: nothing the kernel computes
        // from the orientations carries over)
        let turn = ["b.q.x", "a.q.x"]
            .iter()
            .find_map(|n| vr_of(n))
            .expect("an orientation input");
        let moved: Vec<u32> = if turn == seed {
            vec![seed]
        } else {
            vec![seed, turn]
        };
        let mut x = vec![0.0; moved.len()];
        ok(
            f.env,
            fmi::fmi2GetReal(f.c, moved.as_ptr(), moved.len(), x.as_mut_ptr()),
            "moved inputs",
        );
        let mut u = x.clone();
        let mut dd = vec![0.0; cont.len()];
        let (mut e, mut d, mut j, mut dl, mut jl) = (vec![], vec![], vec![], vec![], vec![]);
        const N: usize = 1000;
        let mut y = 0.0;
        let mut batch = |derivatives: &[u32], unknowns: &[u32], f: &mut Inst| {
            let t0 = Instant::now();
            for i in 0..N {
                // alternate between two points, so that every call sequence is at a new one
                for (u, x) in u.iter_mut().zip(&x) {
                    *u = x + if i % 2 == 0 { 1e-9 } else { 0.0 };
                }
                ok(
                    f.env,
                    fmi::fmi2SetReal(f.c, moved.as_ptr(), moved.len(), u.as_ptr()),
                    "set",
                );
                ok(f.env, fmi::fmi2GetReal(f.c, &cont[0], 1, &mut y), "get");
                for k in derivatives {
                    let s = fmi::fmi2GetDirectionalDerivative(
                        f.c,
                        unknowns.as_ptr(),
                        unknowns.len(),
                        k,
                        1,
                        &1.0,
                        dd.as_mut_ptr(),
                    );
                    ok(f.env, s, "directional derivative");
                }
            }
            std::hint::black_box((&dd, y));
            t0.elapsed().as_nanos() as f64 / N as f64
        };
        for _ in 0..15 {
            e.push(batch(&[], &cont, &mut f));
            d.push(batch(&[seed], &cont, &mut f));
            j.push(batch(&node_b, &cont, &mut f));
            dl.push(batch(&[seed], &loads, &mut f));
            jl.push(batch(&node_b, &loads, &mut f));
        }
        let (me, md, mj) = (median(&mut e), median(&mut d), median(&mut j));
        let (mdl, mjl) = (median(&mut dl), median(&mut jl));
        let n = node_b.len() as f64;
        println!(
            "{}, {me:.0}, {md:.0}, {mj:.0}, {}, {:.2}, {:.2}, {:.2}, {:.2}",
            name_of(v),
            node_b.len(),
            (md - me) / me,
            (mj - me) / n / me,
            (mdl - me) / me,
            (mjl - me) / n / me
        );
    }
}

/// Every variant, in the order the tables and files list them.
const VARIANTS: [Variant; 5] = [
    Variant::Planar,
    Variant::ProjectionCartesian,
    Variant::ProjectionFlexionTorsion,
    Variant::Bushing,
    Variant::RadialThrust,
];

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
