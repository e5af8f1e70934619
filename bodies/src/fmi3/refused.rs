//! The FMI 3.0 functions of what this Co-Simulation FMU does not have, in `fmi3Functions.h`
//! order: value types without variables (an empty request is OK, a value reference is refused
//! naming it), Event Mode, directional and adjoint derivatives, configuration mode, clocks,
//! discrete states, Model Exchange, output derivatives and Scheduled Execution. Each answers
//! fmi3Error with one log message naming the function and why, and changes nothing. Uses
//! `super::{boundary, types}`, the FMI 2.0 boundary's helpers and `crate::instance`.
#![allow(non_snake_case)]
// The C ABI: pointers are checked before use (see `super::exports`).
#![allow(clippy::not_unsafe_ptr_arg_deref)]

use super::boundary::{get_arrays, instance3, set_arrays, status3};
use super::types::{
    fmi3Binary, fmi3Boolean, fmi3Clock, fmi3Float64, fmi3Instance, fmi3Int32,
    fmi3IntervalQualifier, fmi3Status, fmi3String, fmi3ValueReference,
};
use crate::error::{FmuError, FmuResult};
use crate::fmi2::boundary::{ffi_boundary, in_slice, out_slice};
use crate::instance::Call;

/// Defines a function that answers fmi3Error with the reason, whatever its arguments.
macro_rules! refused {
    ($(#[$doc:meta])* $name:ident ( $($arg:ident : $t:ty),* ) => $why:expr) => {
        $(#[$doc])*
        #[no_mangle]
        pub extern "C" fn $name(c: fmi3Instance $(, $arg: $t)*) -> fmi3Status {
            const F: &str = stringify!($name);
            ffi_boundary!(c, F, {
                let inst = instance3!(c, F);
                let r = inst.allowed(Call::Any).and(Err(FmuError::error($why)));
                status3(r, inst, F)
            })
        }
    };
}

/// Defines fmi3Get<Type> / fmi3Set<Type> for a type without variables.
macro_rules! no_variables {
    ($name:ident, $arrays:ident, $call:expr, $ptr:ty, $ty:expr) => {
        #[doc = concat!(stringify!($name), ": this FMU has no ", $ty, " variables; an empty request is OK.")]
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
                let inst = instance3!(c, F);
                // SAFETY: the arrays hold their announced counts (FMI 3.0 §2.2.6.2); NULL with
                // a non-zero count is refused.
                let arrays = unsafe { $arrays(valueReferences, nValueReferences, values, nValues) };
                let r = arrays.and_then(|(vrs, _)| inst.no_variables_of_type($call, vrs, $ty));
                status3(r, inst, F)
            })
        }
    };
}

const NO_EVENT_MODE: &str = "this FMU has no Event Mode (hasEventMode = false): it is in Step Mode right after fmi3ExitInitializationMode";
const NO_DERIVATIVES: &str =
    "no derivatives (providesDirectionalDerivatives = providesAdjointDerivatives = false)";
const NO_CONFIGURATION: &str = "no structural parameters, so no Configuration Mode";
const NO_CLOCKS: &str = "this FMU has no clocks";
const MODEL_EXCHANGE: &str = "a Model Exchange function; this FMU is Co-Simulation only";

refused!(
    /// fmi3EnterEventMode: fmi3Error, no Event Mode.
    fmi3EnterEventMode() => NO_EVENT_MODE
);

no_variables!(fmi3GetFloat32, get_arrays, Call::Get, *mut f32, "Float32");
no_variables!(fmi3GetInt8, get_arrays, Call::Get, *mut i8, "Int8");
no_variables!(fmi3GetUInt8, get_arrays, Call::Get, *mut u8, "UInt8");
no_variables!(fmi3GetInt16, get_arrays, Call::Get, *mut i16, "Int16");
no_variables!(fmi3GetUInt16, get_arrays, Call::Get, *mut u16, "UInt16");
no_variables!(fmi3GetUInt32, get_arrays, Call::Get, *mut u32, "UInt32");
no_variables!(fmi3GetInt64, get_arrays, Call::Get, *mut i64, "Int64");
no_variables!(fmi3GetUInt64, get_arrays, Call::Get, *mut u64, "UInt64");
no_variables!(
    fmi3GetBoolean,
    get_arrays,
    Call::Get,
    *mut fmi3Boolean,
    "Boolean"
);
no_variables!(
    fmi3GetString,
    get_arrays,
    Call::Get,
    *mut fmi3String,
    "String"
);

/// fmi3GetBinary: this FMU has no Binary variables; an empty request is OK.
#[no_mangle]
pub extern "C" fn fmi3GetBinary(
    c: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    valueSizes: *mut usize,
    values: *mut fmi3Binary,
    nValues: usize,
) -> fmi3Status {
    const F: &str = "fmi3GetBinary";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: the arrays hold their announced counts; NULL with a count is refused.
        let (arrays, sizes) = unsafe {
            (
                get_arrays(valueReferences, nValueReferences, values, nValues),
                out_slice(valueSizes, nValues, "valueSizes[]"),
            )
        };
        let r = arrays.and_then(|(vrs, _)| {
            sizes?;
            inst.no_variables_of_type(Call::Get, vrs, "Binary")
        });
        status3(r, inst, F)
    })
}

/// fmi3GetClock: this FMU has no clocks; an empty request is OK.
#[no_mangle]
pub extern "C" fn fmi3GetClock(
    c: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *mut fmi3Clock,
) -> fmi3Status {
    const F: &str = "fmi3GetClock";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        let n = nValueReferences;
        // SAFETY: both arrays hold nValueReferences elements; NULL with a count is refused.
        let arrays = unsafe { get_arrays(valueReferences, n, values, n) };
        let r = arrays.and_then(|(vrs, _)| inst.no_variables_of_type(Call::Get, vrs, "Clock"));
        status3(r, inst, F)
    })
}

no_variables!(fmi3SetFloat32, set_arrays, Call::Set, *const f32, "Float32");
no_variables!(fmi3SetInt8, set_arrays, Call::Set, *const i8, "Int8");
no_variables!(fmi3SetUInt8, set_arrays, Call::Set, *const u8, "UInt8");
no_variables!(fmi3SetInt16, set_arrays, Call::Set, *const i16, "Int16");
no_variables!(fmi3SetUInt16, set_arrays, Call::Set, *const u16, "UInt16");
no_variables!(fmi3SetUInt32, set_arrays, Call::Set, *const u32, "UInt32");
no_variables!(fmi3SetInt64, set_arrays, Call::Set, *const i64, "Int64");
no_variables!(fmi3SetUInt64, set_arrays, Call::Set, *const u64, "UInt64");
no_variables!(
    fmi3SetBoolean,
    set_arrays,
    Call::Set,
    *const fmi3Boolean,
    "Boolean"
);
no_variables!(
    fmi3SetString,
    set_arrays,
    Call::Set,
    *const fmi3String,
    "String"
);

/// fmi3SetBinary: this FMU has no Binary variables; an empty request is OK.
#[no_mangle]
pub extern "C" fn fmi3SetBinary(
    c: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    valueSizes: *const usize,
    values: *const fmi3Binary,
    nValues: usize,
) -> fmi3Status {
    const F: &str = "fmi3SetBinary";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        // SAFETY: the arrays hold their announced counts; NULL with a count is refused.
        let (arrays, sizes) = unsafe {
            (
                set_arrays(valueReferences, nValueReferences, values, nValues),
                in_slice(valueSizes, nValues, "valueSizes[]"),
            )
        };
        let r: FmuResult<()> = arrays.and_then(|(vrs, _)| {
            sizes?;
            inst.no_variables_of_type(Call::Set, vrs, "Binary")
        });
        status3(r, inst, F)
    })
}

/// fmi3SetClock: this FMU has no clocks; an empty request is OK.
#[no_mangle]
pub extern "C" fn fmi3SetClock(
    c: fmi3Instance,
    valueReferences: *const fmi3ValueReference,
    nValueReferences: usize,
    values: *const fmi3Clock,
) -> fmi3Status {
    const F: &str = "fmi3SetClock";
    ffi_boundary!(c, F, {
        let inst = instance3!(c, F);
        let n = nValueReferences;
        // SAFETY: both arrays hold nValueReferences elements; NULL with a count is refused.
        let arrays = unsafe { set_arrays(valueReferences, n, values, n) };
        let r = arrays.and_then(|(vrs, _)| inst.no_variables_of_type(Call::Set, vrs, "Clock"));
        status3(r, inst, F)
    })
}

type Vr = *const fmi3ValueReference;

refused!(
    /// fmi3GetDirectionalDerivative: fmi3Error, no derivatives.
    fmi3GetDirectionalDerivative(_u: Vr, _nu: usize, _k: Vr, _nk: usize, _seed: *const fmi3Float64,
        _ns: usize, _sensitivity: *mut fmi3Float64, _nsens: usize) => NO_DERIVATIVES
);
refused!(
    /// fmi3GetAdjointDerivative: fmi3Error, no derivatives.
    fmi3GetAdjointDerivative(_u: Vr, _nu: usize, _k: Vr, _nk: usize, _seed: *const fmi3Float64,
        _ns: usize, _sensitivity: *mut fmi3Float64, _nsens: usize) => NO_DERIVATIVES
);
refused!(
    /// fmi3EnterConfigurationMode: fmi3Error, no structural parameters.
    fmi3EnterConfigurationMode() => NO_CONFIGURATION
);
refused!(
    /// fmi3ExitConfigurationMode: fmi3Error, no structural parameters.
    fmi3ExitConfigurationMode() => NO_CONFIGURATION
);
refused!(
    /// fmi3GetIntervalDecimal: fmi3Error, no clocks.
    fmi3GetIntervalDecimal(_vr: Vr, _n: usize, _intervals: *mut fmi3Float64,
        _qualifiers: *mut fmi3IntervalQualifier) => NO_CLOCKS
);
refused!(
    /// fmi3GetIntervalFraction: fmi3Error, no clocks.
    fmi3GetIntervalFraction(_vr: Vr, _n: usize, _counters: *mut u64, _resolutions: *mut u64,
        _qualifiers: *mut fmi3IntervalQualifier) => NO_CLOCKS
);
refused!(
    /// fmi3GetShiftDecimal: fmi3Error, no clocks.
    fmi3GetShiftDecimal(_vr: Vr, _n: usize, _shifts: *mut fmi3Float64) => NO_CLOCKS
);
refused!(
    /// fmi3GetShiftFraction: fmi3Error, no clocks.
    fmi3GetShiftFraction(_vr: Vr, _n: usize, _counters: *mut u64, _resolutions: *mut u64) => NO_CLOCKS
);
refused!(
    /// fmi3SetIntervalDecimal: fmi3Error, no clocks.
    fmi3SetIntervalDecimal(_vr: Vr, _n: usize, _intervals: *const fmi3Float64) => NO_CLOCKS
);
refused!(
    /// fmi3SetIntervalFraction: fmi3Error, no clocks.
    fmi3SetIntervalFraction(_vr: Vr, _n: usize, _counters: *const u64, _resolutions: *const u64) => NO_CLOCKS
);
refused!(
    /// fmi3SetShiftDecimal: fmi3Error, no clocks.
    fmi3SetShiftDecimal(_vr: Vr, _n: usize, _shifts: *const fmi3Float64) => NO_CLOCKS
);
refused!(
    /// fmi3SetShiftFraction: fmi3Error, no clocks.
    fmi3SetShiftFraction(_vr: Vr, _n: usize, _counters: *const u64, _resolutions: *const u64) => NO_CLOCKS
);
refused!(
    /// fmi3EvaluateDiscreteStates: fmi3Error (providesEvaluateDiscreteStates = false).
    fmi3EvaluateDiscreteStates() => "no discrete states (providesEvaluateDiscreteStates = false)"
);
refused!(
    /// fmi3UpdateDiscreteStates: fmi3Error, an Event Mode function.
    fmi3UpdateDiscreteStates(_needUpdate: *mut fmi3Boolean, _terminate: *mut fmi3Boolean,
        _nominalsChanged: *mut fmi3Boolean, _valuesChanged: *mut fmi3Boolean,
        _nextEventTimeDefined: *mut fmi3Boolean, _nextEventTime: *mut fmi3Float64) => NO_EVENT_MODE
);
refused!(
    /// fmi3EnterContinuousTimeMode: fmi3Error, Model Exchange only.
    fmi3EnterContinuousTimeMode() => MODEL_EXCHANGE
);
refused!(
    /// fmi3CompletedIntegratorStep: fmi3Error, Model Exchange only.
    fmi3CompletedIntegratorStep(_noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
        _enterEventMode: *mut fmi3Boolean, _terminateSimulation: *mut fmi3Boolean) => MODEL_EXCHANGE
);
refused!(
    /// fmi3SetTime: fmi3Error, Model Exchange only.
    fmi3SetTime(_time: fmi3Float64) => MODEL_EXCHANGE
);
refused!(
    /// fmi3SetContinuousStates: fmi3Error, Model Exchange only.
    fmi3SetContinuousStates(_x: *const fmi3Float64, _n: usize) => MODEL_EXCHANGE
);
refused!(
    /// fmi3GetContinuousStateDerivatives: fmi3Error, Model Exchange only.
    fmi3GetContinuousStateDerivatives(_dx: *mut fmi3Float64, _n: usize) => MODEL_EXCHANGE
);
refused!(
    /// fmi3GetEventIndicators: fmi3Error, Model Exchange only.
    fmi3GetEventIndicators(_z: *mut fmi3Float64, _n: usize) => MODEL_EXCHANGE
);
refused!(
    /// fmi3GetContinuousStates: fmi3Error, Model Exchange only.
    fmi3GetContinuousStates(_x: *mut fmi3Float64, _n: usize) => MODEL_EXCHANGE
);
refused!(
    /// fmi3GetNominalsOfContinuousStates: fmi3Error, Model Exchange only.
    fmi3GetNominalsOfContinuousStates(_nominals: *mut fmi3Float64, _n: usize) => MODEL_EXCHANGE
);
refused!(
    /// fmi3GetNumberOfEventIndicators: fmi3Error, Model Exchange only.
    fmi3GetNumberOfEventIndicators(_n: *mut usize) => MODEL_EXCHANGE
);
refused!(
    /// fmi3GetNumberOfContinuousStates: fmi3Error, Model Exchange only.
    fmi3GetNumberOfContinuousStates(_n: *mut usize) => MODEL_EXCHANGE
);
refused!(
    /// fmi3EnterStepMode: fmi3Error, it leaves Event Mode, which this FMU has not.
    fmi3EnterStepMode() => NO_EVENT_MODE
);
refused!(
    /// fmi3GetOutputDerivatives: fmi3Error (maxOutputDerivativeOrder = 0).
    fmi3GetOutputDerivatives(_vr: Vr, _n: usize, _orders: *const fmi3Int32,
        _values: *mut fmi3Float64, _nValues: usize) => "no output derivatives (maxOutputDerivativeOrder = 0)"
);
refused!(
    /// fmi3ActivateModelPartition: fmi3Error, Scheduled Execution only.
    fmi3ActivateModelPartition(_clockReference: fmi3ValueReference, _activationTime: fmi3Float64)
        => "a Scheduled Execution function; this FMU is Co-Simulation only"
);
