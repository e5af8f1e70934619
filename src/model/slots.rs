//! What fmi2SetReal / fmi2GetReal do with each value reference, as compact per-variant tables
//! for the per-step calls.
//!
//! Uses the table (`variables`) and the access rules (`access`); the instance uses it.

use super::access::{continuous_index, Ty};
use super::variables::{Causality, Field, Table, Variability, NODE_INPUTS};
use std::sync::OnceLock;

/// What fmi2SetReal / fmi2GetReal do with one value reference: the variable table reduced to
/// what the per-step calls need, indexed by VR (built once per variant).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RealSlot {
    /// No Real variable has this VR: the general path reports it.
    None,
    /// A node input (`Field::Input`), by its index 19·node + idx in the flattened inputs.
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
    /// VR → index in `access::continuous_row` of a continuous Real output (the unknowns a
    /// directional derivative may ask for).
    pub continuous_index: Box<[u8]>,
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
        let mut continuous = vec![NO_INDEX; n];
        for v in &t.vars {
            if Ty::of(&v.start) != Ty::Real || !t.get(v.vr).is_some_and(|x| std::ptr::eq(x, v)) {
                continue;
            }
            // (every continuous Real output has a row index: `tests` below)
            if v.causality == Causality::Output && v.variability == Variability::Continuous {
                continuous[v.vr as usize] = continuous_index(v.field).unwrap_or(NO_INDEX);
            }
            slots[v.vr as usize] = match (v.field, v.causality) {
                (Field::Input { node, idx }, _) => RealSlot::Input(NODE_INPUTS as u8 * node + idx),
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
            continuous_index: continuous.into_boxed_slice(),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::access::{continuous_row, read_output, CONTINUOUS_LEN};
    use crate::model::variables::{table, Variability, VARIANTS};
    use crate::physics::connector::Outputs;
    use crate::physics::math::Real;

    /// The row the directional derivatives read gives every continuous Real output of every
    /// variant exactly what the general read gives, and only those have a row index.
    #[test]
    fn continuous_row_reads_every_continuous_output() {
        // every Real of the outputs a different value
        let mut o = Outputs::default();
        let mut next = 1.0;
        let mut fill = |x: &mut Real| {
            *x = next;
            next += 1.0;
        };
        for c in [
            &mut o.cp, &mut o.cu, &mut o.cv, &mut o.cef, &mut o.cvf, &mut o.csf, &mut o.crf,
            &mut o.ctf,
        ] {
            c.iter_mut().for_each(&mut fill);
        }
        for v in [&mut o.fa, &mut o.ma, &mut o.fb, &mut o.mb] {
            v.iter_mut().for_each(&mut fill);
        }
        let (fr, e) = (&mut o.friction, &mut o.energy);
        for x in [
            &mut fr.cnf,
            &mut fr.cnm1,
            &mut fr.csfc,
            &mut fr.csmc1,
            &mut fr.slip,
            &mut fr.slip_r1,
            &mut e.stored,
            &mut e.damping,
            &mut e.friction,
            &mut e.stops,
        ] {
            fill(x);
        }
        assert_eq!(
            next,
            CONTINUOUS_LEN as Real + 1.0,
            "every Real output filled"
        );
        let row = continuous_row(&o);
        for s in VARIANTS {
            let t = table(s.variant);
            let tables = real_tables(t);
            for v in &t.vars {
                let j = tables
                    .continuous_index
                    .get(v.vr as usize)
                    .copied()
                    .unwrap_or(NO_INDEX);
                let continuous = Ty::of(&v.start) == Ty::Real
                    && v.causality == Causality::Output
                    && v.variability == Variability::Continuous;
                assert_eq!(j != NO_INDEX, continuous, "{}", v.name);
                if continuous {
                    assert_eq!(row[j as usize], read_output(&o, v.field), "{}", v.name);
                }
            }
        }
    }
}
