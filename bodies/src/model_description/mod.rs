//! The model descriptions generated from the variable table: FMI 2.0 (`fmi2`,
//! bodies/modelDescription/Body.xml) and FMI 3.0 (`fmi3`, bodies/modelDescription/fmi3/Body.xml),
//! and here, once, what both declare alike: units, log categories, default experiment,
//! copyright and licence, the causality and variability names, the model structure's
//! dependencies and the XML text around the serialized structs. Pure functions of
//! `crate::variables` (and `crate::error`'s categories), no I/O; the committed files must equal
//! their output (bodies/tests/model_description.rs).

pub mod fmi2;
pub mod fmi3;

use crate::error::Category;
use crate::variables::{Causality, Var, Variability, VARS};
use serde::Serialize;

/// `copyright` (the LICENSE file at the repository's top).
pub const COPYRIGHT: &str = "Copyright (c) 2026 the connector_fmu authors";
/// `license` (Cargo.toml's licence; the text is in LICENSE).
pub const LICENSE: &str = "MIT";

/// The XML text: the declaration, then the struct serialized with two-space indentation.
fn to_xml<T: Serialize>(md: &T) -> String {
    let mut body = String::new();
    let mut ser = quick_xml::se::Serializer::new(&mut body);
    ser.indent(' ', 2);
    // Why no `?`: serialising plain structs into a String cannot fail; an error here would be
    // a bug in the structs, which the drift test would show at once.
    if md.serialize(ser).is_err() {
        return String::new();
    }
    format!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n{body}\n")
}

/// The `causality` attribute.
fn causality(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::Input => "input",
        Causality::Output => "output",
    }
}

/// The `variability` attribute.
fn variability(v: Variability) -> &'static str {
    match v {
        Variability::Fixed => "fixed",
        Variability::Continuous => "continuous",
    }
}

/// The unit attribute of a row (none for a dimensionless variable).
fn unit(v: &Var) -> Option<&'static str> {
    (!v.unit.is_empty()).then_some(v.unit)
}

/// The value references an output depends on: none at communication points (`initial ==
/// false`: no direct feedthrough, the outputs are the body's state), every parameter in
/// Initialization Mode. None for a value reference that is not an output.
pub fn dependencies(vr: u32, initial: bool) -> Option<Vec<u32>> {
    let v = VARS.iter().find(|v| v.vr == vr)?;
    if v.causality != Causality::Output {
        return None;
    }
    Some(match initial {
        false => Vec::new(),
        true => VARS
            .iter()
            .filter(|p| p.causality == Causality::Parameter)
            .map(|p| p.vr)
            .collect(),
    })
}

/// `<UnitDefinitions>`.
#[derive(Serialize)]
pub struct UnitDefinitions {
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

/// The table's units and `extra` (FMI 3.0's `s` of `time`), in `UNITS` order.
pub fn unit_definitions(extra: &[&str]) -> UnitDefinitions {
    let used = |n: &str| VARS.iter().any(|v| v.unit == n) || extra.contains(&n);
    UnitDefinitions {
        units: UNITS
            .iter()
            .filter(|(n, _)| used(n))
            .map(|&(name, [kg, m, s, rad])| Unit {
                name,
                base: BaseUnit { kg, m, s, rad },
            })
            .collect(),
    }
}

/// Units with their SI base-unit exponents (kg, m, s, rad).
pub const UNITS: [(&str, [i32; 4]); 12] = [
    ("m", [0, 1, 0, 0]),
    ("rad", [0, 0, 0, 1]),
    ("m/s", [0, 1, -1, 0]),
    ("rad/s", [0, 0, -1, 1]),
    ("m/s2", [0, 1, -2, 0]),
    ("N", [1, 1, -2, 0]),
    ("N.m", [1, 2, -2, 0]),
    ("J", [1, 2, -2, 0]),
    ("N/m", [1, 0, -2, 0]),
    ("kg", [1, 0, 0, 0]),
    ("kg.m2", [1, 2, 0, 0]),
    ("s", [0, 0, 1, 0]),
];

/// `<LogCategories>`.
#[derive(Serialize)]
pub struct LogCategories {
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

/// The log categories, described with the function names of FMI version `fmi` ("fmi2",
/// "fmi3").
pub fn log_categories(fmi: &str) -> LogCategories {
    LogCategories {
        categories: Category::ALL
            .iter()
            .map(|c| LogCategory {
                name: c.name(),
                description: c.description(fmi),
            })
            .collect(),
    }
}

/// `<DefaultExperiment>`.
#[derive(Serialize)]
pub struct DefaultExperiment {
    #[serde(rename = "@startTime")]
    start: &'static str,
    #[serde(rename = "@stopTime")]
    stop: &'static str,
    #[serde(rename = "@stepSize")]
    step: &'static str,
}

/// The default experiment: 1 s in steps of 1 ms.
pub const DEFAULT_EXPERIMENT: DefaultExperiment = DefaultExperiment {
    start: "0",
    stop: "1",
    step: "0.001",
};

/// The generation tool attribute.
fn generation_tool() -> String {
    format!("body_fmu {}", env!("CARGO_PKG_VERSION"))
}
