//! Every FMI 2.0 Co-Simulation function (the 25 common ones and the 9 of Co-Simulation), in
//! `fmi2Functions.h` order. Each is thin: panic wall, instance lookup, pointer checks, one call
//! into `crate::instance::Instance`, one status with its log message. What this FMU does not
//! provide (directional derivatives, input and output derivatives, asynchronous steps, status
//! kinds other than fmi2LastSuccessfulTime and fmi2Terminated) answers fmi2Error or
//! fmi2Discard with a message naming the function and why. Uses `super::{boundary, types}` and
//! `crate::instance`.
//!
//! Calls on one instance must not be concurrent (FMI 2.0 §2.1.5); different instances are
//! independent and may live on different threads.
#![allow(non_snake_case)]
// The C ABI: every pointer is checked for NULL (and alignment) before use and otherwise
// trusted under the FMI calling contract, as any C FMU trusts it.
#![allow(clippy::not_unsafe_ptr_arg_deref)]

use super::boundary::{
    c_str_array, copy_serialized, free_state, in_slice, instance_mut, instantiate, out_ref,
    out_slice, state_ref, status, store_state, trace,
};
use super::types::{
    fmi2Boolean, fmi2Byte, fmi2CallbackFunctions, fmi2Component, fmi2FMUstate, fmi2Integer,
    fmi2Real, fmi2Status, fmi2String, fmi2ValueReference, FMI2_LAST_SUCCESSFUL_TIME,
    FMI2_TERMINATED,
};
use crate::error::{FmuError, FmuResult};
use crate::instance::{Call, Instance};
use std::ffi::{c_char, c_int};

/// `&mut Instance`, or `return fmi2Error` for a NULL component.
macro_rules! instance {
    ($c:expr, $fname:expr) => {
        $crate::fmi2::boundary::instance_or!($c, $fname, fmi2Status::Error)
    };
}

/// `vr[]` and `value[]` of a get or set call, `(NULL, 0)` legal.
macro_rules! arrays {
    (get $vr:expr, $n:expr, $value:expr) => {
        // SAFETY: vr and value hold n elements (FMI 2.0 §2.1.7); NULL with n > 0 is refused.
        unsafe {
            in_slice($vr, $n, "vr[]").and_then(|v| Ok((v, out_slice($value, $n, "value[]")?)))
        }
    };
    (set $vr:expr, $n:expr, $value:expr) => {
        // SAFETY: vr and value hold n elements (FMI 2.0 §2.1.7); NULL with n > 0 is refused.
        unsafe { in_slice($vr, $n, "vr[]").and_then(|v| Ok((v, in_slice($value, $n, "value[]")?))) }
    };
}

/// Defines a getter or setter: `$dir` is `get` or `set`, `$f(inst, vrs, values)` the call.
macro_rules! access {
    ($(#[$doc:meta])* $name:ident, $dir:ident, $ptr:ty, |$inst:ident, $vrs:ident, $v:ident| $call:expr) => {
        $(#[$doc])*
        #[no_mangle]
        pub extern "C" fn $name(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: $ptr,
        ) -> fmi2Status {
            const F: &str = stringify!($name);
            ffi_boundary!(c, F, {
                let $inst = instance!(c, F);
                let r: FmuResult<()> = arrays!($dir vr, nvr, value).and_then(|($vrs, $v)| $call);
                status(r, $inst, F)
            })
        }
    };
}

/// Defines a Co-Simulation status query answering one kind (`None`: no kind).
macro_rules! status_query {
    ($(#[$doc:meta])* $name:ident, $t:ty, $kind:expr, |$inst:ident| $value:expr) => {
        $(#[$doc])*
        #[no_mangle]
        pub extern "C" fn $name(c: fmi2Component, s: c_int, value: *mut $t) -> fmi2Status {
            const F: &str = stringify!($name);
            ffi_boundary!(c, F, {
                let $inst = instance!(c, F);
                // SAFETY: value is NULL (refused) or writable (FMI 2.0 §4.2.3).
                let out = unsafe { out_ref(value, "value") };
                let r = $inst.status_allowed().and(out).and_then(|v| match $kind {
                    Some(k) if k == s => {
                        *v = $value;
                        Ok(())
                    }
                    _ => Err(FmuError::error(format!(
                        "status kind {s} is not provided: fmi2DoStep is synchronous; fmi2GetRealStatus answers fmi2LastSuccessfulTime ({FMI2_LAST_SUCCESSFUL_TIME}), fmi2GetBooleanStatus fmi2Terminated ({FMI2_TERMINATED})"
                    ))),
                });
                status(r, $inst, F)
            })
        }
    };
}

/// Defines a function of a capability this FMU does not declare: fmi2Error with the reason.
macro_rules! not_provided {
    ($(#[$doc:meta])* $name:ident ( $($arg:ident : $t:ty),* ) => $why:expr) => {
        $(#[$doc])*
        #[no_mangle]
        pub extern "C" fn $name(c: fmi2Component $(, $arg: $t)*) -> fmi2Status {
            const F: &str = stringify!($name);
            ffi_boundary!(c, F, {
                let inst = instance!(c, F);
                status(Err(FmuError::error($why)), inst, F)
            })
        }
    };
}

// ---------------------------------------------------------------- common functions

/// fmi2GetTypesPlatform: "default".
#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    ffi_boundary!("fmi2GetTypesPlatform", { c"default".as_ptr() })
}

/// fmi2GetVersion: "2.0".
#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    ffi_boundary!("fmi2GetVersion", { c"2.0".as_ptr() })
}

/// fmi2SetDebugLogging: `(NULL, 0)` categories switch every category.
#[no_mangle]
pub extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    nCategories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    const F: &str = "fmi2SetDebugLogging";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: categories holds nCategories C strings (FMI 2.0 §2.1.5); NULLs are refused.
        let names = unsafe { c_str_array(categories, nCategories, "categories") };
        let r = names.and_then(|n| inst.set_debug_logging(loggingOn != 0, &n));
        status(r, inst, F)
    })
}

/// fmi2Instantiate: NULL (after logging why, when a logger exists) for a NULL or empty name, a
/// type other than fmi2CoSimulation, a GUID of another model, or missing callbacks.
#[no_mangle]
pub extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: c_int,
    fmuGUID: fmi2String,
    _fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    ffi_boundary!("fmi2Instantiate", {
        // SAFETY: the pointers are NULL or as FMI 2.0 §2.1.5 specifies; NULLs are refused.
        let inst =
            unsafe { instantiate(instanceName, fmuType, fmuGUID, functions, loggingOn != 0) };
        inst.map_or(std::ptr::null_mut(), |i| Box::into_raw(Box::new(i)).cast())
    })
}

/// fmi2FreeInstance: NULL is ignored; allowed in every state, also after fmi2Fatal.
#[no_mangle]
pub extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    ffi_boundary!("fmi2FreeInstance", {
        // SAFETY: c is NULL or a live instance from fmi2Instantiate (FMI 2.0 §2.1.5).
        if let Some(inst) = unsafe { instance_mut(c) } {
            trace(inst, "fmi2FreeInstance");
            // SAFETY: the Box made by fmi2Instantiate, released once: the importer may not use
            // c after this call.
            drop(unsafe { Box::from_raw(inst as *mut Instance) });
        }
    })
}

/// fmi2SetupExperiment: the start time (the tolerance and stop time are not used).
#[no_mangle]
pub extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _toleranceDefined: fmi2Boolean,
    _tolerance: fmi2Real,
    startTime: fmi2Real,
    _stopTimeDefined: fmi2Boolean,
    _stopTime: fmi2Real,
) -> fmi2Status {
    const F: &str = "fmi2SetupExperiment";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        status(inst.setup_experiment(startTime), inst, F)
    })
}

/// Defines a lifecycle function: one instance call without arguments.
macro_rules! lifecycle {
    ($(#[$doc:meta])* $name:ident, $method:ident) => {
        $(#[$doc])*
        #[no_mangle]
        pub extern "C" fn $name(c: fmi2Component) -> fmi2Status {
            const F: &str = stringify!($name);
            ffi_boundary!(c, F, {
                let inst = instance!(c, F);
                status(inst.$method(), inst, F)
            })
        }
    };
}

lifecycle!(
    /// fmi2EnterInitializationMode: outputs follow the start parameters from now on.
    fmi2EnterInitializationMode, enter_initialization_mode
);
lifecycle!(
    /// fmi2ExitInitializationMode: parameters checked together, the body starts.
    fmi2ExitInitializationMode, exit_initialization_mode
);
lifecycle!(
    /// fmi2Terminate.
    fmi2Terminate, terminate
);
lifecycle!(
    /// fmi2Reset: start values, the Instantiated state.
    fmi2Reset, reset
);

access!(
    /// fmi2GetReal: outputs are the body at the FMU time (in Initialization Mode: at the start).
    fmi2GetReal, get, *mut fmi2Real, |inst, vrs, out| inst.get_real(vrs, out)
);
access!(
    /// fmi2GetInteger.
    fmi2GetInteger, get, *mut fmi2Integer, |inst, vrs, out| inst.get_integer(vrs, out)
);
access!(
    /// fmi2GetBoolean: this FMU has no Boolean variables; an empty request is OK.
    fmi2GetBoolean, get, *mut fmi2Boolean,
    |inst, vrs, _out| inst.no_variables_of_type(Call::Get, vrs, "Boolean")
);
access!(
    /// fmi2GetString: this FMU has no String variables; an empty request is OK.
    fmi2GetString, get, *mut fmi2String,
    |inst, vrs, _out| inst.no_variables_of_type(Call::Get, vrs, "String")
);
access!(
    /// fmi2SetReal: all or nothing; non-finite and out-of-range values are refused.
    fmi2SetReal, set, *const fmi2Real, |inst, vrs, v| inst.set_real(vrs, v)
);
access!(
    /// fmi2SetInteger: all or nothing; out-of-range values are refused.
    fmi2SetInteger, set, *const fmi2Integer, |inst, vrs, v| inst.set_integer(vrs, v)
);
access!(
    /// fmi2SetBoolean: this FMU has no Boolean variables; an empty request is OK.
    fmi2SetBoolean, set, *const fmi2Boolean,
    |inst, vrs, _v| inst.no_variables_of_type(Call::Set, vrs, "Boolean")
);
access!(
    /// fmi2SetString: this FMU has no String variables; an empty request is OK.
    fmi2SetString, set, *const fmi2String,
    |inst, vrs, _v| inst.no_variables_of_type(Call::Set, vrs, "String")
);

/// fmi2GetFMUstate: a non-NULL `*FMUstate` (a state this FMU returned) is overwritten.
#[no_mangle]
pub extern "C" fn fmi2GetFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
    const F: &str = "fmi2GetFMUstate";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: FMUstate is writable, *FMUstate NULL or a live state of this FMU (§2.1.8).
        let r = inst
            .get_state()
            .and_then(|s| unsafe { store_state(FMUstate, s) });
        status(r, inst, F)
    })
}

/// fmi2SetFMUstate.
#[no_mangle]
pub extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    const F: &str = "fmi2SetFMUstate";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: a non-NULL FMUstate is a live state of this FMU (FMI 2.0 §2.1.8).
        let r = unsafe { state_ref(FMUstate) }.and_then(|s| inst.set_state(s));
        status(r, inst, F)
    })
}

/// fmi2FreeFMUstate: NULL or `*NULL` is OK; allowed in every state (also after fmi2Fatal).
#[no_mangle]
pub extern "C" fn fmi2FreeFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
    const F: &str = "fmi2FreeFMUstate";
    ffi_boundary!(c, F, {
        let _inst = instance!(c, F);
        // SAFETY: FMUstate is NULL or writable, *FMUstate NULL or a live state (§2.1.8).
        unsafe { free_state(FMUstate) };
        fmi2Status::OK
    })
}

/// fmi2SerializedFMUstateSize.
#[no_mangle]
pub extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    const F: &str = "fmi2SerializedFMUstateSize";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: FMUstate is NULL (refused) or a live state; size NULL (refused) or writable.
        let (state, out) = unsafe { (state_ref(FMUstate), out_ref(size, "size")) };
        let r = state.and_then(|s| inst.serialize(s)).and_then(|b| {
            *out? = b.len();
            Ok(())
        });
        status(r, inst, F)
    })
}

/// fmi2SerializeFMUstate: `size` must be at least fmi2SerializedFMUstateSize.
#[no_mangle]
pub extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    const F: &str = "fmi2SerializeFMUstate";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: FMUstate NULL (refused) or live; serializedState holds size bytes.
        let (state, buf) = unsafe {
            (
                state_ref(FMUstate),
                out_slice(serializedState.cast::<u8>(), size, "serializedState"),
            )
        };
        let r = state.and_then(|s| copy_serialized(inst, s, buf?, "fmi2SerializedFMUstateSize"));
        status(r, inst, F)
    })
}

/// fmi2DeSerializeFMUstate: the bytes are validated before a state is made.
#[no_mangle]
pub extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: usize,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    const F: &str = "fmi2DeSerializeFMUstate";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: serializedState holds size bytes (FMI 2.0 §2.1.8); NULL with size > 0 refused.
        let bytes = unsafe { in_slice(serializedState.cast::<u8>(), size, "serializedState") };
        let snapshot = bytes.and_then(|b| inst.deserialize(b));
        // SAFETY: FMUstate is writable, *FMUstate NULL or a live state of this FMU.
        let r = snapshot.and_then(|s| unsafe { store_state(FMUstate, s) });
        status(r, inst, F)
    })
}

not_provided!(
    /// fmi2GetDirectionalDerivative: fmi2Error (providesDirectionalDerivative = false).
    fmi2GetDirectionalDerivative(
        _vUnknown_ref: *const fmi2ValueReference,
        _nUnknown: usize,
        _vKnown_ref: *const fmi2ValueReference,
        _nKnown: usize,
        _dvKnown: *const fmi2Real,
        _dvUnknown: *mut fmi2Real
    ) => "no directional derivatives (providesDirectionalDerivative = false)"
);

// ---------------------------------------------------------------- co-simulation functions

not_provided!(
    /// fmi2SetRealInputDerivatives: fmi2Error (canInterpolateInputs = false: the load is held
    /// over a step).
    fmi2SetRealInputDerivatives(
        _vr: *const fmi2ValueReference,
        _nvr: usize,
        _order: *const fmi2Integer,
        _value: *const fmi2Real
    ) => "no input derivatives (canInterpolateInputs = false): the load is held over each step"
);
not_provided!(
    /// fmi2GetRealOutputDerivatives: fmi2Error (maxOutputDerivativeOrder = 0).
    fmi2GetRealOutputDerivatives(
        _vr: *const fmi2ValueReference,
        _nvr: usize,
        _order: *const fmi2Integer,
        _value: *mut fmi2Real
    ) => "no output derivatives (maxOutputDerivativeOrder = 0)"
);

/// fmi2DoStep: the body moves over the step under the inputs held; a refused step changes
/// nothing.
#[no_mangle]
pub extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    const F: &str = "fmi2DoStep";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        let r = inst.do_step(currentCommunicationPoint, communicationStepSize);
        status(r, inst, F)
    })
}

not_provided!(
    /// fmi2CancelStep: fmi2Error, no step is ever in progress.
    fmi2CancelStep() => "no step is in progress (fmi2DoStep is synchronous and never returns fmi2Pending)"
);

status_query!(
    /// fmi2GetStatus: no kind is provided.
    fmi2GetStatus, fmi2Status, None::<c_int>, |inst| fmi2Status::OK
);
status_query!(
    /// fmi2GetRealStatus: fmi2LastSuccessfulTime, the FMU time.
    fmi2GetRealStatus, fmi2Real, Some(FMI2_LAST_SUCCESSFUL_TIME), |inst| inst.time()
);
status_query!(
    /// fmi2GetIntegerStatus: no kind is provided.
    fmi2GetIntegerStatus, fmi2Integer, None::<c_int>, |inst| 0
);
status_query!(
    /// fmi2GetBooleanStatus: fmi2Terminated, always false (the body never asks to stop).
    fmi2GetBooleanStatus, fmi2Boolean, Some(FMI2_TERMINATED), |inst| 0
);
status_query!(
    /// fmi2GetStringStatus: no kind is provided.
    fmi2GetStringStatus, fmi2String, None::<c_int>, |inst| std::ptr::null()
);
