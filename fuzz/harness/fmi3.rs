//! `Fmi3`: the FMI 3.0 calls behind `Api`, the FMI 3.0 logger (into `support`'s log), the
//! FMI 3.0 program header (token, instance name, eventModeUsed, earlyReturnAllowed, required
//! intermediate variables, logger) and the dispatch of the operations of FMI 3.0 only, some
//! inline (DoStep with a NULL output, the independent variable, output derivatives), the others
//! in `fmi3_ops.rs`. Uses `api`, `program`, `steps`, `states`, `fmi3_ops` and `support` (logger, GUIDs).

use super::api::{Api, Handle, St, StepOut, OK};
use super::fmi3_ops::{adjoint, dependencies, other_interfaces, other_types, refused};
use super::program::{is_real_output, variant_of, Inst, Program};
use super::support;
use connector_fmu::fmi2::types::fmi2Status;
use connector_fmu::fmi3::exports::*;
use connector_fmu::fmi3::types::*;
use connector_fmu::model_description::fmi3::TIME_VR;
use connector_fmu::variables::Variant;
use std::ffi::{c_char, c_void, CString};
use std::ptr::{null, null_mut};

/// The FMI 3.0 calls.
pub struct Fmi3;

/// A C `bool` byte from the FMI 2.0-style int (any non-zero byte is true).
fn bool3(x: i32) -> fmi3Boolean {
    x as u8
}

/// The FMI 3.0 logger: hands each message to the support module's logger, so that messages of
/// both versions are recorded in one place under the program's key (instance name "fmi3").
pub(super) extern "C" fn logger3(
    env: *mut c_void,
    status: fmi3Status,
    category: *const c_char,
    message: *const c_char,
) {
    let Some(log) = support::callbacks(env as usize).logger else {
        return;
    };
    let status = match status {
        fmi3Status::OK => fmi2Status::OK,
        fmi3Status::Warning => fmi2Status::Warning,
        fmi3Status::Discard => fmi2Status::Discard,
        fmi3Status::Error => fmi2Status::Error,
        fmi3Status::Fatal => fmi2Status::Fatal,
    };
    // SAFETY: the support logger reads exactly these five arguments (C strings that live for
    // the duration of the call, as the FMU passes them here).
    unsafe { log(env, c"fmi3".as_ptr(), status, category, message) };
}

impl Api for Fmi3 {
    const N_OPS: u8 = 40;
    const SET_REAL: &'static str = "fmi3SetFloat64";
    const GET_REAL: &'static str = "fmi3GetFloat64";
    const SET_INT: &'static str = "fmi3SetInt32";
    const GET_INT: &'static str = "fmi3GetInt32";
    const SET_BOOL: &'static str = "fmi3SetBoolean";
    const GET_BOOL: &'static str = "fmi3GetBoolean";
    const GET_STATE: &'static str = "fmi3GetFMUState";
    const SET_STATE: &'static str = "fmi3SetFMUState";
    const FREE_STATE: &'static str = "fmi3FreeFMUState";
    const STATE_SIZE: &'static str = "fmi3SerializedFMUStateSize";
    const SERIALIZE: &'static str = "fmi3SerializeFMUState";
    const DESERIALIZE: &'static str = "fmi3DeserializeFMUState";
    const SETUP: &'static str = "fmi3EnterInitializationMode";
    const ENTER_INIT: &'static str = "fmi3EnterInitializationMode";
    const EXIT_INIT: &'static str = "fmi3ExitInitializationMode";
    const DO_STEP: &'static str = "fmi3DoStep";
    const RESET: &'static str = "fmi3Reset";
    const TERMINATE: &'static str = "fmi3Terminate";
    const DIR_DER: &'static str = "fmi3GetDirectionalDerivative";
    const DEBUG_LOGGING: &'static str = "fmi3SetDebugLogging";
    const TIME: &'static str = "fmi3GetFloat64";
    const NULL_THIRD: &'static str = "fmi3GetOutputDerivatives";

    fn set_real(c: Handle, vr: *const u32, n: usize, x: *const f64) -> St {
        fmi3SetFloat64(c, vr, n, x, n).into()
    }
    fn get_real(c: Handle, vr: *const u32, n: usize, x: *mut f64) -> St {
        fmi3GetFloat64(c, vr, n, x, n).into()
    }
    fn set_int(c: Handle, vr: *const u32, n: usize, x: *const i32) -> St {
        fmi3SetInt32(c, vr, n, x, n).into()
    }
    fn get_int(c: Handle, vr: *const u32, n: usize, x: *mut i32) -> St {
        fmi3GetInt32(c, vr, n, x, n).into()
    }
    fn set_bool(c: Handle, vr: u32, x: i32) -> St {
        fmi3SetBoolean(c, &vr, 1, &bool3(x), 1).into()
    }
    fn get_bools(c: Handle, vrs: &[u32]) -> St {
        let mut out = vec![7u8; vrs.len()];
        let s: St = fmi3GetBoolean(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), vrs.len()).into();
        assert!(
            s != OK || out.iter().all(|&b| b <= 1),
            "fmi3GetBoolean OK wrote a byte other than 0 or 1: {out:?}"
        );
        s
    }
    fn get_state(c: Handle, s: *mut Handle) -> St {
        fmi3GetFMUState(c, s).into()
    }
    fn set_state(c: Handle, s: Handle) -> St {
        fmi3SetFMUState(c, s).into()
    }
    fn free_state(c: Handle, s: *mut Handle) -> St {
        fmi3FreeFMUState(c, s).into()
    }
    fn state_size(c: Handle, s: Handle, n: *mut usize) -> St {
        fmi3SerializedFMUStateSize(c, s, n).into()
    }
    fn serialize(c: Handle, s: Handle, p: *mut u8, n: usize) -> St {
        fmi3SerializeFMUState(c, s, p, n).into()
    }
    fn deserialize(c: Handle, p: *const u8, n: usize, s: *mut Handle) -> St {
        fmi3DeserializeFMUState(c, p, n, s).into()
    }
    fn setup(c: Handle, start: f64, stop_defined: bool, stop: f64) -> St {
        fmi3EnterInitializationMode(c, fmi3False, 0.0, start, u8::from(stop_defined), stop).into()
    }
    fn enter_init(c: Handle) -> St {
        fmi3EnterInitializationMode(c, fmi3False, 0.0, 0.0, fmi3False, 0.0).into()
    }
    fn exit_init(c: Handle) -> St {
        fmi3ExitInitializationMode(c).into()
    }
    fn do_step(c: Handle, t: f64, h: f64) -> (St, Option<StepOut>) {
        // sentinels: the FMU must write each output on OK
        let (mut e, mut term, mut early, mut last) = (7u8, 7u8, 7u8, f64::NAN);
        let s = fmi3DoStep(c, t, h, fmi3False, &mut e, &mut term, &mut early, &mut last);
        let out = StepOut {
            event_handling_needed: e,
            terminate: term,
            early_return: early,
            last: last.to_bits(),
        };
        (s.into(), Some(out))
    }
    fn reset(c: Handle) -> St {
        fmi3Reset(c).into()
    }
    fn terminate(c: Handle) -> St {
        fmi3Terminate(c).into()
    }
    fn dir_der(c: Handle, unknowns: &[u32], knowns: &[u32], seed: &[f64], out: &mut [f64]) -> St {
        fmi3GetDirectionalDerivative(
            c,
            unknowns.as_ptr(),
            unknowns.len(),
            knowns.as_ptr(),
            knowns.len(),
            seed.as_ptr(),
            seed.len(),
            out.as_mut_ptr(),
            out.len(),
        )
        .into()
    }
    fn debug_logging(c: Handle, on: bool, n: usize, categories: *const *const c_char) -> St {
        fmi3SetDebugLogging(c, u8::from(on), n, categories).into()
    }
    fn time(c: Handle, t: &mut f64) -> St {
        fmi3GetFloat64(c, &TIME_VR, 1, t, 1).into()
    }
    fn null_third(c: Handle, n: usize) -> St {
        fmi3GetOutputDerivatives(c, null(), n, null(), null_mut(), n).into()
    }
    fn free_instance(c: Handle) {
        fmi3FreeInstance(c);
    }
    fn instantiate_valid(env: usize, v: Variant) -> Handle {
        let token = CString::new(support::guid(v)).expect("no NUL");
        fmi3InstantiateCoSimulation(
            c"cleanup".as_ptr(),
            token.as_ptr(),
            null(),
            fmi3False,
            fmi3False,
            fmi3False,
            fmi3False,
            null(),
            0,
            env as *mut c_void,
            Some(logger3),
            None,
        )
    }

    /// Header: variant/token byte, flags (name, eventModeUsed, loggingOn) as in FMI 2.0, then
    /// an options byte: earlyReturnAllowed (bits 0–1), requiredIntermediateVariables (bits
    /// 2–3), logger (bits 4–6: 7 = none, which FMI 3.0 allows), visible (bit 7).
    fn instantiate(p: &mut Program<'_, Self>, i: usize) {
        let sel = p.b.u8();
        let flags = p.b.u8();
        let opts = p.b.u8();
        let variant = variant_of(sel as usize);
        let mut valid = true;
        let token = p.model_id(sel, variant, &mut valid);
        let name = p.instance_name(i, flags, &mut valid);
        let event_mode_used = match (flags >> 4) % 8 {
            6 => 1,
            7 => p.b.u8(),
            _ => 0,
        };
        valid &= event_mode_used == 0;
        let logging_on = (flags >> 7) & 1;
        let early = [0u8, 1, 0, 0x80][(opts & 3) as usize];
        let required: Vec<u32> = match (opts >> 2) % 4 {
            1 => (0..1 + p.b.u8() % 3).map(|_| p.vr(variant, 0)).collect(),
            _ => Vec::new(),
        };
        let (req_ptr, n_req) = match (opts >> 2) % 4 {
            0 => (null(), 0),
            1 => (required.as_ptr(), required.len()),
            2 => {
                valid = false;
                (null(), 1 + p.b.u8() as usize % 3)
            }
            _ => (required.as_ptr(), 0), // a non-NULL array of 0 elements
        };
        let has_logger = (opts >> 4) % 8 != 7;
        let visible = opts >> 7;
        let ptr = |s: &Option<CString>| s.as_ref().map_or(null(), |s| s.as_ptr());
        let n0 = support::log_len(p.env.0);
        let c = fmi3InstantiateCoSimulation(
            ptr(&name),
            ptr(&token),
            null(),
            visible,
            logging_on,
            event_mode_used,
            early,
            req_ptr,
            n_req,
            p.env.0 as *mut c_void,
            if has_logger { Some(logger3) } else { None },
            None,
        );
        p.trace.push(format!(
            "fmi3 instantiate[{i}] {variant:?} valid={valid} eventModeUsed={event_mode_used} early={early} required={n_req} logger={has_logger} logging={logging_on} -> {}",
            !c.is_null()
        ));
        let inst = Inst {
            c,
            variant,
            logger: has_logger,
            early_allowed: early != 0,
        };
        p.instantiated(i, "fmi3InstantiateCoSimulation", c, valid, n0, inst);
    }

    fn special(p: &mut Program<'_, Self>, i: usize, v: Variant, op: u8) {
        match op {
            24 => adjoint(p, i, v),
            26 => other_types(p, i, v),
            27 => refused(p, i, v),
            32 => dependencies(p, i, v),
            33 => other_interfaces(p, i),
            34 => {
                // DoStep with a NULL output (refused) from the FMU's time
                let which = p.b.u8() % 4;
                let h = p.b.step();
                let t = p.fmu_time(i);
                p.trace.push(format!("doStepNull[{i}] output {which}"));
                let (mut b, mut last) = ([0u8; 3], 0.0);
                let [e, term, early] = &mut b;
                let ptrs: [*mut u8; 3] = [e, term, early];
                let s = p.call(i, "fmi3DoStep", |c| {
                    let n = |k: usize| {
                        if which as usize == k {
                            null_mut()
                        } else {
                            ptrs[k]
                        }
                    };
                    let l = if which == 3 { null_mut() } else { &mut last };
                    fmi3DoStep(c, t, h, fmi3False, n(0), n(1), n(2), l).into()
                });
                if s == OK {
                    p.fail("fmi3DoStep accepted a NULL output pointer".into());
                }
            }
            35 => {
                // the independent variable: readable with the others, never settable; and
                // nValues differing from nValueReferences
                let vr = p.vr(v, 0);
                let x = p.b.real();
                let vrs = [vr, TIME_VR];
                let mut out = [f64::NAN; 2];
                p.trace.push(format!("time/nValues[{i}] {vr} {x}"));
                let s = p.call(i, "fmi3GetFloat64", |c| {
                    fmi3GetFloat64(c, vrs.as_ptr(), 2, out.as_mut_ptr(), 2).into()
                });
                if s == OK
                    && (!out[1].is_finite() || (is_real_output(v, vr) && !out[0].is_finite()))
                {
                    p.fail(format!("fmi3GetFloat64 OK with {out:?}"));
                }
                let xs = [x, 0.0];
                let s = p.call(i, "fmi3SetFloat64", |c| {
                    fmi3SetFloat64(c, vrs.as_ptr(), 2, xs.as_ptr(), 2).into()
                });
                if s == OK {
                    p.fail("fmi3SetFloat64 set the independent variable time".into());
                }
                let nv = [0usize, 2, 3][p.b.u8() as usize % 3];
                let mut buf = [0.0; 3];
                p.call(i, "fmi3GetFloat64", |c| {
                    fmi3GetFloat64(c, &vr, 1, buf.as_mut_ptr(), nv).into()
                });
                p.call(i, "fmi3SetFloat64", |c| {
                    fmi3SetFloat64(c, &vr, 1, buf.as_ptr(), nv).into()
                });
                let iv = p.vr(v, 1);
                let mut ib = [0i32; 3];
                p.call(i, "fmi3GetInt32", |c| {
                    fmi3GetInt32(c, &iv, 1, ib.as_mut_ptr(), nv).into()
                });
            }
            36 | 37 => {
                p.do_step(i);
            }
            38 => p.replay(i),
            _ => {
                // GetOutputDerivatives: none provided (an empty request is OK)
                let n = p.b.u8() as usize % 3;
                let vrs: Vec<u32> = (0..n).map(|_| p.vr(v, 0)).collect();
                let orders = vec![1 + p.b.u8() as i32 % 2; n];
                let mut out = vec![0.0; n];
                p.trace.push(format!("outputDer[{i}] {vrs:?}"));
                let s = p.call(i, "fmi3GetOutputDerivatives", |c| {
                    fmi3GetOutputDerivatives(
                        c,
                        vrs.as_ptr(),
                        n,
                        orders.as_ptr(),
                        out.as_mut_ptr(),
                        n,
                    )
                    .into()
                });
                if s == OK && n > 0 {
                    p.fail(
                        "fmi3GetOutputDerivatives OK for a derivative it does not provide".into(),
                    );
                }
            }
        }
    }
}
