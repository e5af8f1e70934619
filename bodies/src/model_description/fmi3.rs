//! The FMI 3.0 `modelDescription.xml`, generated from the same table as the FMI 2.0 one: the
//! same names, value references, units, start values, causality and variability; Real →
//! Float64, Integer → Int32; `instantiationToken` is the FMI 2.0 GUID; plus the independent
//! variable `time` (value reference 0). A pure function, no I/O:
//! bodies/modelDescription/fmi3/Body.xml must equal its output. Uses the shared elements of
//! `super` and `crate::variables`.

use super::{
    causality, dependencies, generation_tool, log_categories, to_xml, unit, unit_definitions,
    variability, DefaultExperiment, LogCategories, UnitDefinitions, COPYRIGHT, DEFAULT_EXPERIMENT,
    LICENSE,
};
use crate::variables::{
    guid, xml_real, Causality, Var, DESCRIPTION, MODEL_IDENTIFIER, TIME_VR, VARS,
};
use serde::Serialize;

#[derive(Serialize)]
#[serde(rename = "fmiModelDescription")]
struct ModelDescription {
    #[serde(rename = "@fmiVersion")]
    fmi_version: &'static str,
    #[serde(rename = "@modelName")]
    model_name: &'static str,
    #[serde(rename = "@instantiationToken")]
    token: &'static str,
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

/// The capabilities: only what works and is tested; no early return, no Event Mode, no
/// derivatives.
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
}

#[derive(Serialize)]
struct Attrs {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@valueReference")]
    vr: u32,
    #[serde(rename = "@description")]
    description: &'static str,
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

fn variable(v: &Var) -> Variable {
    let i = v.is_integer();
    let number = |x: Option<f64>| {
        x.map(|x| match i {
            true => format!("{}", x as i32),
            false => xml_real(x),
        })
    };
    let attrs = Attrs {
        name: v.name,
        vr: v.vr,
        description: v.description,
        causality: causality(v.causality),
        variability: variability(v.variability),
        unit: if i { None } else { unit(v) },
        min: number(v.min),
        max: number(v.max),
        start: number(v.start),
    };
    if i {
        Variable::Int32(attrs)
    } else {
        Variable::Float64(attrs)
    }
}

/// The FMI 3.0 model description as XML text.
pub fn model_description() -> String {
    let time = Variable::Float64(Attrs {
        name: "time",
        vr: TIME_VR,
        description: "simulation time",
        causality: "independent",
        variability: "continuous",
        unit: Some("s"),
        min: None,
        max: None,
        start: None,
    });
    let unknowns = |initial: bool| {
        VARS.iter()
            .filter(|v| v.causality == Causality::Output)
            .map(|v| Unknown {
                vr: v.vr,
                dependencies: dependencies(v.vr, initial)
                    .unwrap_or_default()
                    .iter()
                    .map(|d| d.to_string())
                    .collect::<Vec<_>>()
                    .join(" "),
            })
            .collect()
    };
    to_xml(&ModelDescription {
        fmi_version: "3.0",
        model_name: MODEL_IDENTIFIER,
        token: guid(),
        description: DESCRIPTION,
        author: env!("CARGO_PKG_AUTHORS"),
        version: env!("CARGO_PKG_VERSION"),
        copyright: COPYRIGHT,
        license: LICENSE,
        generation_tool: generation_tool(),
        naming: "structured",
        co_simulation: CoSimulation {
            model_identifier: MODEL_IDENTIFIER,
            needs_execution_tool: false,
            once_per_process: false,
            get_set_state: true,
            serialize_state: true,
            directional: false,
            adjoint: false,
            per_element_dependencies: false,
            variable_step: true,
            max_output_derivative_order: 0,
            intermediate_update: false,
            might_return_early: false,
            early_after_intermediate: false,
            has_event_mode: false,
            evaluate_discrete_states: false,
        },
        units: unit_definitions(&["s"]),
        log_categories: log_categories("fmi3"),
        default_experiment: DEFAULT_EXPERIMENT,
        variables: ModelVariables {
            vars: std::iter::once(time)
                .chain(VARS.iter().map(variable))
                .collect(),
        },
        structure: ModelStructure {
            outputs: unknowns(false),
            initial: unknowns(true),
        },
    })
}
