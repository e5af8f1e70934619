//! The FMI 3.0 `modelDescription.xml`, from the same rows as the FMI 2.0 one (`super::model`),
//! written by `fmi_shared::model_description::fmi3` (Real → Float64, Integer → Int32;
//! `instantiationToken` is the FMI 2.0 GUID; plus the independent variable `time`, value
//! reference 0) with this FMU's capabilities. A pure function, no I/O:
//! bodies/modelDescription/fmi3/Body.xml must equal its output. Uses `super` and `fmi_shared`;
//! bin/gen_body_model_description and the drift test use it.

use super::model;
use fmi_shared::model_description::fmi3::Capabilities;

/// The capabilities: only what works and is tested; no early return, no Event Mode, no
/// derivatives.
const CAPABILITIES: Capabilities = Capabilities {
    get_set_state: true,
    serialize_state: true,
    directional: false,
    adjoint: false,
    variable_step: true,
    intermediate_update: false,
    might_return_early: false,
    early_after_intermediate: false,
    has_event_mode: false,
};

/// The FMI 3.0 model description as XML text.
pub fn model_description() -> String {
    fmi_shared::model_description::fmi3::model_description(&model(), &CAPABILITIES)
}
