//! The FMI 3.0 `modelDescription.xml` generated from the same variable tables as the FMI 2.0
//! one (`super::fmi2`): same names, value references, units, start values, causality and
//! variability; Real → Float64, Integer → Int32, Boolean → Boolean; `instantiationToken` is
//! the FMI 2.0 GUID. A pure function, no I/O: the committed files under `modelDescription/fmi3/`
//! must equal its output. The model structure (`dependencies`) is also what
//! fmi3GetVariableDependencies answers at run time.

use super::{
    causality, log_categories, to_xml, unit_definitions, variability, xml_real, DefaultExperiment,
    LogCategories, UnitDefinitions, COPYRIGHT, DEFAULT_EXPERIMENT, LICENSE,
};
use crate::model::variables::{table, Causality, Start, Table, Variant};
use serde::Serialize;

/// The value reference of the independent variable `time` (FMI 3.0 requires one; no table
/// uses 0). fmi3GetFloat64 reads the FMU's time through it; it cannot be set.
pub const TIME_VR: u32 = 0;

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
    Float64(Var),
    Int32(Var),
    Boolean(Var),
}

#[derive(Serialize)]
struct Var {
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
    to_xml(&build(table(v)))
}

fn build(t: &Table) -> ModelDescription {
    let spec = t.spec;
    let time = Variable::Float64(Var {
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
        .chain(t.vars.iter().map(|v| {
            let (min, max) = v.range_text();
            let var = |start: Option<String>, unit: Option<&'static str>| Var {
                name: v.name.clone(),
                vr: v.vr,
                description: v.description.clone(),
                causality: causality(v.causality),
                variability: variability(v.variability),
                unit,
                min: min.clone(),
                max: max.clone(),
                start,
            };
            match v.start {
                Start::Real(s) => Variable::Float64(var(
                    s.map(xml_real),
                    (!v.unit.is_empty() && v.unit != "1").then_some(v.unit),
                )),
                Start::Integer(s) => Variable::Int32(var(s.map(|x| x.to_string()), None)),
                Start::Boolean(s) => Variable::Boolean(var(s.map(|x| x.to_string()), None)),
            }
        }))
        .collect();
    let join = |d: Vec<u32>| {
        d.iter()
            .map(|x| x.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    let unknowns = |initial: bool| {
        t.vars
            .iter()
            .filter(|v| v.causality == Causality::Output)
            .map(|v| Unknown {
                vr: v.vr,
                dependencies: join(dependencies(t, v.vr, initial).unwrap_or_default()),
            })
            .collect()
    };
    use capabilities::*;
    ModelDescription {
        fmi_version: "3.0",
        model_name: spec.model_identifier,
        token: t.guid.clone(),
        description: spec.description,
        author: env!("CARGO_PKG_AUTHORS"),
        version: env!("CARGO_PKG_VERSION"),
        copyright: COPYRIGHT,
        license: LICENSE,
        generation_tool: format!("connector_fmu {}", env!("CARGO_PKG_VERSION")),
        naming: "structured",
        co_simulation: CoSimulation {
            model_identifier: spec.model_identifier,
            needs_execution_tool: false,
            once_per_process: false,
            get_set_state: CAN_GET_AND_SET_FMU_STATE,
            serialize_state: CAN_SERIALIZE_FMU_STATE,
            directional: PROVIDES_DIRECTIONAL_DERIVATIVES,
            adjoint: PROVIDES_ADJOINT_DERIVATIVES,
            per_element_dependencies: false,
            variable_step: CAN_HANDLE_VARIABLE_COMMUNICATION_STEP_SIZE,
            max_output_derivative_order: 0,
            intermediate_update: PROVIDES_INTERMEDIATE_UPDATE,
            might_return_early: MIGHT_RETURN_EARLY_FROM_DO_STEP,
            early_after_intermediate: CAN_RETURN_EARLY_AFTER_INTERMEDIATE_UPDATE,
            has_event_mode: HAS_EVENT_MODE,
            evaluate_discrete_states: false,
        },
        units: unit_definitions(t, &["s"]), // "s": the time variable
        log_categories: log_categories("fmi3"),
        default_experiment: DEFAULT_EXPERIMENT,
        variables: ModelVariables { vars },
        structure: ModelStructure {
            outputs: unknowns(false),
            initial: unknowns(true),
        },
    }
}
