//! The model descriptions generated from the variable table: FMI 2.0 (`fmi2`,
//! bodies/modelDescription/Body.xml) and FMI 3.0 (`fmi3`, bodies/modelDescription/fmi3/Body.xml).
//! The XML structures and what both versions declare alike (copyright, licence, default
//! experiment, the XML text) are `fmi_shared::model_description`'s, shared with the connector
//! FMU; here, once for both versions, is what this crate gives them: the table as a
//! `fmi_shared::model_description::Model` (rows, units, log categories, outputs with their
//! dependencies), the unit table and the model
//! structure's `dependencies` (also answered at run time by fmi3GetVariableDependencies). Pure
//! functions of `crate::variables` (and `crate::error`'s categories), no I/O; the committed
//! files must equal their output (bodies/tests/model_description.rs). Uses `fmi_shared`.

pub mod fmi2;
pub mod fmi3;

use crate::error::Category;
use crate::variables::{guid, xml_real, Causality, Var, DESCRIPTION, MODEL_IDENTIFIER, VARS};
use fmi_shared::model_description::{Model, Output, Type, Variable};

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

/// A row as the XML spells it (an integer's numbers without a fraction, no unit).
fn variable(v: &Var) -> Variable {
    let i = v.is_integer();
    let number = |x: Option<f64>| {
        x.map(|x| match i {
            true => format!("{}", x as i32),
            false => xml_real(x),
        })
    };
    Variable {
        name: v.name.to_string(),
        vr: v.vr,
        description: v.description.to_string(),
        causality: v.causality,
        variability: v.variability,
        ty: if i { Type::Integer } else { Type::Real },
        unit: if i { None } else { unit(v) },
        start: number(v.start),
        min: number(v.min),
        max: number(v.max),
    }
}

/// The model both model descriptions declare.
fn model() -> Model {
    let outputs = VARS
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .map(|v| Output {
            vr: v.vr,
            dependencies: dependencies(v.vr, false).unwrap_or_default(),
            initial: dependencies(v.vr, true).unwrap_or_default(),
        })
        .collect();
    Model {
        model_identifier: MODEL_IDENTIFIER,
        guid: guid().to_string(),
        description: DESCRIPTION,
        author: env!("CARGO_PKG_AUTHORS"),
        version: env!("CARGO_PKG_VERSION"),
        generation_tool: format!("body_fmu {}", env!("CARGO_PKG_VERSION")),
        units: &UNITS,
        used_units: VARS.iter().map(|v| v.unit).collect(),
        log_categories: Category::ALL
            .iter()
            .map(|c| (c.name(), c.description("fmi2")))
            .collect(),
        variables: VARS.iter().map(variable).collect(),
        outputs,
    }
}
