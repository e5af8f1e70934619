//! Every FMI 2.0 Co-Simulation function (the 25 common ones and the 9 of Co-Simulation), in
//! `fmi2Functions.h` order. Each is thin: panic wrapper, instance lookup, pointer checks, one
//! call into `ModelInstance`, one mapping to `fmi2Status`.
//!
//! Calls on one instance must not be concurrent (FMI 2.0 §2.1.5); different instances are
//! independent and may live on different threads.
#![allow(non_snake_case)]
// These are the C ABI: every pointer is checked for NULL (and alignment) before use and is
// otherwise trusted under the FMI calling contract, as any C FMU trusts it; Rust callers (the
// integration tests) take on that contract too.
#![allow(clippy::not_unsafe_ptr_arg_deref)]

use super::boundary::{
    c_str_array, derivative_arrays, directional_arrays, free_state, get_arrays, in_slice,
    instance_mut, instantiate, out_ref, out_slice, set_arrays, state_ref, store_state, trace,
    ToStatus,
};
use super::policy::{
    copy_serialized, get_booleans, no_output_derivatives, provided_kind, set_booleans,
    unsupported_status,
};
use super::types::{
    fmi2Boolean, fmi2Byte, fmi2CallbackFunctions, fmi2Component, fmi2FMUstate, fmi2Integer,
    fmi2Real, fmi2Status, fmi2StatusKind, fmi2String, fmi2ValueReference,
};
use crate::error::FmuError;
use crate::instance::{Call, ModelInstance};
use libc::{c_char, c_int, size_t};

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
    nCategories: size_t,
    categories: *const fmi2String,
) -> fmi2Status {
    const F: &str = "fmi2SetDebugLogging";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F, Call::Lifecycle);
        // SAFETY: categories holds nCategories C strings (FMI 2.0 §2.1.5); NULLs are refused.
        let names = unsafe { c_str_array(categories, nCategories, "categories") };
        names
            .and_then(|n| inst.set_debug_logging(loggingOn != 0, &n))
            .to_status(inst, F)
    })
}

/// fmi2Instantiate: NULL (after logging why, when a logger exists) for a NULL or empty name,
/// a type other than fmi2CoSimulation, an unknown GUID, or missing callbacks.
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
            // SAFETY: the Box made by fmi2Instantiate, released once: the importer may not
            // use c after this call.
            drop(unsafe { Box::from_raw(inst as *mut ModelInstance) });
        }
    })
}

/// fmi2SetupExperiment (the tolerance is not used).
#[no_mangle]
pub extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _toleranceDefined: fmi2Boolean,
    _tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    const F: &str = "fmi2SetupExperiment";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        let stop = (stopTimeDefined != 0).then_some(stopTime);
        inst.setup_experiment(startTime, stop).to_status(inst, F)
    })
}

/// fmi2EnterInitializationMode.
#[no_mangle]
pub extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    const F: &str = "fmi2EnterInitializationMode";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        inst.enter_initialization_mode().to_status(inst, F)
    })
}

/// fmi2ExitInitializationMode: parameters are checked, the initial geometry fixed.
#[no_mangle]
pub extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    const F: &str = "fmi2ExitInitializationMode";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        inst.exit_initialization_mode().to_status(inst, F)
    })
}

/// fmi2Terminate.
#[no_mangle]
pub extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    const F: &str = "fmi2Terminate";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        inst.terminate().to_status(inst, F)
    })
}

/// fmi2Reset: back to the start values in the Instantiated state.
#[no_mangle]
pub extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    const F: &str = "fmi2Reset";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        inst.reset().to_status(inst, F)
    })
}

/// fmi2GetReal.
#[no_mangle]
pub extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *mut fmi2Real,
) -> fmi2Status {
    const F: &str = "fmi2GetReal";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: vr and value hold nvr elements (FMI 2.0 §2.1.7); NULL with nvr > 0 is refused.
        let arrays = unsafe { get_arrays(vr, nvr, value) };
        arrays
            .and_then(|(vrs, out)| inst.get_real(vrs, out))
            .to_status(inst, F)
    })
}

/// fmi2GetInteger.
#[no_mangle]
pub extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *mut fmi2Integer,
) -> fmi2Status {
    const F: &str = "fmi2GetInteger";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: vr and value hold nvr elements (FMI 2.0 §2.1.7); NULL with nvr > 0 is refused.
        let arrays = unsafe { get_arrays(vr, nvr, value) };
        arrays
            .and_then(|(vrs, out)| inst.get_integer(vrs, out))
            .to_status(inst, F)
    })
}

/// fmi2GetBoolean.
#[no_mangle]
pub extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    const F: &str = "fmi2GetBoolean";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: vr and value hold nvr elements (FMI 2.0 §2.1.7); NULL with nvr > 0 is refused.
        let arrays = unsafe { get_arrays(vr, nvr, value) };
        arrays
            .and_then(|(vrs, out)| get_booleans(inst, vrs, out))
            .to_status(inst, F)
    })
}

/// fmi2GetString: this FMU has no String variables.
#[no_mangle]
pub extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *mut fmi2String,
) -> fmi2Status {
    const F: &str = "fmi2GetString";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: vr and value hold nvr elements (FMI 2.0 §2.1.7); NULL with nvr > 0 is refused.
        let arrays = unsafe { get_arrays(vr, nvr, value) };
        arrays
            .and_then(|(vrs, _)| inst.get_string(vrs))
            .to_status(inst, F)
    })
}

/// fmi2SetReal.
#[no_mangle]
pub extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *const fmi2Real,
) -> fmi2Status {
    const F: &str = "fmi2SetReal";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: vr and value hold nvr elements (FMI 2.0 §2.1.7); NULL with nvr > 0 is refused.
        let arrays = unsafe { set_arrays(vr, nvr, value) };
        arrays
            .and_then(|(vrs, v)| inst.set_real(vrs, v))
            .to_status(inst, F)
    })
}

/// fmi2SetInteger.
#[no_mangle]
pub extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *const fmi2Integer,
) -> fmi2Status {
    const F: &str = "fmi2SetInteger";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: vr and value hold nvr elements (FMI 2.0 §2.1.7); NULL with nvr > 0 is refused.
        let arrays = unsafe { set_arrays(vr, nvr, value) };
        arrays
            .and_then(|(vrs, v)| inst.set_integer(vrs, v))
            .to_status(inst, F)
    })
}

/// fmi2SetBoolean.
#[no_mangle]
pub extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *const fmi2Boolean,
) -> fmi2Status {
    const F: &str = "fmi2SetBoolean";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: vr and value hold nvr elements (FMI 2.0 §2.1.7); NULL with nvr > 0 is refused.
        let arrays = unsafe { set_arrays(vr, nvr, value) };
        arrays
            .and_then(|(vrs, v)| set_booleans(inst, vrs, v))
            .to_status(inst, F)
    })
}

/// fmi2SetString: this FMU has no String variables.
#[no_mangle]
pub extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    value: *const fmi2String,
) -> fmi2Status {
    const F: &str = "fmi2SetString";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: vr and value hold nvr elements (FMI 2.0 §2.1.7); NULL with nvr > 0 is refused.
        let arrays = unsafe { set_arrays(vr, nvr, value) };
        arrays
            .and_then(|(vrs, _)| inst.set_string(vrs))
            .to_status(inst, F)
    })
}

/// fmi2GetFMUstate: a non-NULL `*FMUstate` (a state this FMU returned) is overwritten in place.
#[no_mangle]
pub extern "C" fn fmi2GetFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
    const F: &str = "fmi2GetFMUstate";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: FMUstate is writable, *FMUstate NULL or a live state of this FMU (FMI 2.0 §2.1.8).
        let stored = inst
            .get_state()
            .and_then(|s| unsafe { store_state(FMUstate, s) });
        stored.to_status(inst, F)
    })
}

/// fmi2SetFMUstate.
#[no_mangle]
pub extern "C" fn fmi2SetFMUstate(c: fmi2Component, FMUstate: fmi2FMUstate) -> fmi2Status {
    const F: &str = "fmi2SetFMUstate";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: a non-NULL FMUstate is a live state of this FMU (FMI 2.0 §2.1.8).
        let state = unsafe { state_ref(FMUstate) };
        state.and_then(|s| inst.set_state(s)).to_status(inst, F)
    })
}

/// fmi2FreeFMUstate: NULL or `*NULL` is OK; allowed in every state (also after fmi2Fatal), so
/// the importer can always release its states.
#[no_mangle]
pub extern "C" fn fmi2FreeFMUstate(c: fmi2Component, FMUstate: *mut fmi2FMUstate) -> fmi2Status {
    const F: &str = "fmi2FreeFMUstate";
    ffi_boundary!(c, F, {
        let _inst = instance!(c, F);
        // SAFETY: FMUstate is NULL or writable, *FMUstate NULL or a live state (FMI 2.0 §2.1.8).
        unsafe { free_state(FMUstate) };
        fmi2Status::OK
    })
}

/// fmi2SerializedFMUstateSize.
#[no_mangle]
pub extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    size: *mut size_t,
) -> fmi2Status {
    const F: &str = "fmi2SerializedFMUstateSize";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F, Call::Lifecycle);
        // SAFETY: FMUstate is NULL (refused) or a live state of this FMU (FMI 2.0 §2.1.8).
        let state = unsafe { state_ref(FMUstate) };
        // SAFETY: size is NULL (refused) or writable.
        let out = unsafe { out_ref(size, "size") };
        let len = state.and_then(|s| inst.own_state(s).map(|()| inst.serialize(s).len()));
        len.and_then(|n| out.map(|o| *o = n)).to_status(inst, F)
    })
}

/// fmi2SerializeFMUstate: `size` must be at least fmi2SerializedFMUstateSize.
#[no_mangle]
pub extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    FMUstate: fmi2FMUstate,
    serializedState: *mut fmi2Byte,
    size: size_t,
) -> fmi2Status {
    const F: &str = "fmi2SerializeFMUstate";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F, Call::Lifecycle);
        // SAFETY: FMUstate is NULL (refused) or a live state of this FMU (FMI 2.0 §2.1.8).
        let state = unsafe { state_ref(FMUstate) };
        // SAFETY: serializedState holds size bytes; NULL with size > 0 is refused.
        let buf = unsafe { out_slice(serializedState.cast::<u8>(), size, "serializedState") };
        state
            .and_then(|s| copy_serialized(inst, s, buf?, "fmi2SerializedFMUstateSize"))
            .to_status(inst, F)
    })
}

/// fmi2DeSerializeFMUstate: bytes are validated before a state is made.
#[no_mangle]
pub extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    serializedState: *const fmi2Byte,
    size: size_t,
    FMUstate: *mut fmi2FMUstate,
) -> fmi2Status {
    const F: &str = "fmi2DeSerializeFMUstate";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: serializedState holds size bytes (FMI 2.0 §2.1.8); NULL with size > 0 is refused.
        let bytes = unsafe { in_slice(serializedState.cast::<u8>(), size, "serializedState") };
        let snapshot = bytes.and_then(|b| inst.deserialize(b));
        // SAFETY: FMUstate is writable, *FMUstate NULL or a live state of this FMU.
        let stored = snapshot.and_then(|s| unsafe { store_state(FMUstate, s) });
        stored.to_status(inst, F)
    })
}

/// fmi2GetDirectionalDerivative: the connector's consistent tangent.
#[no_mangle]
pub extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    vUnknown_ref: *const fmi2ValueReference,
    nUnknown: size_t,
    vKnown_ref: *const fmi2ValueReference,
    nKnown: size_t,
    dvKnown: *const fmi2Real,
    dvUnknown: *mut fmi2Real,
) -> fmi2Status {
    const F: &str = "fmi2GetDirectionalDerivative";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: the arrays hold nUnknown, nKnown, nKnown, nUnknown elements (FMI 2.0 §2.1.9).
        let args = unsafe {
            directional_arrays(
                vUnknown_ref,
                nUnknown,
                vKnown_ref,
                nKnown,
                dvKnown,
                dvUnknown,
            )
        };
        args.and_then(|a| inst.directional_derivative(a.unknowns, a.knowns, a.seed, a.out))
            .to_status(inst, F)
    })
}

// ---------------------------------------------------------------- co-simulation functions

/// fmi2SetRealInputDerivatives: first-order derivatives of inputs, for the next step.
#[no_mangle]
pub extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    order: *const fmi2Integer,
    value: *const fmi2Real,
) -> fmi2Status {
    const F: &str = "fmi2SetRealInputDerivatives";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: vr, order and value hold nvr elements each (FMI 2.0 §4.2.1).
        let args = unsafe { derivative_arrays(vr, nvr, order, value) };
        args.and_then(|(v, o, x)| inst.set_real_input_derivatives(v, o, x))
            .to_status(inst, F)
    })
}

/// fmi2GetRealOutputDerivatives: none are provided (MaxOutputDerivativeOrder = 0).
#[no_mangle]
pub extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: size_t,
    order: *const fmi2Integer,
    value: *mut fmi2Real,
) -> fmi2Status {
    const F: &str = "fmi2GetRealOutputDerivatives";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F, Call::OutputDerivatives);
        // SAFETY: vr, order and value hold nvr elements each (FMI 2.0 §4.2.1).
        let args = unsafe { derivative_arrays(vr, nvr, order, value) };
        args.and_then(|(v, _, _)| no_output_derivatives(v))
            .to_status(inst, F)
    })
}

/// fmi2DoStep (noSetFMUStatePriorToCurrentPoint is not needed: every state is kept cheaply).
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
        inst.do_step(currentCommunicationPoint, communicationStepSize)
            .map(|_| ())
            .to_status(inst, F)
    })
}

/// fmi2CancelStep: always fmi2Error, no step is ever in progress.
#[no_mangle]
pub extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    const F: &str = "fmi2CancelStep";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        let why = format!(
            "{F}: no step is in progress (fmi2DoStep is synchronous and never returns fmi2Pending)"
        );
        Err(FmuError::error(why)).to_status(inst, F)
    })
}

/// fmi2GetStatus: no kind is provided (fmi2Discard).
#[no_mangle]
pub extern "C" fn fmi2GetStatus(c: fmi2Component, s: c_int, value: *mut fmi2Status) -> fmi2Status {
    const F: &str = "fmi2GetStatus";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F, Call::Status);
        // SAFETY: value is NULL (refused) or writable (FMI 2.0 §4.2.3).
        let out = unsafe { out_ref(value, "value") };
        out.and_then(|_| unsupported_status(s)).to_status(inst, F)
    })
}

/// fmi2GetRealStatus: fmi2LastSuccessfulTime.
#[no_mangle]
pub extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    s: c_int,
    value: *mut fmi2Real,
) -> fmi2Status {
    const F: &str = "fmi2GetRealStatus";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: value is NULL (refused) or writable (FMI 2.0 §4.2.3).
        let out = unsafe { out_ref(value, "value") };
        let r = out.and_then(|v| {
            provided_kind(inst, s, fmi2StatusKind::LastSuccessfulTime)?;
            inst.last_successful_time().map(|t| *v = t)
        });
        r.to_status(inst, F)
    })
}

/// fmi2GetIntegerStatus: no kind is provided (fmi2Discard).
#[no_mangle]
pub extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    s: c_int,
    value: *mut fmi2Integer,
) -> fmi2Status {
    const F: &str = "fmi2GetIntegerStatus";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F, Call::Status);
        // SAFETY: value is NULL (refused) or writable (FMI 2.0 §4.2.3).
        let out = unsafe { out_ref(value, "value") };
        out.and_then(|_| unsupported_status(s)).to_status(inst, F)
    })
}

/// fmi2GetBooleanStatus: fmi2Terminated (the slave never asks to terminate).
#[no_mangle]
pub extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    s: c_int,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    const F: &str = "fmi2GetBooleanStatus";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F);
        // SAFETY: value is NULL (refused) or writable (FMI 2.0 §4.2.3).
        let out = unsafe { out_ref(value, "value") };
        let r = out.and_then(|v| {
            provided_kind(inst, s, fmi2StatusKind::Terminated)?;
            inst.terminated_status().map(|b| *v = fmi2Boolean::from(b))
        });
        r.to_status(inst, F)
    })
}

/// fmi2GetStringStatus: no kind is provided (fmi2Discard).
#[no_mangle]
pub extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    s: c_int,
    value: *mut fmi2String,
) -> fmi2Status {
    const F: &str = "fmi2GetStringStatus";
    ffi_boundary!(c, F, {
        let inst = instance!(c, F, Call::Status);
        // SAFETY: value is NULL (refused) or writable (FMI 2.0 §4.2.3).
        let out = unsafe { out_ref(value, "value") };
        out.and_then(|_| unsupported_status(s)).to_status(inst, F)
    })
}
