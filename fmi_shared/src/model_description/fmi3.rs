//! The FMI 3.0 `modelDescription.xml` of a `super::Model` (serde + quick-xml), from the same rows
//! as the FMI 2.0 one: the same names, value references, units, start values, causality and
//! variability; Real → Float64, Integer → Int32, Boolean → Boolean; `instantiationToken` is the
//! FMI 2.0 GUID; plus the independent variable `time` (`TIME_VR`). A pure function, no I/O.
//! Uses the shared elements of `super`; connector_fmu's and body_fmu's
//! `model_description::fmi3` use it with their tables and capabilities.

use super::{
    join, log_categories, to_xml, unit_definitions, DefaultExperiment, LogCategories, Model, Type,
    UnitDefinitions, COPYRIGHT, DEFAULT_EXPERIMENT, LICENSE,
};
use serde::Serialize;

/// The value reference of the independent variable `time` (FMI 3.0 requires one; no table
/// uses 0).
pub const TIME_VR: u32 = 0;

/// The capability flags that differ between the FMUs; the others are the same for both (no
/// execution tool, any number of instances per process, no per-element dependencies, output
/// derivatives of order 0, no evaluation of discrete states).
pub struct Capabilities {
    /// `canGetAndSetFMUState`.
    pub get_set_state: bool,
    /// `canSerializeFMUState`.
    pub serialize_state: bool,
    /// `providesDirectionalDerivatives`.
    pub directional: bool,
    /// `providesAdjointDerivatives`.
    pub adjoint: bool,
    /// `canHandleVariableCommunicationStepSize`.
    pub variable_step: bool,
    /// `providesIntermediateUpdate`.
    pub intermediate_update: bool,
    /// `mightReturnEarlyFromDoStep`.
    pub might_return_early: bool,
    /// `canReturnEarlyAfterIntermediateUpdate`.
    pub early_after_intermediate: bool,
    /// `hasEventMode`.
    pub has_event_mode: bool,
}

#[derive(Serialize)]
#[serde(rename = "fmiModelDescription")]
struct ModelDescription {
    #[serde(rename = "@fmiVersion")]
    fmi_version: &'static str,
    #[serde(rename = "@modelName")]
    model_name: &'static str,
    #[serde(rename = "@instantiationToken")]
    token: String,
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
    #[serde(rename = "@needsExecutionTool")]
    needs_execution_tool: bool,
    #[serde(rename = "@canBeInstantiatedOnlyOncePerProcess")]
    once_per_process: bool,
    #[serde(rename = "@canGetAndSetFMUState")]
    get_set_state: bool,
    #[serde(rename = "@canSerializeFMUState")]
    serialize_state: bool,
    #[serde(rename = "@providesDirectionalDerivatives")]
    directional: bool,
    #[serde(rename = "@providesAdjointDerivatives")]
    adjoint: bool,
    #[serde(rename = "@providesPerElementDependencies")]
    per_element_dependencies: bool,
    #[serde(rename = "@canHandleVariableCommunicationStepSize")]
    variable_step: bool,
    #[serde(rename = "@maxOutputDerivativeOrder")]
    max_output_derivative_order: u32,
    #[serde(rename = "@providesIntermediateUpdate")]
    intermediate_update: bool,
    #[serde(rename = "@mightReturnEarlyFromDoStep")]
    might_return_early: bool,
    #[serde(rename = "@canReturnEarlyAfterIntermediateUpdate")]
    early_after_intermediate: bool,
    #[serde(rename = "@hasEventMode")]
    has_event_mode: bool,
    #[serde(rename = "@providesEvaluateDiscreteStates")]
    evaluate_discrete_states: bool,
}

#[derive(Serialize)]
struct ModelVariables {
    #[serde(rename = "$value")]
    vars: Vec<Variable>,
}

/// One variable element; its name is the FMI 3.0 type.
#[derive(Serialize)]
enum Variable {
    Float64(Attrs),
    Int32(Attrs),
    Boolean(Attrs),
}

#[derive(Serialize)]
struct Attrs {
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
    #[serde(rename = "@unit", skip_serializing_if = "Option::is_none")]
    unit: Option<&'static str>,
    #[serde(rename = "@min", skip_serializing_if = "Option::is_none")]
    min: Option<String>,
    #[serde(rename = "@max", skip_serializing_if = "Option::is_none")]
    max: Option<String>,
    #[serde(rename = "@start", skip_serializing_if = "Option::is_none")]
    start: Option<String>,
}

#[derive(Serialize)]
struct ModelStructure {
    #[serde(rename = "Output")]
    outputs: Vec<Unknown>,
    #[serde(rename = "InitialUnknown")]
    initial: Vec<Unknown>,
}

#[derive(Serialize)]
struct Unknown {
    #[serde(rename = "@valueReference")]
    vr: u32,
    #[serde(rename = "@dependencies")]
    dependencies: String,
}

/// The FMI 3.0 model description of `m` as XML text; dependencies are listed as value
/// references in increasing order.
pub fn model_description(m: &Model, caps: &Capabilities) -> String {
    let time = Variable::Float64(Attrs {
        name: "time".to_string(),
        vr: TIME_VR,
        description: "simulation time".to_string(),
        causality: "independent",
        variability: "continuous",
        unit: Some("s"),
        min: None,
        max: None,
        start: None,
    });
    let vars = std::iter::once(time)
        .chain(m.variables.iter().map(|v| {
            let attrs = |unit| Attrs {
                name: v.name.clone(),
                vr: v.vr,
                description: v.description.clone(),
                causality: v.causality.name(),
                variability: v.variability.name(),
                unit,
                min: v.min.clone(),
                max: v.max.clone(),
                start: v.start.clone(),
            };
            match v.ty {
                Type::Real => Variable::Float64(attrs(v.unit)),
                Type::Integer => Variable::Int32(attrs(None)),
                Type::Boolean => Variable::Boolean(attrs(None)),
            }
        }))
        .collect();
    let unknowns = |initial: bool| {
        m.outputs
            .iter()
            .map(|o| {
                let mut deps = if initial { &o.initial } else { &o.dependencies }.clone();
                deps.sort_unstable();
                Unknown {
                    vr: o.vr,
                    dependencies: join(deps),
                }
            })
            .collect()
    };
    to_xml(&ModelDescription {
        fmi_version: "3.0",
        model_name: m.model_identifier,
        token: m.guid.clone(),
        description: m.description,
        author: m.author,
        version: m.version,
        copyright: COPYRIGHT,
        license: LICENSE,
        generation_tool: m.generation_tool.clone(),
        naming: "structured",
        co_simulation: CoSimulation {
            model_identifier: m.model_identifier,
            needs_execution_tool: false,
            once_per_process: false,
            get_set_state: caps.get_set_state,
            serialize_state: caps.serialize_state,
            directional: caps.directional,
            adjoint: caps.adjoint,
            per_element_dependencies: false,
            variable_step: caps.variable_step,
            max_output_derivative_order: 0,
            intermediate_update: caps.intermediate_update,
            might_return_early: caps.might_return_early,
            early_after_intermediate: caps.early_after_intermediate,
            has_event_mode: caps.has_event_mode,
            evaluate_discrete_states: false,
        },
        units: unit_definitions(m, &["s"]), // "s": the time variable
        log_categories: log_categories(m, "fmi3"),
        default_experiment: DEFAULT_EXPERIMENT,
        variables: ModelVariables { vars },
        structure: ModelStructure {
            outputs: unknowns(false),
            initial: unknowns(true),
        },
    })
}
