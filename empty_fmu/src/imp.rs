//! The bodies of the empty FMU: every FMI 2.0 Co-Simulation function with its C signature and a
//! trivial body. Values live in small arrays indexed by value reference; fmi2DoStep only
//! advances the time. Functions the benchmark does not need return fmi2Error.
//!
//! The functions carry no `#[no_mangle]` so that this file can be compiled twice: into the
//! cdylib (src/lib.rs exports them under their fmi2 names) and into the native benchmark
//! (benches/native/main.rs includes it with `#[path]`, fmus.rs calls the bodies through function
//! pointers, next to the real FMU's exported functions, without a symbol clash).
#![allow(non_snake_case, dead_code, clippy::not_unsafe_ptr_arg_deref)]

use std::ffi::{c_char, c_double, c_int, c_uint, c_void};

/// fmi2Status as the C int (fmi2OK).
pub const OK: c_int = 0;
/// fmi2Error.
pub const ERROR: c_int = 3;
/// The GUID in empty_fmu/modelDescription.xml.
pub const GUID: &str = "{e0e0e0e0-0000-4000-8000-00000000e0f0}";
/// Number of Real inputs (VRs 1..=N_IN) and Real outputs (VRs N_IN+1..=N_IN+N_OUT).
pub const N_IN: u32 = 26;
/// Number of Real outputs.
pub const N_OUT: u32 = 12;
/// Slots per type (VR 0 unused).
const SLOTS: usize = 64;

/// One instance.
pub struct Empty {
    real: [c_double; SLOTS],
    integer: [c_int; SLOTS],
    boolean: [c_int; SLOTS],
    time: c_double,
}

type Comp = *mut c_void;

#[inline(always)]
fn inst<'a>(c: Comp) -> Option<&'a mut Empty> {
    // SAFETY: c is NULL or the Box::into_raw of fmi2Instantiate, not yet freed (FMI 2.0 §2.1.5).
    unsafe { c.cast::<Empty>().as_mut() }
}

#[inline(always)]
fn set<T: Copy>(slots: &mut [T; SLOTS], vr: *const c_uint, n: usize, v: *const T) -> c_int {
    if n == 0 {
        return OK;
    }
    if vr.is_null() || v.is_null() {
        return ERROR;
    }
    for i in 0..n {
        // SAFETY: vr and v hold n elements (FMI 2.0 §2.1.7).
        let (r, x) = unsafe { (*vr.add(i) as usize, *v.add(i)) };
        match slots.get_mut(r) {
            Some(s) => *s = x,
            None => return ERROR,
        }
    }
    OK
}

#[inline(always)]
fn get<T: Copy>(slots: &[T; SLOTS], vr: *const c_uint, n: usize, v: *mut T) -> c_int {
    if n == 0 {
        return OK;
    }
    if vr.is_null() || v.is_null() {
        return ERROR;
    }
    for i in 0..n {
        // SAFETY: vr and v hold n elements (FMI 2.0 §2.1.7).
        let r = unsafe { *vr.add(i) } as usize;
        match slots.get(r) {
            Some(s) => unsafe { *v.add(i) = *s },
            None => return ERROR,
        }
    }
    OK
}

pub extern "C" fn get_types_platform() -> *const c_char {
    c"default".as_ptr()
}

pub extern "C" fn get_version() -> *const c_char {
    c"2.0".as_ptr()
}

pub extern "C" fn set_debug_logging(
    c: Comp,
    _on: c_int,
    _n: usize,
    _cat: *const *const c_char,
) -> c_int {
    if inst(c).is_some() {
        OK
    } else {
        ERROR
    }
}

pub extern "C" fn instantiate(
    name: *const c_char,
    fmu_type: c_int,
    guid: *const c_char,
    _resources: *const c_char,
    functions: *const c_void,
    _visible: c_int,
    _logging_on: c_int,
) -> Comp {
    if name.is_null() || guid.is_null() || functions.is_null() || fmu_type != 1 {
        return std::ptr::null_mut();
    }
    // SAFETY: a NUL-terminated string (FMI 2.0 §2.1.5).
    if unsafe { std::ffi::CStr::from_ptr(guid) }.to_bytes() != GUID.as_bytes() {
        return std::ptr::null_mut();
    }
    let e = Box::new(Empty {
        real: [0.0; SLOTS],
        integer: [0; SLOTS],
        boolean: [0; SLOTS],
        time: 0.0,
    });
    Box::into_raw(e).cast()
}

pub extern "C" fn free_instance(c: Comp) {
    if !c.is_null() {
        // SAFETY: the Box of fmi2Instantiate, freed once.
        drop(unsafe { Box::from_raw(c.cast::<Empty>()) });
    }
}

pub extern "C" fn setup_experiment(
    c: Comp,
    _tol_def: c_int,
    _tol: c_double,
    start: c_double,
    _stop_def: c_int,
    _stop: c_double,
) -> c_int {
    match inst(c) {
        Some(e) => {
            e.time = start;
            OK
        }
        None => ERROR,
    }
}

pub extern "C" fn enter_initialization_mode(c: Comp) -> c_int {
    if inst(c).is_some() {
        OK
    } else {
        ERROR
    }
}

pub extern "C" fn exit_initialization_mode(c: Comp) -> c_int {
    if inst(c).is_some() {
        OK
    } else {
        ERROR
    }
}

pub extern "C" fn terminate(c: Comp) -> c_int {
    if inst(c).is_some() {
        OK
    } else {
        ERROR
    }
}

pub extern "C" fn reset(c: Comp) -> c_int {
    match inst(c) {
        Some(e) => {
            e.real = [0.0; SLOTS];
            e.integer = [0; SLOTS];
            e.boolean = [0; SLOTS];
            e.time = 0.0;
            OK
        }
        None => ERROR,
    }
}

pub extern "C" fn get_real(c: Comp, vr: *const c_uint, n: usize, v: *mut c_double) -> c_int {
    inst(c).map_or(ERROR, |e| get(&e.real, vr, n, v))
}

pub extern "C" fn get_integer(c: Comp, vr: *const c_uint, n: usize, v: *mut c_int) -> c_int {
    inst(c).map_or(ERROR, |e| get(&e.integer, vr, n, v))
}

pub extern "C" fn get_boolean(c: Comp, vr: *const c_uint, n: usize, v: *mut c_int) -> c_int {
    inst(c).map_or(ERROR, |e| get(&e.boolean, vr, n, v))
}

pub extern "C" fn get_string(
    c: Comp,
    _vr: *const c_uint,
    n: usize,
    _v: *mut *const c_char,
) -> c_int {
    // no String variables: only the empty request is valid
    if inst(c).is_some() && n == 0 {
        OK
    } else {
        ERROR
    }
}

pub extern "C" fn set_real(c: Comp, vr: *const c_uint, n: usize, v: *const c_double) -> c_int {
    inst(c).map_or(ERROR, |e| set(&mut e.real, vr, n, v))
}

pub extern "C" fn set_integer(c: Comp, vr: *const c_uint, n: usize, v: *const c_int) -> c_int {
    inst(c).map_or(ERROR, |e| set(&mut e.integer, vr, n, v))
}

pub extern "C" fn set_boolean(c: Comp, vr: *const c_uint, n: usize, v: *const c_int) -> c_int {
    inst(c).map_or(ERROR, |e| set(&mut e.boolean, vr, n, v))
}

pub extern "C" fn set_string(
    c: Comp,
    _vr: *const c_uint,
    n: usize,
    _v: *const *const c_char,
) -> c_int {
    if inst(c).is_some() && n == 0 {
        OK
    } else {
        ERROR
    }
}

/// fmi2DoStep: nothing happens but the clock.
pub extern "C" fn do_step(c: Comp, _t: c_double, h: c_double, _no_set_prior: c_int) -> c_int {
    match inst(c) {
        Some(e) => {
            e.time += h;
            OK
        }
        None => ERROR,
    }
}

// ---- not supported by the empty FMU: fmi2Error --------------------------------------------

pub extern "C" fn get_fmu_state(_c: Comp, _s: *mut *mut c_void) -> c_int {
    ERROR
}
pub extern "C" fn set_fmu_state(_c: Comp, _s: *mut c_void) -> c_int {
    ERROR
}
pub extern "C" fn free_fmu_state(_c: Comp, _s: *mut *mut c_void) -> c_int {
    ERROR
}
pub extern "C" fn serialized_fmu_state_size(_c: Comp, _s: *mut c_void, _n: *mut usize) -> c_int {
    ERROR
}
pub extern "C" fn serialize_fmu_state(
    _c: Comp,
    _s: *mut c_void,
    _b: *mut c_char,
    _n: usize,
) -> c_int {
    ERROR
}
pub extern "C" fn de_serialize_fmu_state(
    _c: Comp,
    _b: *const c_char,
    _n: usize,
    _s: *mut *mut c_void,
) -> c_int {
    ERROR
}
pub extern "C" fn get_directional_derivative(
    _c: Comp,
    _u: *const c_uint,
    _nu: usize,
    _k: *const c_uint,
    _nk: usize,
    _dk: *const c_double,
    _du: *mut c_double,
) -> c_int {
    ERROR
}
pub extern "C" fn set_real_input_derivatives(
    _c: Comp,
    _vr: *const c_uint,
    _n: usize,
    _o: *const c_int,
    _v: *const c_double,
) -> c_int {
    ERROR
}
pub extern "C" fn get_real_output_derivatives(
    _c: Comp,
    _vr: *const c_uint,
    _n: usize,
    _o: *const c_int,
    _v: *mut c_double,
) -> c_int {
    ERROR
}
pub extern "C" fn cancel_step(_c: Comp) -> c_int {
    ERROR
}
pub extern "C" fn get_status(_c: Comp, _k: c_int, _v: *mut c_int) -> c_int {
    ERROR
}
pub extern "C" fn get_real_status(_c: Comp, _k: c_int, _v: *mut c_double) -> c_int {
    ERROR
}
pub extern "C" fn get_integer_status(_c: Comp, _k: c_int, _v: *mut c_int) -> c_int {
    ERROR
}
pub extern "C" fn get_boolean_status(_c: Comp, _k: c_int, _v: *mut c_int) -> c_int {
    ERROR
}
pub extern "C" fn get_string_status(_c: Comp, _k: c_int, _v: *mut *const c_char) -> c_int {
    ERROR
}
