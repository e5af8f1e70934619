//! The two FMUs' functions, called as an importer calls them, through C function pointers:
//! `Api`, the three functions of a round (`REAL`: the connector's exported fmi2 functions), and
//! `empty_fmu`, the empty FMU loaded from its own shared library (or, without it, the bodies of
//! `empty_fmu/src/imp.rs` compiled in) with the life-cycle calls the benchmark makes. Uses the
//! crate's fmi2 exports and `crate::empty`, nothing else of the benchmark.

use crate::empty;
use connector_fmu::fmi2::exports as fmi;
use connector_fmu::fmi2::types::fmi2Status;
use std::ffi::{c_char, c_double, c_int, c_uint, c_void, CStr, CString};

/// The three functions of a round, as C function pointers returning the status type `R`.
pub struct Api<R> {
    pub set_real: extern "C" fn(*mut c_void, *const c_uint, usize, *const c_double) -> R,
    pub do_step: extern "C" fn(*mut c_void, c_double, c_double, c_int) -> R,
    pub get_real: extern "C" fn(*mut c_void, *const c_uint, usize, *mut c_double) -> R,
    pub ok: R,
}

pub const REAL: Api<fmi2Status> = Api {
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
pub struct EmptyFmu {
    pub api: Api<c_int>,
    pub instantiate: InstantiateFn,
    pub setup_experiment: SetupFn,
    pub enter_initialization_mode: ModeFn,
    pub exit_initialization_mode: ModeFn,
    pub free_instance: FreeFn,
    /// Where the functions come from (printed with the results).
    pub source: String,
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
pub fn empty_fmu() -> &'static EmptyFmu {
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
