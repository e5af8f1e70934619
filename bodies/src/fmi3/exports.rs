//! The FMI 3.0 functions this Co-Simulation FMU provides, in `fmi3Functions.h` order: version
//! and logging, instantiation, lifecycle, Float64 and Int32 values, variable dependencies, FMU
//! state and the step. The functions of what it does not have are in `super::refused`. Each is
//! thin: panic wall, instance lookup, pointer checks, one call into
//! `crate::instance::Instance`, one status with its log message. Uses `super::{boundary,
//! types}`, the FMI 2.0 boundary's helpers and `crate::instance`.
//!
//! Calls on one instance must not be concurrent (FMI 3.0 §2.2.3); different instances are
//! independent and may live on different threads.
#![allow(non_snake_case)]
// The C ABI: every pointer is checked for NULL (and alignment) before use and otherwise
// trusted under the FMI calling contract, as any C FMU trusts it.
#![allow(clippy::not_unsafe_ptr_arg_deref)]

use super::boundary::{
    get_arrays, instance3, instantiate, refuse_interface, set_arrays, status3,
    variable_dependencies, InstantiateArgs,
};
use super::types::{
    fmi3Boolean, fmi3ClockUpdateCallback, fmi3DependencyKind, fmi3FMUState, fmi3False, fmi3Float64,
    fmi3Instance, fmi3InstanceEnvironment, fmi3Int32, fmi3IntermediateUpdateCallback,
    fmi3LockPreemptionCallback, fmi3LogMessageCallback, fmi3Status, fmi3String,
    fmi3UnlockPreemptionCallback, fmi3ValueReference,
};
use crate::error::{FmuError, FmuResult};
use crate::fmi2::boundary::{
    c_str_array, copy_serialized, ffi_boundary, free_state, in_slice, instance_mut, out_ref,
    out_slice, state_ref, store_state, trace,
};
use crate::instance::Instance;
use std::ffi::c_char;

// ---------------------------------------------------------------- version, logging

/// fmi3GetVersion: "3.0".
#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    ffi_boundary!("fmi3GetVersion", { c"3.0".as_ptr() })
}

/// fmi3SetDebugLogging: `(NULL, 0)` categories switch every category.
#[no_mangle]
pub extern "C" fn fmi3SetDebugLogging(
    c: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    const F: &str = "fmi3SetDebugLogging";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: categories holds nCategories C strings (FMI 3.0 §2.3.1); NULLs are refused.
        let names = unsafe { c_str_array(categories, nCategories, "categories") };
        let r = names.and_then(|n| inst.set_debug_logging(loggingOn != 0, &n));
        status3(r, inst, F)
    })
}

// ---------------------------------------------------------------- instantiation

/// fmi3InstantiateModelExchange: NULL (Co-Simulation only), logged when a logger is given.
#[no_mangle]
pub extern "C" fn fmi3InstantiateModelExchange(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
) -> fmi3Instance {
    const F: &str = "fmi3InstantiateModelExchange";
    ffi_boundary!(F, {
        refuse_interface(F, instanceEnvironment, logMessage, "Model Exchange");
        std::ptr::null_mut()
    })
}

/// fmi3InstantiateCoSimulation: NULL (after logging why, when a logger exists) for a NULL or
/// empty name, an instantiationToken of another model, eventModeUsed = true (no Event Mode) or
/// a NULL requiredIntermediateVariables with a count. earlyReturnAllowed is accepted and has
/// no effect (every step completes). A NULL logMessage is allowed (nothing is logged then).
#[no_mangle]
pub extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    _earlyReturnAllowed: fmi3Boolean,
    requiredIntermediateVariables: *const fmi3ValueReference,
    nRequiredIntermediateVariables: usize,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
    _intermediateUpdate: Option<fmi3IntermediateUpdateCallback>,
) -> fmi3Instance {
    ffi_boundary!("fmi3InstantiateCoSimulation", {
        let args = InstantiateArgs {
            instance_name: instanceName,
            token: instantiationToken,
            logging_on: loggingOn != 0,
            event_mode_used: eventModeUsed != 0,
            required_intermediate: (
                requiredIntermediateVariables,
                nRequiredIntermediateVariables,
            ),
            env: instanceEnvironment,
            log_message: logMessage,
        };
        // SAFETY: the pointers are NULL or as FMI 3.0 §2.3.1 specifies; NULLs are refused.
        let inst = unsafe { instantiate(args) };
        inst.map_or(std::ptr::null_mut(), |i| Box::into_raw(Box::new(i)).cast())
    })
}

/// fmi3InstantiateScheduledExecution: NULL (Co-Simulation only), logged when a logger is given.
#[no_mangle]
pub extern "C" fn fmi3InstantiateScheduledExecution(
    _instanceName: fmi3String,
    _instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    _loggingOn: fmi3Boolean,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
    _clockUpdate: Option<fmi3ClockUpdateCallback>,
    _lockPreemption: Option<fmi3LockPreemptionCallback>,
    _unlockPreemption: Option<fmi3UnlockPreemptionCallback>,
) -> fmi3Instance {
    const F: &str = "fmi3InstantiateScheduledExecution";
    ffi_boundary!(F, {
        refuse_interface(F, instanceEnvironment, logMessage, "Scheduled Execution");
        std::ptr::null_mut()
    })
}

/// fmi3FreeInstance: NULL is ignored; allowed in every state, also after fmi3Fatal.
#[no_mangle]
pub extern "C" fn fmi3FreeInstance(c: fmi3Instance) {
    ffi_boundary!("fmi3FreeInstance", {
        // SAFETY: c is NULL or a live instance from fmi3InstantiateCoSimulation.
        if let Some(inst) = unsafe { instance_mut(c) } {
            trace(inst, "fmi3FreeInstance");
            // SAFETY: the Box made at instantiation, released once: c is not used after this.
            drop(unsafe { Box::from_raw(inst as *mut Instance) });
        }
    })
}

// ---------------------------------------------------------------- lifecycle

/// fmi3EnterInitializationMode: the start time (finite) and Initialization Mode; tolerance
/// and stop time are not used.
#[no_mangle]
pub extern "C" fn fmi3EnterInitializationMode(
    c: fmi3Instance,
    _toleranceDefined: fmi3Boolean,
    _tolerance: fmi3Float64,
    startTime: fmi3Float64,
    _stopTimeDefined: fmi3Boolean,
    _stopTime: fmi3Float64,
) -> fmi3Status {
    const F: &str = "fmi3EnterInitializationMode";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        let r = inst
            .setup_experiment(startTime)
            .and_then(|()| inst.enter_initialization_mode());
        status3(r, inst, F)
    })
}

/// Defines a lifecycle function: one instance call without arguments.
macro_rules! lifecycle {
    ($(#[$doc:meta])* $name:ident, $method:ident) => {
        $(#[$doc])*
        #[no_mangle]
        pub extern "C" fn $name(c: fmi3Instance) -> fmi3Status {
            const F: &str = stringify!($name);
            ffi_boundary!(c, F, {
                let inst = instance3!(c, F);
                status3(inst.$method(), inst, F)
            })
        }
    };
}

lifecycle!(
    /// fmi3ExitInitializationMode: parameters checked together, the body starts; the instance
    /// goes to Step Mode (no Event Mode).
    fmi3ExitInitializationMode, exit_initialization_mode
);
lifecycle!(
    /// fmi3Terminate.
    fmi3Terminate, terminate
);
lifecycle!(
    /// fmi3Reset: start values, the Instantiated state.
    fmi3Reset, reset
);

// ---------------------------------------------------------------- values

/// Defines fmi3Get<Type> / fmi3Set<Type> for a type the table has.
macro_rules! access {
    ($(#[$doc:meta])* $name:ident, $arrays:ident, $ptr:ty, |$inst:ident, $vrs:ident, $v:ident| $call:expr) => {
        $(#[$doc])*
        #[no_mangle]
        pub extern "C" fn $name(
            c: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: usize,
            values: $ptr,
            nValues: usize,
        ) -> fmi3Status {
            const F: &str = stringify!($name);
            ffi_boundary!(c, F, {
                let $inst = instance3!(c, F);
                // SAFETY: the arrays hold their announced counts (FMI 3.0 §2.2.6.2); NULL with
                // a non-zero count is refused.
                let arrays = unsafe { $arrays(valueReferences, nValueReferences, values, nValues) };
                let r: FmuResult<()> = arrays.and_then(|($vrs, $v)| $call);
                status3(r, $inst, F)
            })
        }
    };
}

access!(
    /// fmi3GetFloat64: the Real variables of the table, and `time` (value reference 0).
    fmi3GetFloat64, get_arrays, *mut fmi3Float64, |inst, vrs, out| inst.get_real(vrs, out)
);
access!(
    /// fmi3GetInt32: the Integer variables of the table.
    fmi3GetInt32, get_arrays, *mut fmi3Int32, |inst, vrs, out| inst.get_integer(vrs, out)
);
access!(
    /// fmi3SetFloat64: all or nothing; non-finite and out-of-range values refused, `time` too.
    fmi3SetFloat64, set_arrays, *const fmi3Float64, |inst, vrs, v| inst.set_real(vrs, v)
);
access!(
    /// fmi3SetInt32: all or nothing; out-of-range values refused.
    fmi3SetInt32, set_arrays, *const fmi3Int32, |inst, vrs, v| inst.set_integer(vrs, v)
);

// ---------------------------------------------------------------- dependencies

/// fmi3GetNumberOfVariableDependencies: per the model structure (InitialUnknown before
/// fmi3ExitInitializationMode: every parameter; Output after: none); fmi3Error for a variable
/// that is not an output.
#[no_mangle]
pub extern "C" fn fmi3GetNumberOfVariableDependencies(
    c: fmi3Instance,
    valueReference: fmi3ValueReference,
    nDependencies: *mut usize,
) -> fmi3Status {
    const F: &str = "fmi3GetNumberOfVariableDependencies";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: nDependencies is NULL (refused) or writable.
        let out = unsafe { out_ref(nDependencies, "nDependencies") };
        let r = out.and_then(|n| {
            *n = variable_dependencies(inst, valueReference)?.len();
            Ok(())
        });
        status3(r, inst, F)
    })
}

/// fmi3GetVariableDependencies: the knowns of fmi3GetNumberOfVariableDependencies, all scalar
/// (element index 0), of kind fmi3Dependent.
#[no_mangle]
pub extern "C" fn fmi3GetVariableDependencies(
    c: fmi3Instance,
    dependent: fmi3ValueReference,
    elementIndicesOfDependent: *mut usize,
    independents: *mut fmi3ValueReference,
    elementIndicesOfIndependents: *mut usize,
    dependencyKinds: *mut fmi3DependencyKind,
    nDependencies: usize,
) -> fmi3Status {
    const F: &str = "fmi3GetVariableDependencies";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        let n = nDependencies;
        // SAFETY: each array holds nDependencies elements (FMI 3.0 §2.2.10); NULL with n > 0
        // is refused.
        let arrays = unsafe {
            (|| {
                Ok::<_, FmuError>((
                    out_slice(elementIndicesOfDependent, n, "elementIndicesOfDependent[]")?,
                    out_slice(independents, n, "independents[]")?,
                    out_slice(
                        elementIndicesOfIndependents,
                        n,
                        "elementIndicesOfIndependents[]",
                    )?,
                    out_slice(dependencyKinds, n, "dependencyKinds[]")?,
                ))
            })()
        };
        let r = arrays.and_then(|(e_dep, indep, e_indep, kinds)| {
            let deps = variable_dependencies(inst, dependent)?;
            if deps.len() != n {
                return Err(FmuError::error(format!(
                    "nDependencies = {n}, but vr {dependent} has {} dependencies now (fmi3GetNumberOfVariableDependencies)",
                    deps.len()
                )));
            }
            for (i, vr) in deps.into_iter().enumerate() {
                (e_dep[i], indep[i], e_indep[i]) = (0, vr, 0);
                kinds[i] = fmi3DependencyKind::Dependent;
            }
            Ok(())
        });
        status3(r, inst, F)
    })
}

// ---------------------------------------------------------------- FMU state

/// fmi3GetFMUState: a non-NULL `*FMUState` (a state this FMU returned) is overwritten.
#[no_mangle]
pub extern "C" fn fmi3GetFMUState(c: fmi3Instance, FMUState: *mut fmi3FMUState) -> fmi3Status {
    const F: &str = "fmi3GetFMUState";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: FMUState is writable, *FMUState NULL or a live state of this FMU.
        let r = inst
            .get_state()
            .and_then(|s| unsafe { store_state(FMUState, s) });
        status3(r, inst, F)
    })
}

/// fmi3SetFMUState.
#[no_mangle]
pub extern "C" fn fmi3SetFMUState(c: fmi3Instance, FMUState: fmi3FMUState) -> fmi3Status {
    const F: &str = "fmi3SetFMUState";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: a non-NULL FMUState is a live state of this FMU.
        let r = unsafe { state_ref(FMUState) }.and_then(|s| inst.set_state(s));
        status3(r, inst, F)
    })
}

/// fmi3FreeFMUState: NULL or `*NULL` is OK; allowed in every state (also after fmi3Fatal).
#[no_mangle]
pub extern "C" fn fmi3FreeFMUState(c: fmi3Instance, FMUState: *mut fmi3FMUState) -> fmi3Status {
    const F: &str = "fmi3FreeFMUState";
    ffi_boundary!(c, F, {
        let _inst = instance3!(c, F);
        // SAFETY: FMUState is NULL or writable, *FMUState NULL or a live state.
        unsafe { free_state(FMUState) };
        fmi3Status::OK
    })
}

/// fmi3SerializedFMUStateSize.
#[no_mangle]
pub extern "C" fn fmi3SerializedFMUStateSize(
    c: fmi3Instance,
    FMUState: fmi3FMUState,
    size: *mut usize,
) -> fmi3Status {
    const F: &str = "fmi3SerializedFMUStateSize";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: FMUState is NULL (refused) or a live state; size NULL (refused) or writable.
        let (state, out) = unsafe { (state_ref(FMUState), out_ref(size, "size")) };
        let r = state.and_then(|s| inst.serialize(s)).and_then(|b| {
            *out? = b.len();
            Ok(())
        });
        status3(r, inst, F)
    })
}

/// fmi3SerializeFMUState: `size` must be at least fmi3SerializedFMUStateSize.
#[no_mangle]
pub extern "C" fn fmi3SerializeFMUState(
    c: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut u8,
    size: usize,
) -> fmi3Status {
    const F: &str = "fmi3SerializeFMUState";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: FMUState NULL (refused) or live; serializedState holds size bytes.
        let (state, buf) = unsafe {
            (
                state_ref(FMUState),
                out_slice(serializedState, size, "serializedState"),
            )
        };
        let r = state.and_then(|s| copy_serialized(inst, s, buf?, "fmi3SerializedFMUStateSize"));
        status3(r, inst, F)
    })
}

/// fmi3DeserializeFMUState: the bytes are validated before a state is made (the FMI 2.0
/// format: either version's bytes restore in the other).
#[no_mangle]
pub extern "C" fn fmi3DeserializeFMUState(
    c: fmi3Instance,
    serializedState: *const u8,
    size: usize,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    const F: &str = "fmi3DeserializeFMUState";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: serializedState holds size bytes; NULL with size > 0 is refused.
        let bytes = unsafe { in_slice(serializedState, size, "serializedState") };
        let snapshot = bytes.and_then(|b| inst.deserialize(b));
        // SAFETY: FMUState is writable, *FMUState NULL or a live state of this FMU.
        let r = snapshot.and_then(|s| unsafe { store_state(FMUState, s) });
        status3(r, inst, F)
    })
}

// ---------------------------------------------------------------- co-simulation

/// fmi3DoStep: the body moves over the step under the inputs held. Never returns early:
/// earlyReturn = fmi3False, lastSuccessfulTime = the FMU time after the call (t + h, or t when
/// the step is refused); eventHandlingNeeded and terminateSimulation are fmi3False.
#[no_mangle]
pub extern "C" fn fmi3DoStep(
    c: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    const F: &str = "fmi3DoStep";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: each is NULL (refused) or writable (FMI 3.0 §4.2.1).
        let outs = unsafe {
            (|| {
                Ok::<_, FmuError>((
                    out_ref(eventHandlingNeeded, "eventHandlingNeeded")?,
                    out_ref(terminateSimulation, "terminateSimulation")?,
                    out_ref(earlyReturn, "earlyReturn")?,
                    out_ref(lastSuccessfulTime, "lastSuccessfulTime")?,
                ))
            })()
        };
        let r = outs.and_then(|(event, terminate, early, last)| {
            let stepped = inst.do_step(currentCommunicationPoint, communicationStepSize);
            (*event, *terminate, *early) = (fmi3False, fmi3False, fmi3False);
            *last = inst.time();
            stepped
        });
        status3(r, inst, F)
    })
}
