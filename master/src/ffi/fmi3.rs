//! FMI 3.0 Co-Simulation through the C API: the functions resolved once per library and an
//! instance whose safe methods wrap `fmi3InstantiateCoSimulation` … `fmi3FreeInstance`, with
//! the getters and setters of every numeric type, Boolean and String. Instantiated without
//! event mode and without early return (a fixed-step master). Uses fmi_shared's fmi3 types,
//! ffi/mod.rs and error.rs.

use super::{c_str, log_to, Library, LogSink, Status};
use crate::error::{Error, Result};
use crate::model_description::VarType;
use fmi_shared::fmi3::{
    fmi3Boolean, fmi3Float64, fmi3Instance, fmi3InstanceEnvironment, fmi3String, fmi3ValueReference,
};
use std::ffi::{c_char, c_int, c_void, CString};
use std::sync::Arc;

type Logger = unsafe extern "C" fn(fmi3InstanceEnvironment, c_int, fmi3String, fmi3String);
type Instantiate = unsafe extern "C" fn(
    fmi3String,
    fmi3String,
    fmi3String,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    *const fmi3ValueReference,
    usize,
    fmi3InstanceEnvironment,
    Option<Logger>,
    *const c_void,
) -> fmi3Instance;
type Free = unsafe extern "C" fn(fmi3Instance);
type EnterInit = unsafe extern "C" fn(
    fmi3Instance,
    fmi3Boolean,
    fmi3Float64,
    fmi3Float64,
    fmi3Boolean,
    fmi3Float64,
) -> c_int;
type Plain = unsafe extern "C" fn(fmi3Instance) -> c_int;
type DoStep = unsafe extern "C" fn(
    fmi3Instance,
    fmi3Float64,
    fmi3Float64,
    fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Float64,
) -> c_int;
type Get<T> =
    unsafe extern "C" fn(fmi3Instance, *const fmi3ValueReference, usize, *mut T, usize) -> c_int;
type Set<T> =
    unsafe extern "C" fn(fmi3Instance, *const fmi3ValueReference, usize, *const T, usize) -> c_int;

/// A getter and a setter of one type, if the library exports them.
#[derive(Clone, Copy)]
struct Pair<T: 'static> {
    get: Option<Get<T>>,
    set: Option<Set<T>>,
}

fn pair<T>(lib: &Library, ty: &str) -> Pair<T> {
    Pair {
        get: lib.symbol(&format!("fmi3Get{ty}")),
        set: lib.symbol(&format!("fmi3Set{ty}")),
    }
}

#[derive(Clone, Copy)]
struct Functions {
    instantiate: Instantiate,
    free: Free,
    enter_init: EnterInit,
    exit_init: Plain,
    terminate: Plain,
    do_step: DoStep,
    f64: Pair<f64>,
    f32: Pair<f32>,
    i8: Pair<i8>,
    u8: Pair<u8>,
    i16: Pair<i16>,
    u16: Pair<u16>,
    i32: Pair<i32>,
    u32: Pair<u32>,
    i64: Pair<i64>,
    u64: Pair<u64>,
    boolean: Pair<fmi3Boolean>,
    string: Pair<fmi3String>,
}

/// A loaded FMI 3.0 library.
pub struct Fmi3Library {
    fns: Functions,
    lib: Arc<Library>,
}

/// What fmi3DoStep reported besides its status.
#[derive(Debug, Clone, Copy, Default)]
pub struct StepReport {
    /// terminateSimulation.
    pub terminate: bool,
    /// eventHandlingNeeded.
    pub event: bool,
}

impl Fmi3Library {
    /// Resolves the functions of `lib`.
    pub fn new(lib: Library) -> Result<Fmi3Library> {
        let fns = Functions {
            instantiate: lib.require("fmi3InstantiateCoSimulation")?,
            free: lib.require("fmi3FreeInstance")?,
            enter_init: lib.require("fmi3EnterInitializationMode")?,
            exit_init: lib.require("fmi3ExitInitializationMode")?,
            terminate: lib.require("fmi3Terminate")?,
            do_step: lib.require("fmi3DoStep")?,
            f64: pair(&lib, "Float64"),
            f32: pair(&lib, "Float32"),
            i8: pair(&lib, "Int8"),
            u8: pair(&lib, "UInt8"),
            i16: pair(&lib, "Int16"),
            u16: pair(&lib, "UInt16"),
            i32: pair(&lib, "Int32"),
            u32: pair(&lib, "UInt32"),
            i64: pair(&lib, "Int64"),
            u64: pair(&lib, "UInt64"),
            boolean: pair(&lib, "Boolean"),
            string: pair(&lib, "String"),
        };
        Ok(Fmi3Library {
            fns,
            lib: Arc::new(lib),
        })
    }

    /// `fmi3InstantiateCoSimulation`; `resources` is the resources folder's path with a
    /// trailing separator.
    pub fn instantiate(
        &self,
        name: &str,
        token: &str,
        resources: &str,
        log: Arc<LogSink>,
    ) -> Result<Fmi3Instance> {
        let cname = cstring(name)?;
        let ctoken = cstring(token)?;
        let cres = cstring(resources)?;
        // SAFETY: every pointer is valid for the call; `log` lives as long as the instance.
        let c = unsafe {
            (self.fns.instantiate)(
                cname.as_ptr(),
                ctoken.as_ptr(),
                cres.as_ptr(),
                0,
                0,
                0,
                0,
                std::ptr::null(),
                0,
                Arc::as_ptr(&log) as *mut c_void,
                Some(logger),
                std::ptr::null(),
            )
        };
        if c.is_null() {
            let logged = log.take();
            return Err(Error::new(format!(
                "fmi3InstantiateCoSimulation returned NULL{}",
                if logged.is_empty() {
                    String::new()
                } else {
                    format!(" ({logged})")
                }
            ))
            .function("fmi3InstantiateCoSimulation"));
        }
        Ok(Fmi3Instance {
            c,
            fns: self.fns,
            log,
            _lib: Arc::clone(&self.lib),
        })
    }
}

fn cstring(s: &str) -> Result<CString> {
    CString::new(s).map_err(|_| Error::new(format!("'{s}' contains a NUL character")))
}

/// One FMI 3.0 Co-Simulation instance; freed on drop.
pub struct Fmi3Instance {
    c: fmi3Instance,
    fns: Functions,
    /// What the instance logged.
    pub log: Arc<LogSink>,
    _lib: Arc<Library>,
}

fn missing(ty: VarType, get: bool) -> Error {
    let f = format!("fmi3{}{ty:?}", if get { "Get" } else { "Set" });
    Error::new(format!("the FMU's library does not export {f}")).function(f)
}

/// Calls getter `g` into a buffer of `T`, then converts each value with `conv`.
fn get_as<T: Copy + Default, U>(
    c: fmi3Instance,
    g: Option<Get<T>>,
    ty: VarType,
    vrs: &[u32],
    out: &mut [U],
    conv: impl Fn(T) -> U,
) -> Result<Status> {
    let g = g.ok_or_else(|| missing(ty, true))?;
    let mut buf = vec![T::default(); out.len()];
    // SAFETY: `vrs` holds nvr references and `buf` out.len() values (the variables' total size).
    let s = Status::from_c(unsafe { g(c, vrs.as_ptr(), vrs.len(), buf.as_mut_ptr(), buf.len()) });
    for (o, b) in out.iter_mut().zip(buf) {
        *o = conv(b);
    }
    Ok(s)
}

/// Converts the values with `conv`, then calls setter `f`.
fn set_as<T, U: Copy>(
    c: fmi3Instance,
    f: Option<Set<T>>,
    ty: VarType,
    vrs: &[u32],
    values: &[U],
    conv: impl Fn(U) -> T,
) -> Result<Status> {
    let f = f.ok_or_else(|| missing(ty, false))?;
    let buf: Vec<T> = values.iter().map(|&v| conv(v)).collect();
    // SAFETY: `vrs` holds nvr references and `buf` values.len() values.
    Ok(Status::from_c(unsafe {
        f(c, vrs.as_ptr(), vrs.len(), buf.as_ptr(), buf.len())
    }))
}

impl Fmi3Instance {
    /// fmi3EnterInitializationMode (no tolerance).
    pub fn enter_initialization(&mut self, start: f64, stop: Option<f64>) -> Status {
        // SAFETY: `c` is a live instance of this library.
        Status::from_c(unsafe {
            (self.fns.enter_init)(
                self.c,
                0,
                0.0,
                start,
                stop.is_some() as u8,
                stop.unwrap_or(0.0),
            )
        })
    }
    /// fmi3ExitInitializationMode.
    pub fn exit_initialization(&mut self) -> Status {
        // SAFETY: `c` is a live instance.
        Status::from_c(unsafe { (self.fns.exit_init)(self.c) })
    }
    /// fmi3Terminate.
    pub fn terminate(&mut self) -> Status {
        // SAFETY: `c` is a live instance.
        Status::from_c(unsafe { (self.fns.terminate)(self.c) })
    }
    /// fmi3DoStep.
    pub fn do_step(&mut self, t: f64, h: f64) -> (Status, StepReport) {
        let (mut event, mut terminate, mut early, mut last) = (0u8, 0u8, 0u8, 0.0f64);
        // SAFETY: `c` is a live instance; the out-pointers are valid.
        let s = Status::from_c(unsafe {
            (self.fns.do_step)(
                self.c,
                t,
                h,
                1,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        });
        (
            s,
            StepReport {
                terminate: terminate != 0,
                event: event != 0,
            },
        )
    }
    /// fmi3GetFloat64 (the lean path of every step: no buffer).
    pub fn get_f64(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<Status> {
        let g = self
            .fns
            .f64
            .get
            .ok_or_else(|| missing(VarType::Float64, true))?;
        // SAFETY: `vrs` holds nvr references and `out` the variables' total size.
        Ok(Status::from_c(unsafe {
            g(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), out.len())
        }))
    }
    /// fmi3SetFloat64.
    pub fn set_f64(&mut self, vrs: &[u32], values: &[f64]) -> Result<Status> {
        let f = self
            .fns
            .f64
            .set
            .ok_or_else(|| missing(VarType::Float64, false))?;
        // SAFETY: `vrs` holds nvr references and `values` the variables' total size.
        Ok(Status::from_c(unsafe {
            f(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        }))
    }
    /// The getter of a Real type other than Float64 (Float32), as f64.
    pub fn get_real(&mut self, ty: VarType, vrs: &[u32], out: &mut [f64]) -> Result<Status> {
        match ty {
            VarType::Float32 => get_as(self.c, self.fns.f32.get, ty, vrs, out, f64::from),
            _ => self.get_f64(vrs, out),
        }
    }
    /// The setter of a Real type, from f64 (Float32 rounds).
    pub fn set_real(&mut self, ty: VarType, vrs: &[u32], values: &[f64]) -> Result<Status> {
        match ty {
            VarType::Float32 => set_as(self.c, self.fns.f32.set, ty, vrs, values, |v| v as f32),
            _ => self.set_f64(vrs, values),
        }
    }
    /// The getter of an integer type (or Boolean as 0/1), as i64 (UInt64 as its bits).
    pub fn get_int(&mut self, ty: VarType, vrs: &[u32], out: &mut [i64]) -> Result<Status> {
        let c = self.c;
        let f = &self.fns;
        match ty {
            VarType::Int8 => get_as(c, f.i8.get, ty, vrs, out, i64::from),
            VarType::UInt8 => get_as(c, f.u8.get, ty, vrs, out, i64::from),
            VarType::Int16 => get_as(c, f.i16.get, ty, vrs, out, i64::from),
            VarType::UInt16 => get_as(c, f.u16.get, ty, vrs, out, i64::from),
            VarType::Int32 => get_as(c, f.i32.get, ty, vrs, out, i64::from),
            VarType::UInt32 => get_as(c, f.u32.get, ty, vrs, out, i64::from),
            VarType::UInt64 => get_as(c, f.u64.get, ty, vrs, out, |v| v as i64),
            VarType::Boolean => get_as(c, f.boolean.get, ty, vrs, out, |v| i64::from(v != 0)),
            _ => get_as(c, f.i64.get, VarType::Int64, vrs, out, |v| v),
        }
    }
    /// The setter of an integer type (or Boolean, non-zero = true), from i64; a value outside
    /// the type's range is an error naming it.
    pub fn set_int(&mut self, ty: VarType, vrs: &[u32], values: &[i64]) -> Result<Status> {
        fn fit<T: TryFrom<i64>>(ty: VarType, values: &[i64]) -> Result<()> {
            match values.iter().find(|&&v| T::try_from(v).is_err()) {
                Some(v) => Err(Error::new(format!("{v} is out of the range of {ty:?}"))),
                None => Ok(()),
            }
        }
        let c = self.c;
        let f = &self.fns;
        match ty {
            VarType::Int8 => fit::<i8>(ty, values)
                .and_then(|_| set_as(c, f.i8.set, ty, vrs, values, |v| v as i8)),
            VarType::UInt8 => fit::<u8>(ty, values)
                .and_then(|_| set_as(c, f.u8.set, ty, vrs, values, |v| v as u8)),
            VarType::Int16 => fit::<i16>(ty, values)
                .and_then(|_| set_as(c, f.i16.set, ty, vrs, values, |v| v as i16)),
            VarType::UInt16 => fit::<u16>(ty, values)
                .and_then(|_| set_as(c, f.u16.set, ty, vrs, values, |v| v as u16)),
            VarType::Int32 => fit::<i32>(ty, values)
                .and_then(|_| set_as(c, f.i32.set, ty, vrs, values, |v| v as i32)),
            VarType::UInt32 => fit::<u32>(ty, values)
                .and_then(|_| set_as(c, f.u32.set, ty, vrs, values, |v| v as u32)),
            // UInt64 travels as its bits in an i64
            VarType::UInt64 => set_as(c, f.u64.set, ty, vrs, values, |v| v as u64),
            VarType::Boolean => set_as(c, f.boolean.set, ty, vrs, values, |v| u8::from(v != 0)),
            _ => set_as(c, f.i64.set, VarType::Int64, vrs, values, |v| v),
        }
    }
    /// fmi3GetString.
    pub fn get_string(&mut self, vrs: &[u32], out: &mut Vec<String>) -> Result<Status> {
        let g = self
            .fns
            .string
            .get
            .ok_or_else(|| missing(VarType::String, true))?;
        let mut ptrs: Vec<fmi3String> = vec![std::ptr::null(); out.len().max(vrs.len())];
        // SAFETY: `ptrs` holds the variables' total number of out-pointers.
        let s = Status::from_c(unsafe {
            g(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                ptrs.as_mut_ptr(),
                ptrs.len(),
            )
        });
        out.clear();
        // SAFETY: each pointer is NULL or a NUL-terminated string of the FMU, copied at once.
        out.extend(ptrs.iter().map(|&p| unsafe { c_str(p) }));
        Ok(s)
    }
    /// fmi3SetString.
    pub fn set_string(&mut self, vrs: &[u32], values: &[String]) -> Result<Status> {
        let f = self
            .fns
            .string
            .set
            .ok_or_else(|| missing(VarType::String, false))?;
        let owned: Vec<CString> = values.iter().map(|v| cstring(v)).collect::<Result<_>>()?;
        let ptrs: Vec<*const c_char> = owned.iter().map(|s| s.as_ptr()).collect();
        // SAFETY: `ptrs` holds values.len() NUL-terminated strings alive for the call.
        Ok(Status::from_c(unsafe {
            f(self.c, vrs.as_ptr(), vrs.len(), ptrs.as_ptr(), ptrs.len())
        }))
    }
}

impl Drop for Fmi3Instance {
    fn drop(&mut self) {
        // SAFETY: `c` is live and freed once; the library outlives it (Arc).
        unsafe { (self.fns.free)(self.c) }
    }
}

unsafe extern "C" fn logger(
    env: fmi3InstanceEnvironment,
    status: c_int,
    category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: env is the LogSink given at instantiation; the strings are NUL-terminated or NULL.
    unsafe {
        log_to(env, || {
            format!(
                "[{}] {}: {}",
                c_str(category),
                Status::from_c(status).name("fmi3"),
                c_str(message)
            )
        })
    }
}
