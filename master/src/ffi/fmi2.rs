//! FMI 2.0 Co-Simulation through the C API: the functions resolved once per library, and an
//! instance whose safe methods wrap `fmi2Instantiate` … `fmi2FreeInstance`. Uses fmi_shared's
//! fmi2 types, ffi/mod.rs (Library, Status, LogSink) and error.rs.

use super::{c_str, log_to, Library, LogSink, Status};
use crate::error::{Error, Result};
use fmi_shared::fmi2::{
    fmi2Boolean, fmi2CallbackFunctions, fmi2CallbackLogger, fmi2Component,
    fmi2ComponentEnvironment, fmi2Real, fmi2String, fmi2ValueReference, FMI2_CO_SIMULATION,
    FMI2_TERMINATED,
};
use std::ffi::{c_char, c_int, c_void, CString};
use std::sync::Arc;

type Instantiate = unsafe extern "C" fn(
    fmi2String,
    c_int,
    fmi2String,
    fmi2String,
    *const fmi2CallbackFunctions,
    fmi2Boolean,
    fmi2Boolean,
) -> fmi2Component;
type Free = unsafe extern "C" fn(fmi2Component);
type Setup = unsafe extern "C" fn(
    fmi2Component,
    fmi2Boolean,
    fmi2Real,
    fmi2Real,
    fmi2Boolean,
    fmi2Real,
) -> c_int;
type Plain = unsafe extern "C" fn(fmi2Component) -> c_int;
type DoStep = unsafe extern "C" fn(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean) -> c_int;
type GetReal =
    unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2Real) -> c_int;
type SetReal =
    unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const fmi2Real) -> c_int;
type GetInt =
    unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *mut c_int) -> c_int;
type SetInt =
    unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const c_int) -> c_int;
type GetString =
    unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *mut fmi2String) -> c_int;
type SetString = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *const fmi2String,
) -> c_int;
type GetBooleanStatus = unsafe extern "C" fn(fmi2Component, c_int, *mut fmi2Boolean) -> c_int;

/// The FMI 2.0 functions of one library.
#[derive(Clone, Copy)]
struct Functions {
    instantiate: Instantiate,
    free: Free,
    setup: Setup,
    enter_init: Plain,
    exit_init: Plain,
    terminate: Plain,
    do_step: DoStep,
    get_real: GetReal,
    set_real: SetReal,
    get_integer: GetInt,
    set_integer: SetInt,
    get_boolean: GetInt,
    set_boolean: SetInt,
    get_string: GetString,
    set_string: SetString,
    get_boolean_status: Option<GetBooleanStatus>,
}

/// A loaded FMI 2.0 library.
pub struct Fmi2Library {
    fns: Functions,
    lib: Arc<Library>,
}

impl Fmi2Library {
    /// Resolves the functions of `lib`.
    pub fn new(lib: Library) -> Result<Fmi2Library> {
        let fns = Functions {
            instantiate: lib.require("fmi2Instantiate")?,
            free: lib.require("fmi2FreeInstance")?,
            setup: lib.require("fmi2SetupExperiment")?,
            enter_init: lib.require("fmi2EnterInitializationMode")?,
            exit_init: lib.require("fmi2ExitInitializationMode")?,
            terminate: lib.require("fmi2Terminate")?,
            do_step: lib.require("fmi2DoStep")?,
            get_real: lib.require("fmi2GetReal")?,
            set_real: lib.require("fmi2SetReal")?,
            get_integer: lib.require("fmi2GetInteger")?,
            set_integer: lib.require("fmi2SetInteger")?,
            get_boolean: lib.require("fmi2GetBoolean")?,
            set_boolean: lib.require("fmi2SetBoolean")?,
            get_string: lib.require("fmi2GetString")?,
            set_string: lib.require("fmi2SetString")?,
            get_boolean_status: lib.symbol("fmi2GetBooleanStatus"),
        };
        Ok(Fmi2Library {
            fns,
            lib: Arc::new(lib),
        })
    }

    /// `fmi2Instantiate` as Co-Simulation; `resources` is the file URI of the resources folder.
    pub fn instantiate(
        &self,
        name: &str,
        guid: &str,
        resources: &str,
        log: Arc<LogSink>,
    ) -> Result<Fmi2Instance> {
        let cname = cstring(name)?;
        let cguid = cstring(guid)?;
        let cres = cstring(resources)?;
        let callbacks = Box::new(fmi2CallbackFunctions {
            logger: Some(logger_fn()),
            allocateMemory: Some(allocate),
            freeMemory: Some(free_memory),
            stepFinished: None,
            componentEnvironment: Arc::as_ptr(&log) as *mut c_void,
        });
        // SAFETY: every pointer is valid for the call; `callbacks` and `log` live as long as
        // the instance (they move into it), as FMI 2.0 requires.
        let c = unsafe {
            (self.fns.instantiate)(
                cname.as_ptr(),
                FMI2_CO_SIMULATION,
                cguid.as_ptr(),
                cres.as_ptr(),
                &*callbacks,
                0,
                0,
            )
        };
        if c.is_null() {
            let logged = log.take();
            return Err(Error::new(format!(
                "fmi2Instantiate returned NULL{}",
                if logged.is_empty() {
                    String::new()
                } else {
                    format!(" ({logged})")
                }
            ))
            .function("fmi2Instantiate"));
        }
        Ok(Fmi2Instance {
            c,
            fns: self.fns,
            _callbacks: callbacks,
            log,
            _lib: Arc::clone(&self.lib),
            strings: Vec::new(),
        })
    }
}

fn cstring(s: &str) -> Result<CString> {
    CString::new(s).map_err(|_| Error::new(format!("'{s}' contains a NUL character")))
}

/// One FMI 2.0 Co-Simulation instance; freed on drop.
pub struct Fmi2Instance {
    c: fmi2Component,
    fns: Functions,
    _callbacks: Box<fmi2CallbackFunctions>,
    /// What the instance logged.
    pub log: Arc<LogSink>,
    _lib: Arc<Library>,
    strings: Vec<CString>,
}

impl Fmi2Instance {
    /// fmi2SetupExperiment.
    pub fn setup(&mut self, start: f64, stop: Option<f64>) -> Status {
        // SAFETY: `c` is a live instance of this library.
        Status::from_c(unsafe {
            (self.fns.setup)(
                self.c,
                0,
                0.0,
                start,
                stop.is_some() as c_int,
                stop.unwrap_or(0.0),
            )
        })
    }
    /// fmi2EnterInitializationMode.
    pub fn enter_initialization(&mut self) -> Status {
        // SAFETY: `c` is a live instance.
        Status::from_c(unsafe { (self.fns.enter_init)(self.c) })
    }
    /// fmi2ExitInitializationMode.
    pub fn exit_initialization(&mut self) -> Status {
        // SAFETY: `c` is a live instance.
        Status::from_c(unsafe { (self.fns.exit_init)(self.c) })
    }
    /// fmi2Terminate.
    pub fn terminate(&mut self) -> Status {
        // SAFETY: `c` is a live instance.
        Status::from_c(unsafe { (self.fns.terminate)(self.c) })
    }
    /// fmi2DoStep.
    pub fn do_step(&mut self, t: f64, h: f64) -> Status {
        // SAFETY: `c` is a live instance.
        Status::from_c(unsafe { (self.fns.do_step)(self.c, t, h, 1) })
    }
    /// fmi2GetBooleanStatus(fmi2Terminated): has the FMU asked to end the simulation?
    pub fn terminated(&mut self) -> bool {
        let Some(f) = self.fns.get_boolean_status else {
            return false;
        };
        let mut v: fmi2Boolean = 0;
        // SAFETY: `c` is a live instance and `v` a valid out-pointer.
        let s = Status::from_c(unsafe { f(self.c, FMI2_TERMINATED, &mut v) });
        s.ok() && v != 0
    }
    /// fmi2GetReal.
    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Status {
        assert_eq!(vrs.len(), out.len());
        // SAFETY: both slices hold vrs.len() elements.
        Status::from_c(unsafe {
            (self.fns.get_real)(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr())
        })
    }
    /// fmi2SetReal.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        assert_eq!(vrs.len(), values.len());
        // SAFETY: both slices hold vrs.len() elements.
        Status::from_c(unsafe {
            (self.fns.set_real)(self.c, vrs.as_ptr(), vrs.len(), values.as_ptr())
        })
    }
    /// fmi2GetInteger (`boolean`: fmi2GetBoolean).
    pub fn get_int(&mut self, boolean: bool, vrs: &[u32], out: &mut [i32]) -> Status {
        assert_eq!(vrs.len(), out.len());
        let f = if boolean {
            self.fns.get_boolean
        } else {
            self.fns.get_integer
        };
        // SAFETY: both slices hold vrs.len() elements; fmi2Boolean is a C int like fmi2Integer.
        Status::from_c(unsafe { f(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) })
    }
    /// fmi2SetInteger (`boolean`: fmi2SetBoolean).
    pub fn set_int(&mut self, boolean: bool, vrs: &[u32], values: &[i32]) -> Status {
        assert_eq!(vrs.len(), values.len());
        let f = if boolean {
            self.fns.set_boolean
        } else {
            self.fns.set_integer
        };
        // SAFETY: both slices hold vrs.len() elements.
        Status::from_c(unsafe { f(self.c, vrs.as_ptr(), vrs.len(), values.as_ptr()) })
    }
    /// fmi2GetString.
    pub fn get_string(&mut self, vrs: &[u32], out: &mut Vec<String>) -> Status {
        let mut ptrs: Vec<fmi2String> = vec![std::ptr::null(); vrs.len()];
        // SAFETY: `ptrs` holds vrs.len() out-pointers; the FMU's strings are copied at once.
        let s = Status::from_c(unsafe {
            (self.fns.get_string)(self.c, vrs.as_ptr(), vrs.len(), ptrs.as_mut_ptr())
        });
        out.clear();
        // SAFETY: on success each pointer is NULL or a NUL-terminated string of the FMU.
        out.extend(ptrs.iter().map(|&p| unsafe { c_str(p) }));
        s
    }
    /// fmi2SetString.
    pub fn set_string(&mut self, vrs: &[u32], values: &[String]) -> Result<Status> {
        self.strings = values.iter().map(|v| cstring(v)).collect::<Result<_>>()?;
        let ptrs: Vec<*const c_char> = self.strings.iter().map(|s| s.as_ptr()).collect();
        // SAFETY: `ptrs` holds vrs.len() NUL-terminated strings alive for the call.
        Ok(Status::from_c(unsafe {
            (self.fns.set_string)(self.c, vrs.as_ptr(), vrs.len(), ptrs.as_ptr())
        }))
    }
}

impl Drop for Fmi2Instance {
    fn drop(&mut self) {
        // SAFETY: `c` is live and freed once; the library outlives it (Arc).
        unsafe { (self.fns.free)(self.c) }
    }
}

/// The logger FMI 2.0 declares C-variadic. Stable Rust cannot define a variadic function; the
/// FMU calls it with the five fixed arguments (its message already formatted), which on the
/// platforms' C ABIs this five-argument function receives exactly as a variadic one would.
unsafe extern "C" fn logger(
    env: fmi2ComponentEnvironment,
    instance: fmi2String,
    status: c_int,
    category: fmi2String,
    message: fmi2String,
) {
    // SAFETY: env is the LogSink given at instantiation; the strings are NUL-terminated or NULL.
    unsafe {
        log_to(env, || {
            format!(
                "{} [{}] {}: {}",
                c_str(instance),
                c_str(category),
                Status::from_c(status).name("fmi2"),
                c_str(message)
            )
        })
    }
}

fn logger_fn() -> fmi2CallbackLogger {
    type Fixed =
        unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2String, c_int, fmi2String, fmi2String);
    let f: Fixed = logger;
    // SAFETY: see `logger`: same fixed arguments (fmi2Status is a C int enum), called with no
    // variadic arguments.
    unsafe { std::mem::transmute::<Fixed, fmi2CallbackLogger>(f) }
}

unsafe extern "C" fn allocate(n: usize, size: usize) -> *mut c_void {
    // SAFETY: calloc with the FMU's arguments, as the standard's default allocator.
    unsafe { libc_calloc(n, size) }
}

unsafe extern "C" fn free_memory(p: *mut c_void) {
    // SAFETY: p came from `allocate` (calloc) or is NULL.
    unsafe { libc_free(p) }
}

extern "C" {
    #[link_name = "calloc"]
    fn libc_calloc(n: usize, size: usize) -> *mut c_void;
    #[link_name = "free"]
    fn libc_free(p: *mut c_void);
}
