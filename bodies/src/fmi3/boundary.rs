//! What the FMI 3.0 functions share beyond the FMI 2.0 boundary's helpers (the panic wall,
//! slices, C strings, FMU state handles, reused from `crate::fmi2::boundary`): the mapping of
//! results to `fmi3Status`, the array checks of FMI 3.0 signatures (`nValues`), the variable
//! dependencies and fmi3InstantiateCoSimulation's argument checks. Uses `super::{types,
//! logger}`, `crate::fmi2::boundary`, `crate::instance` and `crate::model_description`.

use super::logger::CallbackLogger;
use super::types::{fmi3InstanceEnvironment, fmi3LogMessageCallback, fmi3Status};
use crate::error::{Category, FmuError, FmuResult};
use crate::fmi2::boundary::{checked_name, in_slice, out_slice, refused, trace, PanicDefault};
use crate::instance::{Call, FmiVersion, Instance, LogSink};
use crate::model_description::dependencies;
use std::ffi::c_char;

impl PanicDefault for fmi3Status {
    /// A caught panic is fmi3Fatal: the instance is unusable.
    fn panic_default() -> Self {
        fmi3Status::Fatal
    }
}

/// `&mut Instance`, or `return fmi3Error` for a NULL instance.
macro_rules! instance3 {
    ($c:expr, $fname:expr) => {
        $crate::fmi2::boundary::instance_or!($c, $fname, $crate::fmi3::types::fmi3Status::Error)
    };
}
pub(crate) use instance3;

/// The one mapping of an instance-layer result to `fmi3Status`, the error logged once.
pub(crate) fn status3(r: FmuResult<()>, inst: &Instance, fname: &str) -> fmi3Status {
    match r {
        Ok(()) => fmi3Status::OK,
        Err(e) => refused(e, inst, fname).into(),
    }
}

/// Every variable of this FMU is a scalar: `nValues` must equal `nValueReferences`.
fn same_count(n_vr: usize, n_values: usize) -> FmuResult<()> {
    if n_vr == n_values {
        return Ok(());
    }
    Err(FmuError::error(format!(
        "nValues = {n_values} differs from nValueReferences = {n_vr} (every variable of this FMU is a scalar)"
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
    same_count(n_vr, n_values)?;
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
    same_count(n_vr, n_values)?;
    // SAFETY: forwarded contract.
    unsafe {
        Ok((
            in_slice(vr, n_vr, "valueReferences[]")?,
            in_slice(values, n_values, "values[]")?,
        ))
    }
}

/// The knowns an output depends on now: the model structure's InitialUnknown before
/// fmi3ExitInitializationMode (every parameter), its Output after (none). Err for a value
/// reference that is not an output.
pub(crate) fn variable_dependencies(inst: &Instance, vr: u32) -> FmuResult<Vec<u32>> {
    inst.allowed(Call::Any)?;
    dependencies(vr, !inst.initialized()).ok_or_else(|| {
        FmuError::error(format!(
            "vr {vr} is not an output: only outputs have dependencies here"
        ))
    })
}

/// The arguments of fmi3InstantiateCoSimulation that decide whether there is an instance.
pub(crate) struct InstantiateArgs {
    pub instance_name: *const c_char,
    pub token: *const c_char,
    pub logging_on: bool,
    pub event_mode_used: bool,
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
pub(crate) unsafe fn instantiate(a: InstantiateArgs) -> Option<Instance> {
    const F: &str = "fmi3InstantiateCoSimulation";
    let logger = CallbackLogger::new(a.log_message, a.env);
    // SAFETY: caller's contract for the C strings.
    let checked = unsafe { checked_name(a.instance_name, a.token, "instantiationToken") }.and_then(
        |_| match a.event_mode_used {
            true => Err(FmuError::error(
                "eventModeUsed = true, but this FMU has no Event Mode (hasEventMode = false)",
            )),
            // intermediate variables are never accessed (providesIntermediateUpdate = false):
            // the list is checked as an array and otherwise ignored
            // SAFETY: caller's contract for the array.
            false => unsafe {
                in_slice(
                    a.required_intermediate.0,
                    a.required_intermediate.1,
                    "requiredIntermediateVariables[]",
                )
            }
            .map(|_| ()),
        },
    );
    match checked {
        Ok(()) => {
            let inst = Instance::new(Box::new(logger), a.logging_on, FmiVersion::V3);
            trace(&inst, F);
            Some(inst)
        }
        Err(e) => {
            logger.log(e.level, Category::Error, &format!("{F}: {}", e.message));
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
        crate::error::Level::Error,
        Category::Error,
        &format!("{fname}: {interface} is not supported: this FMU implements Co-Simulation only (fmi3InstantiateCoSimulation)"),
    );
}
