//! What every exported function shares: the panic wrapper, the instance lookup with its state
//! check, the one mapping of results to `fmi2Status`, and the pointer-to-slice conversions.
//!
//! Uses the FMI 2.0 C types and logger, the instance, the model's snapshot and GUIDs, and the error
//! mapping; `exports` (and fmi3's boundary) use it.

use super::logger::CallbackLogger;
use super::types::{
    fmi2CallbackFunctions, fmi2Component, fmi2FMUstate, fmi2Status, fmi2String, fmi2Type,
};
use crate::error::{Category, FmuError, FmuResult, Level};
use crate::instance::{LogSink, ModelInstance};
use crate::model::snapshot::Snapshot;
use crate::model::variables::variant_by_guid;
use libc::{c_char, c_void};
use std::any::Any;
use std::ffi::CStr;

/// The value an exported function returns when its body panicked (rustls-ffi `PanicOrDefault`).
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
    /// fmi2Instantiate: no instance.
    fn panic_default() -> Self {
        std::ptr::null_mut()
    }
}

impl PanicDefault for *const c_char {
    /// fmi2GetVersion / fmi2GetTypesPlatform: no string.
    fn panic_default() -> Self {
        std::ptr::null()
    }
}

impl PanicDefault for () {
    /// fmi2FreeInstance: nothing.
    fn panic_default() -> Self {}
}

/// Runs an exported body with panics caught, so that no unwind crosses the C boundary.
///
/// `ffi_boundary!(F, { .. })` for functions without an instance; `ffi_boundary!(c, F, { .. })`
/// (an fmi2Component or fmi3Instance: both are the boxed `ModelInstance`)
/// marks the instance behind `c` Fatal and logs the panic through its logger. The fallback
/// value comes from the return type (`PanicDefault`). `return` inside the body returns from
/// the exported function with that value.
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
/// For the FMI 3.0 boundary, which shares this panic wall (`crate::fmi3`).
pub(crate) use ffi_boundary;

/// `&mut ModelInstance` from the component, or `return fmi2Error` for NULL (nothing to log
/// through). Traces the call under logAll. With a `Call`, also checks that the call is allowed
/// in the current state (for the functions whose instance method does not check it).
macro_rules! instance {
    ($c:expr, $fname:expr) => {
        // SAFETY: a non-NULL component is the pointer fmi2Instantiate returned and that the
        // importer has not freed (FMI 2.0 §2.1.5); FMI forbids concurrent calls on one
        // instance, so this is the only reference to it while the call runs.
        match unsafe { $crate::fmi2::boundary::instance_mut($c) } {
            Some(inst) => {
                $crate::fmi2::boundary::trace(inst, $fname);
                inst
            }
            None => return $crate::fmi2::types::fmi2Status::Error,
        }
    };
    ($c:expr, $fname:expr, $call:expr) => {{
        let inst = instance!($c, $fname);
        if let Err(e) = inst.allowed($call) {
            return $crate::fmi2::boundary::ToStatus::to_status(Err::<(), _>(e), inst, $fname);
        }
        inst
    }};
}

/// Marks the instance Fatal after a caught panic and logs the payload (when there is an
/// instance to log through).
pub(crate) fn panic_caught(c: fmi2Component, fname: &str, payload: Box<dyn Any + Send>) {
    let what = payload
        .downcast_ref::<&str>()
        .copied()
        .or_else(|| payload.downcast_ref::<String>().map(String::as_str))
        .unwrap_or("(no message)");
    // SAFETY: as in `instance!`; the reference taken by the panicking body ended with the unwind.
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

/// The instance behind a component, None for NULL.
///
/// # Safety
/// `c` is NULL or a pointer returned by fmi2Instantiate and not yet freed, with no other
/// reference to the instance alive.
pub(crate) unsafe fn instance_mut<'a>(c: fmi2Component) -> Option<&'a mut ModelInstance> {
    // SAFETY: the caller's contract above; `as_mut` maps NULL to None.
    unsafe { c.cast::<ModelInstance>().as_mut() }
}

/// Logs the call's name under logAll (cheap check first: nothing is formatted otherwise).
#[inline]
pub(crate) fn trace(inst: &ModelInstance, fname: &str) {
    if inst.wants(Category::All) {
        inst.log(Level::Ok, Category::All, fname);
    }
}

/// The one mapping of an instance-layer result to `fmi2Status`; the error is logged once,
/// its message led by the name of the FMI function (`fname`) that answers it.
pub(crate) trait ToStatus {
    /// Logs a non-OK outcome through the instance and returns its status.
    fn to_status(self, inst: &mut ModelInstance, fname: &str) -> fmi2Status;
}

impl ToStatus for FmuResult<()> {
    #[inline]
    fn to_status(self, inst: &mut ModelInstance, fname: &str) -> fmi2Status {
        match self {
            Ok(()) => fmi2Status::OK,
            Err(e) => refused(e, inst, fname),
        }
    }
}

/// Logs a refused call's error (off the path of the calls that succeed) and returns its status.
#[cold]
#[inline(never)]
fn refused(e: FmuError, inst: &mut ModelInstance, fname: &str) -> fmi2Status {
    inst.log(e.level, e.category(), &format!("{fname}: {}", e.message));
    e.level.into()
}

fn null_error(what: &str, n: usize) -> FmuError {
    FmuError::error(format!(
        "argument {what} is NULL but {n} elements were announced"
    ))
}

/// Checks what `from_raw_parts` needs: non-NULL, alignment and a sane total size.
#[inline]
fn check_array<T>(p: *const T, n: usize, what: &str) -> FmuResult<()> {
    if !p.is_null() && p.is_aligned() && n <= isize::MAX as usize / std::mem::size_of::<T>().max(1)
    {
        return Ok(());
    }
    Err(array_error(p, n, what))
}

/// The error `check_array` reports (off the per-step path).
#[cold]
#[inline(never)]
fn array_error<T>(p: *const T, n: usize, what: &str) -> FmuError {
    if p.is_null() {
        null_error(what, n)
    } else if !p.is_aligned() {
        FmuError::error(format!(
            "argument {what} is not aligned for its element type"
        ))
    } else {
        FmuError::error(format!("argument {what} has an impossible length {n}"))
    }
}

/// An input array: `(NULL, 0)` is legal FMI (and `from_raw_parts(NULL, 0)` would be UB);
/// NULL with `n > 0` is refused with a message naming the argument.
///
/// # Safety
/// A non-NULL `p` points to `n` initialised elements that stay valid and unmodified for `'a`.
#[inline]
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
/// A non-NULL `p` points to `n` writable elements, not aliased by anything else, for `'a`.
#[inline]
pub(crate) unsafe fn out_slice<'a, T>(p: *mut T, n: usize, what: &str) -> FmuResult<&'a mut [T]> {
    if n == 0 {
        return Ok(&mut []);
    }
    check_array(p, n, what)?;
    // SAFETY: non-NULL, aligned, size checked; the caller guarantees n writable elements.
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// `vr[]` and `value[]` of an fmi2Get* call.
///
/// # Safety
/// As `in_slice` for `vr` and `out_slice` for `value`, both of length `n`.
pub(crate) unsafe fn get_arrays<'a, V, T>(
    vr: *const V,
    n: usize,
    value: *mut T,
) -> FmuResult<(&'a [V], &'a mut [T])> {
    // SAFETY: forwarded contract.
    unsafe { Ok((in_slice(vr, n, "vr[]")?, out_slice(value, n, "value[]")?)) }
}

/// `vr[]` and `value[]` of an fmi2Set* call.
///
/// # Safety
/// As `in_slice` for both, of length `n`.
pub(crate) unsafe fn set_arrays<'a, V, T>(
    vr: *const V,
    n: usize,
    value: *const T,
) -> FmuResult<(&'a [V], &'a [T])> {
    // SAFETY: forwarded contract.
    unsafe { Ok((in_slice(vr, n, "vr[]")?, in_slice(value, n, "value[]")?)) }
}

/// `vr[]`, `order[]` and `value[]` of fmi2SetRealInputDerivatives / fmi2GetRealOutputDerivatives.
///
/// # Safety
/// As `in_slice` for `vr` and `order`, `in_slice`/`out_slice` for `value`, all of length `n`.
pub(crate) unsafe fn derivative_arrays<'a, T: ValueArray<'a>>(
    vr: *const u32,
    n: usize,
    order: *const libc::c_int,
    value: T,
) -> FmuResult<(&'a [u32], &'a [libc::c_int], T::Slice)> {
    // SAFETY: forwarded contract.
    let vrs = unsafe { in_slice(vr, n, "vr[]")? };
    // SAFETY: forwarded contract.
    let orders = unsafe { in_slice(order, n, "order[]")? };
    // SAFETY: forwarded contract.
    let values = unsafe { value.slice(n, "value[]")? };
    Ok((vrs, orders, values))
}

/// A `value[]` argument that is read (`*const`) or written (`*mut`).
pub(crate) trait ValueArray<'a> {
    /// `&[T]` or `&mut [T]`.
    type Slice;
    /// `in_slice` or `out_slice`.
    ///
    /// # Safety
    /// As `in_slice` / `out_slice`.
    unsafe fn slice(self, n: usize, what: &str) -> FmuResult<Self::Slice>;
}

impl<'a, T: 'a> ValueArray<'a> for *const T {
    type Slice = &'a [T];
    unsafe fn slice(self, n: usize, what: &str) -> FmuResult<&'a [T]> {
        // SAFETY: forwarded contract.
        unsafe { in_slice(self, n, what) }
    }
}

impl<'a, T: 'a> ValueArray<'a> for *mut T {
    type Slice = &'a mut [T];
    unsafe fn slice(self, n: usize, what: &str) -> FmuResult<&'a mut [T]> {
        // SAFETY: forwarded contract.
        unsafe { out_slice(self, n, what) }
    }
}

/// The four arrays of fmi2GetDirectionalDerivative.
pub(crate) struct DirectionalArrays<'a> {
    /// vUnknown_ref[nUnknown]
    pub unknowns: &'a [u32],
    /// vKnown_ref[nKnown]
    pub knowns: &'a [u32],
    /// dvKnown[nKnown]
    pub seed: &'a [f64],
    /// dvUnknown[nUnknown]
    pub out: &'a mut [f64],
}

/// Checks and wraps the arrays of fmi2GetDirectionalDerivative.
///
/// # Safety
/// As `in_slice` for the first three and `out_slice` for `dv_unknown`.
pub(crate) unsafe fn directional_arrays<'a>(
    v_unknown: *const u32,
    n_unknown: usize,
    v_known: *const u32,
    n_known: usize,
    dv_known: *const f64,
    dv_unknown: *mut f64,
) -> FmuResult<DirectionalArrays<'a>> {
    // SAFETY: forwarded contract.
    let unknowns = unsafe { in_slice(v_unknown, n_unknown, "vUnknown_ref[]")? };
    // SAFETY: forwarded contract.
    let knowns = unsafe { in_slice(v_known, n_known, "vKnown_ref[]")? };
    // SAFETY: forwarded contract.
    let seed = unsafe { in_slice(dv_known, n_known, "dvKnown[]")? };
    // SAFETY: forwarded contract.
    let out = unsafe { out_slice(dv_unknown, n_unknown, "dvUnknown[]")? };
    Ok(DirectionalArrays {
        unknowns,
        knowns,
        seed,
        out,
    })
}

/// A single output value (`size_t* size`, `fmi2Real* value`, …).
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
pub(crate) unsafe fn c_str<'a>(p: fmi2String, what: &str) -> FmuResult<&'a str> {
    if p.is_null() {
        return Err(FmuError::error(format!("argument {what} is NULL")));
    }
    // SAFETY: non-NULL; the caller guarantees NUL termination and lifetime.
    let s = unsafe { CStr::from_ptr(p) };
    s.to_str()
        .map_err(|_| FmuError::error(format!("argument {what} is not valid UTF-8")))
}

/// The snapshot behind an FMU state handle (NULL refused).
///
/// # Safety
/// A non-NULL `state` was created by fmi2GetFMUstate/fmi2DeSerializeFMUstate of this library
/// and not yet freed.
pub(crate) unsafe fn state_ref<'a>(state: fmi2FMUstate) -> FmuResult<&'a Snapshot> {
    if state.is_null() {
        return Err(FmuError::error("argument FMUstate is NULL"));
    }
    // SAFETY: the caller's contract: a live Box<Snapshot> made by `store_state`.
    Ok(unsafe { &*state.cast::<Snapshot>() })
}

/// Stores a snapshot into `*state`: overwrites the state it already points to (FMI 2.0: a
/// non-NULL `*FMUstate` is a state this FMU returned earlier), else allocates a new one.
///
/// # Safety
/// `state` is writable (NULL is refused); a non-NULL `*state` is a live state of this library.
pub(crate) unsafe fn store_state(state: *mut fmi2FMUstate, snapshot: Snapshot) -> FmuResult<()> {
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
pub(crate) unsafe fn free_state(state: *mut fmi2FMUstate) {
    // SAFETY: forwarded contract; `as_mut` maps NULL to None.
    if let Some(slot) = unsafe { state.as_mut() } {
        if !slot.is_null() {
            // SAFETY: a live Box<Snapshot> made by `store_state`, released exactly once: the
            // handle is set to NULL right after.
            drop(unsafe { Box::from_raw(slot.cast::<Snapshot>()) });
            *slot = std::ptr::null_mut();
        }
    }
}

/// fmi2Instantiate without the raw-pointer return: validates every argument, logging the
/// reason for a refusal through the importer's logger when there is one.
///
/// # Safety
/// Each pointer is NULL or valid as FMI 2.0 §2.1.5 requires (C strings NUL-terminated,
/// `functions` pointing to a callback struct).
pub(crate) unsafe fn instantiate(
    instance_name: fmi2String,
    fmu_type: libc::c_int,
    guid: fmi2String,
    functions: *const fmi2CallbackFunctions,
    logging_on: bool,
) -> Option<ModelInstance> {
    const F: &str = "fmi2Instantiate";
    // SAFETY: NULL or a valid callback struct (caller's contract); copied, not kept.
    let functions = unsafe { functions.as_ref() }.copied()?;
    let callback = functions.logger?;
    // SAFETY: caller's contract for the C strings.
    let name = unsafe { c_str(instance_name, "instanceName") };
    let logger = CallbackLogger::new(
        callback,
        functions.componentEnvironment,
        name.as_deref().unwrap_or(""),
    );
    let checked = (|| {
        let name = name?;
        if name.is_empty() {
            return Err(FmuError::error("instanceName is empty"));
        }
        match fmi2Type::try_from(fmu_type) {
            Ok(fmi2Type::CoSimulation) => {}
            Ok(fmi2Type::ModelExchange) => {
                return Err(FmuError::error("fmuType fmi2ModelExchange is not supported: this FMU implements Co-Simulation only"))
            }
            Err(t) => {
                return Err(FmuError::error(format!(
                    "invalid fmuType {t} (fmi2ModelExchange = 0, fmi2CoSimulation = 1)"
                )))
            }
        }
        // SAFETY: caller's contract for the C strings.
        let guid = unsafe { c_str(guid, "fmuGUID") }?;
        let variant = variant_by_guid(guid).ok_or_else(|| {
            FmuError::error(format!(
                "fmuGUID \"{guid}\" matches no model of this binary (modelDescription.xml and binary from different builds?)"
            ))
        })?;
        Ok((variant, name))
    })();
    match checked {
        Ok((variant, name)) => {
            let inst = ModelInstance::new(variant, name, Box::new(logger), logging_on);
            trace(&inst, F);
            Some(inst)
        }
        Err(e) => {
            logger.log(e.level, e.category(), &format!("{F}: {}", e.message));
            None
        }
    }
}

/// An array of C strings (`categories[]` of fmi2SetDebugLogging), with `(NULL, 0)` legal.
///
/// # Safety
/// As `in_slice`, and each non-NULL element is a NUL-terminated string valid for `'a`.
pub(crate) unsafe fn c_str_array<'a>(
    p: *const fmi2String,
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
