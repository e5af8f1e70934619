//! What fmi2SetReal / fmi2GetReal do with each value reference, as compact per-variant tables
//! for the per-step calls.

use super::access::Ty;
use super::variables::{Causality, Field, Table};
use std::sync::OnceLock;

/// What fmi2SetReal / fmi2GetReal do with one value reference: the variable table reduced to
/// what the per-step calls need, indexed by VR (built once per variant).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RealSlot {
    /// No Real variable has this VR: the general path reports it.
    None,
    /// A node input (`Field::Input`), by its index 13·node + idx in the flattened inputs.
    Input(u8),
    /// A node load (`Field::Load`), by its index 3·which + i: fa, ma, fb, mb.
    Load(u8),
    /// Any other Real output: read from the outputs at the current inputs.
    Output(Field),
    /// A Real parameter: read from the parameters (set through the checked batch).
    Param(Field),
}

/// No fast index for this VR (see `RealTables`).
pub const NO_INDEX: u8 = u8::MAX;

/// The Real slots of a variant's table by VR, and two compact views of them for the per-step
/// calls: VR → the flat index of a node input (fmi2SetReal) and VR → the index of a node load
/// (fmi2GetReal), `NO_INDEX` for every other VR.
pub struct RealTables {
    /// Every Real VR's slot.
    pub slots: Box<[RealSlot]>,
    /// VR → flat node-input index.
    pub input_index: Box<[u8]>,
    /// VR → node-load index.
    pub load_index: Box<[u8]>,
}

/// The Real tables of a variant (built once per variant).
pub fn real_tables(t: &'static Table) -> &'static RealTables {
    static TABLES: [OnceLock<RealTables>; 5] = [
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
        OnceLock::new(),
    ];
    TABLES[t.spec.variant as usize].get_or_init(|| {
        let n = t.vars.iter().map(|v| v.vr as usize + 1).max().unwrap_or(0);
        let mut slots = vec![RealSlot::None; n];
        for v in &t.vars {
            if Ty::of(&v.start) != Ty::Real || !t.get(v.vr).is_some_and(|x| std::ptr::eq(x, v)) {
                continue;
            }
            slots[v.vr as usize] = match (v.field, v.causality) {
                (Field::Input { node, idx }, _) => RealSlot::Input(13 * node + idx),
                (Field::Load { which, i }, Causality::Output) => RealSlot::Load(3 * which + i),
                (f, Causality::Output) => RealSlot::Output(f),
                (f, _) => RealSlot::Param(f),
            };
        }
        let index = |pick: fn(RealSlot) -> Option<u8>| -> Box<[u8]> {
            slots.iter().map(|&s| pick(s).unwrap_or(NO_INDEX)).collect()
        };
        RealTables {
            input_index: index(|s| match s {
                RealSlot::Input(j) => Some(j),
                _ => None,
            }),
            load_index: index(|s| match s {
                RealSlot::Load(j) => Some(j),
                _ => None,
            }),
            slots: slots.into_boxed_slice(),
        }
    })
}
