//! The FMI 2.0 `modelDescription.xml` of a `super::Model` (serde + quick-xml); a pure function,
//! no I/O. Uses the shared elements of `super` (units, log categories, default experiment,
//! header); connector_fmu's and body_fmu's `model_description::fmi2` use it with their tables
//! and capabilities.

use super::{
    join, log_categories, to_xml, unit_definitions, DefaultExperiment, LogCategories, Model, Type,
    UnitDefinitions, COPYRIGHT, DEFAULT_EXPERIMENT, LICENSE,
};
use serde::Serialize;

/// The capability flags that differ between the FMUs; the others are the same for both
/// (variable communication step size, no asynchronous steps, no memory management functions,
/// any number of instances per process, output derivatives of order 0).
pub struct Capabilities {
    /// `canInterpolateInputs` (fmi2SetRealInputDerivatives).
    pub interpolate_inputs: bool,
    /// `canGetAndSetFMUstate`.
    pub get_set_state: bool,
    /// `canSerializeFMUstate`.
    pub serialize_state: bool,
    /// `providesDirectionalDerivative`.
    pub directional_derivative: bool,
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
    Real(Attrs),
    Integer(Attrs),
    Boolean(Attrs),
}

#[derive(Serialize)]
struct Attrs {
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

/// The FMI 2.0 model description of `m` as XML text.
pub fn model_description(m: &Model, caps: &Capabilities) -> String {
    let vars = m
        .variables
        .iter()
        .map(|v| ScalarVariable {
            name: v.name.clone(),
            vr: v.vr,
            description: v.description.clone(),
            causality: v.causality.name(),
            variability: v.variability.name(),
            ty: match v.ty {
                Type::Real => TypeElement::Real(Attrs {
                    start: v.start.clone(),
                    unit: v.unit,
                    min: v.min.clone(),
                    max: v.max.clone(),
                }),
                Type::Integer => TypeElement::Integer(Attrs {
                    start: v.start.clone(),
                    unit: None,
                    min: v.min.clone(),
                    max: v.max.clone(),
                }),
                // FMI 2.0's Boolean has no min/max
                Type::Boolean => TypeElement::Boolean(Attrs {
                    start: v.start.clone(),
                    unit: None,
                    min: None,
                    max: None,
                }),
            },
        })
        .collect();
    // ModelStructure: 1-based indices into ModelVariables
    let index = |vr: u32| {
        m.variables
            .iter()
            .position(|v| v.vr == vr)
            .map_or(0, |i| i + 1)
    };
    let unknowns = |initial: bool| Unknowns {
        unknowns: m
            .outputs
            .iter()
            .map(|o| Unknown {
                index: index(o.vr),
                dependencies: join(
                    (if initial { &o.initial } else { &o.dependencies })
                        .iter()
                        .map(|&d| index(d)),
                ),
            })
            .collect(),
    };
    to_xml(&ModelDescription {
        fmi_version: "2.0",
        model_name: m.model_identifier,
        guid: m.guid.clone(),
        description: m.description,
        author: m.author,
        version: m.version,
        copyright: COPYRIGHT,
        license: LICENSE,
        generation_tool: m.generation_tool.clone(),
        naming: "structured",
        event_indicators: 0,
        co_simulation: CoSimulation {
            model_identifier: m.model_identifier,
            variable_step: true,
            interpolate_inputs: caps.interpolate_inputs,
            max_output_derivative_order: 0,
            asynchronous: false,
            once_per_process: false,
            no_memory_functions: true,
            get_set_state: caps.get_set_state,
            serialize_state: caps.serialize_state,
            directional_derivative: caps.directional_derivative,
        },
        units: unit_definitions(m, &[]),
        log_categories: log_categories(m, "fmi2"),
        default_experiment: DEFAULT_EXPERIMENT,
        variables: ModelVariables { vars },
        structure: ModelStructure {
            outputs: unknowns(false),
            initial: unknowns(true),
        },
    })
}
