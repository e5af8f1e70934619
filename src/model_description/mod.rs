//! The model descriptions generated from the variable tables: FMI 2.0 (`fmi2`,
//! `modelDescription/<Variant>.xml`) and FMI 3.0 (`fmi3`, `modelDescription/fmi3/<Variant>.xml`),
//! and here, once, what both declare alike: units, log categories, the default experiment,
//! copyright and licence, the causality and variability names, and the XML text around the
//! serialized structs. Pure functions of the tables (`crate::model::variables`), no I/O; the
//! committed files must equal their output (tests/model_description*.rs).

pub mod fmi2;
pub mod fmi3;

use crate::error::Category;
use crate::model::variables::{Causality, Table, Variability};
use serde::Serialize;

pub use crate::model::variables::xml_real;

/// `copyright` of every model description (the LICENSE file at the repository's top).
pub const COPYRIGHT: &str = "Copyright (c) 2026 the connector_fmu authors";
/// `license` of every model description (Cargo.toml's licence; the text is in LICENSE).
pub const LICENSE: &str = "MIT";

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

/// The `causality` attribute of a table row.
fn causality(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::Input => "input",
        Causality::Output => "output",
    }
}

/// The `variability` attribute of a table row.
fn variability(v: Variability) -> &'static str {
    match v {
        Variability::Fixed => "fixed",
        Variability::Tunable => "tunable",
        Variability::Discrete => "discrete",
        Variability::Continuous => "continuous",
    }
}

/// `<UnitDefinitions>`: the units a table uses .
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

/// `<LogCategories>` .
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

/// `<DefaultExperiment>` .
#[derive(Serialize)]
pub struct DefaultExperiment {
    #[serde(rename = "@startTime")]
    start: &'static str,
    #[serde(rename = "@stopTime")]
    stop: &'static str,
    #[serde(rename = "@stepSize")]
    step: &'static str,
}

/// The units of `t`'s variables and of `extra` (FMI 3.0's `time`), in `UNITS` order.
pub fn unit_definitions(t: &Table, extra: &[&str]) -> UnitDefinitions {
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
pub fn log_categories(fmi: &str) -> LogCategories {
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
pub const DEFAULT_EXPERIMENT: DefaultExperiment = DefaultExperiment {
    start: "0",
    stop: "1",
    step: "0.001",
};

/// Units used by the tables, with their SI base-unit exponents (kg, m, s, rad).
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
