//! The FMI 2.0 `modelDescription.xml`: the table as `super::model` gives it, written by
//! `fmi_shared::model_description::fmi2` with this FMU's capabilities; a pure function, no I/O.
//! bodies/modelDescription/Body.xml must equal its output. Uses `super` and `fmi_shared`;
//! bin/gen_body_model_description and the drift test use it.

use super::model;
use fmi_shared::model_description::fmi2::Capabilities;

/// The capabilities: only what works and is tested (no input interpolation, no derivatives).
const CAPABILITIES: Capabilities = Capabilities {
    interpolate_inputs: false,
    get_set_state: true,
    serialize_state: true,
    directional_derivative: false,
};

/// The FMI 2.0 model description as XML text.
pub fn model_description() -> String {
    fmi_shared::model_description::fmi2::model_description(&model(), &CAPABILITIES)
}
