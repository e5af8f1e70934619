//! Getting and setting values through the variable table: every value reference and type is
//! checked before anything is written (a get writes its outputs only on success, a set applies
//! all of its values or none), a non-finite or out-of-range value is refused naming the
//! variable, and outputs are computed from the body when read. Uses the instance's data
//! (`super`), `crate::variables` and `crate::physics`.

use super::data::Mode;
use super::{Call, FmiVersion, Instance};
use crate::error::{FmuError, FmuResult};
use crate::physics::{self, ports, Body, PORTS};
use crate::variables::{by_vr, Causality, Out, Slot, Var, TIME_VR};

/// What a value reference is, for an access of Reals (`integer == false`) or Integers.
enum Target {
    Time,
    Var(&'static Var),
}

impl Instance {
    /// The row of `vr` for an access of the given type; Err names the value reference.
    fn target(&self, vr: u32, integer: bool) -> FmuResult<Target> {
        let ty = if integer { "Integer" } else { "Real" };
        if vr == TIME_VR && self.version == FmiVersion::V3 && !integer {
            return Ok(Target::Time);
        }
        match by_vr(vr) {
            Some(v) if v.is_integer() == integer => Ok(Target::Var(v)),
            Some(v) => Err(FmuError::error(format!(
                "vr {vr} ({}) is not of type {}",
                v.name,
                self.type_name(ty)
            ))),
            None => Err(FmuError::error(format!(
                "vr {vr} is no {} variable of this FMU",
                self.type_name(ty)
            ))),
        }
    }

    /// The FMI version's name of a type.
    fn type_name(&self, ty: &'static str) -> &'static str {
        match (self.version, ty) {
            (FmiVersion::V3, "Real") => "Float64",
            (FmiVersion::V3, "Integer") => "Int32",
            _ => ty,
        }
    }

    /// The body whose values the outputs show: in Initialization Mode the start state of the
    /// current parameters (refused with the reason when they do not fit together).
    fn shown_body(&self) -> FmuResult<Body> {
        if self.data.mode == Mode::Initialization {
            return physics::initial(&self.data.params()).map_err(|e| {
                FmuError::error(format!(
                    "the outputs follow the start parameters in Initialization Mode, and {e}"
                ))
            });
        }
        Ok(self.data.body)
    }

    /// Reals (and FMI 3.0's time) into `out`, written only when every value reference is good:
    /// every one is checked first, then each read (no allocation; a port's frame is computed
    /// once per call, however many of its outputs are read).
    pub fn get_real(&self, vrs: &[u32], out: &mut [f64]) -> FmuResult<()> {
        self.allowed(Call::Get)?;
        let mut reads_output = false;
        for &vr in vrs {
            let t = self.target(vr, false)?;
            reads_output |= matches!(t, Target::Var(v) if v.causality == Causality::Output);
        }
        let body = match reads_output {
            true => self.shown_body()?,
            false => self.data.body,
        };
        let params = self.data.params();
        let mut frames = [None; PORTS];
        for (o, &vr) in out.iter_mut().zip(vrs) {
            *o = match self.target(vr, false)? {
                Target::Time => self.data.time,
                Target::Var(v) => match v.slot {
                    Slot::Real(i) => self.data.reals[i],
                    Slot::Out(out) => output(&params, &body, out, &mut frames),
                    // `target` gives Real rows only; an Integer slot cannot occur here
                    Slot::Int(i) => f64::from(self.data.ints[i]),
                },
            };
        }
        Ok(())
    }

    /// Integers into `out`, written only when every value reference is good.
    pub fn get_integer(&self, vrs: &[u32], out: &mut [i32]) -> FmuResult<()> {
        self.allowed(Call::Get)?;
        let slots = vrs
            .iter()
            .map(|&vr| match self.target(vr, true)? {
                Target::Var(Var {
                    slot: Slot::Int(i), ..
                }) => Ok(*i),
                _ => Err(FmuError::error(format!("vr {vr} is no Integer variable"))),
            })
            .collect::<FmuResult<Vec<_>>>()?;
        for (o, i) in out.iter_mut().zip(slots) {
            *o = self.data.ints[i];
        }
        Ok(())
    }

    /// Ok when `v` may be set now; Err names it and why not.
    fn settable(&self, v: &Var) -> FmuResult<()> {
        let p = self.version.prefix();
        match (v.causality, self.data.mode) {
            (Causality::Output, _) => Err(FmuError::error(format!(
                "{} is an output and cannot be set",
                v.name
            ))),
            (Causality::Parameter, Mode::Step) => Err(FmuError::error(format!(
                "{} is a fixed parameter: it can be set only before {p}ExitInitializationMode",
                v.name
            ))),
            _ => Ok(()),
        }
    }

    /// Sets Reals: all of them or, when one is refused (unknown, wrong type, not settable now,
    /// not finite, out of range), none.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> FmuResult<()> {
        self.allowed(Call::Set)?;
        // every value checked before any is written (no allocation: the look-up is an index)
        for (&vr, &x) in vrs.iter().zip(values) {
            self.real_to_set(vr, x)?;
        }
        for (&vr, &x) in vrs.iter().zip(values) {
            if let Slot::Real(i) = self.real_to_set(vr, x)?.slot {
                self.data.reals[i] = x;
            }
        }
        Ok(())
    }

    /// The row `vr` of a Real that may be set to `x` now; Err names it and why not.
    fn real_to_set(&self, vr: u32, x: f64) -> FmuResult<&'static Var> {
        let v = match self.target(vr, false)? {
            Target::Time => {
                return Err(FmuError::error(
                    "time (vr 0) is the independent variable and cannot be set",
                ))
            }
            Target::Var(v) => v,
        };
        self.settable(v)?;
        if !x.is_finite() {
            return Err(FmuError::error(format!(
                "{} = {x:?} is refused: values must be finite",
                v.name
            )));
        }
        v.check_range(x).map_err(FmuError::error)?;
        Ok(v)
    }

    /// Sets Integers: all of them or none (as `set_real`).
    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> FmuResult<()> {
        self.allowed(Call::Set)?;
        let mut slots = Vec::with_capacity(vrs.len());
        for (&vr, &x) in vrs.iter().zip(values) {
            let Target::Var(v) = self.target(vr, true)? else {
                return Err(FmuError::error(format!("vr {vr} is no Integer variable")));
            };
            self.settable(v)?;
            v.check_range(f64::from(x)).map_err(FmuError::error)?;
            if let Slot::Int(i) = v.slot {
                slots.push((i, x));
            }
        }
        for (i, x) in slots {
            self.data.ints[i] = x;
        }
        Ok(())
    }

    /// Get or set of a type this FMU has no variables of (Boolean, String, FMI 3.0's other
    /// types): an empty request is OK, any value reference is refused naming it.
    pub fn no_variables_of_type(&self, call: Call, vrs: &[u32], ty: &str) -> FmuResult<()> {
        self.allowed(call)?;
        match vrs.first() {
            None => Ok(()),
            Some(&vr) => Err(FmuError::error(match by_vr(vr) {
                Some(v) => format!(
                    "vr {vr} ({}) is not of type {ty}: this FMU has no {ty} variables",
                    v.name
                ),
                None => format!("vr {vr}: this FMU has no {ty} variables"),
            })),
        }
    }
}

/// The value of an output for the body `b`; `frames` holds the port frames computed so far in
/// this read.
fn output(
    p: &physics::Params,
    b: &Body,
    out: Out,
    frames: &mut [Option<ports::PortState>; PORTS],
) -> f64 {
    let mut frame = |k: usize| *frames[k].get_or_insert_with(|| ports::kinematics(b, &p.ports[k]));
    match out {
        Out::R(i) => b.r[i],
        Out::Q(i) => b.q[i],
        Out::V(i) => b.v[i],
        Out::W(i) => b.w[i],
        Out::PortR(k, i) => frame(k).r[i],
        Out::PortQ(k, i) => frame(k).q[i],
        Out::PortV(k, i) => frame(k).v[i],
        Out::PortW(k, i) => frame(k).w[i],
        Out::Kinetic => physics::energies(p, b).0,
        Out::Potential => physics::energies(p, b).1,
    }
}
