//! The FMI 3.0 `modelDescription.xml` of a variant, from the same rows as the FMI 2.0 one
//! (`super::model`), written by `fmi_shared::model_description::fmi3` (Real → Float64, Integer
//! → Int32, Boolean → Boolean; `instantiationToken` is the FMI 2.0 GUID; plus `time`) with this
//! FMU's capabilities. A pure function, no I/O: the committed files under
//! `modelDescription/fmi3/` must equal its output. The model structure (`dependencies`) is also
//! what fmi3GetVariableDependencies answers at run time (`crate::fmi3::policy`). Uses `super`,
//! the model's tables and `fmi_shared`.

use super::model;
use crate::model::variables::{table, Table, Variant};
use fmi_shared::model_description::fmi3::Capabilities;

/// The value reference of the independent variable `time` (FMI 3.0 requires one; no table
/// uses 0; `fmi_shared` declares it). fmi3GetFloat64 reads the FMU's time through it; it cannot
/// be set.
pub use fmi_shared::model_description::fmi3::TIME_VR;

/// Capability flags of the FMI 3.0 Co-Simulation element, declared only for what works and is
/// tested (tests/abi_fmi3_*.rs, tests/python/test_fmpy_fmi3.py).
pub mod capabilities {
    /// fmi3DoStep with any communicationStepSize > 0.
    pub const CAN_HANDLE_VARIABLE_COMMUNICATION_STEP_SIZE: bool = true;
    /// fmi3GetFMUState / fmi3SetFMUState / fmi3FreeFMUState.
    pub const CAN_GET_AND_SET_FMU_STATE: bool = true;
    /// fmi3SerializeFMUState and friends (the FMI 2.0 byte format).
    pub const CAN_SERIALIZE_FMU_STATE: bool = true;
    /// fmi3GetDirectionalDerivative (the FMI 2.0 tangent).
    pub const PROVIDES_DIRECTIONAL_DERIVATIVES: bool = true;
    /// fmi3GetAdjointDerivative (Jᵀ·v from the directional derivatives' columns).
    pub const PROVIDES_ADJOINT_DERIVATIVES: bool = true;
    /// No intermediate update callback is ever called.
    pub const PROVIDES_INTERMEDIATE_UPDATE: bool = false;
    /// With earlyReturnAllowed, fmi3DoStep ends at the first event located inside the step.
    pub const MIGHT_RETURN_EARLY_FROM_DO_STEP: bool = true;
    /// Needs intermediate update.
    pub const CAN_RETURN_EARLY_AFTER_INTERMEDIATE_UPDATE: bool = false;
    /// No Event Mode or clocks (the events are the FMU's own, met by early return):
    /// fmi3EnterEventMode answers fmi3Error.
    pub const HAS_EVENT_MODE: bool = false;
}

/// The knowns an output of `t` depends on, as value references in increasing order: at
/// communication points (`initial == false`, ModelStructure/Output) the node inputs its
/// `Deps` names; in Initialization Mode (`initial == true`, ModelStructure/InitialUnknown)
/// also every parameter, for an output that depends on anything. None when `vr` is not an
/// output of the table.
pub fn dependencies(t: &Table, vr: u32, initial: bool) -> Option<Vec<u32>> {
    // the FMI 2.0 ModelStructure's rule (`Table::dependencies`, 1-based indices), as VRs
    let i = t.vars.iter().position(|v| v.vr == vr)?;
    let (outputs, init) = t.dependencies(i)?;
    let ix = if initial { init } else { outputs };
    let mut deps: Vec<u32> = ix
        .iter()
        .filter_map(|&k| t.vars.get(k - 1))
        .map(|v| v.vr)
        .collect();
    deps.sort_unstable();
    Some(deps)
}

/// The FMI 3.0 model description of a variant as XML text.
pub fn model_description(v: Variant) -> String {
    use capabilities::*;
    let caps = Capabilities {
        get_set_state: CAN_GET_AND_SET_FMU_STATE,
        serialize_state: CAN_SERIALIZE_FMU_STATE,
        directional: PROVIDES_DIRECTIONAL_DERIVATIVES,
        adjoint: PROVIDES_ADJOINT_DERIVATIVES,
        variable_step: CAN_HANDLE_VARIABLE_COMMUNICATION_STEP_SIZE,
        intermediate_update: PROVIDES_INTERMEDIATE_UPDATE,
        might_return_early: MIGHT_RETURN_EARLY_FROM_DO_STEP,
        early_after_intermediate: CAN_RETURN_EARLY_AFTER_INTERMEDIATE_UPDATE,
        has_event_mode: HAS_EVENT_MODE,
    };
    fmi_shared::model_description::fmi3::model_description(&model(table(v)), &caps)
}
