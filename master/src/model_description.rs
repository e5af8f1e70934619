//! modelDescription.xml of FMI 2.0 and 3.0, read into one form for both versions: the model's
//! identifier and token, its Co-Simulation capabilities, its variables (name, value reference,
//! type, causality, variability, start, dimensions) and, for each output, the inputs it
//! depends on directly (feedthrough, for Gauss-Seidel's order). The version's differences end
//! here. Uses xml.rs and error.rs.

use crate::error::{Error, Result};
use crate::xml::{self, Element};

/// FMI 2.0 or 3.0.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Version {
    /// FMI 2.0.
    Fmi2,
    /// FMI 3.0.
    Fmi3,
}

/// A variable's type, as the FMI calls distinguish them (FMI 2.0 Real = Float64,
/// Integer = Int32, Enumeration = Int32 calls in 2.0 and Int64 calls in 3.0).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum VarType {
    Float64,
    Float32,
    Int8,
    UInt8,
    Int16,
    UInt16,
    Int32,
    UInt32,
    Int64,
    UInt64,
    Enumeration,
    Boolean,
    String,
    Binary,
    Clock,
}

/// What family a value belongs to: what a connection may join and a CSV column holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    /// Float64, Float32 (SSP Real).
    Real,
    /// Every integer type and Enumeration (SSP Integer, Enumeration).
    Integer,
    /// Boolean.
    Boolean,
    /// String.
    String,
    /// Binary and Clock: not exchanged by this master.
    Other,
}

impl VarType {
    /// The family of the type.
    pub fn family(self) -> Family {
        use VarType::*;
        match self {
            Float64 | Float32 => Family::Real,
            Int8 | UInt8 | Int16 | UInt16 | Int32 | UInt32 | Int64 | UInt64 | Enumeration => {
                Family::Integer
            }
            Boolean => Family::Boolean,
            String => Family::String,
            Binary | Clock => Family::Other,
        }
    }
    fn from_fmi3(tag: &str) -> Option<Self> {
        use VarType::*;
        Some(match tag {
            "Float64" => Float64,
            "Float32" => Float32,
            "Int8" => Int8,
            "UInt8" => UInt8,
            "Int16" => Int16,
            "UInt16" => UInt16,
            "Int32" => Int32,
            "UInt32" => UInt32,
            "Int64" => Int64,
            "UInt64" => UInt64,
            "Enumeration" => Enumeration,
            "Boolean" => Boolean,
            "String" => String,
            "Binary" => Binary,
            "Clock" => Clock,
            _ => return None,
        })
    }
}

/// FMI causality.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    StructuralParameter,
    Input,
    Output,
    Local,
    Independent,
}

impl Causality {
    fn parse(s: &str) -> Option<Self> {
        Some(match s {
            "parameter" => Causality::Parameter,
            "calculatedParameter" => Causality::CalculatedParameter,
            "structuralParameter" => Causality::StructuralParameter,
            "input" => Causality::Input,
            "output" => Causality::Output,
            "local" => Causality::Local,
            "independent" => Causality::Independent,
            _ => return None,
        })
    }
    /// The name as the XML spells it.
    pub fn name(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::CalculatedParameter => "calculatedParameter",
            Causality::StructuralParameter => "structuralParameter",
            Causality::Input => "input",
            Causality::Output => "output",
            Causality::Local => "local",
            Causality::Independent => "independent",
        }
    }
}

/// FMI variability.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[allow(missing_docs)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

/// One model variable.
#[derive(Debug, Clone)]
pub struct Variable {
    /// Name.
    pub name: String,
    /// Value reference.
    pub vr: u32,
    /// Type.
    pub ty: VarType,
    /// Causality.
    pub causality: Causality,
    /// Variability.
    pub variability: Variability,
    /// The `initial` attribute, if given.
    pub initial: Option<String>,
    /// The start value as written, if any.
    pub start: Option<String>,
    /// Array dimensions (FMI 3.0): a fixed size, or the value reference of a structural
    /// parameter. Empty for scalars.
    pub dims: Vec<Dim>,
}

/// One array dimension of an FMI 3.0 variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dim {
    /// `start="n"`.
    Fixed(u64),
    /// `valueReference="vr"` of a structural parameter.
    Reference(u32),
}

/// An output's direct dependencies: `None` = on every input (no `dependencies` attribute).
#[derive(Debug, Clone)]
pub struct OutputDeps {
    /// Index of the output in `variables`.
    pub output: usize,
    /// Indices (into `variables`) of what it depends on, if listed.
    pub on: Option<Vec<usize>>,
}

/// The default experiment.
#[derive(Debug, Clone, Copy, Default)]
#[allow(missing_docs)]
pub struct DefaultExperiment {
    pub start: Option<f64>,
    pub stop: Option<f64>,
    pub step: Option<f64>,
}

/// A model description of either version.
#[derive(Debug, Clone)]
pub struct ModelDescription {
    /// FMI version.
    pub version: Version,
    /// modelName.
    pub model_name: String,
    /// The Co-Simulation modelIdentifier (the library's name).
    pub model_identifier: String,
    /// guid (2.0) or instantiationToken (3.0).
    pub token: String,
    /// canHandleVariableCommunicationStepSize.
    pub variable_step: bool,
    /// Variables in document order.
    pub variables: Vec<Variable>,
    /// The outputs' dependencies (ModelStructure).
    pub outputs: Vec<OutputDeps>,
    /// DefaultExperiment.
    pub experiment: DefaultExperiment,
}

impl ModelDescription {
    /// The variable named `name`.
    pub fn variable(&self, name: &str) -> Option<(usize, &Variable)> {
        self.variables
            .iter()
            .enumerate()
            .find(|(_, v)| v.name == name)
    }
    /// Does output `output` (an index) depend directly on input `input`?
    pub fn feedthrough(&self, output: usize, input: usize) -> bool {
        match self.outputs.iter().find(|o| o.output == output) {
            Some(OutputDeps { on: Some(on), .. }) => on.contains(&input),
            // not listed, or listed without dependencies: depends on every input
            _ => true,
        }
    }
}

fn flag(e: &Element, key: &str) -> bool {
    e.attr(key) == Some("true")
}

fn variability(s: Option<&str>, ty: VarType, at: &Element) -> Result<Variability> {
    Ok(match s {
        Some("constant") => Variability::Constant,
        Some("fixed") => Variability::Fixed,
        Some("tunable") => Variability::Tunable,
        Some("discrete") => Variability::Discrete,
        Some("continuous") => Variability::Continuous,
        None if ty.family() == Family::Real => Variability::Continuous,
        None => Variability::Discrete,
        Some(other) => {
            return Err(Error::new(format!(
                "{}: unknown variability '{other}'",
                at.at()
            )))
        }
    })
}

fn causality(s: Option<&str>, at: &Element) -> Result<Causality> {
    match s {
        None => Ok(Causality::Local),
        Some(c) => Causality::parse(c)
            .ok_or_else(|| Error::new(format!("{}: unknown causality '{c}'", at.at()))),
    }
}

fn vr(e: &Element) -> Result<u32> {
    let v = xml::required(e, "valueReference")?;
    v.trim().parse().map_err(|_| {
        Error::new(format!(
            "{}: valueReference '{v}' is not a whole number",
            e.at()
        ))
    })
}

fn fmi2_variable(sv: &Element) -> Result<Variable> {
    let name = xml::required(sv, "name")?.to_string();
    let typed = sv
        .children
        .iter()
        .find(|c| {
            matches!(
                c.name.as_str(),
                "Real" | "Integer" | "Boolean" | "String" | "Enumeration"
            )
        })
        .ok_or_else(|| {
            Error::new(format!(
                "{}: variable '{name}' has no type element",
                sv.at()
            ))
        })?;
    let ty = match typed.name.as_str() {
        "Real" => VarType::Float64,
        "Integer" => VarType::Int32,
        "Boolean" => VarType::Boolean,
        "String" => VarType::String,
        _ => VarType::Enumeration,
    };
    Ok(Variable {
        vr: vr(sv)?,
        ty,
        causality: causality(sv.attr("causality"), sv)?,
        variability: variability(sv.attr("variability"), ty, sv)?,
        initial: sv.attr("initial").map(str::to_string),
        start: typed.attr("start").map(str::to_string),
        dims: Vec::new(),
        name,
    })
}

fn fmi3_variable(e: &Element, ty: VarType) -> Result<Variable> {
    let name = xml::required(e, "name")?.to_string();
    let mut dims = Vec::new();
    for d in e.all("Dimension") {
        if let Some(s) = d.attr("start") {
            dims.push(Dim::Fixed(s.trim().parse().map_err(|_| {
                Error::new(format!(
                    "{}: Dimension start '{s}' is not a whole number",
                    d.at()
                ))
            })?));
        } else {
            dims.push(Dim::Reference(vr(d)?));
        }
    }
    let start = match ty {
        VarType::String => e
            .first("Start")
            .and_then(|s| s.attr("value"))
            .map(str::to_string),
        _ => e.attr("start").map(str::to_string),
    };
    Ok(Variable {
        vr: vr(e)?,
        ty,
        causality: causality(e.attr("causality"), e)?,
        variability: variability(e.attr("variability"), ty, e)?,
        initial: e.attr("initial").map(str::to_string),
        start,
        dims,
        name,
    })
}

fn deps(
    list: Option<&str>,
    at: &Element,
    resolve: &dyn Fn(u64) -> Option<usize>,
) -> Result<Option<Vec<usize>>> {
    let Some(list) = list else { return Ok(None) };
    let mut out = Vec::new();
    for tok in list.split_whitespace() {
        let n: u64 = tok.parse().map_err(|_| {
            Error::new(format!(
                "{}: dependency '{tok}' is not a whole number",
                at.at()
            ))
        })?;
        out.push(resolve(n).ok_or_else(|| {
            Error::new(format!("{}: dependency {tok} names no variable", at.at()))
        })?);
    }
    Ok(Some(out))
}

/// Reads a model description from its XML text.
pub fn parse(text: &str) -> Result<ModelDescription> {
    let root = xml::parse(text)?;
    if root.name != "fmiModelDescription" {
        return Err(Error::new(format!(
            "the root element is <{}>, not <fmiModelDescription>",
            root.name
        )));
    }
    let fmi_version = xml::required(&root, "fmiVersion")?;
    let version = if fmi_version.starts_with("2.") {
        Version::Fmi2
    } else if fmi_version.starts_with("3.") {
        Version::Fmi3
    } else {
        return Err(Error::new(format!(
            "fmiVersion {fmi_version} is not supported (FMI 2.0 and 3.0 are)"
        )));
    };
    let cs = root.first("CoSimulation").ok_or_else(|| {
        Error::new("the FMU has no <CoSimulation> interface (this master runs Co-Simulation FMUs)")
    })?;
    let token = match version {
        Version::Fmi2 => xml::required(&root, "guid")?,
        Version::Fmi3 => xml::required(&root, "instantiationToken")?,
    }
    .to_string();
    let mv = root.first("ModelVariables");
    let mut variables = Vec::new();
    for e in mv.map(|m| m.children.as_slice()).unwrap_or(&[]) {
        match version {
            Version::Fmi2 if e.name == "ScalarVariable" => variables.push(fmi2_variable(e)?),
            Version::Fmi3 => {
                if let Some(ty) = VarType::from_fmi3(&e.name) {
                    variables.push(fmi3_variable(e, ty)?);
                }
            }
            _ => {}
        }
    }
    let mut outputs = Vec::new();
    if let Some(ms) = root.first("ModelStructure") {
        match version {
            Version::Fmi2 => {
                let by_index =
                    |n: u64| (n >= 1 && (n as usize) <= variables.len()).then(|| n as usize - 1);
                for u in ms
                    .first("Outputs")
                    .map(|o| o.children.as_slice())
                    .unwrap_or(&[])
                {
                    let index: u64 = xml::required(u, "index")?.trim().parse().map_err(|_| {
                        Error::new(format!("{}: index is not a whole number", u.at()))
                    })?;
                    let output = by_index(index).ok_or_else(|| {
                        Error::new(format!("{}: index {index} names no variable", u.at()))
                    })?;
                    outputs.push(OutputDeps {
                        output,
                        on: deps(u.attr("dependencies"), u, &by_index)?,
                    });
                }
            }
            Version::Fmi3 => {
                let by_vr = |n: u64| variables.iter().position(|v| u64::from(v.vr) == n);
                for u in ms.all("Output") {
                    let r = u64::from(vr(u)?);
                    let output = by_vr(r).ok_or_else(|| {
                        Error::new(format!("{}: valueReference {r} names no variable", u.at()))
                    })?;
                    outputs.push(OutputDeps {
                        output,
                        on: deps(u.attr("dependencies"), u, &by_vr)?,
                    });
                }
            }
        }
    }
    let experiment = match root.first("DefaultExperiment") {
        Some(d) => DefaultExperiment {
            start: xml::number(d, "startTime")?,
            stop: xml::number(d, "stopTime")?,
            step: xml::number(d, "stepSize")?,
        },
        None => DefaultExperiment::default(),
    };
    Ok(ModelDescription {
        version,
        model_name: root.attr("modelName").unwrap_or("").to_string(),
        model_identifier: xml::required(cs, "modelIdentifier")?.to_string(),
        token,
        variable_step: flag(cs, "canHandleVariableCommunicationStepSize"),
        variables,
        outputs,
        experiment,
    })
}
