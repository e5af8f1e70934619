//! What every exported function shares (FMI 3.0's too): the panic wall, the instance lookup,
//! the one mapping of results to a status with its log message, and the pointer-to-slice,
//! C-string and FMU-state-handle conversions. Uses `super::{types, logger}`, `crate::instance`,
//! `crate::error` and `crate::variables`.

use super::logger::CallbackLogger;
use super::types::{fmi2CallbackFunctions, fmi2Status, fmi2String, FMI2_CO_SIMULATION};
use crate::error::{Category, FmuError, FmuResult, Level};
use crate::instance::{FmiVersion, Instance, LogSink, Snapshot};
use crate::variables::guid;
use std::any::Any;
use std::ffi::{c_char, c_int, c_void, CStr};

/// The value an exported function returns when its body panicked.
pub(crate) trait PanicDefault {
    /// The fallback value.
    fn panic_default() -> Self;
}

impl PanicDefault for fmi2Status {
    /// A caught panic is a run-time exception: fmi2Fatal (FMI 2.0 §2.1.3).
    fn panic_default() -> Self {
        fmi2Status::Fatal
    }
}

impl PanicDefault for *mut c_void {
    /// Instantiate: no instance.
    fn panic_default() -> Self {
        std::ptr::null_mut()
    }
}

impl PanicDefault for *const c_char {
    /// GetVersion / GetTypesPlatform: no string.
    fn panic_default() -> Self {
        std::ptr::null()
    }
}

impl PanicDefault for () {
    /// FreeInstance: nothing.
    fn panic_default() -> Self {}
}

/// Runs an exported body with panics caught, so that no unwind crosses the C boundary.
/// `ffi_boundary!(F, { .. })` without an instance; `ffi_boundary!(c, F, { .. })` also marks the
/// instance behind `c` (fmi2Component or fmi3Instance) fatal and logs the panic. The fallback
/// comes from the return type (`PanicDefault`); `return` in the body returns from the function.
macro_rules! ffi_boundary {
    ($fname:expr, $body:block) => {
        match ::std::panic::catch_unwind(::std::panic::AssertUnwindSafe(|| $body)) {
            Ok(v) => v,
            Err(payload) => {
                $crate::fmi2::boundary::panic_caught(::std::ptr::null_mut(), $fname, payload);
                $crate::fmi2::boundary::PanicDefault::panic_default()
            }
        }
    };
    ($c:expr, $fname:expr, $body:block) => {
        match ::std::panic::catch_unwind(::std::panic::AssertUnwindSafe(|| $body)) {
            Ok(v) => v,
            Err(payload) => {
                $crate::fmi2::boundary::panic_caught($c, $fname, payload);
                $crate::fmi2::boundary::PanicDefault::panic_default()
            }
        }
    };
}
pub(crate) use ffi_boundary;

/// `&mut Instance` from the handle, or `return $null` for NULL (nothing to log through);
/// traces the call under logAll.
macro_rules! instance_or {
    ($c:expr, $fname:expr, $null:expr) => {
        // SAFETY: a non-NULL handle is the pointer Instantiate returned and the importer has
        // not freed (FMI 2.0 §2.1.5, FMI 3.0 §2.2.3); FMI forbids concurrent calls on one
        // instance, so this is the only reference to it while the call runs.
        match unsafe { $crate::fmi2::boundary::instance_mut($c) } {
            Some(inst) => {
                $crate::fmi2::boundary::trace(inst, $fname);
                inst
            }
            None => return $null,
        }
    };
}
pub(crate) use instance_or;

/// Marks the instance fatal after a caught panic and logs the payload (when there is an
/// instance to log through).
pub(crate) fn panic_caught(c: *mut c_void, fname: &str, payload: Box<dyn Any + Send>) {
    let what = payload
        .downcast_ref::<&str>()
        .copied()
        .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("(no message)");
    // SAFETY: as in `instance_or!`; the reference the panicking body held ended with the unwind.
    let Some(inst) = (unsafe { instance_mut(c) }) else {
        return;
    };
    inst.set_fatal();
    let message = format!(
        "{fname}: internal error (Rust panic: {what}); the instance is unusable, only {}FreeInstance is allowed",
        inst.version().prefix()
    );
    // a second panic while logging must not escape either
    let _ = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        inst.log(Level::Fatal, Category::Error, &message)
    }));
}

/// The instance behind a handle, None for NULL.
///
/// # Safety
/// `c` is NULL or a pointer returned by Instantiate and not yet freed, with no other reference
/// to the instance alive.
pub(crate) unsafe fn instance_mut<'a>(c: *mut c_void) -> Option<&'a mut Instance> {
    // SAFETY: the caller's contract; `as_mut` maps NULL to None.
    unsafe { c.cast::<Instance>().as_mut() }
}

/// Logs the call's name under logAll.
pub(crate) fn trace(inst: &Instance, fname: &str) {
    if inst.wants(Category::All) {
        inst.log(Level::Ok, Category::All, fname);
    }
}

/// Logs a refused call's error, led by the FMI function's name, and returns its level: every
/// non-OK status comes with one message.
pub(crate) fn refused(e: FmuError, inst: &Instance, fname: &str) -> Level {
    inst.log(e.level, Category::Error, &format!("{fname}: {}", e.message));
    e.level
}

/// The one mapping of an instance-layer result to `fmi2Status`.
pub(crate) fn status(r: FmuResult<()>, inst: &Instance, fname: &str) -> fmi2Status {
    match r {
        Ok(()) => fmi2Status::OK,
        Err(e) => refused(e, inst, fname).into(),
    }
}

/// Checks what `from_raw_parts` needs: non-NULL, aligned, a possible length.
fn check_array<T>(p: *const T, n: usize, what: &str) -> FmuResult<()> {
    if p.is_null() {
        return Err(FmuError::error(format!(
            "argument {what} is NULL but {n} elements were announced"
        )));
    }
    if !p.is_aligned() || n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return Err(FmuError::error(format!(
            "argument {what} is misaligned or of impossible length {n}"
        )));
    }
    Ok(())
}

/// An input array: `(NULL, 0)` is legal FMI (and `from_raw_parts(NULL, 0)` would be UB);
/// NULL with `n > 0` is refused with a message naming the argument.
///
/// # Safety
/// A non-NULL `p` points to `n` initialised elements valid and unmodified for `'a`.
pub(crate) unsafe fn in_slice<'a, T>(p: *const T, n: usize, what: &str) -> FmuResult<&'a [T]> {
    if n == 0 {
        return Ok(&[]);
    }
    check_array(p, n, what)?;
    // SAFETY: non-NULL, aligned, size checked; the caller guarantees n valid elements.
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// An output array, with the same rules as `in_slice`.
///
/// # Safety
/// A non-NULL `p` points to `n` writable elements, aliased by nothing else, for `'a`.
pub(crate) unsafe fn out_slice<'a, T>(p: *mut T, n: usize, what: &str) -> FmuResult<&'a mut [T]> {
    if n == 0 {
        return Ok(&mut []);
    }
    check_array(p, n, what)?;
    // SAFETY: non-NULL, aligned, size checked; the caller guarantees n writable elements.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// A single output value (`size_t* size`, `fmi2Real* value`, …); NULL is refused.
///
/// # Safety
/// A non-NULL `p` is valid for writes and not aliased for `'a`.
pub(crate) unsafe fn out_ref<'a, T>(p: *mut T, what: &str) -> FmuResult<&'a mut T> {
    check_array(p, 1, what)?;
    // SAFETY: non-NULL and aligned; the caller guarantees it is writable.
    Ok(unsafe { &mut *p })
}

/// A C string argument as UTF-8 (NULL and invalid UTF-8 are refused).
///
/// # Safety
/// A non-NULL `p` points to a NUL-terminated string valid for `'a`.
pub(crate) unsafe fn c_str<'a>(p: *const c_char, what: &str) -> FmuResult<&'a str> {
    if p.is_null() {
        return Err(FmuError::error(format!("argument {what} is NULL")));
    }
    // SAFETY: non-NULL; the caller guarantees NUL termination and lifetime.
    let s = unsafe { CStr::from_ptr(p) };
    s.to_str()
        .map_err(|_| FmuError::error(format!("argument {what} is not valid UTF-8")))
}

/// An array of C strings (`categories[]` of SetDebugLogging), `(NULL, 0)` legal.
///
/// # Safety
/// As `in_slice`, and each non-NULL element is a NUL-terminated string valid for `'a`.
pub(crate) unsafe fn c_str_array<'a>(
    p: *const *const c_char,
    n: usize,
    what: &str,
) -> FmuResult<Vec<&'a str>> {
    // SAFETY: forwarded contract.
    let ptrs = unsafe { in_slice(p, n, what)? };
    ptrs.iter()
        .enumerate()
        // SAFETY: forwarded contract for each element.
        .map(|(i, &s)| unsafe { c_str(s, &format!("{what}[{i}]")) })
        .collect()
}

/// The snapshot behind an FMU state handle (NULL refused).
///
/// # Safety
/// A non-NULL `state` was made by `store_state` of this library and not yet freed.
pub(crate) unsafe fn state_ref<'a>(state: *mut c_void) -> FmuResult<&'a Snapshot> {
    if state.is_null() {
        return Err(FmuError::error("argument FMUstate is NULL"));
    }
    // SAFETY: the caller's contract: a live Box<Snapshot> made by `store_state`.
    Ok(unsafe { &*state.cast::<Snapshot>() })
}

/// Stores a snapshot into `*state`: overwrites the state it points to (a non-NULL `*state` is
/// a state this FMU returned earlier), else allocates a new one.
///
/// # Safety
/// `state` is NULL (refused) or writable; a non-NULL `*state` is a live state of this library.
pub(crate) unsafe fn store_state(state: *mut *mut c_void, snapshot: Snapshot) -> FmuResult<()> {
    // SAFETY: forwarded contract.
    let slot = unsafe { out_ref(state, "FMUstate")? };
    if slot.is_null() {
        *slot = Box::into_raw(Box::new(snapshot)).cast();
    } else {
        // SAFETY: a live Box<Snapshot> made by this function earlier (caller's contract).
        unsafe { *slot.cast::<Snapshot>() = snapshot };
    }
    Ok(())
}

/// Releases `*state` and sets it to NULL; NULL `state` or NULL `*state` is a no-op.
///
/// # Safety
/// As `store_state`.
pub(crate) unsafe fn free_state(state: *mut *mut c_void) {
    // SAFETY: forwarded contract; `as_mut` maps NULL to None.
    if let Some(slot) = unsafe { state.as_mut() } {
        if !slot.is_null() {
            // SAFETY: a live Box<Snapshot> made by `store_state`, released once: the handle is
            // set to NULL right after.
            drop(unsafe { Box::from_raw(slot.cast::<Snapshot>()) });
            *slot = std::ptr::null_mut();
        }
    }
}

/// Copies a state's serialized bytes into the importer's buffer, which must be large enough
/// (`size_fn` names the function that tells the size).
pub(crate) fn copy_serialized(
    inst: &Instance,
    s: &Snapshot,
    buf: &mut [u8],
    size_fn: &str,
) -> FmuResult<()> {
    let bytes = inst.serialize(s)?;
    let size = buf.len();
    let dst = buf.get_mut(..bytes.len()).ok_or_else(|| {
        FmuError::error(format!(
            "size {size} is smaller than the serialized state ({} bytes, see {size_fn})",
            bytes.len()
        ))
    })?;
    dst.copy_from_slice(&bytes);
    Ok(())
}

/// The name and GUID checks shared by both versions' instantiation: the instance name (not
/// empty) and the GUID / instantiationToken of this model.
///
/// # Safety
/// `name` and `token` are NULL or NUL-terminated strings.
pub(crate) unsafe fn checked_name<'a>(
    name: *const c_char,
    token: *const c_char,
    token_arg: &str,
) -> FmuResult<&'a str> {
    // SAFETY: caller's contract for the C strings.
    let name = unsafe { c_str(name, "instanceName") }?;
    if name.is_empty() {
        return Err(FmuError::error("instanceName is empty"));
    }
    // SAFETY: caller's contract for the C strings.
    let token = unsafe { c_str(token, token_arg) }?;
    if token != guid() {
        return Err(FmuError::error(format!(
            "{token_arg} \"{token}\" is not this model's {} (modelDescription.xml and binary from different builds?)",
            guid()
        )));
    }
    Ok(name)
}

/// fmi2Instantiate without the raw-pointer return: validates every argument, logging the
/// reason for a refusal through the importer's logger when there is one.
///
/// # Safety
/// Each pointer is NULL or valid as FMI 2.0 §2.1.5 requires.
pub(crate) unsafe fn instantiate(
    instance_name: fmi2String,
    fmu_type: c_int,
    guid: fmi2String,
    functions: *const fmi2CallbackFunctions,
    logging_on: bool,
) -> Option<Instance> {
    const F: &str = "fmi2Instantiate";
    // SAFETY: NULL or a valid callback struct (caller's contract); copied, not kept.
    let functions = unsafe { functions.as_ref() }.copied()?;
    let callback = functions.logger?;
    // SAFETY: caller's contract for the C strings.
    let shown = unsafe { c_str(instance_name, "instanceName") }.unwrap_or("");
    let logger = CallbackLogger::new(callback, functions.componentEnvironment, shown);
    let checked = match fmu_type {
        // SAFETY: caller's contract for the C strings.
        FMI2_CO_SIMULATION => unsafe { checked_name(instance_name, guid, "fmuGUID") },
        0 => Err(FmuError::error(
            "fmuType fmi2ModelExchange is not supported: this FMU implements Co-Simulation only",
        )),
        t => Err(FmuError::error(format!(
            "invalid fmuType {t} (fmi2ModelExchange = 0, fmi2CoSimulation = 1)"
        ))),
    };
    match checked {
        Ok(_) => {
            let inst = Instance::new(Box::new(logger), logging_on, FmiVersion::V2);
            trace(&inst, F);
            Some(inst)
        }
        Err(e) => {
            logger.log(e.level, Category::Error, &format!("{F}: {}", e.message));
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    /// A LogSink that keeps the messages.
    struct Keep(Arc<Mutex<Vec<String>>>);

    impl LogSink for Keep {
        fn log(&self, _: Level, _: Category, message: &str) {
            self.0.lock().unwrap().push(message.to_string());
        }
    }

    #[test]
    fn a_panic_is_caught_logged_and_leaves_the_instance_fatal() {
        let log = Arc::new(Mutex::new(Vec::new()));
        let inst = Instance::new(Box::new(Keep(log.clone())), false, FmiVersion::V2);
        let c: *mut c_void = Box::into_raw(Box::new(inst)).cast();
        let st: fmi2Status = ffi_boundary!(c, "fmi2DoStep", {
            if !c.is_null() {
                panic!("boom");
            }
            fmi2Status::OK
        });
        assert_eq!(st, fmi2Status::Fatal);
        // SAFETY: c is the live Box made above; no other reference exists.
        let inst = unsafe { instance_mut(c) }.unwrap();
        let e = inst.allowed(crate::instance::Call::Get).unwrap_err();
        assert!(e.message.contains("only fmi2FreeInstance is allowed"));
        let msgs = log.lock().unwrap().clone();
        assert_eq!(msgs.len(), 1);
        assert!(msgs[0].starts_with("fmi2DoStep: internal error (Rust panic: boom)"));
        // SAFETY: the Box made above, released once.
        drop(unsafe { Box::from_raw(c.cast::<Instance>()) });
        // without an instance the fallback is returned all the same
        let p: *const c_char = ffi_boundary!("fmi2GetVersion", { panic!("no instance") });
        assert!(p.is_null());
    }

    #[test]
    fn null_with_a_count_is_refused_and_null_with_zero_is_empty() {
        // SAFETY: NULL pointers are never dereferenced by these helpers.
        unsafe {
            assert_eq!(
                in_slice::<u32>(std::ptr::null(), 0, "vr[]").unwrap(),
                &[] as &[u32]
            );
            let e = in_slice::<u32>(std::ptr::null(), 3, "vr[]").unwrap_err();
            assert!(e.message.contains("argument vr[] is NULL but 3 elements"));
            assert!(out_slice::<f64>(std::ptr::null_mut(), 1, "value[]").is_err());
            assert!(out_ref::<usize>(std::ptr::null_mut(), "size").is_err());
            assert!(c_str(std::ptr::null(), "instanceName").is_err());
        }
    }
}
