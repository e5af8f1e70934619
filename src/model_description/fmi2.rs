//! The FMI 2.0 `modelDescription.xml` of a variant, generated from its variable table (serde +
//! quick-xml); a pure function, no I/O. The committed files under `modelDescription/` must
//! equal its output. Uses the shared elements of `super` (units, log categories, default
//! experiment, header) and the model's tables; nothing here is used by `fmi3`.

use super::{
    causality, log_categories, to_xml, unit_definitions, variability, DefaultExperiment,
    LogCategories, UnitDefinitions, COPYRIGHT, DEFAULT_EXPERIMENT, LICENSE,
};
use crate::model::variables::{table, Start, Table, Variant};
use serde::Serialize;

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

#[derive(Serialize)]
#[serde(rename = "fmiModelDescription")]
struct ModelDescription {
    #[serde(rename = "@fmiVersion")]
    fmi_version: &'static str,
    #[serde(rename = "@modelName")]
    model_name: &'static str,
    #[serde(rename = "@guid")]
    guid: String,
    #[serde(rename = "@description")]
    description: &'static str,
    #[serde(rename = "@author")]
    author: &'static str,
    #[serde(rename = "@version")]
    version: &'static str,
    #[serde(rename = "@copyright")]
    copyright: &'static str,
    #[serde(rename = "@license")]
    license: &'static str,
    #[serde(rename = "@generationTool")]
    generation_tool: String,
    #[serde(rename = "@variableNamingConvention")]
    naming: &'static str,
    #[serde(rename = "@numberOfEventIndicators")]
    event_indicators: u32,
    #[serde(rename = "CoSimulation")]
    co_simulation: CoSimulation,
    #[serde(rename = "UnitDefinitions")]
    units: UnitDefinitions,
    #[serde(rename = "LogCategories")]
    log_categories: LogCategories,
    #[serde(rename = "DefaultExperiment")]
    default_experiment: DefaultExperiment,
    #[serde(rename = "ModelVariables")]
    variables: ModelVariables,
    #[serde(rename = "ModelStructure")]
    structure: ModelStructure,
}

#[derive(Serialize)]
struct CoSimulation {
    #[serde(rename = "@modelIdentifier")]
    model_identifier: &'static str,
    #[serde(rename = "@canHandleVariableCommunicationStepSize")]
    variable_step: bool,
    #[serde(rename = "@canInterpolateInputs")]
    interpolate_inputs: bool,
    #[serde(rename = "@maxOutputDerivativeOrder")]
    max_output_derivative_order: u32,
    #[serde(rename = "@canRunAsynchronuously")]
    asynchronous: bool,
    #[serde(rename = "@canBeInstantiatedOnlyOncePerProcess")]
    once_per_process: bool,
    #[serde(rename = "@canNotUseMemoryManagementFunctions")]
    no_memory_functions: bool,
    #[serde(rename = "@canGetAndSetFMUstate")]
    get_set_state: bool,
    #[serde(rename = "@canSerializeFMUstate")]
    serialize_state: bool,
    #[serde(rename = "@providesDirectionalDerivative")]
    directional_derivative: bool,
}

#[derive(Serialize)]
struct ModelVariables {
    #[serde(rename = "ScalarVariable")]
    vars: Vec<ScalarVariable>,
}

#[derive(Serialize)]
struct ScalarVariable {
    #[serde(rename = "@name")]
    name: String,
    #[serde(rename = "@valueReference")]
    vr: u32,
    #[serde(rename = "@description")]
    description: String,
    #[serde(rename = "@causality")]
    causality: &'static str,
    #[serde(rename = "@variability")]
    variability: &'static str,
    #[serde(rename = "$value")]
    ty: TypeElement,
}

#[derive(Serialize)]
enum TypeElement {
    Real(RealAttrs),
    Integer(PlainAttrs),
    Boolean(PlainAttrs),
}

#[derive(Serialize)]
struct RealAttrs {
    #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
    start: Option<String>,
    #[serde(rename = "@unit", skip_serializing_if = "Option::is_none")]
    unit: Option<&'static str>,
    #[serde(rename = "@min", skip_serializing_if = "Option::is_none")]
    min: Option<String>,
    #[serde(rename = "@max", skip_serializing_if = "Option::is_none")]
    max: Option<String>,
}

#[derive(Serialize)]
struct PlainAttrs {
    #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
    start: Option<String>,
    #[serde(rename = "@min", skip_serializing_if = "Option::is_none")]
    min: Option<String>,
    #[serde(rename = "@max", skip_serializing_if = "Option::is_none")]
    max: Option<String>,
}

#[derive(Serialize)]
struct ModelStructure {
    #[serde(rename = "Outputs")]
    outputs: Unknowns,
    #[serde(rename = "InitialUnknowns")]
    initial: Unknowns,
}

#[derive(Serialize)]
struct Unknowns {
    #[serde(rename = "Unknown")]
    unknowns: Vec<Unknown>,
}

#[derive(Serialize)]
struct Unknown {
    #[serde(rename = "@index")]
    index: usize,
    #[serde(rename = "@dependencies")]
    dependencies: String,
}

/// The model description of a variant as XML text.
pub fn model_description(v: Variant) -> String {
    to_xml(&build(table(v)))
}

fn build(t: &Table) -> ModelDescription {
    let spec = t.spec;
    let vars = t
        .vars
        .iter()
        .map(|v| ScalarVariable {
            name: v.name.clone(),
            vr: v.vr,
            description: v.description.clone(),
            causality: causality(v.causality),
            variability: variability(v.variability),
            ty: {
                let (min, max) = v.range_text();
                match v.start {
                    Start::Real(_) => TypeElement::Real(RealAttrs {
                        start: v.start_text(),
                        unit: v.unit_text(),
                        min,
                        max,
                    }),
                    Start::Integer(_) => TypeElement::Integer(PlainAttrs {
                        start: v.start_text(),
                        min,
                        max,
                    }),
                    // FMI 2.0's Boolean has no min/max (the table gives none)
                    Start::Boolean(_) => TypeElement::Boolean(PlainAttrs {
                        start: v.start_text(),
                        min: None,
                        max: None,
                    }),
                }
            },
        })
        .collect();
    // ModelStructure: 1-based indices, from the table
    let join = |ix: &[usize]| {
        ix.iter()
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    let mut outputs = Vec::new();
    let mut initial = Vec::new();
    for i in 0..t.vars.len() {
        if let Some((inputs, init)) = t.dependencies(i) {
            outputs.push(Unknown {
                index: i + 1,
                dependencies: join(&inputs),
            });
            initial.push(Unknown {
                index: i + 1,
                dependencies: join(&init),
            });
        }
    }
    use capabilities::*;
    ModelDescription {
        fmi_version: "2.0",
        model_name: spec.model_identifier,
        guid: t.guid.clone(),
        description: spec.description,
        author: env!("CARGO_PKG_AUTHORS"),
        version: env!("CARGO_PKG_VERSION"),
        copyright: COPYRIGHT,
        license: LICENSE,
        generation_tool: format!("connector_fmu {}", env!("CARGO_PKG_VERSION")),
        naming: "structured",
        event_indicators: 0,
        co_simulation: CoSimulation {
            model_identifier: spec.model_identifier,
            variable_step: true,
            interpolate_inputs: CAN_INTERPOLATE_INPUTS,
            max_output_derivative_order: 0,
            asynchronous: false,
            once_per_process: false,
            no_memory_functions: true,
            get_set_state: CAN_GET_AND_SET_FMU_STATE,
            serialize_state: CAN_SERIALIZE_FMU_STATE,
            directional_derivative: PROVIDES_DIRECTIONAL_DERIVATIVE,
        },
        units: unit_definitions(t, &[]),
        log_categories: log_categories("fmi2"),
        default_experiment: DEFAULT_EXPERIMENT,
        variables: ModelVariables { vars },
        structure: ModelStructure {
            outputs: Unknowns { unknowns: outputs },
            initial: Unknowns { unknowns: initial },
        },
    }
}
