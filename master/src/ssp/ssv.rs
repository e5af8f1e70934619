//! SSP 1.0 parameter sets (SystemStructureParameterValues, `.ssv`), inline in the SSD or in a
//! file of the archive: each `ssv:Parameter` as a name, a family and the value's text, with
//! where it was written for messages. Uses xml.rs, model_description.rs (Family) and error.rs.

use crate::error::{Error, Result};
use crate::model_description::Family;
use crate::xml::{self, Element};

/// One parameter value.
#[derive(Debug, Clone)]
pub struct Parameter {
    /// The parameter's name (a variable of the component).
    pub name: String,
    /// Its family (ssv:Real, ssv:Integer, ssv:Boolean, ssv:String, ssv:Enumeration = Integer
    /// when given as a number).
    pub family: Family,
    /// The value as written.
    pub value: String,
    /// `file line N <Parameter>`, for messages.
    pub origin: String,
}

/// Reads an `ssv:ParameterSet` element (`file` names it in messages).
pub fn parameter_set(set: &Element, file: &str) -> Result<Vec<Parameter>> {
    let here = |e: &Element| format!("{file} {}", e.at());
    if set.name != "ParameterSet" {
        return Err(Error::new(format!(
            "the root element is <{}>, not <ssv:ParameterSet>",
            set.name
        ))
        .element(here(set)));
    }
    match set.attr("version") {
        Some("1.0") => {}
        Some(v) => {
            return Err(Error::new(format!("version '{v}' is not SSP 1.0")).element(here(set)))
        }
        None => {
            return Err(
                Error::new("the attribute version is missing (SSP 1.0 requires it)")
                    .element(here(set)),
            )
        }
    }
    xml::required(set, "name").map_err(|e| e.element(file))?;
    let mut out = Vec::new();
    let Some(params) = set.first("Parameters") else {
        return Ok(out);
    };
    for p in params.all("Parameter") {
        let name = xml::required(p, "name")
            .map_err(|e| e.element(file))?
            .to_string();
        let typed = p
            .children
            .iter()
            .find(|c| {
                matches!(
                    c.name.as_str(),
                    "Real" | "Integer" | "Boolean" | "String" | "Enumeration" | "Binary"
                )
            })
            .ok_or_else(|| {
                Error::new("the parameter has no value element (ssv:Real, ssv:Integer, …)")
                    .element(here(p))
                    .variable(&name)
            })?;
        let family = match typed.name.as_str() {
            "Real" => Family::Real,
            "Integer" => Family::Integer,
            "Boolean" => Family::Boolean,
            "String" => Family::String,
            other => {
                return Err(Error::new(format!(
                    "ssv:{other} values are not supported by this master"
                ))
                .element(here(typed))
                .variable(&name))
            }
        };
        let value = xml::required(typed, "value")
            .map_err(|e| e.element(file).variable(&name))?
            .to_string();
        out.push(Parameter {
            name,
            family,
            value,
            origin: here(p),
        });
    }
    Ok(out)
}

/// Reads a `.ssv` file's text.
pub fn parse(text: &str, file: &str) -> Result<Vec<Parameter>> {
    let root = xml::parse(text).map_err(|e| e.element(file))?;
    parameter_set(&root, file)
}
