//! `modelDescription.xml` generated from the variable tables (serde + quick-xml); a pure
//! function, no I/O. The committed files under `modelDescription/` must equal its output.

use crate::error::Category;
use crate::model::variables::{table, Causality, Start, Table, Variability, Variant};

pub use crate::model::variables::xml_real;

/// `copyright` of every model description (the LICENSE file at the repository's top).
pub const COPYRIGHT: &str = "Copyright (c) 2026 the connector_fmu authors";
/// `license` of every model description (Cargo.toml's licence; the text is in LICENSE).
pub const LICENSE: &str = "MIT";
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

/// `<UnitDefinitions>`: the units a table uses (shared by the FMI 2.0 and 3.0 generators).
#[derive(Serialize)]
pub(crate) struct UnitDefinitions {
    #[serde(rename = "Unit")]
    units: Vec<Unit>,
}

#[derive(Serialize)]
struct Unit {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "BaseUnit")]
    base: BaseUnit,
}

#[derive(Serialize, Default)]
struct BaseUnit {
    #[serde(rename = "@kg", skip_serializing_if = "is_zero")]
    kg: i32,
    #[serde(rename = "@m", skip_serializing_if = "is_zero")]
    m: i32,
    #[serde(rename = "@s", skip_serializing_if = "is_zero")]
    s: i32,
    #[serde(rename = "@rad", skip_serializing_if = "is_zero")]
    rad: i32,
}

fn is_zero(x: &i32) -> bool {
    *x == 0
}

/// `<LogCategories>` (shared by the FMI 2.0 and 3.0 generators).
#[derive(Serialize)]
pub(crate) struct LogCategories {
    #[serde(rename = "Category")]
    categories: Vec<LogCategory>,
}

#[derive(Serialize)]
struct LogCategory {
    #[serde(rename = "@name")]
    name: &'static str,
    #[serde(rename = "@description")]
    description: String,
}

/// `<DefaultExperiment>` (shared by the FMI 2.0 and 3.0 generators).
#[derive(Serialize)]
pub(crate) struct DefaultExperiment {
    #[serde(rename = "@startTime")]
    start: &'static str,
    #[serde(rename = "@stopTime")]
    stop: &'static str,
    #[serde(rename = "@stepSize")]
    step: &'static str,
}

/// The units of `t`'s variables and of `extra` (FMI 3.0's `time`), in `UNITS` order.
pub(crate) fn unit_definitions(t: &Table, extra: &[&str]) -> UnitDefinitions {
    let mut used: std::collections::BTreeSet<&str> = t.vars.iter().map(|v| v.unit).collect();
    used.extend(extra);
    let units = UNITS
        .iter()
        .filter(|(n, _)| used.contains(n))
        .map(|&(name, [kg, m, s, rad])| Unit {
            name,
            base: BaseUnit { kg, m, s, rad },
        })
        .collect();
    UnitDefinitions { units }
}

/// The log categories, their descriptions naming the functions of FMI version `fmi` ("fmi2",
/// "fmi3").
pub(crate) fn log_categories(fmi: &str) -> LogCategories {
    LogCategories {
        categories: Category::ALL
            .iter()
            .map(|c| LogCategory {
                name: c.name(),
                description: c.description().replace("fmi2", fmi),
            })
            .collect(),
    }
}

/// The default experiment: 1 s in steps of 1 ms.
pub(crate) const DEFAULT_EXPERIMENT: DefaultExperiment = DefaultExperiment {
    start: "0",
    stop: "1",
    step: "0.001",
};

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

/// Units used by the tables, with their SI base-unit exponents (kg, m, s, rad); the FMI 3.0
/// description declares the same.
pub const UNITS: [(&str, [i32; 4]); 15] = [
    ("m", [0, 1, 0, 0]),
    ("rad", [0, 0, 0, 1]),
    ("m/s", [0, 1, -1, 0]),
    ("rad/s", [0, 0, -1, 1]),
    ("m/s2", [0, 1, -2, 0]),
    ("rad/s2", [0, 0, -2, 1]),
    ("N", [1, 1, -2, 0]),
    ("N.m", [1, 2, -2, 0]),
    ("J", [1, 2, -2, 0]),
    ("N/m", [1, 0, -2, 0]),
    ("N.s/m", [1, 0, -1, 0]),
    ("N.m/rad", [1, 2, -2, -1]),
    ("N.m.s/rad", [1, 2, -1, -1]),
    ("s/m", [0, -1, 1, 0]),
    ("s", [0, 0, 1, 0]),
];

/// The model description of a variant as XML text.
pub fn model_description(v: Variant) -> String {
    let t = table(v);
    let md = build(t);
    let mut body = String::new();
    let mut ser = quick_xml::se::Serializer::new(&mut body);
    ser.indent(' ', 2);
    // Why no `?`: serialising plain structs into a String cannot fail; an error here would
    // be a bug in the structs above, which the drift test would show at once.
    if md.serialize(ser).is_err() {
        return String::new();
    }
    format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{body}\n")
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
            causality: match v.causality {
                Causality::Parameter => "parameter",
                Causality::Input => "input",
                Causality::Output => "output",
            },
            variability: match v.variability {
                Variability::Fixed => "fixed",
                Variability::Tunable => "tunable",
                Variability::Discrete => "discrete",
                Variability::Continuous => "continuous",
            },
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
