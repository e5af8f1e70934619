//! The model descriptions generated from the variable tables: FMI 2.0 (`fmi2`,
//! `modelDescription/<Variant>.xml`) and FMI 3.0 (`fmi3`, `modelDescription/fmi3/<Variant>.xml`).
//! The XML structures and what both versions declare alike (copyright, licence, default
//! experiment, the XML text) are `fmi_shared::model_description`'s, shared with the Body FMU;
//! here, once for both versions, is what this crate gives them: a variant's table as a
//! `fmi_shared::model_description::Model` (its rows, units, log categories, outputs with their
//! dependencies) and the unit table. Pure functions
//! of the tables (`crate::model::variables`, `crate::error`'s categories), no I/O; the
//! committed files must equal their output (tests/model_description*.rs).

pub mod fmi2;
pub mod fmi3;

use crate::error::Category;
use crate::model::variables::{Start, Table};
use fmi_shared::model_description::{Model, Output, Type, Variable};

/// The model both model descriptions of `t` declare: its rows as the XML spells them and its
/// outputs' dependencies (value references, in table order; FMI 2.0 writes them as indices).
fn model(t: &Table) -> Model {
    let variables = t
        .vars
        .iter()
        .map(|v| {
            let (min, max) = v.range_text();
            Variable {
                name: v.name.clone(),
                vr: v.vr,
                description: v.description.clone(),
                causality: v.causality,
                variability: v.variability,
                ty: match v.start {
                    Start::Real(_) => Type::Real,
                    Start::Integer(_) => Type::Integer,
                    Start::Boolean(_) => Type::Boolean,
                },
                unit: v.unit_text(),
                start: v.start_text(),
                min,
                max,
            }
        })
        .collect();
    // the table's 1-based indices as value references
    let vrs = |ix: Vec<usize>| -> Vec<u32> {
        ix.iter()
            .filter_map(|&k| t.vars.get(k - 1))
            .map(|v| v.vr)
            .collect()
    };
    let outputs = (0..t.vars.len())
        .filter_map(|i| {
            let (inputs, init) = t.dependencies(i)?;
            Some(Output {
                vr: t.vars[i].vr,
                dependencies: vrs(inputs),
                initial: vrs(init),
            })
        })
        .collect();
    Model {
        model_identifier: t.spec.model_identifier,
        guid: t.guid.clone(),
        description: t.spec.description,
        author: env!("CARGO_PKG_AUTHORS"),
        version: env!("CARGO_PKG_VERSION"),
        generation_tool: format!("connector_fmu {}", env!("CARGO_PKG_VERSION")),
        units: &UNITS,
        used_units: t.vars.iter().map(|v| v.unit).collect(),
        log_categories: Category::ALL
            .iter()
            .map(|c| (c.name(), c.description().to_string()))
            .collect(),
        variables,
        outputs,
    }
}

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
