//! Empty FMI 2.0 Co-Simulation FMU (modelIdentifier `Empty`): the floor of an FMI round trip.
//!
//! All 34 FMI 2.0 CS functions are exported under their C names; the bodies are in `imp.rs`
//! (shared with benches/native/ of the main crate). Set/Get store and return values in small
//! arrays, fmi2DoStep only advances the clock, the state functions return fmi2Error.
#![allow(non_snake_case)]

mod imp;

use std::ffi::{c_char, c_double, c_int, c_uint, c_void};

macro_rules! export {
    ($( $name:ident => $body:ident ( $($arg:ident : $ty:ty),* ) -> $ret:ty; )*) => {
        $(
            #[no_mangle]
            pub extern "C" fn $name($($arg: $ty),*) -> $ret {
                imp::$body($($arg),*)
            }
        )*
    };
}

type Comp = *mut c_void;

export! {
    fmi2GetTypesPlatform => get_types_platform() -> *const c_char;
    fmi2GetVersion => get_version() -> *const c_char;
    fmi2SetDebugLogging => set_debug_logging(c: Comp, on: c_int, n: usize, cat: *const *const c_char) -> c_int;
    fmi2Instantiate => instantiate(name: *const c_char, fmu_type: c_int, guid: *const c_char, resources: *const c_char, functions: *const c_void, visible: c_int, logging_on: c_int) -> Comp;
    fmi2FreeInstance => free_instance(c: Comp) -> ();
    fmi2SetupExperiment => setup_experiment(c: Comp, tol_def: c_int, tol: c_double, start: c_double, stop_def: c_int, stop: c_double) -> c_int;
    fmi2EnterInitializationMode => enter_initialization_mode(c: Comp) -> c_int;
    fmi2ExitInitializationMode => exit_initialization_mode(c: Comp) -> c_int;
    fmi2Terminate => terminate(c: Comp) -> c_int;
    fmi2Reset => reset(c: Comp) -> c_int;
    fmi2GetReal => get_real(c: Comp, vr: *const c_uint, n: usize, v: *mut c_double) -> c_int;
    fmi2GetInteger => get_integer(c: Comp, vr: *const c_uint, n: usize, v: *mut c_int) -> c_int;
    fmi2GetBoolean => get_boolean(c: Comp, vr: *const c_uint, n: usize, v: *mut c_int) -> c_int;
    fmi2GetString => get_string(c: Comp, vr: *const c_uint, n: usize, v: *mut *const c_char) -> c_int;
    fmi2SetReal => set_real(c: Comp, vr: *const c_uint, n: usize, v: *const c_double) -> c_int;
    fmi2SetInteger => set_integer(c: Comp, vr: *const c_uint, n: usize, v: *const c_int) -> c_int;
    fmi2SetBoolean => set_boolean(c: Comp, vr: *const c_uint, n: usize, v: *const c_int) -> c_int;
    fmi2SetString => set_string(c: Comp, vr: *const c_uint, n: usize, v: *const *const c_char) -> c_int;
    fmi2GetFMUstate => get_fmu_state(c: Comp, s: *mut *mut c_void) -> c_int;
    fmi2SetFMUstate => set_fmu_state(c: Comp, s: *mut c_void) -> c_int;
    fmi2FreeFMUstate => free_fmu_state(c: Comp, s: *mut *mut c_void) -> c_int;
    fmi2SerializedFMUstateSize => serialized_fmu_state_size(c: Comp, s: *mut c_void, n: *mut usize) -> c_int;
    fmi2SerializeFMUstate => serialize_fmu_state(c: Comp, s: *mut c_void, b: *mut c_char, n: usize) -> c_int;
    fmi2DeSerializeFMUstate => de_serialize_fmu_state(c: Comp, b: *const c_char, n: usize, s: *mut *mut c_void) -> c_int;
    fmi2GetDirectionalDerivative => get_directional_derivative(c: Comp, u: *const c_uint, nu: usize, k: *const c_uint, nk: usize, dk: *const c_double, du: *mut c_double) -> c_int;
    fmi2SetRealInputDerivatives => set_real_input_derivatives(c: Comp, vr: *const c_uint, n: usize, o: *const c_int, v: *const c_double) -> c_int;
    fmi2GetRealOutputDerivatives => get_real_output_derivatives(c: Comp, vr: *const c_uint, n: usize, o: *const c_int, v: *mut c_double) -> c_int;
    fmi2DoStep => do_step(c: Comp, t: c_double, h: c_double, no_set_prior: c_int) -> c_int;
    fmi2CancelStep => cancel_step(c: Comp) -> c_int;
    fmi2GetStatus => get_status(c: Comp, k: c_int, v: *mut c_int) -> c_int;
    fmi2GetRealStatus => get_real_status(c: Comp, k: c_int, v: *mut c_double) -> c_int;
    fmi2GetIntegerStatus => get_integer_status(c: Comp, k: c_int, v: *mut c_int) -> c_int;
    fmi2GetBooleanStatus => get_boolean_status(c: Comp, k: c_int, v: *mut c_int) -> c_int;
    fmi2GetStringStatus => get_string_status(c: Comp, k: c_int, v: *mut *const c_char) -> c_int;
}
