//! `Fmi2`: the FMI 2.0 calls behind `Api`, the FMI 2.0 program header (GUID, instance name,
//! fmuType, callbacks) and the operations of FMI 2.0 only (input derivatives, the status
//! functions, CancelStep, output derivatives, Strings). Uses `api`, `program` and `support`
//! (callback struct, log, instantiation).

use super::api::{Api, Handle, St, StepOut, OK};
use super::program::{variant_of, Inst, Program};
use super::support::{self, CO_SIMULATION};
use connector_fmu::fmi2::exports::*;
use connector_fmu::fmi2::types::*;
use connector_fmu::variables::Variant;
use std::ffi::{c_char, c_int, CString};
use std::ptr::null;

/// The callback struct of program `env`, with or without a logger.
fn callbacks(env: usize, with_logger: bool) -> fmi2CallbackFunctions {
    let cb = support::callbacks(env);
    fmi2CallbackFunctions {
        logger: cb.logger.filter(|_| with_logger),
        ..cb
    }
}

/// The FMI 2.0 calls.
pub struct Fmi2;

impl Api for Fmi2 {
    const N_OPS: u8 = 32;
    const SET_REAL: &'static str = "fmi2SetReal";
    const GET_REAL: &'static str = "fmi2GetReal";
    const SET_INT: &'static str = "fmi2SetInteger";
    const GET_INT: &'static str = "fmi2GetInteger";
    const SET_BOOL: &'static str = "fmi2SetBoolean";
    const GET_BOOL: &'static str = "fmi2GetBoolean";
    const GET_STATE: &'static str = "fmi2GetFMUstate";
    const SET_STATE: &'static str = "fmi2SetFMUstate";
    const FREE_STATE: &'static str = "fmi2FreeFMUstate";
    const STATE_SIZE: &'static str = "fmi2SerializedFMUstateSize";
    const SERIALIZE: &'static str = "fmi2SerializeFMUstate";
    const DESERIALIZE: &'static str = "fmi2DeSerializeFMUstate";
    const SETUP: &'static str = "fmi2SetupExperiment";
    const ENTER_INIT: &'static str = "fmi2EnterInitializationMode";
    const EXIT_INIT: &'static str = "fmi2ExitInitializationMode";
    const DO_STEP: &'static str = "fmi2DoStep";
    const RESET: &'static str = "fmi2Reset";
    const TERMINATE: &'static str = "fmi2Terminate";
    const DIR_DER: &'static str = "fmi2GetDirectionalDerivative";
    const DEBUG_LOGGING: &'static str = "fmi2SetDebugLogging";
    const TIME: &'static str = "fmi2GetRealStatus";
    const NULL_THIRD: &'static str = "fmi2SetRealInputDerivatives";

    fn set_real(c: Handle, vr: *const u32, n: usize, x: *const f64) -> St {
        fmi2SetReal(c, vr, n, x).into()
    }
    fn get_real(c: Handle, vr: *const u32, n: usize, x: *mut f64) -> St {
        fmi2GetReal(c, vr, n, x).into()
    }
    fn set_int(c: Handle, vr: *const u32, n: usize, x: *const i32) -> St {
        fmi2SetInteger(c, vr, n, x).into()
    }
    fn get_int(c: Handle, vr: *const u32, n: usize, x: *mut i32) -> St {
        fmi2GetInteger(c, vr, n, x).into()
    }
    fn set_bool(c: Handle, vr: u32, x: i32) -> St {
        fmi2SetBoolean(c, &vr, 1, &x).into()
    }
    fn get_bools(c: Handle, vrs: &[u32]) -> St {
        let mut out = vec![0; vrs.len()];
        fmi2GetBoolean(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()).into()
    }
    fn get_state(c: Handle, s: *mut Handle) -> St {
        fmi2GetFMUstate(c, s).into()
    }
    fn set_state(c: Handle, s: Handle) -> St {
        fmi2SetFMUstate(c, s).into()
    }
    fn free_state(c: Handle, s: *mut Handle) -> St {
        fmi2FreeFMUstate(c, s).into()
    }
    fn state_size(c: Handle, s: Handle, n: *mut usize) -> St {
        fmi2SerializedFMUstateSize(c, s, n).into()
    }
    fn serialize(c: Handle, s: Handle, p: *mut u8, n: usize) -> St {
        fmi2SerializeFMUstate(c, s, p.cast(), n).into()
    }
    fn deserialize(c: Handle, p: *const u8, n: usize, s: *mut Handle) -> St {
        fmi2DeSerializeFMUstate(c, p.cast(), n, s).into()
    }
    fn setup(c: Handle, start: f64, stop_defined: bool, stop: f64) -> St {
        fmi2SetupExperiment(c, fmi2False, 0.0, start, stop_defined as fmi2Boolean, stop).into()
    }
    fn enter_init(c: Handle) -> St {
        fmi2EnterInitializationMode(c).into()
    }
    fn exit_init(c: Handle) -> St {
        fmi2ExitInitializationMode(c).into()
    }
    fn do_step(c: Handle, t: f64, h: f64) -> (St, Option<StepOut>) {
        (fmi2DoStep(c, t, h, fmi2False).into(), None)
    }
    fn reset(c: Handle) -> St {
        fmi2Reset(c).into()
    }
    fn terminate(c: Handle) -> St {
        fmi2Terminate(c).into()
    }
    fn dir_der(c: Handle, unknowns: &[u32], knowns: &[u32], seed: &[f64], out: &mut [f64]) -> St {
        fmi2GetDirectionalDerivative(
            c,
            unknowns.as_ptr(),
            unknowns.len(),
            knowns.as_ptr(),
            knowns.len(),
            seed.as_ptr(),
            out.as_mut_ptr(),
        )
        .into()
    }
    fn debug_logging(c: Handle, on: bool, n: usize, categories: *const *const c_char) -> St {
        fmi2SetDebugLogging(c, on as fmi2Boolean, n, categories).into()
    }
    fn time(c: Handle, t: &mut f64) -> St {
        // fmi2LastSuccessfulTime = 2
        fmi2GetRealStatus(c, 2, t).into()
    }
    fn null_third(c: Handle, n: usize) -> St {
        fmi2SetRealInputDerivatives(c, null(), n, null(), null()).into()
    }
    fn free_instance(c: Handle) {
        fmi2FreeInstance(c);
    }
    fn instantiate_valid(env: usize, v: Variant) -> Handle {
        let cb = support::callbacks(env);
        let guid = support::guid(v);
        support::instantiate_raw(
            Some("cleanup"),
            CO_SIMULATION,
            Some(&guid),
            Some(&cb),
            false,
        )
    }

    fn instantiate(p: &mut Program<'_, Self>, i: usize) {
        let sel = p.b.u8();
        let flags = p.b.u8();
        let variant = variant_of(sel as usize);
        let mut valid = true;
        let guid = p.model_id(sel, variant, &mut valid);
        let name = p.instance_name(i, flags, &mut valid);
        let fmu_type = match (flags >> 4) % 8 {
            6 => {
                valid = false;
                0
            }
            7 => {
                let t = p.b.u32() as c_int;
                valid &= t == CO_SIMULATION;
                t
            }
            _ => CO_SIMULATION,
        };
        let logging_on = (flags >> 7) & 1;
        let cb_kind = p.b.u8() % 16;
        let cb = callbacks(p.env.0, cb_kind != 15);
        let cb_ptr: *const fmi2CallbackFunctions = if cb_kind == 14 { null() } else { &cb };
        let has_logger = cb_kind < 14;
        valid &= has_logger;
        let ptr = |s: &Option<CString>| s.as_ref().map_or(null(), |s| s.as_ptr());
        let n0 = support::log_len(p.env.0);
        let c = fmi2Instantiate(
            ptr(&name),
            fmu_type,
            ptr(&guid),
            null(),
            cb_ptr,
            fmi2False,
            logging_on as fmi2Boolean,
        );
        p.trace.push(format!(
            "instantiate[{i}] {variant:?} valid={valid} type={fmu_type} logging={logging_on} cb={cb_kind} -> {}",
            !c.is_null()
        ));
        let inst = Inst {
            c,
            variant,
            logger: has_logger,
            early_allowed: false,
        };
        p.instantiated(i, "fmi2Instantiate", c, valid, n0, inst);
    }

    fn special(p: &mut Program<'_, Self>, i: usize, v: Variant, op: u8) {
        match op {
            24 => {
                let n = 1 + p.b.u8() as usize % 4;
                let vrs: Vec<u32> = (0..n).map(|_| p.vr(v, 0)).collect();
                let orders: Vec<c_int> = (0..n)
                    .map(|_| [1, 1, 1, 0, 2, -1][p.b.u8() as usize % 6])
                    .collect();
                let xs: Vec<f64> = (0..n).map(|_| p.b.real()).collect();
                p.trace
                    .push(format!("inputDer[{i}] {vrs:?} {orders:?} {xs:?}"));
                p.call(i, "fmi2SetRealInputDerivatives", |c| {
                    fmi2SetRealInputDerivatives(c, vrs.as_ptr(), n, orders.as_ptr(), xs.as_ptr())
                        .into()
                });
            }
            26 => {
                let kind = [0, 1, 2, 3, -1, 99][p.b.u8() as usize % 6];
                let which = p.b.u8() % 5;
                p.trace.push(format!("status[{i}] fn {which} kind {kind}"));
                match which {
                    0 => {
                        let mut x = fmi2Status::OK;
                        p.call(i, "fmi2GetStatus", |c| {
                            fmi2GetStatus(c, kind, &mut x).into()
                        });
                    }
                    1 => {
                        let mut x = 0.0;
                        let s = p.call(i, "fmi2GetRealStatus", |c| {
                            fmi2GetRealStatus(c, kind, &mut x).into()
                        });
                        if s == OK && !x.is_finite() {
                            p.fail(format!("fmi2GetRealStatus OK with {x}"));
                        }
                    }
                    2 => {
                        let mut x = 0;
                        p.call(i, "fmi2GetIntegerStatus", |c| {
                            fmi2GetIntegerStatus(c, kind, &mut x).into()
                        });
                    }
                    3 => {
                        let mut x = 0;
                        p.call(i, "fmi2GetBooleanStatus", |c| {
                            fmi2GetBooleanStatus(c, kind, &mut x).into()
                        });
                    }
                    _ => {
                        let mut x: fmi2String = null();
                        p.call(i, "fmi2GetStringStatus", |c| {
                            fmi2GetStringStatus(c, kind, &mut x).into()
                        });
                    }
                }
            }
            27 => {
                p.trace.push(format!("cancel/outputDer/strings[{i}]"));
                p.call(i, "fmi2CancelStep", |c| fmi2CancelStep(c).into());
                let vr = p.vr(v, 0);
                let order = 1;
                let mut x = 0.0;
                let n = p.b.u8() as usize % 2;
                p.call(i, "fmi2GetRealOutputDerivatives", |c| {
                    fmi2GetRealOutputDerivatives(c, &vr, n, &order, &mut x).into()
                });
                let mut sx: fmi2String = null();
                p.call(i, "fmi2GetString", |c| {
                    fmi2GetString(c, &vr, n, &mut sx).into()
                });
                let val = c"x".as_ptr();
                p.call(i, "fmi2SetString", |c| {
                    fmi2SetString(c, &vr, n, &val).into()
                });
            }
            _ => unreachable!("FMI 2.0 has {} operation codes", Self::N_OPS),
        }
    }
}
