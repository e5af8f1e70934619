//! A system ready to run, built and checked from an SSP description or a lone FMU: each FMU
//! imported once (components sharing a source share it), every connector, parameter value and
//! connection resolved to a model variable and checked as it is added — the variable exists,
//! its causality and type match the SSD, a connection runs from an output to an input of the
//! same type, a linear transformation joins Reals — so a bad archive fails before the first
//! step, with the element, component and variable named. Uses ssp/, fmu.rs, slave.rs (Value),
//! model_description.rs and error.rs.

use crate::error::{Error, Result};
use crate::fmu::Fmu;
use crate::model_description::{Causality, Family, ModelDescription, Variability};
use crate::slave::Value;
use crate::ssp::{self, ssd};
use std::path::Path;
use std::sync::Arc;

/// A start value or parameter to set before initialization.
#[derive(Debug, Clone)]
pub struct StartValue {
    /// Index of the variable in the component's model description.
    pub var: usize,
    /// The value.
    pub value: Value,
    /// Where it was given (an SSV element, `--start`).
    pub origin: String,
}

/// One component: an instance of one of the system's FMUs.
#[derive(Debug, Clone)]
pub struct Component {
    /// Instance name.
    pub name: String,
    /// Index into `System::fmus`.
    pub fmu: usize,
    /// Start values and parameters, in the order they are set.
    pub starts: Vec<StartValue>,
}

/// A connection between two variables, y_to = factor · y_from + offset.
#[derive(Debug, Clone)]
pub struct Link {
    /// Source component and variable index.
    pub from: (usize, usize),
    /// Destination component and variable index.
    pub to: (usize, usize),
    /// Factor.
    pub factor: f64,
    /// Offset.
    pub offset: f64,
    /// Where the connection is written.
    pub origin: String,
}

/// A checked system.
pub struct System {
    /// Its name (the SSD's, or the lone FMU's model name).
    pub name: String,
    /// Imported FMUs.
    pub fmus: Vec<Fmu>,
    /// Components.
    pub components: Vec<Component>,
    /// Connections.
    pub links: Vec<Link>,
    /// A lone FMU (columns are plain variable names).
    pub lone: bool,
    /// Default start, stop and step (DefaultExperiment, OSP's base step, the FMU's stepSize).
    pub start: Option<f64>,
    /// Default stop time.
    pub stop: Option<f64>,
    /// Default step.
    pub step: Option<f64>,
    _archive: Option<ssp::Archive>,
}

impl System {
    /// The model description of component `c`.
    pub fn md(&self, c: usize) -> &Arc<ModelDescription> {
        &self.fmus[self.components[c].fmu].md
    }

    /// Opens an `.ssp` archive or an `.fmu` file, by its extension.
    pub fn open(path: &Path) -> Result<System> {
        let shown = path.display().to_string();
        if !path.exists() {
            return Err(Error::new("no such file").element(shown));
        }
        match path.extension().and_then(|e| e.to_str()) {
            Some("ssp") => from_archive(path),
            Some("fmu") => lone(path),
            _ => Err(Error::new("neither an SSP archive (.ssp) nor an FMU (.fmu)").element(shown)),
        }
    }

    /// Finds `COMPONENT.VARIABLE` (or, for a lone FMU, `VARIABLE`): the component and variable.
    pub fn find(&self, qualified: &str) -> Option<(usize, usize)> {
        if self.lone {
            return self.md(0).variable(qualified).map(|(i, _)| (0, i));
        }
        let mut best = None;
        for (c, comp) in self.components.iter().enumerate() {
            if let Some(rest) = qualified
                .strip_prefix(&comp.name)
                .and_then(|r| r.strip_prefix('.'))
            {
                if let Some((v, _)) = self.md(c).variable(rest) {
                    if best.is_none_or(|(bc, _): (usize, usize)| {
                        self.components[bc].name.len() < comp.name.len()
                    }) {
                        best = Some((c, v));
                    }
                }
            }
        }
        best
    }

    /// Adds a start value `qualified = text` (from the command line or the bindings).
    pub fn add_start(&mut self, qualified: &str, text: &str, origin: &str) -> Result<()> {
        let (c, v) = self.find(qualified).ok_or_else(|| {
            Error::new(if self.lone {
                "the FMU has no such variable".to_string()
            } else {
                "no component has this variable (write COMPONENT.VARIABLE)".to_string()
            })
            .element(origin)
            .variable(qualified)
        })?;
        let var = &self.md(c).variables[v];
        check_settable(var.causality, var.variability).map_err(|e| {
            e.element(origin)
                .component(&self.components[c].name)
                .variable(&var.name)
        })?;
        let value = Value::parse(var.ty.family(), text).map_err(|e| {
            Error::new(e)
                .element(origin)
                .component(&self.components[c].name)
                .variable(&var.name)
        })?;
        self.components[c].starts.push(StartValue {
            var: v,
            value,
            origin: origin.to_string(),
        });
        Ok(())
    }
}

fn check_settable(c: Causality, v: Variability) -> Result<()> {
    if v == Variability::Constant {
        return Err(Error::new("it is a constant and cannot be set"));
    }
    if matches!(
        c,
        Causality::Output | Causality::CalculatedParameter | Causality::Independent
    ) {
        return Err(Error::new(format!(
            "its causality is {} and it cannot be set",
            c.name()
        )));
    }
    Ok(())
}

fn lone(path: &Path) -> Result<System> {
    let shown = path.display().to_string();
    let fmu = Fmu::load(path, &shown)?;
    let md = Arc::clone(&fmu.md);
    let name = md.model_identifier.clone();
    Ok(System {
        name: md.model_name.clone(),
        components: vec![Component {
            name,
            fmu: 0,
            starts: Vec::new(),
        }],
        fmus: vec![fmu],
        links: Vec::new(),
        lone: true,
        start: md.experiment.start,
        stop: md.experiment.stop,
        step: md.experiment.step,
        _archive: None,
    })
}

fn kind_matches(kind: &str, c: Causality) -> bool {
    match kind {
        "input" => c == Causality::Input,
        "output" => c == Causality::Output,
        "parameter" => matches!(c, Causality::Parameter | Causality::StructuralParameter),
        "calculatedParameter" => c == Causality::CalculatedParameter,
        _ => matches!(c, Causality::Input | Causality::Output),
    }
}

fn from_archive(path: &Path) -> Result<System> {
    let archive = ssp::open(path)?;
    let desc = &archive.description;
    let mut fmus: Vec<Fmu> = Vec::new();
    let mut components = Vec::new();
    for comp in &desc.components {
        let fmu = match fmus.iter().position(|f| f.source == comp.source) {
            Some(i) => i,
            None => {
                let file =
                    archive
                        .unpacked
                        .dir
                        .join(crate::unzip::safe_path(&comp.source).map_err(|why| {
                            Error::new(format!(
                                "the source '{}' leaves the archive: {why}",
                                comp.source
                            ))
                            .element(&comp.origin)
                            .component(&comp.name)
                        })?);
                if !file.is_file() {
                    return Err(Error::new(format!(
                        "the FMU '{}' is missing from the archive",
                        comp.source
                    ))
                    .element(&comp.origin)
                    .component(&comp.name));
                }
                fmus.push(Fmu::load(&file, &comp.source).map_err(|e| e.component(&comp.name))?);
                fmus.len() - 1
            }
        };
        let md = &fmus[fmu].md;
        for c in &comp.connectors {
            let (_, var) = md.variable(&c.name).ok_or_else(|| {
                Error::new(format!("{} has no variable of this name", comp.source))
                    .element(&c.origin)
                    .component(&comp.name)
                    .variable(&c.name)
            })?;
            if !kind_matches(&c.kind, var.causality) {
                return Err(Error::new(format!(
                    "the SSD declares it {}, {} declares it {}",
                    c.kind,
                    comp.source,
                    var.causality.name()
                ))
                .element(&c.origin)
                .component(&comp.name)
                .variable(&c.name));
            }
            if let Some(f) = c.family {
                if f != var.ty.family() {
                    return Err(Error::new(format!(
                        "the SSD types it {f:?}, {} types it {:?}",
                        comp.source, var.ty
                    ))
                    .element(&c.origin)
                    .component(&comp.name)
                    .variable(&c.name));
                }
            }
        }
        let mut starts = Vec::new();
        for p in &comp.parameters {
            let (v, var) = md.variable(&p.name).ok_or_else(|| {
                Error::new(format!(
                    "the parameter set names a variable {} does not have",
                    comp.source
                ))
                .element(&p.origin)
                .component(&comp.name)
                .variable(&p.name)
            })?;
            check_settable(var.causality, var.variability)
                .map_err(|e| e.element(&p.origin).component(&comp.name).variable(&p.name))?;
            let fam = var.ty.family();
            if !(p.family == fam || (p.family == Family::Integer && fam == Family::Real)) {
                return Err(Error::new(format!(
                    "the parameter set gives a {:?} value, {} types it {:?}",
                    p.family, comp.source, var.ty
                ))
                .element(&p.origin)
                .component(&comp.name)
                .variable(&p.name));
            }
            let value = Value::parse(fam, &p.value).map_err(|e| {
                Error::new(e)
                    .element(&p.origin)
                    .component(&comp.name)
                    .variable(&p.name)
            })?;
            starts.push(StartValue {
                var: v,
                value,
                origin: p.origin.clone(),
            });
        }
        components.push(Component {
            name: comp.name.clone(),
            fmu,
            starts,
        });
    }
    let mut links = Vec::new();
    for c in &desc.connections {
        let var = |(ci, name): &(usize, String)| -> Result<(usize, usize)> {
            let md = &fmus[components[*ci].fmu].md;
            md.variable(name).map(|(v, _)| (*ci, v)).ok_or_else(|| {
                Error::new(format!(
                    "{} has no variable of this name",
                    desc.components[*ci].source
                ))
                .element(&c.origin)
                .component(&components[*ci].name)
                .variable(name)
            })
        };
        let (from, to) = (var(&c.from)?, var(&c.to)?);
        let vf = &fmus[components[from.0].fmu].md.variables[from.1];
        let vt = &fmus[components[to.0].fmu].md.variables[to.1];
        let name_from = format!("{}.{}", components[from.0].name, vf.name);
        let name_to = format!("{}.{}", components[to.0].name, vt.name);
        if vf.causality != Causality::Output {
            return Err(Error::new(format!(
                "a connection starts at {name_from}, whose causality is {}, not output",
                vf.causality.name()
            ))
            .element(&c.origin)
            .component(&components[from.0].name)
            .variable(&vf.name));
        }
        if vt.causality != Causality::Input {
            return Err(Error::new(format!(
                "a connection ends at {name_to}, whose causality is {}, not input",
                vt.causality.name()
            ))
            .element(&c.origin)
            .component(&components[to.0].name)
            .variable(&vt.name));
        }
        if vf.ty.family() != vt.ty.family() || vf.ty.family() == Family::Other {
            return Err(Error::new(format!(
                "the connection joins {name_from} ({:?}) to {name_to} ({:?}): the types differ",
                vf.ty, vt.ty
            ))
            .element(&c.origin)
            .component(&components[to.0].name)
            .variable(&vt.name));
        }
        if (c.factor != 1.0 || c.offset != 0.0) && vf.ty.family() != Family::Real {
            return Err(Error::new(format!(
                "a linear transformation joins {name_from} to {name_to}, which are not Real"
            ))
            .element(&c.origin)
            .component(&components[to.0].name)
            .variable(&vt.name));
        }
        if !vf.dims.is_empty() || !vt.dims.is_empty() {
            return Err(Error::new(format!("the connection joins array variables ({name_from} to {name_to}); this master connects scalars")).element(&c.origin));
        }
        links.push(Link {
            from,
            to,
            factor: c.factor,
            offset: c.offset,
            origin: c.origin.clone(),
        });
    }
    let (start, stop, step) = (desc.start, desc.stop, desc.step);
    Ok(System {
        name: desc.name.clone(),
        fmus,
        components,
        links,
        lone: false,
        start,
        stop,
        step,
        _archive: Some(archive),
    })
}

/// The archive element a message names for the SSD itself.
pub const SSD: &str = ssd::SSD;
