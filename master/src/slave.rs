//! One running instance behind one interface, either FMI version: set up, initialise, step,
//! get and set values by type, terminate. Every call is counted (and timed when profiling), and
//! a failing call becomes an `Error` naming the component, the FMI function, the time and what
//! the FMU logged. FMI 2.0 and 3.0 differences end here. Uses fmu.rs, ffi/, model_description.rs
//! and error.rs.

use crate::error::{Error, Result};
use crate::ffi::fmi2::Fmi2Instance;
use crate::ffi::fmi3::Fmi3Instance;
use crate::ffi::{LogSink, Status};
use crate::fmu::{Fmu, Loaded};
use crate::model_description::{Family, ModelDescription, VarType, Variable};
use std::sync::Arc;
use std::time::{Duration, Instant};

enum Instance {
    V2(Fmi2Instance),
    V3(Fmi3Instance),
}

/// How a step ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StepEnd {
    /// The FMU reached the end of the step.
    Done,
    /// The FMU asks to end the simulation (terminate requested): a normal end.
    Terminate,
}

/// A value of one of the families.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// Real.
    Real(f64),
    /// Integer (and Enumeration).
    Integer(i64),
    /// Boolean.
    Boolean(bool),
    /// String.
    String(String),
}

impl Value {
    /// Parses `text` as a value of `family`.
    pub fn parse(family: Family, text: &str) -> std::result::Result<Value, String> {
        let t = text.trim();
        match family {
            Family::Real => t
                .parse::<f64>()
                .map(Value::Real)
                .map_err(|_| format!("'{text}' is not a number")),
            Family::Integer => t
                .parse::<i64>()
                .or_else(|_| {
                    t.parse::<f64>()
                        .ok()
                        .filter(|v| v.fract() == 0.0 && v.abs() < 9.0e15)
                        .map(|v| v as i64)
                        .ok_or(())
                })
                .map(Value::Integer)
                .map_err(|_| format!("'{text}' is not a whole number")),
            Family::Boolean => match t {
                "true" | "1" => Ok(Value::Boolean(true)),
                "false" | "0" => Ok(Value::Boolean(false)),
                _ => Err(format!("'{text}' is not a Boolean (true, false, 1, 0)")),
            },
            Family::String => Ok(Value::String(text.to_string())),
            Family::Other => Err("Binary and Clock values cannot be set".to_string()),
        }
    }
}

/// One instance of an FMU.
pub struct Slave {
    /// The instance (component) name.
    pub name: String,
    /// The FMU's model description.
    pub md: Arc<ModelDescription>,
    inst: Instance,
    start: f64,
    stop: Option<f64>,
    /// FMI calls made so far.
    pub calls: u64,
    /// Time spent inside FMI functions (when `profile` is on).
    pub fmu_time: Duration,
    /// Time each FMI call.
    pub profile: bool,
    strings: Vec<String>,
}

impl Slave {
    /// Instantiates `fmu` as `name`.
    pub fn new(fmu: &Fmu, name: &str, echo_log: bool) -> Result<Slave> {
        let log = Arc::new(LogSink::new(echo_log));
        let inst = match &fmu.lib {
            Loaded::V2(l) => {
                Instance::V2(l.instantiate(name, &fmu.md.token, &fmu.resources(), log)?)
            }
            Loaded::V3(l) => {
                Instance::V3(l.instantiate(name, &fmu.md.token, &fmu.resources(), log)?)
            }
        };
        Ok(Slave {
            name: name.to_string(),
            md: Arc::clone(&fmu.md),
            inst,
            start: 0.0,
            stop: None,
            calls: 1,
            fmu_time: Duration::ZERO,
            profile: false,
            strings: Vec::new(),
        })
    }

    fn prefix(&self) -> &'static str {
        match self.inst {
            Instance::V2(_) => "fmi2",
            Instance::V3(_) => "fmi3",
        }
    }

    fn logged(&self) -> String {
        match &self.inst {
            Instance::V2(i) => i.log.take(),
            Instance::V3(i) => i.log.take(),
        }
    }

    /// An error for `function` (without its prefix) returning `status`.
    fn failed(&self, function: &str, status: Status, t: Option<f64>) -> Error {
        let logged = self.logged();
        let mut e = Error::new(format!(
            "returned {}{}",
            status.name(self.prefix()),
            if logged.is_empty() {
                String::new()
            } else {
                format!(" ({logged})")
            }
        ))
        .component(&self.name)
        .function(format!("{}{function}", self.prefix()));
        if let Some(t) = t {
            e = e.at(t);
        }
        e
    }

    fn check(&self, function: &str, status: Status, t: Option<f64>) -> Result<()> {
        if status.ok() {
            Ok(())
        } else {
            Err(self.failed(function, status, t))
        }
    }

    /// Runs `f` on the instance, counting (and timing) the call.
    #[inline]
    fn call<R>(&mut self, f: impl FnOnce(&mut Instance) -> R) -> R {
        self.calls += 1;
        if self.profile {
            let clock = Instant::now();
            let r = f(&mut self.inst);
            self.fmu_time += clock.elapsed();
            r
        } else {
            f(&mut self.inst)
        }
    }

    /// fmi2SetupExperiment (FMI 2.0); FMI 3.0 keeps start and stop for its
    /// fmi3EnterInitializationMode.
    pub fn setup(&mut self, start: f64, stop: Option<f64>) -> Result<()> {
        self.start = start;
        self.stop = stop;
        if matches!(self.inst, Instance::V2(_)) {
            let s = self.call(|i| {
                if let Instance::V2(i) = i {
                    i.setup(start, stop)
                } else {
                    Status::Ok
                }
            });
            self.check("SetupExperiment", s, Some(start))?;
        }
        Ok(())
    }

    /// Enter initialization mode.
    pub fn enter_initialization(&mut self) -> Result<()> {
        let (start, stop) = (self.start, self.stop);
        let s = self.call(|i| match i {
            Instance::V2(i) => i.enter_initialization(),
            Instance::V3(i) => i.enter_initialization(start, stop),
        });
        self.check("EnterInitializationMode", s, Some(start))
    }

    /// Exit initialization mode.
    pub fn exit_initialization(&mut self) -> Result<()> {
        let s = self.call(|i| match i {
            Instance::V2(i) => i.exit_initialization(),
            Instance::V3(i) => i.exit_initialization(),
        });
        self.check("ExitInitializationMode", s, Some(self.start))
    }

    /// One step from `t` of `h`: Done, or Terminate when the FMU asks to end; Discard, Error
    /// and Fatal are errors.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<StepEnd> {
        match self.call(|i| match i {
            Instance::V2(i) => (i.do_step(t, h), None),
            Instance::V3(i) => {
                let (s, r) = i.do_step(t, h);
                (s, Some(r))
            }
        }) {
            (s, Some(r)) if s.ok() => Ok(if r.terminate {
                StepEnd::Terminate
            } else {
                StepEnd::Done
            }),
            (s, None) if s.ok() => Ok(StepEnd::Done),
            (Status::Discard, None) => {
                let terminated = self.call(|i| {
                    if let Instance::V2(i) = i {
                        i.terminated()
                    } else {
                        false
                    }
                });
                if terminated {
                    Ok(StepEnd::Terminate)
                } else {
                    Err(self.failed("DoStep", Status::Discard, Some(t)))
                }
            }
            (Status::Discard, Some(r)) if r.terminate => Ok(StepEnd::Terminate),
            (s, _) => Err(self.failed("DoStep", s, Some(t))),
        }
    }

    /// Terminate (errors are reported, but the instance is freed anyway on drop).
    pub fn terminate(&mut self) -> Result<()> {
        let s = self.call(|i| match i {
            Instance::V2(i) => i.terminate(),
            Instance::V3(i) => i.terminate(),
        });
        self.check("Terminate", s, None)
    }

    fn fn_name(get: bool, ty: VarType, v2: bool) -> String {
        let dir = if get { "Get" } else { "Set" };
        if v2 {
            let t = match ty.family() {
                Family::Real => "Real",
                Family::Integer => "Integer",
                Family::Boolean => "Boolean",
                _ => "String",
            };
            format!("fmi2{dir}{t}")
        } else {
            format!("fmi3{dir}{ty:?}")
        }
    }

    fn value_error(&self, get: bool, ty: VarType, s: Status, t: Option<f64>) -> Error {
        let f = Self::fn_name(get, ty, matches!(self.inst, Instance::V2(_)));
        let short = f.trim_start_matches(self.prefix()).to_string();
        self.failed(&short, s, t)
    }

    /// Reads Real variables of type `ty` (f64 for every Real type).
    pub fn get_real(&mut self, ty: VarType, vrs: &[u32], out: &mut [f64], t: f64) -> Result<()> {
        let s = self.call(|i| match i {
            Instance::V2(i) => Ok(i.get_real(vrs, out)),
            Instance::V3(i) => i.get_real(ty, vrs, out),
        });
        let s = s.map_err(|e| e.component(&self.name).at(t))?;
        if s.ok() {
            Ok(())
        } else {
            Err(self.value_error(true, ty, s, Some(t)))
        }
    }

    /// Writes Real variables of type `ty`.
    pub fn set_real(&mut self, ty: VarType, vrs: &[u32], values: &[f64], t: f64) -> Result<()> {
        let s = self.call(|i| match i {
            Instance::V2(i) => Ok(i.set_real(vrs, values)),
            Instance::V3(i) => i.set_real(ty, vrs, values),
        });
        let s = s.map_err(|e| e.component(&self.name).at(t))?;
        if s.ok() {
            Ok(())
        } else {
            Err(self.value_error(false, ty, s, Some(t)))
        }
    }

    /// Reads integer-like variables (integers, Enumeration, Boolean as 0/1) of type `ty`.
    pub fn get_int(&mut self, ty: VarType, vrs: &[u32], out: &mut [i64], t: f64) -> Result<()> {
        let s = self.call(|i| match i {
            Instance::V2(i) => {
                let mut buf = vec![0i32; out.len()];
                let s = i.get_int(ty == VarType::Boolean, vrs, &mut buf);
                for (o, b) in out.iter_mut().zip(buf) {
                    *o = i64::from(b);
                }
                Ok(s)
            }
            Instance::V3(i) => i.get_int(ty, vrs, out),
        });
        let s = s.map_err(|e| e.component(&self.name).at(t))?;
        if s.ok() {
            Ok(())
        } else {
            Err(self.value_error(true, ty, s, Some(t)))
        }
    }

    /// Writes integer-like variables of type `ty`.
    pub fn set_int(&mut self, ty: VarType, vrs: &[u32], values: &[i64], t: f64) -> Result<()> {
        let name = self.name.clone();
        let s = self.call(|i| match i {
            Instance::V2(i) => {
                let buf = values
                    .iter()
                    .map(|&v| {
                        i32::try_from(v).map_err(|_| {
                            Error::new(format!("{v} is out of the range of a 32-bit Integer"))
                        })
                    })
                    .collect::<Result<Vec<i32>>>()?;
                let buf: Vec<i32> = if ty == VarType::Boolean {
                    buf.iter().map(|&v| i32::from(v != 0)).collect()
                } else {
                    buf
                };
                Ok(i.set_int(ty == VarType::Boolean, vrs, &buf))
            }
            Instance::V3(i) => i.set_int(ty, vrs, values),
        });
        let s = s.map_err(|e| e.component(name).at(t))?;
        if s.ok() {
            Ok(())
        } else {
            Err(self.value_error(false, ty, s, Some(t)))
        }
    }

    /// Reads String variables.
    pub fn get_string(&mut self, vrs: &[u32], out: &mut Vec<String>, t: f64) -> Result<()> {
        let s = self.call(|i| match i {
            Instance::V2(i) => Ok(i.get_string(vrs, out)),
            Instance::V3(i) => i.get_string(vrs, out),
        });
        let s = s.map_err(|e| e.component(&self.name).at(t))?;
        if s.ok() {
            Ok(())
        } else {
            Err(self.value_error(true, VarType::String, s, Some(t)))
        }
    }

    /// Sets one variable to `value` (a start value or parameter), by its type.
    pub fn set_value(&mut self, var: &Variable, value: &Value, t: f64) -> Result<()> {
        let vr = [var.vr];
        let r = match value {
            Value::Real(x) => self.set_real(var.ty, &vr, &[*x], t),
            Value::Integer(n) => self.set_int(var.ty, &vr, &[*n], t),
            Value::Boolean(b) => self.set_int(var.ty, &vr, &[i64::from(*b)], t),
            Value::String(s) => {
                self.strings = vec![s.clone()];
                let strings = std::mem::take(&mut self.strings);
                let r = self.call(|i| match i {
                    Instance::V2(i) => i.set_string(&vr, &strings),
                    Instance::V3(i) => i.set_string(&vr, &strings),
                });
                let s = r.map_err(|e| e.component(&self.name).at(t))?;
                if s.ok() {
                    Ok(())
                } else {
                    Err(self.value_error(false, VarType::String, s, Some(t)))
                }
            }
        };
        r.map_err(|e| e.variable(&var.name))
    }
}
