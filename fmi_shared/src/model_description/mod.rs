//! The model-description XML of both FMUs, once: the serde + quick-xml structures of the FMI 2.0
//! (`fmi2`) and FMI 3.0 (`fmi3`) `modelDescription.xml`, and here what both versions declare
//! alike: copyright and licence, units, log categories, the default experiment, the causality
//! and variability enums (the FMU crates' tables use them) and the XML text around the
//! serialized structs. Generic over plain data: a crate describes its model as a
//! `Model` (identifier, GUID, descriptive attributes, unit table, log categories, variable rows,
//! outputs with their dependencies) built from its own variable table. Pure functions, no I/O.
//! Uses serde and quick-xml only; connector_fmu (src/model_description) and body_fmu
//! (bodies/src/model_description) use it.

pub mod fmi2;
pub mod fmi3;

use serde::Serialize;

/// `copyright` of every model description (the LICENSE file at the repository's top).
pub const COPYRIGHT: &str = "Copyright (c) 2026 the connector_fmu authors";
/// `license` of every model description (Cargo.toml's licence; the text is in LICENSE).
pub const LICENSE: &str = "MIT";

/// A model as its model descriptions declare it, the same for FMI 2.0 and FMI 3.0.
pub struct Model {
    /// `modelName` and `modelIdentifier`.
    pub model_identifier: &'static str,
    /// The FMI 2.0 `guid`, also the FMI 3.0 `instantiationToken`.
    pub guid: String,
    /// `description`.
    pub description: &'static str,
    /// `author` (the FMU crate's authors).
    pub author: &'static str,
    /// `version` (the FMU crate's version).
    pub version: &'static str,
    /// `generationTool`.
    pub generation_tool: String,
    /// The crate's units with their SI base-unit exponents (kg, m, s, rad), in declaration order.
    pub units: &'static [(&'static str, [i32; 4])],
    /// The units the variables use (as in the table: "" and "1" are never declared).
    pub used_units: Vec<&'static str>,
    /// The log categories' names and descriptions, written for FMI 2.0 (`fmi2…` function names;
    /// the FMI 3.0 description spells them `fmi3…`).
    pub log_categories: Vec<(&'static str, String)>,
    /// The variables, in model-description order.
    pub variables: Vec<Variable>,
    /// The outputs, in model-description order, with what they depend on.
    pub outputs: Vec<Output>,
}

/// FMI causality of a variable (FMI 3.0's `independent` is only `time`'s, written by `fmi3`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    /// parameter
    Parameter,
    /// input
    Input,
    /// output
    Output,
}

impl Causality {
    /// The `causality` attribute.
    pub fn name(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::Input => "input",
            Causality::Output => "output",
        }
    }
}

/// FMI variability of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    /// fixed: set before initialization ends
    Fixed,
    /// tunable: may change between steps
    Tunable,
    /// discrete
    Discrete,
    /// continuous
    Continuous,
}

impl Variability {
    /// The `variability` attribute.
    pub fn name(self) -> &'static str {
        match self {
            Variability::Fixed => "fixed",
            Variability::Tunable => "tunable",
            Variability::Discrete => "discrete",
            Variability::Continuous => "continuous",
        }
    }
}

/// The base type of a variable (FMI 3.0: Real → Float64, Integer → Int32).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Type {
    /// Real / Float64
    Real,
    /// Integer / Int32
    Integer,
    /// Boolean
    Boolean,
}

/// One variable row with its attributes as the XML spells them.
pub struct Variable {
    /// `name`.
    pub name: String,
    /// `valueReference`.
    pub vr: u32,
    /// `description`.
    pub description: String,
    /// `causality`.
    pub causality: Causality,
    /// `variability`.
    pub variability: Variability,
    /// The base type.
    pub ty: Type,
    /// `unit` (Real only).
    pub unit: Option<&'static str>,
    /// `start`.
    pub start: Option<String>,
    /// `min` (never written for an FMI 2.0 Boolean).
    pub min: Option<String>,
    /// `max` (never written for an FMI 2.0 Boolean).
    pub max: Option<String>,
}

/// An output and the value references it depends on, in model-description order: at
/// communication points (ModelStructure Outputs / Output) and in Initialization Mode
/// (InitialUnknowns / InitialUnknown).
pub struct Output {
    /// The output's value reference.
    pub vr: u32,
    /// What it depends on at communication points.
    pub dependencies: Vec<u32>,
    /// What it depends on in Initialization Mode.
    pub initial: Vec<u32>,
}

/// The XML text of a model description: the declaration, then the struct serialized with
/// two-space indentation.
fn to_xml<T: Serialize>(md: &T) -> String {
    let mut body = String::new();
    let mut ser = quick_xml::se::Serializer::new(&mut body);
    ser.indent(' ', 2);
    // Why no `?`: serialising plain structs into a String cannot fail; an error here would
    // be a bug in the structs, which the drift tests would show at once.
    if md.serialize(ser).is_err() {
        return String::new();
    }
    format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{body}\n")
}

/// Space-separated numbers, as `dependencies` lists them.
fn join(xs: impl IntoIterator<Item = impl ToString>) -> String {
    xs.into_iter()
        .map(|x| x.to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

/// `<UnitDefinitions>`: the units a model uses.
#[derive(Serialize)]
struct UnitDefinitions {
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

#[derive(Serialize)]
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

/// The units of `m`'s variables and of `extra` (FMI 3.0's `s` of `time`), in `m.units` order.
fn unit_definitions(m: &Model, extra: &[&str]) -> UnitDefinitions {
    let used = |n: &str| m.used_units.contains(&n) || extra.contains(&n);
    UnitDefinitions {
        units: m
            .units
            .iter()
            .filter(|(n, _)| used(n))
            .map(|&(name, [kg, m, s, rad])| Unit {
                name,
                base: BaseUnit { kg, m, s, rad },
            })
            .collect(),
    }
}

/// `<LogCategories>`.
#[derive(Serialize)]
struct LogCategories {
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

/// `m`'s log categories, their descriptions naming the functions of FMI version `fmi` ("fmi2",
/// "fmi3").
fn log_categories(m: &Model, fmi: &str) -> LogCategories {
    LogCategories {
        categories: m
            .log_categories
            .iter()
            .map(|&(name, ref description)| LogCategory {
                name,
                description: description.replace("fmi2", fmi),
            })
            .collect(),
    }
}

/// `<DefaultExperiment>`.
#[derive(Serialize)]
struct DefaultExperiment {
    #[serde(rename = "@startTime")]
    start: &'static str,
    #[serde(rename = "@stopTime")]
    stop: &'static str,
    #[serde(rename = "@stepSize")]
    step: &'static str,
}

/// The default experiment: 1 s in steps of 1 ms.
const DEFAULT_EXPERIMENT: DefaultExperiment = DefaultExperiment {
    start: "0",
    stop: "1",
    step: "0.001",
};
