//! Every FMI 3.0 function, in `fmi3Functions.h` order. Each is thin: panic wrapper, instance
//! lookup, pointer checks, one call into `ModelInstance` (or a refusal from `policy`), one
//! mapping to `fmi3Status`. Functions of interfaces and features this Co-Simulation FMU does
//! not have (Model Exchange, Scheduled Execution, events, clocks, configuration) answer
//! fmi3Error with a log line naming the function and why.
//!
//! Calls on one instance must not be concurrent (FMI 3.0 §2.2.3); different instances are
//! independent and may live on different threads.
#![allow(non_snake_case)]
// These are the C ABI: every pointer is checked for NULL (and alignment) before use and is
// otherwise trusted under the FMI calling contract, as any C FMU trusts it; Rust callers (the
// integration tests) take on that contract too.
#![allow(clippy::not_unsafe_ptr_arg_deref)]

use super::boundary::{
    derivative_arrays, get_arrays, instantiate, refuse_interface, set_arrays, InstantiateArgs,
    ToStatus,
};
use super::policy::{
    copy_serialized, get_booleans, get_float64, no_output_derivatives, no_variables_of_type,
    set_booleans, set_float64, unsupported, variable_dependencies, Unsupported,
};
use super::types::{
    fmi3Binary, fmi3Boolean, fmi3Byte, fmi3Clock, fmi3ClockUpdateCallback, fmi3DependencyKind,
    fmi3FMUState, fmi3False, fmi3Float32, fmi3Float64, fmi3Instance, fmi3InstanceEnvironment,
    fmi3Int32, fmi3IntermediateUpdateCallback, fmi3IntervalQualifier, fmi3LockPreemptionCallback,
    fmi3LogMessageCallback, fmi3Status, fmi3String, fmi3UnlockPreemptionCallback,
    fmi3ValueReference,
};
use crate::error::{FmuError, FmuResult};
use crate::fmi2::boundary::{
    c_str_array, free_state, in_slice, instance_mut, out_ref, out_slice, state_ref, store_state,
    trace,
};
use crate::instance::{Call, ModelInstance};
use libc::{c_char, size_t};

// ---------------------------------------------------------------- version, logging

/// fmi3GetVersion: "3.0".
#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    ffi3!("fmi3GetVersion", { c"3.0".as_ptr() })
}

/// fmi3SetDebugLogging: `(NULL, 0)` categories switch every category.
#[no_mangle]
pub extern "C" fn fmi3SetDebugLogging(
    c: fmi3Instance,
    loggingOn: fmi3Boolean,
    nCategories: size_t,
    categories: *const fmi3String,
) -> fmi3Status {
    const F: &str = "fmi3SetDebugLogging";
    ffi3!(c, F, {
        let inst = instance3!(c, F, Call::Lifecycle);
        // SAFETY: categories holds nCategories C strings (FMI 3.0 §2.3.1); NULLs are refused.
        let names = unsafe { c_str_array(categories, nCategories, "categories") };
        names
            .and_then(|n| inst.set_debug_logging(loggingOn != 0, &n))
            .to_status(inst, F)
    })
}

// ---------------------------------------------------------------- instantiation

/// fmi3InstantiateModelExchange: NULL (this FMU is Co-Simulation only), logged when a logger
/// is given.
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
    ffi3!(F, {
        refuse_interface(F, instanceEnvironment, logMessage, "Model Exchange");
        std::ptr::null_mut()
    })
}

/// fmi3InstantiateCoSimulation: NULL (after logging why, when a logger exists) for a NULL or
/// empty name, an unknown instantiationToken, eventModeUsed = true (no Event Mode) or a NULL
/// requiredIntermediateVariables with a non-zero count. With earlyReturnAllowed, fmi3DoStep
/// returns early at the first event inside a step. A NULL logMessage is allowed (nothing is
/// logged then).
#[no_mangle]
pub extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    _resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    earlyReturnAllowed: fmi3Boolean,
    requiredIntermediateVariables: *const fmi3ValueReference,
    nRequiredIntermediateVariables: size_t,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: Option<fmi3LogMessageCallback>,
    _intermediateUpdate: Option<fmi3IntermediateUpdateCallback>,
) -> fmi3Instance {
    ffi3!("fmi3InstantiateCoSimulation", {
        let args = InstantiateArgs {
            instance_name: instanceName,
            token: instantiationToken,
            logging_on: loggingOn != 0,
            event_mode_used: eventModeUsed != 0,
            early_return_allowed: earlyReturnAllowed != 0,
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

/// fmi3InstantiateScheduledExecution: NULL (this FMU is Co-Simulation only), logged when a
/// logger is given.
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
    ffi3!(F, {
        refuse_interface(F, instanceEnvironment, logMessage, "Scheduled Execution");
        std::ptr::null_mut()
    })
}

/// fmi3FreeInstance: NULL is ignored; allowed in every state, also after fmi3Fatal.
#[no_mangle]
pub extern "C" fn fmi3FreeInstance(c: fmi3Instance) {
    ffi3!("fmi3FreeInstance", {
        // SAFETY: c is NULL or a live instance from fmi3InstantiateCoSimulation.
        if let Some(inst) = unsafe { instance_mut(c) } {
            trace(inst, "fmi3FreeInstance");
            // SAFETY: the Box made by fmi3InstantiateCoSimulation, released once: the importer
            // may not use c after this call.
            drop(unsafe { Box::from_raw(inst as *mut ModelInstance) });
        }
    })
}

// ---------------------------------------------------------------- lifecycle

/// fmi3EnterInitializationMode: start time (finite) and Initialization Mode; the tolerance
/// and stop time are not used.
#[no_mangle]
pub extern "C" fn fmi3EnterInitializationMode(
    c: fmi3Instance,
    _toleranceDefined: fmi3Boolean,
    _tolerance: fmi3Float64,
    startTime: fmi3Float64,
    stopTimeDefined: fmi3Boolean,
    stopTime: fmi3Float64,
) -> fmi3Status {
    const F: &str = "fmi3EnterInitializationMode";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        let stop = (stopTimeDefined != 0).then_some(stopTime);
        inst.setup_experiment(startTime, stop)
            .and_then(|()| inst.enter_initialization_mode())
            .to_status(inst, F)
    })
}

/// fmi3ExitInitializationMode: parameters are checked, the initial geometry fixed; the
/// instance goes to Step Mode (no Event Mode).
#[no_mangle]
pub extern "C" fn fmi3ExitInitializationMode(c: fmi3Instance) -> fmi3Status {
    const F: &str = "fmi3ExitInitializationMode";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        inst.exit_initialization_mode().to_status(inst, F)
    })
}

/// Defines an exported function that answers fmi3Error with the reason, whatever its
/// arguments (each named with a leading `_`).
macro_rules! refused {
    ($(#[$doc:meta])* $name:ident ( $($arg:ident : $t:ty),* ) => $why:expr) => {
        $(#[$doc])*
        #[no_mangle]
        pub extern "C" fn $name(c: fmi3Instance $(, $arg: $t)*) -> fmi3Status {
            const F: &str = stringify!($name);
            ffi3!(c, F, {
                let inst = instance3!(c, F);
                Err(unsupported($why)).to_status(inst, F)
            })
        }
    };
}

refused!(
    /// fmi3EnterEventMode: fmi3Error, this FMU has no Event Mode (hasEventMode = false).
    fmi3EnterEventMode() => Unsupported::EventMode
);

/// fmi3Terminate.
#[no_mangle]
pub extern "C" fn fmi3Terminate(c: fmi3Instance) -> fmi3Status {
    const F: &str = "fmi3Terminate";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        inst.terminate().to_status(inst, F)
    })
}

/// fmi3Reset: back to the start values in the Instantiated state.
#[no_mangle]
pub extern "C" fn fmi3Reset(c: fmi3Instance) -> fmi3Status {
    const F: &str = "fmi3Reset";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        inst.reset().to_status(inst, F)
    })
}

// ---------------------------------------------------------------- getters

/// Defines fmi3Get<Type> for a type this FMU has no variables of.
macro_rules! no_getter {
    ($name:ident, $t:ty, $ty:expr) => {
        #[doc = concat!(stringify!($name), ": this FMU has no ", $ty, " variables; an empty request is OK.")]
        #[no_mangle]
        pub extern "C" fn $name(
            c: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            values: *mut $t,
            nValues: size_t,
        ) -> fmi3Status {
            const F: &str = stringify!($name);
            ffi3!(c, F, {
                let inst = instance3!(c, F);
                // SAFETY: the arrays hold their announced counts (FMI 3.0 §2.2.6.2); NULL with
                // a non-zero count is refused.
                let arrays = unsafe { get_arrays(valueReferences, nValueReferences, values, nValues) };
                arrays
                    .and_then(|(vrs, _)| no_variables_of_type(inst, Call::Get, vrs, $ty))
                    .to_status(inst, F)
            })
        }
    };
}

/// Defines fmi3Get<Type> for a type backed by the variable table.
macro_rules! getter {
    ($(#[$doc:meta])* $name:ident, $t:ty, |$inst:ident, $vrs:ident, $out:ident| $get:expr) => {
        $(#[$doc])*
        #[no_mangle]
        pub extern "C" fn $name(
            c: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            values: *mut $t,
            nValues: size_t,
        ) -> fmi3Status {
            const F: &str = stringify!($name);
            ffi3!(c, F, {
                let $inst = instance3!(c, F);
                // SAFETY: the arrays hold their announced counts (FMI 3.0 §2.2.6.2); NULL with
                // a non-zero count is refused.
                let arrays = unsafe { get_arrays(valueReferences, nValueReferences, values, nValues) };
                let r: FmuResult<()> = arrays.and_then(|($vrs, $out)| $get);
                r.to_status($inst, F)
            })
        }
    };
}

no_getter!(fmi3GetFloat32, fmi3Float32, "Float32");
getter!(
    /// fmi3GetFloat64 (the FMI 2.0 Real variables, and `time`).
    fmi3GetFloat64, fmi3Float64, |inst, vrs, out| get_float64(inst, vrs, out)
);
no_getter!(fmi3GetInt8, i8, "Int8");
no_getter!(fmi3GetUInt8, u8, "UInt8");
no_getter!(fmi3GetInt16, i16, "Int16");
no_getter!(fmi3GetUInt16, u16, "UInt16");
getter!(
    /// fmi3GetInt32 (the FMI 2.0 Integer variables).
    fmi3GetInt32, fmi3Int32, |inst, vrs, out| inst.get_integer(vrs, out)
);
no_getter!(fmi3GetUInt32, u32, "UInt32");
no_getter!(fmi3GetInt64, i64, "Int64");
no_getter!(fmi3GetUInt64, u64, "UInt64");
getter!(
    /// fmi3GetBoolean: 0 or 1 written.
    fmi3GetBoolean, fmi3Boolean, |inst, vrs, out| get_booleans(inst, vrs, out)
);
no_getter!(fmi3GetString, fmi3String, "String");

/// fmi3GetBinary: this FMU has no Binary variables; an empty request is OK.
#[no_mangle]
pub extern "C" fn fmi3GetBinary(
    c: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    valueSizes: *mut size_t,
    values: *mut fmi3Binary,
    nValues: size_t,
) -> fmi3Status {
    const F: &str = "fmi3GetBinary";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: the arrays hold their announced counts (FMI 3.0 §2.2.6.2); NULL with a
        // non-zero count is refused.
        let arrays = unsafe { get_arrays(valueReferences, nValueReferences, values, nValues) };
        // SAFETY: as above, valueSizes has nValues elements.
        let sizes = unsafe { out_slice(valueSizes, nValues, "valueSizes[]") };
        let r = arrays.and_then(|(vrs, _)| {
            sizes?;
            no_variables_of_type(inst, Call::Get, vrs, "Binary")
        });
        r.to_status(inst, F)
    })
}

/// fmi3GetClock: this FMU has no clocks; an empty request is OK.
#[no_mangle]
pub extern "C" fn fmi3GetClock(
    c: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *mut fmi3Clock,
) -> fmi3Status {
    const F: &str = "fmi3GetClock";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: both arrays hold nValueReferences elements; NULL with a non-zero count is
        // refused.
        let arrays =
            unsafe { get_arrays(valueReferences, nValueReferences, values, nValueReferences) };
        arrays
            .and_then(|(vrs, _)| no_variables_of_type(inst, Call::Get, vrs, "Clock"))
            .to_status(inst, F)
    })
}

// ---------------------------------------------------------------- setters

/// Defines fmi3Set<Type> for a type this FMU has no variables of.
macro_rules! no_setter {
    ($name:ident, $t:ty, $ty:expr) => {
        #[doc = concat!(stringify!($name), ": this FMU has no ", $ty, " variables; an empty request is OK.")]
        #[no_mangle]
        pub extern "C" fn $name(
            c: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            values: *const $t,
            nValues: size_t,
        ) -> fmi3Status {
            const F: &str = stringify!($name);
            ffi3!(c, F, {
                let inst = instance3!(c, F);
                // SAFETY: the arrays hold their announced counts (FMI 3.0 §2.2.6.2); NULL with
                // a non-zero count is refused.
                let arrays = unsafe { set_arrays(valueReferences, nValueReferences, values, nValues) };
                arrays
                    .and_then(|(vrs, _)| no_variables_of_type(inst, Call::Set, vrs, $ty))
                    .to_status(inst, F)
            })
        }
    };
}

/// Defines fmi3Set<Type> for a type backed by the variable table.
macro_rules! setter {
    ($(#[$doc:meta])* $name:ident, $t:ty, |$inst:ident, $vrs:ident, $v:ident| $set:expr) => {
        $(#[$doc])*
        #[no_mangle]
        pub extern "C" fn $name(
            c: fmi3Instance,
            valueReferences: *const fmi3ValueReference,
            nValueReferences: size_t,
            values: *const $t,
            nValues: size_t,
        ) -> fmi3Status {
            const F: &str = stringify!($name);
            ffi3!(c, F, {
                let $inst = instance3!(c, F);
                // SAFETY: the arrays hold their announced counts (FMI 3.0 §2.2.6.2); NULL with
                // a non-zero count is refused.
                let arrays = unsafe { set_arrays(valueReferences, nValueReferences, values, nValues) };
                let r: FmuResult<()> = arrays.and_then(|($vrs, $v)| $set);
                r.to_status($inst, F)
            })
        }
    };
}

no_setter!(fmi3SetFloat32, fmi3Float32, "Float32");
setter!(
    /// fmi3SetFloat64 (all or nothing; a non-finite value is refused; `time` cannot be set).
    fmi3SetFloat64, fmi3Float64, |inst, vrs, v| set_float64(inst, vrs, v)
);
no_setter!(fmi3SetInt8, i8, "Int8");
no_setter!(fmi3SetUInt8, u8, "UInt8");
no_setter!(fmi3SetInt16, i16, "Int16");
no_setter!(fmi3SetUInt16, u16, "UInt16");
setter!(
    /// fmi3SetInt32 (all or nothing).
    fmi3SetInt32, fmi3Int32, |inst, vrs, v| inst.set_integer(vrs, v)
);
no_setter!(fmi3SetUInt32, u32, "UInt32");
no_setter!(fmi3SetInt64, i64, "Int64");
no_setter!(fmi3SetUInt64, u64, "UInt64");
setter!(
    /// fmi3SetBoolean: any non-zero byte is true.
    fmi3SetBoolean, fmi3Boolean, |inst, vrs, v| set_booleans(inst, vrs, v)
);
no_setter!(fmi3SetString, fmi3String, "String");

/// fmi3SetBinary: this FMU has no Binary variables; an empty request is OK.
#[no_mangle]
pub extern "C" fn fmi3SetBinary(
    c: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    valueSizes: *const size_t,
    values: *const fmi3Binary,
    nValues: size_t,
) -> fmi3Status {
    const F: &str = "fmi3SetBinary";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: the arrays hold their announced counts (FMI 3.0 §2.2.6.2); NULL with a
        // non-zero count is refused.
        let arrays = unsafe { set_arrays(valueReferences, nValueReferences, values, nValues) };
        // SAFETY: as above, valueSizes has nValues elements.
        let sizes = unsafe { in_slice(valueSizes, nValues, "valueSizes[]") };
        let r = arrays.and_then(|(vrs, _)| {
            sizes?;
            no_variables_of_type(inst, Call::Set, vrs, "Binary")
        });
        r.to_status(inst, F)
    })
}

/// fmi3SetClock: this FMU has no clocks; an empty request is OK.
#[no_mangle]
pub extern "C" fn fmi3SetClock(
    c: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    values: *const fmi3Clock,
) -> fmi3Status {
    const F: &str = "fmi3SetClock";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: both arrays hold nValueReferences elements; NULL with a non-zero count is
        // refused.
        let arrays =
            unsafe { set_arrays(valueReferences, nValueReferences, values, nValueReferences) };
        arrays
            .and_then(|(vrs, _)| no_variables_of_type(inst, Call::Set, vrs, "Clock"))
            .to_status(inst, F)
    })
}

// ---------------------------------------------------------------- dependencies

/// fmi3GetNumberOfVariableDependencies: per the model structure (InitialUnknown before
/// fmi3ExitInitializationMode, Output after); fmi3Error for a variable that is not an output.
#[no_mangle]
pub extern "C" fn fmi3GetNumberOfVariableDependencies(
    c: fmi3Instance,
    valueReference: fmi3ValueReference,
    nDependencies: *mut size_t,
) -> fmi3Status {
    const F: &str = "fmi3GetNumberOfVariableDependencies";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: nDependencies is NULL (refused) or writable.
        let out = unsafe { out_ref(nDependencies, "nDependencies") };
        let r = out.and_then(|n| {
            *n = variable_dependencies(inst, valueReference)?.len();
            Ok(())
        });
        r.to_status(inst, F)
    })
}

/// fmi3GetVariableDependencies: the knowns of fmi3GetNumberOfVariableDependencies, all scalar
/// (element index 0) and of kind fmi3Dependent.
#[no_mangle]
pub extern "C" fn fmi3GetVariableDependencies(
    c: fmi3Instance,
    dependent: fmi3ValueReference,
    elementIndicesOfDependent: *mut size_t,
    independents: *mut fmi3ValueReference,
    elementIndicesOfIndependents: *mut size_t,
    dependencyKinds: *mut fmi3DependencyKind,
    nDependencies: size_t,
) -> fmi3Status {
    const F: &str = "fmi3GetVariableDependencies";
    ffi3!(c, F, {
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
                    "nDependencies = {n}, but vr {dependent} has {} dependencies (fmi3GetNumberOfVariableDependencies)",
                    deps.len()
                )));
            }
            for (i, vr) in deps.into_iter().enumerate() {
                e_dep[i] = 0;
                indep[i] = vr;
                e_indep[i] = 0;
                kinds[i] = fmi3DependencyKind::Dependent;
            }
            Ok(())
        });
        r.to_status(inst, F)
    })
}

// ---------------------------------------------------------------- FMU state

/// fmi3GetFMUState: a non-NULL `*FMUState` (a state this FMU returned) is overwritten in place.
#[no_mangle]
pub extern "C" fn fmi3GetFMUState(c: fmi3Instance, FMUState: *mut fmi3FMUState) -> fmi3Status {
    const F: &str = "fmi3GetFMUState";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: FMUState is writable, *FMUState NULL or a live state of this FMU.
        let stored = inst
            .get_state()
            .and_then(|s| unsafe { store_state(FMUState, s) });
        stored.to_status(inst, F)
    })
}

/// fmi3SetFMUState.
#[no_mangle]
pub extern "C" fn fmi3SetFMUState(c: fmi3Instance, FMUState: fmi3FMUState) -> fmi3Status {
    const F: &str = "fmi3SetFMUState";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: a non-NULL FMUState is a live state of this FMU.
        let state = unsafe { state_ref(FMUState) };
        state.and_then(|s| inst.set_state(s)).to_status(inst, F)
    })
}

/// fmi3FreeFMUState: NULL or `*NULL` is OK; allowed in every state (also after fmi3Fatal).
#[no_mangle]
pub extern "C" fn fmi3FreeFMUState(c: fmi3Instance, FMUState: *mut fmi3FMUState) -> fmi3Status {
    const F: &str = "fmi3FreeFMUState";
    ffi3!(c, F, {
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
    size: *mut size_t,
) -> fmi3Status {
    const F: &str = "fmi3SerializedFMUStateSize";
    ffi3!(c, F, {
        let inst = instance3!(c, F, Call::Lifecycle);
        // SAFETY: FMUState is NULL (refused) or a live state of this FMU.
        let state = unsafe { state_ref(FMUState) };
        // SAFETY: size is NULL (refused) or writable.
        let out = unsafe { out_ref(size, "size") };
        let len = state.and_then(|s| inst.own_state(s).map(|()| inst.serialize(s).len()));
        len.and_then(|n| out.map(|o| *o = n)).to_status(inst, F)
    })
}

/// fmi3SerializeFMUState: `size` must be at least fmi3SerializedFMUStateSize.
#[no_mangle]
pub extern "C" fn fmi3SerializeFMUState(
    c: fmi3Instance,
    FMUState: fmi3FMUState,
    serializedState: *mut fmi3Byte,
    size: size_t,
) -> fmi3Status {
    const F: &str = "fmi3SerializeFMUState";
    ffi3!(c, F, {
        let inst = instance3!(c, F, Call::Lifecycle);
        // SAFETY: FMUState is NULL (refused) or a live state of this FMU.
        let state = unsafe { state_ref(FMUState) };
        // SAFETY: serializedState holds size bytes; NULL with size > 0 is refused.
        let buf = unsafe { out_slice(serializedState, size, "serializedState") };
        state
            .and_then(|s| copy_serialized(inst, s, buf?))
            .to_status(inst, F)
    })
}

/// fmi3DeserializeFMUState: bytes are validated before a state is made.
#[no_mangle]
pub extern "C" fn fmi3DeserializeFMUState(
    c: fmi3Instance,
    serializedState: *const fmi3Byte,
    size: size_t,
    FMUState: *mut fmi3FMUState,
) -> fmi3Status {
    const F: &str = "fmi3DeserializeFMUState";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: serializedState holds size bytes; NULL with size > 0 is refused.
        let bytes = unsafe { in_slice(serializedState, size, "serializedState") };
        let snapshot = bytes.and_then(|b| inst.deserialize(b));
        // SAFETY: FMUState is writable, *FMUState NULL or a live state of this FMU.
        let stored = snapshot.and_then(|s| unsafe { store_state(FMUState, s) });
        stored.to_status(inst, F)
    })
}

// ---------------------------------------------------------------- derivatives

/// fmi3GetDirectionalDerivative: the connector's consistent tangent (the FMI 2.0 one).
#[no_mangle]
pub extern "C" fn fmi3GetDirectionalDerivative(
    c: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    nUnknowns: size_t,
    knowns: *const fmi3ValueReference,
    nKnowns: size_t,
    seed: *const fmi3Float64,
    nSeed: size_t,
    sensitivity: *mut fmi3Float64,
    nSensitivity: size_t,
) -> fmi3Status {
    const F: &str = "fmi3GetDirectionalDerivative";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: each array holds its announced count (FMI 3.0 §2.2.11); NULL with a
        // non-zero count is refused.
        let args = unsafe {
            derivative_arrays(
                (unknowns, nUnknowns),
                (knowns, nKnowns),
                (seed, nSeed),
                (sensitivity, nSensitivity),
                (nKnowns, "nKnowns"),
                (nUnknowns, "nUnknowns"),
            )
        };
        args.and_then(|a| inst.directional_derivative(a.unknowns, a.knowns, a.seed, a.sensitivity))
            .to_status(inst, F)
    })
}

/// fmi3GetAdjointDerivative: Jᵀ·seed for the J of fmi3GetDirectionalDerivative.
#[no_mangle]
pub extern "C" fn fmi3GetAdjointDerivative(
    c: fmi3Instance,
    unknowns: *const fmi3ValueReference,
    nUnknowns: size_t,
    knowns: *const fmi3ValueReference,
    nKnowns: size_t,
    seed: *const fmi3Float64,
    nSeed: size_t,
    sensitivity: *mut fmi3Float64,
    nSensitivity: size_t,
) -> fmi3Status {
    const F: &str = "fmi3GetAdjointDerivative";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: each array holds its announced count (FMI 3.0 §2.2.11); NULL with a
        // non-zero count is refused.
        let args = unsafe {
            derivative_arrays(
                (unknowns, nUnknowns),
                (knowns, nKnowns),
                (seed, nSeed),
                (sensitivity, nSensitivity),
                (nUnknowns, "nUnknowns"),
                (nKnowns, "nKnowns"),
            )
        };
        args.and_then(|a| inst.adjoint_derivative(a.unknowns, a.knowns, a.seed, a.sensitivity))
            .to_status(inst, F)
    })
}

// ---------------------------------------------------------------- configuration, clocks

refused!(
    /// fmi3EnterConfigurationMode: fmi3Error, no structural parameters.
    fmi3EnterConfigurationMode() => Unsupported::Configuration
);
refused!(
    /// fmi3ExitConfigurationMode: fmi3Error, no structural parameters.
    fmi3ExitConfigurationMode() => Unsupported::Configuration
);
refused!(
    /// fmi3GetIntervalDecimal: fmi3Error, no clocks.
    fmi3GetIntervalDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: size_t,
        _intervals: *mut fmi3Float64,
        _qualifiers: *mut fmi3IntervalQualifier
    ) => Unsupported::Clocks
);
refused!(
    /// fmi3GetIntervalFraction: fmi3Error, no clocks.
    fmi3GetIntervalFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: size_t,
        _counters: *mut u64,
        _resolutions: *mut u64,
        _qualifiers: *mut fmi3IntervalQualifier
    ) => Unsupported::Clocks
);
refused!(
    /// fmi3GetShiftDecimal: fmi3Error, no clocks.
    fmi3GetShiftDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: size_t,
        _shifts: *mut fmi3Float64
    ) => Unsupported::Clocks
);
refused!(
    /// fmi3GetShiftFraction: fmi3Error, no clocks.
    fmi3GetShiftFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: size_t,
        _counters: *mut u64,
        _resolutions: *mut u64
    ) => Unsupported::Clocks
);
refused!(
    /// fmi3SetIntervalDecimal: fmi3Error, no clocks.
    fmi3SetIntervalDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: size_t,
        _intervals: *const fmi3Float64
    ) => Unsupported::Clocks
);
refused!(
    /// fmi3SetIntervalFraction: fmi3Error, no clocks.
    fmi3SetIntervalFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: size_t,
        _counters: *const u64,
        _resolutions: *const u64
    ) => Unsupported::Clocks
);
refused!(
    /// fmi3SetShiftDecimal: fmi3Error, no clocks.
    fmi3SetShiftDecimal(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: size_t,
        _shifts: *const fmi3Float64
    ) => Unsupported::Clocks
);
refused!(
    /// fmi3SetShiftFraction: fmi3Error, no clocks.
    fmi3SetShiftFraction(
        _valueReferences: *const fmi3ValueReference,
        _nValueReferences: size_t,
        _counters: *const u64,
        _resolutions: *const u64
    ) => Unsupported::Clocks
);
refused!(
    /// fmi3EvaluateDiscreteStates: fmi3Error (providesEvaluateDiscreteStates = false).
    fmi3EvaluateDiscreteStates() => Unsupported::EvaluateDiscreteStates
);
refused!(
    /// fmi3UpdateDiscreteStates: fmi3Error, only meaningful in Event Mode, which this FMU has
    /// not.
    fmi3UpdateDiscreteStates(
        _discreteStatesNeedUpdate: *mut fmi3Boolean,
        _terminateSimulation: *mut fmi3Boolean,
        _nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
        _valuesOfContinuousStatesChanged: *mut fmi3Boolean,
        _nextEventTimeDefined: *mut fmi3Boolean,
        _nextEventTime: *mut fmi3Float64
    ) => Unsupported::EventMode
);

// ---------------------------------------------------------------- model exchange (refused)

refused!(
    /// fmi3EnterContinuousTimeMode: fmi3Error, Model Exchange only.
    fmi3EnterContinuousTimeMode() => Unsupported::ModelExchange
);
refused!(
    /// fmi3CompletedIntegratorStep: fmi3Error, Model Exchange only.
    fmi3CompletedIntegratorStep(
        _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
        _enterEventMode: *mut fmi3Boolean,
        _terminateSimulation: *mut fmi3Boolean
    ) => Unsupported::ModelExchange
);
refused!(
    /// fmi3SetTime: fmi3Error, Model Exchange only.
    fmi3SetTime(_time: fmi3Float64) => Unsupported::ModelExchange
);
refused!(
    /// fmi3SetContinuousStates: fmi3Error, Model Exchange only.
    fmi3SetContinuousStates(
        _continuousStates: *const fmi3Float64,
        _nContinuousStates: size_t
    ) => Unsupported::ModelExchange
);
refused!(
    /// fmi3GetContinuousStateDerivatives: fmi3Error, Model Exchange only.
    fmi3GetContinuousStateDerivatives(
        _derivatives: *mut fmi3Float64,
        _nContinuousStates: size_t
    ) => Unsupported::ModelExchange
);
refused!(
    /// fmi3GetEventIndicators: fmi3Error, Model Exchange only.
    fmi3GetEventIndicators(
        _eventIndicators: *mut fmi3Float64,
        _nEventIndicators: size_t
    ) => Unsupported::ModelExchange
);
refused!(
    /// fmi3GetContinuousStates: fmi3Error, Model Exchange only.
    fmi3GetContinuousStates(
        _continuousStates: *mut fmi3Float64,
        _nContinuousStates: size_t
    ) => Unsupported::ModelExchange
);
refused!(
    /// fmi3GetNominalsOfContinuousStates: fmi3Error, Model Exchange only.
    fmi3GetNominalsOfContinuousStates(
        _nominals: *mut fmi3Float64,
        _nContinuousStates: size_t
    ) => Unsupported::ModelExchange
);
refused!(
    /// fmi3GetNumberOfEventIndicators: fmi3Error, Model Exchange only.
    fmi3GetNumberOfEventIndicators(_nEventIndicators: *mut size_t) => Unsupported::ModelExchange
);
refused!(
    /// fmi3GetNumberOfContinuousStates: fmi3Error, Model Exchange only.
    fmi3GetNumberOfContinuousStates(_nContinuousStates: *mut size_t) => Unsupported::ModelExchange
);

// ---------------------------------------------------------------- co-simulation

refused!(
    /// fmi3EnterStepMode: fmi3Error, it leaves Event Mode, which this FMU has not (it is in
    /// Step Mode right after fmi3ExitInitializationMode).
    fmi3EnterStepMode() => Unsupported::EventMode
);

/// fmi3GetOutputDerivatives: none are provided (maxOutputDerivativeOrder = 0); an empty
/// request is OK.
#[no_mangle]
pub extern "C" fn fmi3GetOutputDerivatives(
    c: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: size_t,
    orders: *const fmi3Int32,
    values: *mut fmi3Float64,
    nValues: size_t,
) -> fmi3Status {
    const F: &str = "fmi3GetOutputDerivatives";
    ffi3!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: valueReferences and orders hold nValueReferences elements, values nValues
        // (FMI 3.0 §4.2.1); NULL with a non-zero count is refused.
        let arrays = unsafe { get_arrays(valueReferences, nValueReferences, values, nValues) };
        // SAFETY: as above.
        let ord = unsafe { in_slice(orders, nValueReferences, "orders[]") };
        let r = arrays.and_then(|(vrs, _)| {
            ord?;
            no_output_derivatives(inst, vrs)
        });
        r.to_status(inst, F)
    })
}

/// fmi3DoStep: advances from currentCommunicationPoint by communicationStepSize along the input
/// extrapolation. With earlyReturnAllowed (at instantiation) it stops at the first event inside
/// the step (docs/fmi3.md, "Early return"): earlyReturn = fmi3True and lastSuccessfulTime = the
/// event time, where outputs and state now are; otherwise earlyReturn = fmi3False and
/// lastSuccessfulTime = t + h (t when the step is refused). eventHandlingNeeded and
/// terminateSimulation are always fmi3False (no Event Mode, never terminates).
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
    ffi3!(c, F, {
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
            *event = fmi3False;
            *terminate = fmi3False;
            *early = fmi3Boolean::from(stepped == Ok(true));
            *last = inst.time();
            stepped.map(|_| ())
        });
        r.to_status(inst, F)
    })
}

// ---------------------------------------------------------------- scheduled execution

refused!(
    /// fmi3ActivateModelPartition: fmi3Error, Scheduled Execution only.
    fmi3ActivateModelPartition(
        _clockReference: fmi3ValueReference,
        _activationTime: fmi3Float64
    ) => Unsupported::ScheduledExecution
);
