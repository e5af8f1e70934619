//! The FMI 2.0 `modelDescription.xml`, generated from the variable table (serde + quick-xml); a
//! pure function, no I/O. bodies/modelDescription/Body.xml must equal its output. Uses the
//! shared elements of `super` and `crate::variables`.

use super::{
    causality, dependencies, generation_tool, log_categories, to_xml, unit, unit_definitions,
    variability, DefaultExperiment, LogCategories, UnitDefinitions, COPYRIGHT, DEFAULT_EXPERIMENT,
    LICENSE,
};
use crate::variables::{guid, xml_real, Causality, Var, DESCRIPTION, MODEL_IDENTIFIER, VARS};
use serde::Serialize;

#[derive(Serialize)]
#[serde(rename = "fmiModelDescription")]
struct ModelDescription {
    #[serde(rename = "@fmiVersion")]
    fmi_version: &'static str,
    #[serde(rename = "@modelName")]
    model_name: &'static str,
    #[serde(rename = "@guid")]
    guid: &'static str,
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

/// The capabilities: only what works and is tested.
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
    name: &'static str,
    #[serde(rename = "@valueReference")]
    vr: u32,
    #[serde(rename = "@description")]
    description: &'static str,
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

fn variable(v: &Var) -> ScalarVariable {
    let number = |x: Option<f64>, integer: bool| {
        x.map(|x| match integer {
            true => format!("{}", x as i32),
            false => xml_real(x),
        })
    };
    let i = v.is_integer();
    let attrs = Attrs {
        start: number(v.start, i),
        unit: if i { None } else { unit(v) },
        min: number(v.min, i),
        max: number(v.max, i),
    };
    ScalarVariable {
        name: v.name,
        vr: v.vr,
        description: v.description,
        causality: causality(v.causality),
        variability: variability(v.variability),
        ty: if i {
            TypeElement::Integer(attrs)
        } else {
            TypeElement::Real(attrs)
        },
    }
}

/// The FMI 2.0 model description as XML text.
pub fn model_description() -> String {
    // ModelStructure: 1-based indices into ModelVariables
    let index = |vr: u32| VARS.iter().position(|v| v.vr == vr).map_or(0, |i| i + 1);
    let unknowns = |initial: bool| Unknowns {
        unknowns: VARS
            .iter()
            .filter(|v| v.causality == Causality::Output)
            .map(|v| Unknown {
                index: index(v.vr),
                dependencies: dependencies(v.vr, initial)
                    .unwrap_or_default()
                    .iter()
                    .map(|&d| index(d).to_string())
                    .collect::<Vec<_>>()
                    .join(" "),
            })
            .collect(),
    };
    to_xml(&ModelDescription {
        fmi_version: "2.0",
        model_name: MODEL_IDENTIFIER,
        guid: guid(),
        description: DESCRIPTION,
        author: env!("CARGO_PKG_AUTHORS"),
        version: env!("CARGO_PKG_VERSION"),
        copyright: COPYRIGHT,
        license: LICENSE,
        generation_tool: generation_tool(),
        naming: "structured",
        event_indicators: 0,
        co_simulation: CoSimulation {
            model_identifier: MODEL_IDENTIFIER,
            variable_step: true,
            interpolate_inputs: false,
            max_output_derivative_order: 0,
            asynchronous: false,
            once_per_process: false,
            no_memory_functions: true,
            get_set_state: true,
            serialize_state: true,
            directional_derivative: false,
        },
        units: unit_definitions(&[]),
        log_categories: log_categories("fmi2"),
        default_experiment: DEFAULT_EXPERIMENT,
        variables: ModelVariables {
            vars: VARS.iter().map(variable).collect(),
        },
        structure: ModelStructure {
            outputs: unknowns(false),
            initial: unknowns(true),
        },
    })
}
