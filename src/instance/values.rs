//! Get and set through the variable table: every value reference and type is checked, and a
//! set call is all or nothing (a rejected value leaves the instance as it was).
//!
//! Uses the instance (mod.rs), its memo, the model's access rules, slots, snapshot and table, and
//! the physics; nothing below the instance uses it.

use super::memo::copy_runs;
use super::{Call, FmiVersion, ModelInstance};
use crate::error::{FmuError, FmuResult};
use crate::model::access::{
    node_loads, read_int_param, read_output, read_real_param, write_int, write_real, Ty,
};
use crate::model::slots::{RealSlot, NO_INDEX};
use crate::model::snapshot::{Mode, Snapshot};
use crate::model::variables::{
    Causality, CompPar, Field, FrictionField, NodeInputs, VarSpec, Variability,
};
use crate::physics::connector::{Outputs, Params};
use crate::physics::math::{all_finite, Real};

impl ModelInstance {
    /// Looks a VR up and checks its type, naming the function in errors.
    #[inline]
    pub(super) fn var(&self, vr: u32, want: Ty) -> FmuResult<&'static VarSpec> {
        match self.table.get(vr) {
            Some(v) if Ty::of(&v.start) == want => Ok(v),
            found => Err(var_error(vr, found, want, self.fmi)),
        }
    }

    /// The (node, index) of a Real node input `vr` given a finite `what` value `x`, or the
    /// error that names the variable (input derivatives, directional-derivative seeds).
    pub(super) fn finite_input(&self, vr: u32, x: Real, what: &str) -> FmuResult<(usize, usize)> {
        let v = self.var(vr, Ty::Real)?;
        let Field::Input { node, idx } = v.field else {
            return Err(FmuError::error(format!("{} is not an input", v.name)));
        };
        if !x.is_finite() {
            return Err(FmuError::error(format!(
                "the {what} for {} is not finite",
                v.name
            )));
        }
        Ok((node as usize, idx as usize))
    }

    /// Checks that `v` may be set in the current mode.
    fn settable(&self, v: &VarSpec) -> FmuResult<()> {
        let ok = match (v.causality, v.variability) {
            (Causality::Output, _) => false,
            (Causality::Parameter, Variability::Fixed) => {
                matches!(self.s.mode, Mode::Instantiated | Mode::InitializationMode)
            }
            _ => true,
        };
        if ok {
            Ok(())
        } else if v.causality == Causality::Output {
            Err(FmuError::error(format!(
                "{} is an output and cannot be set",
                v.name
            )))
        } else {
            Err(FmuError::error(format!(
                "fixed parameter {} cannot be set in state {:?}",
                v.name, self.s.mode
            )))
        }
    }

    /// Applies a batch of sets to a copy and commits only when every value is accepted.
    #[inline(never)]
    fn set_batch<T: Copy>(
        &mut self,
        vrs: &[u32],
        values: &[T],
        ty: Ty,
        write: impl Fn(&mut Params, &mut [NodeInputs; 2], &VarSpec, T) -> Result<(), String>,
    ) -> FmuResult<()> {
        self.allowed(Call::Set)?;
        let mut touches_params = false;
        for &vr in vrs {
            let v = self.var(vr, ty)?;
            self.settable(v)?;
            touches_params |= v.causality == Causality::Parameter;
        }
        if !touches_params {
            // the per-step path: node inputs only, no parameter copy or check
            let mut inputs = self.s.inputs;
            for (&vr, &x) in vrs.iter().zip(values) {
                let v = self.var(vr, ty)?;
                write(&mut self.s.params, &mut inputs, v, x)
                    .map_err(|why| FmuError::error(format!("{} {why}; value not set", v.name)))?;
            }
            if inputs != self.s.inputs {
                self.s.inputs = inputs;
                self.s.outputs.clear();
            }
            return Ok(());
        }
        let mut params = self.s.params;
        let mut inputs = self.s.inputs;
        for (&vr, &x) in vrs.iter().zip(values) {
            let v = self.var(vr, ty)?;
            write(&mut params, &mut inputs, v, x)
                .map_err(|why| FmuError::error(format!("{} {why}; value not set", v.name)))?;
        }
        if self.s.mode == Mode::StepComplete && params != self.s.params {
            params.check(&self.ct.roles()).map_err(|name| {
                FmuError::error(format!("invalid parameter {name}; values not set"))
            })?;
        }
        if params != self.s.params {
            // stops and friction parameters move the event functions
            self.s.events = None;
        }
        if params != self.s.params || inputs != self.s.inputs {
            self.s.params = params;
            self.s.inputs = inputs;
            self.s.outputs.clear();
        }
        Ok(())
    }

    /// fmi2SetReal.
    pub fn set_real(&mut self, vrs: &[u32], values: &[Real]) -> FmuResult<()> {
        // The per-step path: finite values of node inputs only, written in place in one pass;
        // the first value that is not for this path puts the inputs back as they were and
        // hands the whole call to the general batch, which names the culprit (all or nothing).
        self.allowed(Call::Set)?;
        // The list of the last call again (every step's case): its slots are known, so the
        // values are checked first and then written run by run (`memo::Run`), without a
        // look-up or a copy to put back.
        if self.set_memo.holds(vrs) && all_finite(values) {
            let flat = self.s.inputs.as_flattened_mut();
            match self.set_memo.runs() {
                Some(runs) => copy_runs(runs, (flat, |r| r.slot), (values, |r| r.at)),
                None => {
                    for (&j, &x) in self.set_memo.slots().iter().zip(values) {
                        if let Some(u) = flat.get_mut(j as usize) {
                            *u = x;
                        }
                    }
                }
            }
            self.s.outputs.clear();
            return Ok(());
        }
        let index = &*self.real.input_index;
        let slot = |vr: u32| index.get(vr as usize).copied().unwrap_or(NO_INDEX);
        let before = self.s.inputs;
        let flat = self.s.inputs.as_flattened_mut();
        for (&vr, &x) in vrs.iter().zip(values) {
            match flat.get_mut(slot(vr) as usize) {
                Some(u) if x.is_finite() => *u = x,
                _ => {
                    self.s.inputs = before;
                    return self.set_batch(vrs, values, Ty::Real, write_real);
                }
            }
        }
        self.set_memo.remember(vrs, vrs.iter().map(|&vr| slot(vr)));
        // the cached outputs were those at the old inputs: they are evaluated again when read
        self.s.outputs.clear();
        Ok(())
    }

    /// fmi2SetInteger.
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> FmuResult<()> {
        self.set_batch(vrs, values, Ty::Integer, |p, _, v, x| write_int(p, v, x))
    }

    /// fmi2SetBoolean.
    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> FmuResult<()> {
        self.set_batch(vrs, values, Ty::Boolean, |p, _, v, x| match v.field {
            Field::CompParam {
                par: CompPar::RefGiven,
                k,
            } => {
                p.ref_given[k as usize] = x;
                Ok(())
            }
            _ => Err("is not a Boolean".to_string()),
        })
    }

    /// fmi2SetString: there are no String variables.
    pub fn set_string(&mut self, vrs: &[u32]) -> FmuResult<()> {
        self.allowed(Call::Set)?;
        match vrs.first() {
            None => Ok(()),
            Some(vr) => Err(FmuError::error(format!(
                "unknown value reference {vr} (this FMU has no String variables)"
            ))),
        }
    }

    /// fmi2GetString: there are no String variables.
    pub fn get_string(&mut self, vrs: &[u32]) -> FmuResult<()> {
        self.allowed(Call::Get)?;
        match vrs.first() {
            None => Ok(()),
            Some(vr) => Err(FmuError::error(format!(
                "unknown value reference {vr} (this FMU has no String variables)"
            ))),
        }
    }

    /// A get call: every VR is checked (type and existence) before anything is written, the
    /// outputs are evaluated once when one is asked for, then `read` fills each slot.
    fn get_values<T>(
        &mut self,
        vrs: &[u32],
        out: &mut [T],
        ty: Ty,
        read: impl Fn(&Snapshot, &VarSpec, Option<&Outputs>) -> T,
    ) -> FmuResult<()> {
        self.allowed(Call::Get)?;
        let mut any_output = false;
        for &vr in vrs {
            any_output |= self.var(vr, ty)?.causality == Causality::Output;
        }
        if any_output {
            self.outputs()?;
        }
        let o = self.s.outputs.get();
        for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
            *slot = read(&self.s, self.var(vr, ty)?, o);
        }
        Ok(())
    }

    /// fmi2GetReal.
    pub fn get_real(&mut self, vrs: &[u32], out: &mut [Real]) -> FmuResult<()> {
        // The per-step path: node loads only (the usual read after a step), then every VR a
        // Real variable (else the general get names the culprit); all are checked before
        // anything is written, then read through the slot tables.
        self.allowed(Call::Get)?;
        let index = &*self.real.load_index;
        let load = |vr: u32| index.get(vr as usize).copied().unwrap_or(NO_INDEX);
        // the list of the last call again (every step's case): its slots are known
        if self.get_memo.holds(vrs) {
            let loads = node_loads(self.outputs()?);
            match self.get_memo.runs() {
                Some(runs) => copy_runs(runs, (out, |r| r.at), (&loads, |r| r.slot)),
                None => {
                    for (&l, slot) in self.get_memo.slots().iter().zip(out.iter_mut()) {
                        *slot = loads.get(l as usize).copied().unwrap_or(0.0);
                    }
                }
            }
            return Ok(());
        }
        if vrs.iter().all(|&vr| load(vr) != NO_INDEX) {
            let loads = node_loads(self.outputs()?);
            for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
                if let Some(&l) = loads.get(load(vr) as usize) {
                    *slot = l;
                }
            }
            self.get_memo.remember(vrs, vrs.iter().map(|&vr| load(vr)));
            return Ok(());
        }
        let mut any_output = false;
        for &vr in vrs {
            match self.real.slots.get(vr as usize) {
                Some(RealSlot::Load(_) | RealSlot::Output(_)) => any_output = true,
                Some(RealSlot::Input(_) | RealSlot::Param(_)) => {}
                _ => return self.get_real_general(vrs, out),
            }
        }
        if any_output {
            self.outputs()?;
        }
        let (o, loads) = match self.s.outputs.get() {
            Some(o) => (Some(o), node_loads(o)),
            None => (None, [0.0; 12]),
        };
        let (slots, s) = (&self.real.slots, &self.s);
        for (&vr, slot) in vrs.iter().zip(out.iter_mut()) {
            *slot = match (slots[vr as usize], o) {
                (RealSlot::Input(j), _) => s.inputs.as_flattened()[j as usize],
                (RealSlot::Load(j), _) => loads[j as usize],
                (RealSlot::Output(f), Some(o)) => read_output(o, f),
                (RealSlot::Output(f) | RealSlot::Param(f), _) => read_real_param(&s.params, f),
                (RealSlot::None, _) => 0.0,
            };
        }
        Ok(())
    }

    /// fmi2GetReal through the variable table (reports unknown VRs and VRs of other types).
    #[cold]
    fn get_real_general(&mut self, vrs: &[u32], out: &mut [Real]) -> FmuResult<()> {
        self.get_values(vrs, out, Ty::Real, |s, v, o| match (v.field, o) {
            (Field::Input { node, idx }, _) => s.inputs[node as usize][idx as usize],
            (f, Some(o)) if v.causality == Causality::Output => read_output(o, f),
            (f, _) => read_real_param(&s.params, f),
        })
    }

    /// fmi2GetInteger.
    pub fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> FmuResult<()> {
        self.get_values(vrs, out, Ty::Integer, |s, v, o| match (v.field, o) {
            (Field::StopStatus(k), Some(o)) => o.cslst[k as usize],
            (Field::Friction(FrictionField::Status), Some(o)) => o.friction.status as i32,
            (Field::Friction(FrictionField::StatusR1), Some(o)) => o.friction.status_r1 as i32,
            (Field::Event(_), Some(o)) => o.event_count,
            (f, _) => read_int_param(&s.params, f),
        })
    }

    /// fmi2GetBoolean.
    pub fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> FmuResult<()> {
        self.get_values(vrs, out, Ty::Boolean, |s, v, _| match v.field {
            Field::CompParam { k, .. } => s.params.ref_given[k as usize],
            _ => false,
        })
    }
}

/// The message for an unknown VR or a VR of another type (off the hot path).
#[cold]
fn var_error(vr: u32, found: Option<&VarSpec>, want: Ty, fmi: FmiVersion) -> FmuError {
    match found {
        None => FmuError::error(format!("unknown value reference {vr}")),
        Some(v) => FmuError::error(format!(
            "variable {} (vr {vr}) is of type {}, not {}",
            v.name,
            fmi.type_name(Ty::of(&v.start)),
            fmi.type_name(want)
        )),
    }
}
