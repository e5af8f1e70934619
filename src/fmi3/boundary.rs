//! What every FMI 3.0 function shares beyond the FMI 2.0 boundary's pointer helpers (reused
//! from `crate::fmi2::boundary`: slices, C strings, FMU state handles): the panic wrapper, the
//! instance lookup, the one mapping of results to `fmi3Status`, the array checks of FMI 3.0
//! signatures (`nValues`, `nSeed`, …) and fmi3InstantiateCoSimulation's argument checks.

use super::logger::CallbackLogger;
use super::types::{fmi3InstanceEnvironment, fmi3LogMessageCallback, fmi3Status};
use crate::error::{Category, FmuError, FmuResult, Level};
use crate::fmi2::boundary::{c_str, in_slice, out_slice, trace, PanicDefault};
use crate::instance::{FmiVersion, LogSink, ModelInstance};
use crate::model::variables::variant_by_guid;

impl PanicDefault for fmi3Status {
    /// A caught panic is fmi3Fatal: the instance is unusable.
    fn panic_default() -> Self {
        fmi3Status::Fatal
    }
}

/// Runs an exported body with panics caught, so that no unwind crosses the C boundary: the
/// FMI 2.0 boundary's `ffi_boundary!` (`ffi3!(F, { .. })` without an instance, `ffi3!(c, F,
/// { .. })` marks the instance behind `c` Fatal and logs the panic through its logger).
macro_rules! ffi3 {
    ($($args:tt)*) => {
        $crate::fmi2::boundary::ffi_boundary!($($args)*)
    };
}

/// `&mut ModelInstance` from the instance handle, or `return fmi3Error` for NULL (nothing to
/// log through). Traces the call under logAll. With a `Call`, also checks that the call is
/// allowed in the current state.
macro_rules! instance3 {
    ($c:expr, $fname:expr) => {
        // SAFETY: a non-NULL handle is the pointer fmi3InstantiateCoSimulation returned and
        // that the importer has not freed (FMI 3.0 §2.2.3); FMI forbids concurrent calls on one
        // instance, so this is the only reference to it while the call runs.
        match unsafe { $crate::fmi2::boundary::instance_mut($c) } {
            Some(inst) => {
                $crate::fmi2::boundary::trace(inst, $fname);
                inst
            }
            None => return $crate::fmi3::types::fmi3Status::Error,
        }
    };
    ($c:expr, $fname:expr, $call:expr) => {{
        let inst = instance3!($c, $fname);
        if let Err(e) = inst.allowed($call) {
            return $crate::fmi3::boundary::ToStatus::to_status(Err::<(), _>(e), inst, $fname);
        }
        inst
    }};
}

/// The one mapping of an instance-layer result to `fmi3Status`; the error is logged once, its
/// message led by the name of the FMI function (`fname`) that answers it.
pub(crate) trait ToStatus {
    /// Logs a non-OK outcome through the instance and returns its status.
    fn to_status(self, inst: &mut ModelInstance, fname: &str) -> fmi3Status;
}

impl ToStatus for FmuResult<()> {
    #[inline]
    fn to_status(self, inst: &mut ModelInstance, fname: &str) -> fmi3Status {
        match self {
            Ok(()) => fmi3Status::OK,
            Err(e) => refused(e, inst, fname),
        }
    }
}

/// Logs a refused call's error (off the path of the calls that succeed) and returns its status.
#[cold]
#[inline(never)]
fn refused(e: FmuError, inst: &mut ModelInstance, fname: &str) -> fmi3Status {
    inst.log(e.level, e.category(), &format!("{fname}: {}", e.message));
    e.level.into()
}

/// Every variable of this FMU is a scalar: `nValues` must equal `nValueReferences`.
pub(crate) fn same_count(n_vr: usize, n_values: usize, what: &str) -> FmuResult<()> {
    if n_vr == n_values {
        return Ok(());
    }
    Err(FmuError::error(format!(
        "{what} = {n_values} differs from nValueReferences = {n_vr} (every variable of this FMU is a scalar)"
    )))
}

/// `valueReferences[]` and `values[]` of an fmi3Get* call.
///
/// # Safety
/// As `in_slice` for `vr` (`n_vr` elements) and `out_slice` for `values` (`n_values`).
pub(crate) unsafe fn get_arrays<'a, T>(
    vr: *const u32,
    n_vr: usize,
    values: *mut T,
    n_values: usize,
) -> FmuResult<(&'a [u32], &'a mut [T])> {
    same_count(n_vr, n_values, "nValues")?;
    // SAFETY: forwarded contract.
    unsafe {
        Ok((
            in_slice(vr, n_vr, "valueReferences[]")?,
            out_slice(values, n_values, "values[]")?,
        ))
    }
}

/// `valueReferences[]` and `values[]` of an fmi3Set* call.
///
/// # Safety
/// As `in_slice` for both (`n_vr` and `n_values` elements).
pub(crate) unsafe fn set_arrays<'a, T>(
    vr: *const u32,
    n_vr: usize,
    values: *const T,
    n_values: usize,
) -> FmuResult<(&'a [u32], &'a [T])> {
    same_count(n_vr, n_values, "nValues")?;
    // SAFETY: forwarded contract.
    unsafe {
        Ok((
            in_slice(vr, n_vr, "valueReferences[]")?,
            in_slice(values, n_values, "values[]")?,
        ))
    }
}

/// The arrays of fmi3GetDirectionalDerivative / fmi3GetAdjointDerivative.
pub(crate) struct DerivativeArrays<'a> {
    /// unknowns[nUnknowns]
    pub unknowns: &'a [u32],
    /// knowns[nKnowns]
    pub knowns: &'a [u32],
    /// seed[nSeed]
    pub seed: &'a [f64],
    /// sensitivity[nSensitivity]
    pub sensitivity: &'a mut [f64],
}

/// Checks and wraps the arrays of a derivative call: `seed` has `n_seed_want` elements and
/// `sensitivity` `n_sens_want` (nKnowns and nUnknowns for directional derivatives, the other
/// way round for adjoint ones).
///
/// # Safety
/// As `in_slice` for the first three and `out_slice` for `sensitivity`.
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn derivative_arrays<'a>(
    unknowns: (*const u32, usize),
    knowns: (*const u32, usize),
    seed: (*const f64, usize),
    sensitivity: (*mut f64, usize),
    n_seed_want: (usize, &str),
    n_sens_want: (usize, &str),
) -> FmuResult<DerivativeArrays<'a>> {
    if seed.1 != n_seed_want.0 {
        return Err(FmuError::error(format!(
            "nSeed = {} differs from {} = {} (every variable of this FMU is a scalar)",
            seed.1, n_seed_want.1, n_seed_want.0
        )));
    }
    if sensitivity.1 != n_sens_want.0 {
        return Err(FmuError::error(format!(
            "nSensitivity = {} differs from {} = {} (every variable of this FMU is a scalar)",
            sensitivity.1, n_sens_want.1, n_sens_want.0
        )));
    }
    // SAFETY: forwarded contract.
    unsafe {
        Ok(DerivativeArrays {
            unknowns: in_slice(unknowns.0, unknowns.1, "unknowns[]")?,
            knowns: in_slice(knowns.0, knowns.1, "knowns[]")?,
            seed: in_slice(seed.0, seed.1, "seed[]")?,
            sensitivity: out_slice(sensitivity.0, sensitivity.1, "sensitivity[]")?,
        })
    }
}

/// The arguments of fmi3InstantiateCoSimulation that decide whether there is an instance.
pub(crate) struct InstantiateArgs {
    pub instance_name: *const libc::c_char,
    pub token: *const libc::c_char,
    pub logging_on: bool,
    pub event_mode_used: bool,
    pub early_return_allowed: bool,
    pub required_intermediate: (*const u32, usize),
    pub env: fmi3InstanceEnvironment,
    pub log_message: Option<fmi3LogMessageCallback>,
}

/// fmi3InstantiateCoSimulation without the raw-pointer return: validates every argument,
/// logging the reason for a refusal through the importer's logger when there is one.
///
/// # Safety
/// Each pointer is NULL or valid as FMI 3.0 §2.3.1 requires (C strings NUL-terminated,
/// `required_intermediate` holding its announced number of value references).
pub(crate) unsafe fn instantiate(a: InstantiateArgs) -> Option<ModelInstance> {
    const F: &str = "fmi3InstantiateCoSimulation";
    let logger = CallbackLogger::new(a.log_message, a.env);
    let checked = (|| {
        // SAFETY: caller's contract for the C strings.
        let name = unsafe { c_str(a.instance_name, "instanceName") }?;
        if name.is_empty() {
            return Err(FmuError::error("instanceName is empty"));
        }
        // SAFETY: caller's contract for the C strings.
        let token = unsafe { c_str(a.token, "instantiationToken") }?;
        let variant = variant_by_guid(token).ok_or_else(|| {
            FmuError::error(format!(
                "instantiationToken \"{token}\" matches no model of this binary (modelDescription.xml and binary from different builds?)"
            ))
        })?;
        if a.event_mode_used {
            return Err(FmuError::error(
                "eventModeUsed = true, but this FMU has no Event Mode (hasEventMode = false)",
            ));
        }
        // Intermediate variables are never accessed (providesIntermediateUpdate = false): the
        // list is checked as an array and otherwise ignored.
        // SAFETY: caller's contract for the array.
        unsafe {
            in_slice(
                a.required_intermediate.0,
                a.required_intermediate.1,
                "requiredIntermediateVariables[]",
            )
        }?;
        Ok((variant, name))
    })();
    match checked {
        Ok((variant, name)) => {
            let inst = ModelInstance::new(variant, name, Box::new(logger), a.logging_on)
                .with_version(FmiVersion::V3)
                .with_early_return(a.early_return_allowed);
            trace(&inst, F);
            Some(inst)
        }
        Err(e) => {
            logger.log(e.level, e.category(), &format!("{F}: {}", e.message));
            None
        }
    }
}

/// fmi3InstantiateModelExchange / fmi3InstantiateScheduledExecution: no instance, the reason
/// logged through the importer's logger when there is one.
pub(crate) fn refuse_interface(
    fname: &str,
    env: fmi3InstanceEnvironment,
    log_message: Option<fmi3LogMessageCallback>,
    interface: &str,
) {
    CallbackLogger::new(log_message, env).log(
        Level::Error,
        Category::Error,
        &format!(
            "{fname}: {interface} is not supported: this FMU implements Co-Simulation only (fmi3InstantiateCoSimulation)"
        ),
    );
}
