//! The FMI 3.0 rules that need no pointer: fmi3Boolean bytes to `bool`, copying a serialized
//! state, the answers for variable types this FMU does not have, the variable dependencies,
//! and the refusals of functions for events, clocks, configuration, Model Exchange and
//! Scheduled Execution. Safe code, called by `exports` after `boundary` has turned the
//! pointers into slices.
#![forbid(unsafe_code)]

use crate::error::{FmuError, FmuResult};
use crate::instance::{Call, Mode, ModelInstance};
use crate::model::access::Ty;
use crate::model::snapshot::Snapshot;
use crate::model_description::fmi3::{dependencies, TIME_VR};

/// fmi3GetFloat64: the table's Real variables and the independent variable `time`.
pub(crate) fn get_float64(inst: &mut ModelInstance, vrs: &[u32], out: &mut [f64]) -> FmuResult<()> {
    if !vrs.contains(&TIME_VR) {
        return inst.get_real(vrs, out);
    }
    // all or nothing: the other variables are read (and checked) first
    let others: Vec<u32> = vrs.iter().copied().filter(|&v| v != TIME_VR).collect();
    let mut values = vec![0.0; others.len()];
    inst.get_real(&others, &mut values)?;
    let mut next = values.into_iter();
    for (&vr, o) in vrs.iter().zip(out.iter_mut()) {
        *o = if vr == TIME_VR {
            inst.time()
        } else {
            next.next().unwrap_or(f64::NAN)
        };
    }
    Ok(())
}

/// fmi3SetFloat64: the table's Real variables; `time` cannot be set.
pub(crate) fn set_float64(inst: &mut ModelInstance, vrs: &[u32], values: &[f64]) -> FmuResult<()> {
    if vrs.contains(&TIME_VR) {
        inst.allowed(Call::Set)?;
        return Err(FmuError::error(format!(
            "time (vr {TIME_VR}) is the independent variable and cannot be set; values not set"
        )));
    }
    inst.set_real(vrs, values)
}

/// The error for a value reference `vr` that the table does not hold.
fn not_in_table(vr: u32, ty: Option<&str>) -> FmuError {
    if vr == TIME_VR {
        return FmuError::error(match ty {
            Some(ty) => format!("time (vr {vr}) is of type Float64, not {ty}"),
            None => format!("time (vr {vr}) is the independent variable, not an output"),
        });
    }
    FmuError::error(match ty {
        Some(ty) => format!("unknown value reference {vr} (this FMU has no {ty} variables)"),
        None => format!("unknown value reference {vr}"),
    })
}

pub(crate) use crate::fmi2::policy::{get_booleans, set_booleans};

/// fmi3SerializeFMUState into the caller's buffer (which must be large enough).
pub(crate) fn copy_serialized(inst: &ModelInstance, s: &Snapshot, buf: &mut [u8]) -> FmuResult<()> {
    crate::fmi2::policy::copy_serialized(inst, s, buf, "fmi3SerializedFMUStateSize")
}

/// fmi3Get/Set of a type this FMU has no variables of (`ty`: Float32, Int8, …, String, Binary,
/// Clock): the state is checked as for the supported types, an empty request is OK, any
/// value reference is an error naming it and what it is.
pub(crate) fn no_variables_of_type(
    inst: &ModelInstance,
    call: Call,
    vrs: &[u32],
    ty: &str,
) -> FmuResult<()> {
    inst.allowed(call)?;
    let Some(&vr) = vrs.first() else {
        return Ok(());
    };
    Err(match inst.table.get(vr) {
        None => not_in_table(vr, Some(ty)),
        Some(v) => FmuError::error(format!(
            "variable {} (vr {vr}) is of type {}, not {ty} (this FMU has no {ty} variables)",
            v.name,
            inst.version().type_name(Ty::of(&v.start))
        )),
    })
}

/// fmi3GetNumberOfVariableDependencies / fmi3GetVariableDependencies: the value references an
/// output depends on, per the model structure: the InitialUnknown dependencies before
/// fmi3ExitInitializationMode, the Output dependencies after it.
pub(crate) fn variable_dependencies(inst: &ModelInstance, vr: u32) -> FmuResult<Vec<u32>> {
    inst.allowed(Call::Lifecycle)?;
    let initial = matches!(inst.mode(), Mode::Instantiated | Mode::InitializationMode);
    dependencies(inst.table, vr, initial).ok_or_else(|| match inst.table.get(vr) {
        None => not_in_table(vr, None),
        Some(v) => FmuError::error(format!(
            "{} (vr {vr}) is not an output: only outputs have dependencies in the model structure",
            v.name
        )),
    })
}

/// fmi3GetOutputDerivatives: nothing to provide (maxOutputDerivativeOrder = 0); an empty
/// request is answered with OK.
pub(crate) fn no_output_derivatives(inst: &ModelInstance, vrs: &[u32]) -> FmuResult<()> {
    inst.allowed(Call::OutputDerivatives)?;
    match vrs.first() {
        None => Ok(()),
        Some(vr) => Err(FmuError::error(format!(
            "no output derivatives (maxOutputDerivativeOrder = 0), asked for vr {vr}"
        ))),
    }
}

/// Why a function of an interface or feature this FMU does not have answers fmi3Error.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Unsupported {
    /// fmi3EnterEventMode, fmi3UpdateDiscreteStates, fmi3EnterStepMode.
    EventMode,
    /// fmi3EvaluateDiscreteStates.
    EvaluateDiscreteStates,
    /// fmi3EnterConfigurationMode / fmi3ExitConfigurationMode.
    Configuration,
    /// fmi3Get/SetInterval*, fmi3Get/SetShift*.
    Clocks,
    /// The Model Exchange functions.
    ModelExchange,
    /// fmi3ActivateModelPartition.
    ScheduledExecution,
}

/// The error an unsupported function answers with.
pub(crate) fn unsupported(why: Unsupported) -> FmuError {
    FmuError::error(match why {
        Unsupported::EventMode => {
            "this FMU has no Event Mode (hasEventMode = false: no events, no clocks); after fmi3ExitInitializationMode it is in Step Mode"
        }
        Unsupported::EvaluateDiscreteStates => {
            "not provided (providesEvaluateDiscreteStates = false: this FMU has no discrete states to evaluate)"
        }
        Unsupported::Configuration => {
            "this FMU has no structural parameters, so there is no Configuration Mode"
        }
        Unsupported::Clocks => "this FMU has no clocks",
        Unsupported::ModelExchange => {
            "a Model Exchange function; this FMU implements Co-Simulation only"
        }
        Unsupported::ScheduledExecution => {
            "a Scheduled Execution function; this FMU implements Co-Simulation only"
        }
    })
}
