//! The values that move between components: every output of every component has a slot (f64
//! for Reals, i64 for integers and Booleans, String for strings), read with one get call per
//! component and type; every connected input is set from its source slot through the linear
//! transformation, with one set call per component and type. Buffers are allocated once; a
//! step's exchange of Reals allocates nothing. A NaN output is an error naming it.
//! Uses structure.rs, slave.rs, model_description.rs and error.rs.

use crate::error::{Error, Result};
use crate::model_description::{Dim, Family, ModelDescription, VarType, Variable};
use crate::slave::Slave;
use crate::structure::System;

/// Where a column's values live.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Slot {
    /// `reals[i]`.
    Real(usize),
    /// `ints[i]` (an integer).
    Int(usize),
    /// `ints[i]` (a UInt64, as its bits).
    UInt(usize),
    /// `ints[i]` (a Boolean, 0 or 1).
    Bool(usize),
    /// `strings[i]`.
    Str(usize),
}

/// Variables of one type read or written by one call.
#[derive(Debug, Clone)]
struct Group {
    ty: VarType,
    vrs: Vec<u32>,
    /// First slot and number of values.
    at: usize,
    len: usize,
}

/// The sources of one component's connected inputs of one type.
#[derive(Debug, Clone)]
struct InputGroup {
    ty: VarType,
    vrs: Vec<u32>,
    /// (source slot, factor, offset), one per value.
    sources: Vec<(usize, f64, f64)>,
    reals: Vec<f64>,
    ints: Vec<i64>,
}

#[derive(Debug, Clone, Default)]
struct Ports {
    outputs: Vec<Group>,
    inputs: Vec<InputGroup>,
}

/// Output slots, input sources and the columns of the result.
#[derive(Debug, Clone, Default)]
pub struct Exchange {
    /// Real output values.
    pub reals: Vec<f64>,
    /// Integer and Boolean output values.
    pub ints: Vec<i64>,
    /// String output values.
    pub strings: Vec<String>,
    /// Column names and slots, in component then variable order.
    pub columns: Vec<(String, Slot)>,
    ports: Vec<Ports>,
    /// The variable's name of each Real slot (for messages).
    real_names: Vec<(usize, String)>,
    scratch: Vec<String>,
}

/// The number of values of `var` (1 for a scalar; FMI 3.0 arrays: the product of their
/// dimensions, a structural parameter's start value where it refers to one).
pub fn size(md: &ModelDescription, var: &Variable) -> Result<usize> {
    let mut n = 1usize;
    for d in &var.dims {
        n *= match *d {
            Dim::Fixed(k) => k as usize,
            Dim::Reference(vr) => {
                let p = md.variables.iter().find(|v| v.vr == vr).ok_or_else(|| {
                    Error::new(format!(
                        "its dimension refers to value reference {vr}, which is no variable"
                    ))
                    .variable(&var.name)
                })?;
                p.start
                    .as_deref()
                    .and_then(|s| s.trim().parse::<usize>().ok())
                    .ok_or_else(|| {
                        Error::new(format!("its dimension {} has no whole start value", p.name))
                            .variable(&var.name)
                    })?
            }
        };
    }
    Ok(n)
}

fn columns_of(var: &Variable, n: usize) -> Vec<String> {
    if var.dims.is_empty() {
        vec![var.name.clone()]
    } else {
        (1..=n).map(|i| format!("{}[{i}]", var.name)).collect()
    }
}

impl Exchange {
    /// Lays out the slots of every output of every component and the sources of every
    /// connected input.
    pub fn new(sys: &System) -> Result<Exchange> {
        let mut x = Exchange::default();
        let mut slot_of = Vec::new(); // per component: var index -> first slot
        for (c, comp) in sys.components.iter().enumerate() {
            let md = sys.md(c);
            let mut ports = Ports::default();
            let mut slots = std::collections::BTreeMap::new();
            // slots are laid out type by type (one get call per type and component), the
            // columns stay in the model description's order
            let mut outputs: Vec<(usize, &Variable)> = md
                .variables
                .iter()
                .enumerate()
                .filter(|(_, v)| v.causality == crate::model_description::Causality::Output)
                .collect();
            outputs.sort_by_key(|(vi, v)| (v.ty as u8, *vi));
            let mut columns = Vec::new();
            for (vi, var) in outputs {
                let fam = var.ty.family();
                if fam == Family::Other {
                    continue;
                }
                let n = size(md, var).map_err(|e| e.component(&comp.name))?;
                let at = match fam {
                    Family::Real => x.reals.len(),
                    Family::String => x.strings.len(),
                    _ => x.ints.len(),
                };
                for (i, col) in columns_of(var, n).into_iter().enumerate() {
                    let name = if sys.lone {
                        col
                    } else {
                        format!("{}.{col}", comp.name)
                    };
                    let slot = match (fam, var.ty) {
                        (Family::Real, _) => {
                            x.reals.push(0.0);
                            x.real_names.push((c, var.name.clone()));
                            Slot::Real(at + i)
                        }
                        (Family::String, _) => {
                            x.strings.push(String::new());
                            Slot::Str(at + i)
                        }
                        (_, VarType::Boolean) => {
                            x.ints.push(0);
                            Slot::Bool(at + i)
                        }
                        (_, VarType::UInt64) => {
                            x.ints.push(0);
                            Slot::UInt(at + i)
                        }
                        _ => {
                            x.ints.push(0);
                            Slot::Int(at + i)
                        }
                    };
                    columns.push(((vi, i), name, slot));
                }
                slots.insert(vi, at);
                match ports
                    .outputs
                    .iter_mut()
                    .find(|g| g.ty == var.ty && g.at + g.len == at)
                {
                    Some(g) => {
                        g.vrs.push(var.vr);
                        g.len += n;
                    }
                    None => ports.outputs.push(Group {
                        ty: var.ty,
                        vrs: vec![var.vr],
                        at,
                        len: n,
                    }),
                }
            }
            columns.sort_by_key(|(key, _, _)| *key);
            x.columns
                .extend(columns.into_iter().map(|(_, name, slot)| (name, slot)));
            slot_of.push(slots);
            x.ports.push(ports);
        }
        for l in &sys.links {
            let src = slot_of[l.from.0][&l.from.1];
            let (c, v) = l.to;
            let var = &sys.md(c).variables[v];
            let ports = &mut x.ports[c];
            let i = match ports.inputs.iter().position(|g| g.ty == var.ty) {
                Some(i) => i,
                None => {
                    ports.inputs.push(InputGroup {
                        ty: var.ty,
                        vrs: Vec::new(),
                        sources: Vec::new(),
                        reals: Vec::new(),
                        ints: Vec::new(),
                    });
                    ports.inputs.len() - 1
                }
            };
            let g = &mut ports.inputs[i];
            g.vrs.push(var.vr);
            g.sources.push((src, l.factor, l.offset));
            g.reals.push(0.0);
            g.ints.push(0);
        }
        Ok(x)
    }

    /// Reads every output of component `c` at time `t`; a NaN is an error naming it.
    pub fn read(&mut self, slaves: &mut [Slave], c: usize, t: f64) -> Result<()> {
        let slave = &mut slaves[c];
        for g in &self.ports[c].outputs {
            match g.ty.family() {
                Family::Real => {
                    let out = &mut self.reals[g.at..g.at + g.len];
                    slave.get_real(g.ty, &g.vrs, out, t)?;
                    if let Some(i) = out.iter().position(|v| v.is_nan()) {
                        let (_, name) = &self.real_names[g.at + i];
                        let f = if slave.md.version == crate::model_description::Version::Fmi2 {
                            "fmi2GetReal".to_string()
                        } else {
                            format!("fmi3Get{:?}", g.ty)
                        };
                        return Err(Error::new("the output is NaN")
                            .component(&slave.name)
                            .variable(name)
                            .function(f)
                            .at(t));
                    }
                }
                Family::String => {
                    slave.get_string(&g.vrs, &mut self.scratch, t)?;
                    for (i, s) in self.scratch.drain(..).enumerate().take(g.len) {
                        self.strings[g.at + i] = s;
                    }
                }
                _ => slave.get_int(g.ty, &g.vrs, &mut self.ints[g.at..g.at + g.len], t)?,
            }
        }
        Ok(())
    }

    /// Sets the connected inputs of component `c` from the current output slots.
    pub fn write(&mut self, slaves: &mut [Slave], c: usize, t: f64) -> Result<()> {
        let slave = &mut slaves[c];
        for g in &mut self.ports[c].inputs {
            if g.ty.family() == Family::Real {
                for (v, &(s, factor, offset)) in g.reals.iter_mut().zip(&g.sources) {
                    *v = factor * self.reals[s] + offset;
                }
                slave.set_real(g.ty, &g.vrs, &g.reals, t)?;
            } else {
                for (v, &(s, _, _)) in g.ints.iter_mut().zip(&g.sources) {
                    *v = self.ints[s];
                }
                slave.set_int(g.ty, &g.vrs, &g.ints, t)?;
            }
        }
        Ok(())
    }

    /// The current connected input values (for the fixed point of initialization).
    pub fn inputs_snapshot(&self) -> Vec<u64> {
        let mut v = Vec::new();
        for p in &self.ports {
            for g in &p.inputs {
                for &(s, f, o) in &g.sources {
                    v.push(if g.ty.family() == Family::Real {
                        (f * self.reals[s] + o).to_bits()
                    } else {
                        self.ints[s] as u64
                    });
                }
            }
        }
        v
    }

    /// Does `c` have connected inputs whose source is a String (never: refused at build)?
    pub fn has_inputs(&self, c: usize) -> bool {
        !self.ports[c].inputs.is_empty()
    }
}
