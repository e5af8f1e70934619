//! SSP 1.0 SystemStructureDescription (`SystemStructure.ssd`) read into a flat description: the
//! FMU components of the system and of its nested systems (named `sub.component`), each with
//! its connectors, FMU source and parameter values (bindings to `.ssv` files or inline sets,
//! with their prefix); the connections from an FMU output to an FMU input, traced through the
//! connectors of nested systems and with their linear transformations composed; and the
//! DefaultExperiment (with OSP's base step annotation). What SSP 1.0 requires is checked here
//! (version, required attributes, kinds, one source per connector).
//! Uses xml.rs, ssp/ssv.rs, model_description.rs (Family) and error.rs.

use super::ssv::{self, Parameter};
use crate::error::{Error, Result};
use crate::model_description::Family;
use crate::xml::{self, Element};
use std::collections::BTreeMap;

/// The SSD's file name inside an archive.
pub const SSD: &str = "SystemStructure.ssd";

/// One connector of a component as the SSD declares it.
#[derive(Debug, Clone)]
pub struct Connector {
    /// Name (the FMU variable's).
    pub name: String,
    /// kind: input, output, parameter, calculatedParameter, inout.
    pub kind: String,
    /// Declared type, if any.
    pub family: Option<Family>,
    /// `SystemStructure.ssd line N <Connector>`.
    pub origin: String,
}

/// One FMU component.
#[derive(Debug, Clone)]
pub struct Component {
    /// Name, qualified by the nested systems (`sub.comp`).
    pub name: String,
    /// The FMU's path inside the archive.
    pub source: String,
    /// Its connectors.
    pub connectors: Vec<Connector>,
    /// Its parameter values, in binding order (a later binding overrides).
    pub parameters: Vec<Parameter>,
    /// Where it is declared.
    pub origin: String,
}

/// One connection from an FMU output to an FMU input, y_end = factor · y_start + offset.
#[derive(Debug, Clone)]
pub struct Connection {
    /// Source component (index into `components`) and connector.
    pub from: (usize, String),
    /// Destination component and connector.
    pub to: (usize, String),
    /// Linear transformation factor.
    pub factor: f64,
    /// Linear transformation offset.
    pub offset: f64,
    /// `SystemStructure.ssd line N <Connection>` (the one into the input).
    pub origin: String,
}

/// A system, flat.
#[derive(Debug, Clone, Default)]
pub struct Description {
    /// The system's name.
    pub name: String,
    /// The FMU components.
    pub components: Vec<Component>,
    /// The connections between them.
    pub connections: Vec<Connection>,
    /// DefaultExperiment startTime.
    pub start: Option<f64>,
    /// DefaultExperiment stopTime.
    pub stop: Option<f64>,
    /// OSP's FixedStepAlgorithm baseStepSize, if annotated.
    pub step: Option<f64>,
}

/// An endpoint of the connection graph: an FMU connector or a system connector.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
enum Node {
    Fmu(usize, String),
    System(String, String),
}

struct Edge {
    from: Node,
    factor: f64,
    offset: f64,
    origin: String,
}

/// Reads files of the archive by path (for parameter sets).
pub type Files<'a> = &'a dyn Fn(&str) -> Option<std::io::Result<String>>;

struct Reader<'a> {
    files: Files<'a>,
    desc: Description,
    edges: BTreeMap<Node, Edge>,
}

fn here(e: &Element) -> String {
    format!("{SSD} {}", e.at())
}

fn family(e: &Element) -> Option<Family> {
    e.children.iter().find_map(|c| match c.name.as_str() {
        "Real" => Some(Family::Real),
        "Integer" | "Enumeration" => Some(Family::Integer),
        "Boolean" => Some(Family::Boolean),
        "String" => Some(Family::String),
        _ => None,
    })
}

/// The parameters of a system's bindings that reach its element `name` (written `name.rest`), as
/// `rest`.
fn scoped(params: &[Parameter], name: &str) -> Vec<Parameter> {
    let prefix = format!("{name}.");
    params
        .iter()
        .filter_map(|p| {
            p.name.strip_prefix(&prefix).map(|rest| Parameter {
                name: rest.to_string(),
                ..p.clone()
            })
        })
        .collect()
}

fn req<'e>(e: &'e Element, key: &str) -> Result<&'e str> {
    xml::required(e, key).map_err(|err| Error {
        element: Some(format!("{SSD} {}", e.at())),
        cause: format!("the attribute {key} is missing (SSP 1.0 requires it)"),
        ..err
    })
}

impl Reader<'_> {
    fn bindings(
        &self,
        e: &Element,
        component: &str,
        prefix_filter: &str,
    ) -> Result<Vec<Parameter>> {
        let mut out = Vec::new();
        let Some(bs) = e.first("ParameterBindings") else {
            return Ok(out);
        };
        for b in bs.all("ParameterBinding") {
            let at = here(b);
            if b.first("ParameterMapping").is_some() {
                return Err(
                    Error::new("ssd:ParameterMapping is not supported by this master")
                        .element(at)
                        .component(component),
                );
            }
            let set = match (b.attr("source"), b.first("ParameterValues")) {
                (Some(src), _) => {
                    let path = src.trim_start_matches("./");
                    let text = match (self.files)(path) {
                        None => {
                            return Err(Error::new(format!(
                                "the parameter set '{src}' is missing from the archive"
                            ))
                            .element(at)
                            .component(component))
                        }
                        Some(Err(err)) => {
                            return Err(Error::new(format!(
                                "cannot read the parameter set '{src}': {err}"
                            ))
                            .element(at)
                            .component(component))
                        }
                        Some(Ok(t)) => t,
                    };
                    ssv::parse(&text, path).map_err(|err| err.component(component))?
                }
                (None, Some(values)) => {
                    let set = values.first("ParameterSet").ok_or_else(|| {
                        Error::new("ssd:ParameterValues holds no ssv:ParameterSet")
                            .element(here(values))
                            .component(component)
                    })?;
                    ssv::parameter_set(set, SSD).map_err(|err| err.component(component))?
                }
                (None, None) => {
                    return Err(Error::new(
                        "the binding has neither a source nor inline ssd:ParameterValues",
                    )
                    .element(at)
                    .component(component))
                }
            };
            let prefix = format!("{prefix_filter}{}", b.attr("prefix").unwrap_or(""));
            for mut p in set {
                if let Some(rest) = p.name.strip_prefix(&prefix) {
                    p.name = rest.to_string();
                    out.push(p);
                }
            }
        }
        Ok(out)
    }

    fn endpoint(
        &self,
        element: Option<&str>,
        connector: &str,
        path: &str,
        names: &BTreeMap<String, bool>,
        at: &Element,
    ) -> Result<Node> {
        match element {
            None | Some("") => Ok(Node::System(path.to_string(), connector.to_string())),
            Some(el) => match names.get(el) {
                Some(true) => {
                    let q = format!("{path}{el}");
                    // components are read before connections
                    match self.desc.components.iter().position(|c| c.name == q) {
                        Some(i) => Ok(Node::Fmu(i, connector.to_string())),
                        None => Err(Error::new(format!(
                            "the connection names the component '{q}', which was not read"
                        ))),
                    }
                }
                Some(false) => Ok(Node::System(format!("{path}{el}."), connector.to_string())),
                None => Err(Error::new(format!(
                    "the connection names the element '{el}', which is no element of the system"
                ))
                .element(here(at))
                .component(el)
                .variable(connector)),
            },
        }
    }

    fn system(&mut self, sys: &Element, path: &str, inherited: &[Parameter]) -> Result<()> {
        let mut names = BTreeMap::new();
        let own = self.bindings(sys, path.trim_end_matches('.'), "")?;
        let mut params: Vec<Parameter> = inherited.to_vec();
        params.extend(own);
        if let Some(elements) = sys.first("Elements") {
            for e in &elements.children {
                let name = req(e, "name")?.to_string();
                if names.contains_key(&name) {
                    return Err(Error::new("two elements of the system have this name")
                        .element(here(e))
                        .component(&name));
                }
                match e.name.as_str() {
                    "Component" => {
                        names.insert(name.clone(), true);
                        let q = format!("{path}{name}");
                        let source = req(e, "source")?.trim_start_matches("./").to_string();
                        if let Some(t) = e.attr("type") {
                            if t != "application/x-fmu-sharedlibrary" {
                                return Err(Error::new(format!("component type '{t}' is not an FMU (application/x-fmu-sharedlibrary)")).element(here(e)).component(&q));
                            }
                        }
                        let mut connectors = Vec::new();
                        for c in e
                            .first("Connectors")
                            .map(|c| c.children.as_slice())
                            .unwrap_or(&[])
                        {
                            let cname = req(c, "name")?.to_string();
                            let kind = req(c, "kind")?.to_string();
                            if !matches!(
                                kind.as_str(),
                                "input" | "output" | "parameter" | "calculatedParameter" | "inout"
                            ) {
                                return Err(Error::new(format!("kind '{kind}' is not one of SSP 1.0's (input, output, parameter, calculatedParameter, inout)")).element(here(c)).component(&q).variable(&cname));
                            }
                            connectors.push(Connector {
                                name: cname,
                                kind,
                                family: family(c),
                                origin: here(c),
                            });
                        }
                        // the system's bindings reach the component as `name.parameter`
                        let mut parameters = scoped(&params, &name);
                        parameters.extend(self.bindings(e, &q, "")?);
                        self.desc.components.push(Component {
                            name: q,
                            source,
                            connectors,
                            parameters,
                            origin: here(e),
                        });
                    }
                    "System" => {
                        names.insert(name.clone(), false);
                        let inner = scoped(&params, &name);
                        self.system(e, &format!("{path}{name}."), &inner)?;
                    }
                    "SignalDictionaryReference" => {
                        return Err(Error::new(
                            "signal dictionaries are not supported by this master",
                        )
                        .element(here(e))
                        .component(&name));
                    }
                    other => {
                        return Err(Error::new(format!(
                            "<{other}> is no element of an SSP 1.0 system"
                        ))
                        .element(here(e)))
                    }
                }
            }
        }
        if let Some(conns) = sys.first("Connections") {
            for c in conns.all("Connection") {
                let from = self.endpoint(
                    c.attr("startElement"),
                    req(c, "startConnector")?,
                    path,
                    &names,
                    c,
                )?;
                let to = self.endpoint(
                    c.attr("endElement"),
                    req(c, "endConnector")?,
                    path,
                    &names,
                    c,
                )?;
                let (mut factor, mut offset) = (1.0, 0.0);
                for t in &c.children {
                    match t.name.as_str() {
                        "LinearTransformation" => {
                            factor = xml::number(t, "factor")
                                .map_err(|e| e.element(SSD))?
                                .unwrap_or(1.0);
                            offset = xml::number(t, "offset")
                                .map_err(|e| e.element(SSD))?
                                .unwrap_or(0.0);
                        }
                        "BooleanMappingTransformation"
                        | "IntegerMappingTransformation"
                        | "EnumerationMappingTransformation" => {
                            return Err(Error::new(format!(
                                "ssc:{} is not supported by this master",
                                t.name
                            ))
                            .element(here(t)));
                        }
                        _ => {}
                    }
                }
                let origin = here(c);
                if let Some(prev) = self.edges.get(&to) {
                    let (comp, var) = self.node_names(&to);
                    return Err(Error::new(format!(
                        "two connections lead into this input: {} and {origin}",
                        prev.origin
                    ))
                    .element(origin)
                    .component(comp)
                    .variable(var));
                }
                self.edges.insert(
                    to,
                    Edge {
                        from,
                        factor,
                        offset,
                        origin,
                    },
                );
            }
        }
        Ok(())
    }

    fn node_names(&self, n: &Node) -> (String, String) {
        match n {
            Node::Fmu(i, c) => (self.desc.components[*i].name.clone(), c.clone()),
            Node::System(p, c) => (p.trim_end_matches('.').to_string(), c.clone()),
        }
    }

    /// Each FMU input's source FMU output, through system connectors.
    fn resolve(&mut self) -> Result<()> {
        let ends: Vec<Node> = self
            .edges
            .keys()
            .filter(|n| matches!(n, Node::Fmu(..)))
            .cloned()
            .collect();
        for end in ends {
            let edge = &self.edges[&end];
            let origin = edge.origin.clone();
            let (mut factor, mut offset) = (edge.factor, edge.offset);
            let mut from = edge.from.clone();
            let mut hops = 0;
            while let Node::System(..) = from {
                let Some(prev) = self.edges.get(&from) else {
                    break;
                };
                // y = f·(f_prev·x + o_prev) + o
                offset += factor * prev.offset;
                factor *= prev.factor;
                from = prev.from.clone();
                hops += 1;
                if hops > self.edges.len() {
                    return Err(Error::new(
                        "the connections through system connectors form a loop",
                    )
                    .element(origin));
                }
            }
            if let (Node::Fmu(fi, fc), Node::Fmu(ti, tc)) = (from, &end) {
                self.desc.connections.push(Connection {
                    from: (fi, fc),
                    to: (*ti, tc.clone()),
                    factor,
                    offset,
                    origin,
                });
            }
        }
        self.desc
            .connections
            .sort_by(|a, b| a.origin.cmp(&b.origin));
        Ok(())
    }
}

/// Reads the SSD's text; `files` reads the archive's other files (parameter sets).
pub fn parse(text: &str, files: Files) -> Result<Description> {
    let root = xml::parse(text).map_err(|e| e.element(SSD))?;
    if root.name != "SystemStructureDescription" {
        return Err(Error::new(format!(
            "the root element is <{}>, not <ssd:SystemStructureDescription>",
            root.name
        ))
        .element(SSD));
    }
    match root.attr("version") {
        Some("1.0") => {}
        Some(v) => {
            return Err(Error::new(format!("version '{v}' is not SSP 1.0")).element(here(&root)))
        }
        None => {
            return Err(
                Error::new("the attribute version is missing (SSP 1.0 requires it)")
                    .element(here(&root)),
            )
        }
    }
    let name = req(&root, "name")?.to_string();
    let sys = root.first("System").ok_or_else(|| {
        Error::new("the SSD has no <ssd:System> (SSP 1.0 requires one)").element(here(&root))
    })?;
    req(sys, "name")?;
    let mut r = Reader {
        files,
        desc: Description {
            name,
            ..Default::default()
        },
        edges: BTreeMap::new(),
    };
    r.system(sys, "", &[])?;
    r.resolve()?;
    if let Some(d) = root.first("DefaultExperiment") {
        r.desc.start = xml::number(d, "startTime").map_err(|e| e.element(SSD))?;
        r.desc.stop = xml::number(d, "stopTime").map_err(|e| e.element(SSD))?;
        let base = d
            .first("Annotations")
            .into_iter()
            .flat_map(|a| a.all("Annotation"))
            .flat_map(|a| a.all("Algorithm"))
            .flat_map(|a| a.all("FixedStepAlgorithm"))
            .next();
        if let Some(f) = base {
            r.desc.step = xml::number(f, "baseStepSize").map_err(|e| e.element(SSD))?;
        }
    }
    Ok(r.desc)
}
