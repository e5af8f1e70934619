//! The FMI 2.0 `modelDescription.xml` of a variant: its table as `super::model` gives it,
//! written by `fmi_shared::model_description::fmi2` with this FMU's capabilities; a pure
//! function, no I/O. The committed files under `modelDescription/` must equal its output.
//! Uses `super`, the model's tables and `fmi_shared`; bin/gen_model_description and the drift
//! tests use it; nothing here is used by `fmi3`.

use super::model;
use crate::model::variables::{table, Variant};
use fmi_shared::model_description::fmi2::Capabilities;

/// Capability flags, declared only for what works and is tested.
pub mod capabilities {
    /// fmi2SetRealInputDerivatives, first order.
    pub const CAN_INTERPOLATE_INPUTS: bool = true;
    /// fmi2GetFMUstate / fmi2SetFMUstate / fmi2FreeFMUstate.
    pub const CAN_GET_AND_SET_FMU_STATE: bool = true;
    /// fmi2SerializeFMUstate and friends.
    pub const CAN_SERIALIZE_FMU_STATE: bool = true;
    /// fmi2GetDirectionalDerivative.
    pub const PROVIDES_DIRECTIONAL_DERIVATIVE: bool = true;
}

/// The model description of a variant as XML text.
pub fn model_description(v: Variant) -> String {
    use capabilities::*;
    let caps = Capabilities {
        interpolate_inputs: CAN_INTERPOLATE_INPUTS,
        get_set_state: CAN_GET_AND_SET_FMU_STATE,
        serialize_state: CAN_SERIALIZE_FMU_STATE,
        directional_derivative: PROVIDES_DIRECTIONAL_DERIVATIVE,
    };
    fmi_shared::model_description::fmi2::model_description(&model(table(v)), &caps)
}
