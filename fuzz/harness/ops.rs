//! The operation decoder shared by both versions (`Program::op`: codes 0–31 but 24, 26 and 27,
//! which each version defines itself, as it does the codes from 32 on) and the value sets it
//! writes: Real values, a coherent parameter set, a plausible motion, the arguments of a
//! derivative call. Uses `api`, `bytes` (through `Program`), `program`, `steps`, `states`.

use super::api::{Api, OK};
use super::program::{is_real_output, reals_of, Program};
use connector_fmu::variables::{table, Causality, Start, Variability, Variant};
use std::ffi::{c_char, CString};
use std::ptr::{null, null_mut};

/// The arguments of a directional (or adjoint) derivative call.
pub(super) struct DerArgs {
    pub(super) unknowns: Vec<u32>,
    pub(super) knowns: Vec<u32>,
    pub(super) seed: Vec<f64>,
}

impl<A: Api> Program<'_, A> {
    fn set_reals(&mut self, i: usize, v: Variant) {
        let n = 1 + self.b.u8() as usize % 4;
        let mut vrs = Vec::with_capacity(n);
        let mut xs = Vec::with_capacity(n);
        for _ in 0..n {
            vrs.push(self.vr(v, 0));
            xs.push(self.b.real());
        }
        self.trace.push(format!("setReal[{i}] {vrs:?} {xs:?}"));
        self.call(i, A::SET_REAL, |c| {
            A::set_real(c, vrs.as_ptr(), n, xs.as_ptr())
        });
    }

    /// A coherent parameter set: each parameter of the variant set (or not) to a plausible
    /// value, sometimes an awkward one; Integer parameters 0..3 (cosim.extrapolation's range;
    /// friction.coupling refuses 2 and 3).
    fn param_set(&mut self, i: usize, v: Variant) {
        let mut vrs = Vec::new();
        let mut xs = Vec::new();
        let mut ivrs = Vec::new();
        let mut ixs = Vec::new();
        for var in &table(v).vars {
            if var.causality != Causality::Parameter || self.b.u8() < 100 {
                continue;
            }
            match var.start {
                Start::Real(_) => {
                    vrs.push(var.vr);
                    xs.push(self.b.param_value(&var.name));
                }
                Start::Integer(_) => {
                    ivrs.push(var.vr);
                    ixs.push((self.b.u8() % 4) as i32);
                }
                Start::Boolean(_) => {}
            }
        }
        self.trace
            .push(format!("paramSet[{i}] {vrs:?} {xs:?} int {ivrs:?} {ixs:?}"));
        self.call(i, A::SET_REAL, |c| {
            A::set_real(c, vrs.as_ptr(), vrs.len(), xs.as_ptr())
        });
        self.call(i, A::SET_INT, |c| {
            A::set_int(c, ivrs.as_ptr(), ivrs.len(), ixs.as_ptr())
        });
    }

    /// A plausible motion: positions, orientations, velocities, angular velocities.
    fn motion(&mut self, i: usize, v: Variant) {
        let mut vrs = Vec::new();
        let mut xs = Vec::new();
        let scale = [0.01, 0.1, 1.0, 10.0][self.b.u8() as usize % 4];
        for node in ["a", "b"] {
            let q = self.b.quat();
            for var in &table(v).vars {
                if var.causality != Causality::Input || !var.name.starts_with(node) {
                    continue;
                }
                let x = match &var.name[2..] {
                    "q.w" => q[0],
                    "q.x" => q[1],
                    "q.y" => q[2],
                    "q.z" => q[3],
                    _ => scale * self.b.unit(),
                };
                vrs.push(var.vr);
                xs.push(x);
            }
        }
        self.trace.push(format!("motion[{i}] {xs:?}"));
        self.call(i, A::SET_REAL, |c| {
            A::set_real(c, vrs.as_ptr(), vrs.len(), xs.as_ptr())
        });
    }

    /// Unknowns (mostly continuous Real outputs), knowns (mostly inputs) and `n_seed` seeds
    /// (None: one per known) of a derivative call.
    pub(super) fn der_args(&mut self, v: Variant, seeds_per_unknown: bool) -> DerArgs {
        let outs = reals_of(v, |x| {
            x.causality == Causality::Output && x.variability == Variability::Continuous
        });
        let ins = reals_of(v, |x| x.causality == Causality::Input);
        let nu = self.b.u8() as usize % 6;
        let nk = self.b.u8() as usize % 6;
        let unknowns: Vec<u32> = (0..nu)
            .map(|_| {
                if self.b.u8().is_multiple_of(8) {
                    self.vr(v, 0)
                } else {
                    outs[self.b.u8() as usize % outs.len()]
                }
            })
            .collect();
        let knowns: Vec<u32> = (0..nk)
            .map(|_| {
                if self.b.u8().is_multiple_of(8) {
                    self.vr(v, 0)
                } else {
                    ins[self.b.u8() as usize % ins.len()]
                }
            })
            .collect();
        let ns = if seeds_per_unknown { nu } else { nk };
        let seed: Vec<f64> = (0..ns)
            .map(|_| {
                if self.b.u8().is_multiple_of(2) {
                    self.b.real()
                } else {
                    self.b.unit()
                }
            })
            .collect();
        DerArgs {
            unknowns,
            knowns,
            seed,
        }
    }

    pub(super) fn op(&mut self) {
        let i = (self.b.u8() & 1) as usize;
        if self.inst[i].is_none() {
            // an instance slot that is empty: make one (or stop trying when it is refused)
            A::instantiate(self, i);
            return;
        }
        let v = self.variant(i).expect("live");
        let op = self.b.u8() % A::N_OPS;
        match op {
            0..=2 => self.set_reals(i, v),
            3 => {
                let vr = self.vr(v, 1);
                let x = match self.b.u8() % 6 {
                    0 => i32::MIN,
                    1 => i32::MAX,
                    2 => -1,
                    _ => (self.b.u8() % 4) as i32,
                };
                self.trace.push(format!("setInteger[{i}] {vr} {x}"));
                self.call(i, A::SET_INT, |c| A::set_int(c, &vr, 1, &x));
            }
            4 => {
                let vr = self.vr(v, 2);
                let x = [0, 1, 2, -1][self.b.u8() as usize % 4];
                self.trace.push(format!("setBoolean[{i}] {vr} {x}"));
                self.call(i, A::SET_BOOL, |c| A::set_bool(c, vr, x));
            }
            5 => {
                let node = if self.b.u8().is_multiple_of(2) {
                    "a"
                } else {
                    "b"
                };
                let q = self.b.quat();
                let vrs: Vec<u32> = ["w", "x", "y", "z"]
                    .iter()
                    .filter_map(|c| {
                        let name = format!("{node}.q.{c}");
                        table(v).vars.iter().find(|x| x.name == name).map(|x| x.vr)
                    })
                    .collect();
                if vrs.len() == 4 {
                    self.trace.push(format!("setQuat[{i}] {node} {q:?}"));
                    self.call(i, A::SET_REAL, |c| {
                        A::set_real(c, vrs.as_ptr(), 4, q.as_ptr())
                    });
                }
            }
            6 => self.param_set(i, v),
            7 => self.motion(i, v),
            8 => {
                let start = if self.b.u8().is_multiple_of(4) {
                    self.b.real()
                } else {
                    0.0
                };
                let stop_def = self.b.u8() % 2;
                let stop = self.b.real();
                self.trace.push(format!("setup[{i}] {start:e}"));
                self.call(i, A::SETUP, |c| A::setup(c, start, stop_def == 1, stop));
            }
            9 => {
                self.trace.push(format!("enterInit[{i}]"));
                self.call(i, A::ENTER_INIT, |c| A::enter_init(c));
            }
            10 => {
                let s = self.call(i, A::EXIT_INIT, |c| A::exit_init(c));
                self.trace.push(format!("exitInit[{i}] -> {s:?}"));
            }
            11..=13 => {
                self.do_step(i);
            }
            14 => {
                self.trace.push(format!("readOutputs[{i}]"));
                self.read_outputs(i);
            }
            15 => {
                // random reads of any type
                let ty = self.b.u8() % 3;
                let n = self.b.u8() as usize % 5;
                let vrs: Vec<u32> = (0..n).map(|_| self.vr(v, ty)).collect();
                self.trace.push(format!("get[{i}] type {ty} {vrs:?}"));
                match ty {
                    0 => {
                        let mut out = vec![0.0; n];
                        let s = self.call(i, A::GET_REAL, |c| {
                            A::get_real(c, vrs.as_ptr(), n, out.as_mut_ptr())
                        });
                        if s == OK {
                            for (vr, x) in vrs.iter().zip(&out) {
                                if is_real_output(v, *vr) && !x.is_finite() {
                                    self.fail(format!(
                                        "{} OK with output vr {vr} = {x}",
                                        A::GET_REAL
                                    ));
                                }
                            }
                        }
                    }
                    1 => {
                        let mut out = vec![0; n];
                        self.call(i, A::GET_INT, |c| {
                            A::get_int(c, vrs.as_ptr(), n, out.as_mut_ptr())
                        });
                    }
                    _ => {
                        self.call(i, A::GET_BOOL, |c| A::get_bools(c, &vrs));
                    }
                }
            }
            16 => {
                let k = self.b.u8() as usize % 4;
                self.trace.push(format!("getState[{i}] -> slot {k}"));
                let mut slot = self.slots[k];
                if self.call(i, A::GET_STATE, |c| A::get_state(c, &mut slot.s)) == OK {
                    slot.variant = v;
                }
                self.slots[k] = slot;
            }
            17 => {
                let k = self.b.u8() as usize % 4;
                let slot = self.slots[k];
                self.trace
                    .push(format!("setState[{i}] <- slot {k} ({:?})", slot.variant));
                let s = self.call(i, A::SET_STATE, |c| A::set_state(c, slot.s));
                if s == OK && slot.variant != v {
                    self.fail(format!(
                        "{} accepted a {:?} state in {v:?}",
                        A::SET_STATE,
                        slot.variant
                    ));
                }
            }
            18 => {
                let k = self.b.u8() as usize % 4;
                self.trace.push(format!("freeState[{i}] slot {k}"));
                let mut slot = self.slots[k];
                self.call(i, A::FREE_STATE, |c| A::free_state(c, &mut slot.s));
                if !slot.s.is_null() {
                    self.fail(format!("{} did not set the handle to NULL", A::FREE_STATE));
                }
                self.slots[k] = slot;
            }
            19 => {
                let k = self.b.u8() as usize % 4;
                self.trace.push(format!("serialize[{i}] slot {k}"));
                self.serialize(i, k);
            }
            20 => {
                let k = self.b.u8() as usize % 4;
                self.deserialize(i, k);
            }
            21 => {
                self.trace.push(format!("reset[{i}]"));
                self.call(i, A::RESET, |c| A::reset(c));
            }
            22 => {
                self.trace.push(format!("terminate[{i}]"));
                self.call(i, A::TERMINATE, |c| A::terminate(c));
            }
            23 => {
                // directional derivative of outputs w.r.t. inputs (sometimes anything)
                let a = self.der_args(v, false);
                let mut out = vec![f64::NAN; a.unknowns.len()];
                self.trace.push(format!(
                    "dirDer[{i}] {:?} {:?} {:?}",
                    a.unknowns, a.knowns, a.seed
                ));
                let s = self.call(i, A::DIR_DER, |c| {
                    A::dir_der(c, &a.unknowns, &a.knowns, &a.seed, &mut out)
                });
                if s == OK {
                    if let Some(x) = out.iter().find(|x| !x.is_finite()) {
                        self.fail(format!("{} OK with a value {x}", A::DIR_DER));
                    }
                }
            }
            25 => {
                let on = self.b.u8() % 2;
                let n = self.b.u8() as usize % 4;
                let names: Vec<CString> = (0..n)
                    .map(|_| match self.b.u8() % 6 {
                        0 => c"logEvents".to_owned(),
                        1 => c"logAll".to_owned(),
                        2 => c"logStatusError".to_owned(),
                        3 => c"logStatusWarning".to_owned(),
                        _ => {
                            let k = self.b.u8() % 10;
                            let bytes: Vec<u8> = (0..k).map(|_| self.b.u8().max(1)).collect();
                            CString::new(bytes).expect("no NUL")
                        }
                    })
                    .collect();
                let ptrs: Vec<*const c_char> = names.iter().map(|s| s.as_ptr()).collect();
                let p = if n == 0 && self.b.u8().is_multiple_of(2) {
                    null()
                } else {
                    ptrs.as_ptr()
                };
                self.trace.push(format!("debugLogging[{i}] {on} {names:?}"));
                self.call(i, A::DEBUG_LOGGING, |c| A::debug_logging(c, on == 1, n, p));
            }
            28 => {
                // NULL arrays with a count (refused) and (NULL, 0) (legal)
                let n = self.b.u8() as usize % 3;
                self.trace.push(format!("nullArrays[{i}] n={n}"));
                self.call(i, A::SET_REAL, |c| A::set_real(c, null(), n, null()));
                self.call(i, A::GET_REAL, |c| A::get_real(c, null(), n, null_mut()));
                self.call(i, A::NULL_THIRD, |c| A::null_third(c, n));
                self.call(i, A::GET_STATE, |c| A::get_state(c, null_mut()));
            }
            29 => self.replay(i),
            30 => {
                self.trace.push(format!("free[{i}]"));
                self.free_instance(i);
            }
            31 => {
                // a short run of plain steps: drives the friction and stop state
                let n = 1 + self.b.u8() % 4;
                for _ in 0..n {
                    if self.do_step(i).is_none() {
                        break;
                    }
                }
                self.read_outputs(i);
            }
            _ => A::special(self, i, v, op),
        }
    }
}
