//! Input derivatives (for the next step's extrapolation) and directional derivatives.
//!
//! Uses the instance (mod.rs), its memo, the model's access rules, slots and table, and the
//! physics; nothing below the instance uses it.

use super::memo::copy_runs;
use super::{Call, ModelInstance};
use crate::error::{FmuError, FmuResult};
use crate::model::access::{continuous_row_map, Ty};
use crate::model::slots::NO_INDEX;
use crate::model::variables::{Causality, Table, Variability, NODE_INPUTS, POSE_TWIST};
use crate::physics::friction::Eval;
use crate::physics::math::{all_finite, Real};

impl ModelInstance {
    /// fmi2SetRealInputDerivatives (first order only; valid for the next fmi2DoStep).
    pub fn set_real_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[Real],
    ) -> FmuResult<()> {
        self.allowed(Call::Set)?;
        let mut der = self.s.input_der;
        let mut set = self.s.input_der_set;
        for ((&vr, &order), &x) in vrs.iter().zip(orders).zip(values) {
            let (node, idx) = self.finite_input(vr, x, "derivative")?;
            if idx >= POSE_TWIST {
                return Err(FmuError::error(format!(
                    "{} takes no input derivative (only positions, orientations and velocities do; the accelerations are themselves the velocities' derivatives); not set",
                    self.table.get(vr).map_or("?", |v| v.name.as_str())
                )));
            }
            if order != 1 {
                return Err(FmuError::error(format!(
                    "derivative order {order} of {} is not supported (only 1); not set",
                    self.table.get(vr).map_or("?", |v| v.name.as_str())
                )));
            }
            der[node][idx] = x;
            set[node][idx] = true;
        }
        self.s.input_der = der;
        self.s.input_der_set = set;
        Ok(())
    }

    /// fmi2GetDirectionalDerivative: J·dknown, J = ∂(unknowns)/∂(knowns) at the current
    /// inputs and committed state: the connector's consistent tangent (stick: stick stiffness;
    /// slip: tangent of the return map; active stops and penalties included).
    ///
    /// A friction effect is differentiated on the branch of its status at the current inputs
    /// (`Eval::Tangent`): where a slipping step ended, the return map's slip tangent; where an
    /// effect sticks (also held at rest on its limit), the stick spring's; never the average of
    /// the stick and slip sides of the kink.
    ///
    /// Analytic: one evaluation of the kernel in dual numbers (`math::Dual`) with the inputs
    /// seeded along dknown gives J·dknown exactly, up to round-off: the kinematics' first and
    /// second derivatives (the gradients' own derivatives enter the rates and node loads),
    /// the quaternions' normalisation, and the constitutive tangents (springs, dampers, stops,
    /// penalties, stick springs, the return map, the coupled mode's disc flow by the implicit
    /// function). Where a step ended, the accumulated slips |Δs| and the plastic work sit on
    /// their kinks and take the central difference's value there; a stop exactly at contact is
    /// differentiated on its free side. The committed state is not touched.
    pub fn directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        dknown: &[Real],
        out: &mut [Real],
    ) -> FmuResult<()> {
        self.allowed(Call::Get)?;
        let (rows, inputs) = (&*self.real.continuous_index, &*self.real.input_index);
        let row_of = |vr: u32| rows.get(vr as usize).copied().unwrap_or(NO_INDEX);
        let input_of = |vr: u32| inputs.get(vr as usize).copied().unwrap_or(NO_INDEX);
        // every unknown and seed is checked before anything is computed, through the compact
        // tables; the variable table only names the first one refused. The unknowns' rows are
        // remembered with their list: a linear-implicit master asks for the same unknowns
        // along every input, and a list equal to the last one was checked then.
        if !self.unknown_memo.holds(unknowns) {
            if unknowns.iter().any(|&vr| row_of(vr) == NO_INDEX) {
                return Err(self.unknown_error(unknowns));
            }
            let rows = unknowns.iter().map(|&vr| row_of(vr));
            self.unknown_memo.remember(unknowns, rows);
        }
        let seeds = knowns.iter().zip(dknown);
        if seeds
            .clone()
            .any(|(&vr, &d)| input_of(vr) == NO_INDEX || !d.is_finite())
        {
            return Err(self.seed_error(knowns, dknown));
        }
        let dmax = seeds.clone().fold(0.0, |m: Real, (_, d)| m.max(d.abs()));
        if dmax == 0.0 {
            out.iter_mut().for_each(|x| *x = 0.0);
            return Ok(());
        }
        // J·δ is linear in δ: seeded with δ/max|δ| and scaled back by max|δ|, so that neither
        // huge nor denormal seeds overflow or underflow inside the kernel (regression 003)
        // (the outputs do not depend on the acceleration inputs: their seeds add nothing)
        let mut seed = [[0.0; POSE_TWIST]; 2];
        for (&vr, &d) in seeds {
            let j = input_of(vr) as usize;
            if let Some(s) = seed[j / NODE_INPUTS].get_mut(j % NODE_INPUTS) {
                *s += d / dmax;
            }
        }
        // effects slipping at the current inputs are differentiated on their slip branch
        let here = self.outputs()?.friction;
        let mode = Eval::Tangent([here.status, here.status_r1]);
        self.tangent_into(&seed, mode)?;
        // the derivatives of every continuous output, scaled back; the remembered rows (all
        // within the row) as slices where they run in the row's order (the usual list: the
        // model description's), then whether every value is finite (in one vectorised pass;
        // the first that is not is named)
        let row = continuous_row_map(&self.tangent.o, |x| dmax * x.eps);
        match self.unknown_memo.runs() {
            Some(runs) => copy_runs(runs, (out, |r| r.at), (&row, |r| r.slot)),
            None => {
                for (&r, slot) in self.unknown_memo.slots().iter().zip(out.iter_mut()) {
                    *slot = row.get(r as usize).copied().unwrap_or(0.0);
                }
            }
        }
        if !all_finite(&out[..unknowns.len().min(out.len())]) {
            return Err(not_finite_error(self.table, unknowns, out, dmax));
        }
        Ok(())
    }
}

/// The error for the first derivative that is not finite (its seed's size `dmax` takes it
/// beyond the range of a double).
#[cold]
#[inline(never)]
fn not_finite_error(table: &Table, unknowns: &[u32], out: &[Real], dmax: Real) -> FmuError {
    let vr = unknowns
        .iter()
        .zip(out)
        .find(|(_, d)| !d.is_finite())
        .map_or(0, |(&vr, _)| vr);
    let name = table.get(vr).map_or("?", |v| v.name.as_str());
    FmuError::error(format!(
        "the derivative of {name} along dvKnown is not finite (the seed's size {dmax:e} takes it beyond the range of a double)"
    ))
}

impl ModelInstance {
    /// The error for the first unknown that is not a continuous Real output.
    #[cold]
    #[inline(never)]
    fn unknown_error(&self, unknowns: &[u32]) -> FmuError {
        for &vr in unknowns {
            let v = match self.var(vr, Ty::Real) {
                Ok(v) => v,
                Err(e) => return e,
            };
            if v.causality != Causality::Output || v.variability != Variability::Continuous {
                return FmuError::error(format!(
                    "unknown {} is not a continuous Real output",
                    v.name
                ));
            }
        }
        FmuError::error("an unknown is not a continuous Real output")
    }

    /// The error for the first seed that is not a finite value of a node input.
    #[cold]
    #[inline(never)]
    fn seed_error(&self, knowns: &[u32], dknown: &[Real]) -> FmuError {
        for (&vr, &d) in knowns.iter().zip(dknown) {
            if let Err(e) = self.finite_input(vr, d, "seed") {
                return e;
            }
        }
        FmuError::error("a seed is not a finite value of a node input")
    }

    /// fmi3GetAdjointDerivative: Jᵀ·v for the same J as `directional_derivative`, built from
    /// its columns: entry j is Σᵢ vᵢ·(J·eⱼ)ᵢ with J·eⱼ the directional derivative along the unit
    /// seed of known j. So the adjoint is the exact transpose of the Jacobian the directional
    /// derivatives give column by column (up to the rounding of the sum), not a second
    /// approximation of it.
    pub fn adjoint_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[Real],
        out: &mut [Real],
    ) -> FmuResult<()> {
        self.allowed(Call::Get)?;
        let mut column = vec![0.0; unknowns.len()];
        // checks every unknown (continuous Real output) before anything is computed
        self.directional_derivative(unknowns, &[], &[], &mut column)?;
        for (&vr, &v) in unknowns.iter().zip(seed) {
            if !v.is_finite() {
                let name = self.table.get(vr).map_or("?", |x| x.name.as_str());
                return Err(FmuError::error(format!(
                    "the seed for {name} is not finite"
                )));
            }
        }
        let mut result = vec![0.0; knowns.len()];
        for (slot, &k) in result.iter_mut().zip(knowns) {
            self.directional_derivative(unknowns, &[k], &[1.0], &mut column)?;
            let x: Real = column.iter().zip(seed).map(|(c, v)| c * v).sum();
            if !x.is_finite() {
                let name = self.table.get(k).map_or("?", |x| x.name.as_str());
                return Err(FmuError::error(format!(
                    "the adjoint derivative for {name} is not finite (the seed takes it beyond the range of a double)"
                )));
            }
            *slot = x;
        }
        for (o, r) in out.iter_mut().zip(result) {
            *o = r;
        }
        Ok(())
    }
}
