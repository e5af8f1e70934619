//! Tests of the FMI 2.0 boundary through the exported functions: a panic caught by the
//! wrapper is fmi2Fatal, logged, and leaves the instance refusing everything but
//! fmi2FreeInstance; without an instance the wrapper returns the type's default. A file of
//! its own because it uses both `boundary` and `exports` (which uses `boundary`).

use super::boundary::instance_mut;
use super::exports::{fmi2DoStep, fmi2FreeInstance, fmi2GetReal, fmi2Reset, fmi2SetDebugLogging};
use super::types::{fmi2Component, fmi2Status};
use crate::error::{Category, Level};
use crate::instance::Mode;
use crate::instance::{LogSink, ModelInstance};
use crate::model::variables::Variant;
use libc::c_char;
use std::sync::{Arc, Mutex};

/// Records messages for inspection.
struct Sink(Arc<Mutex<Vec<(Level, String)>>>);

impl LogSink for Sink {
    fn log(&self, level: Level, _category: Category, message: &str) {
        self.0.lock().unwrap().push((level, message.to_string()));
    }
}

#[test]
fn a_caught_panic_is_fatal_logged_and_leaves_only_free() {
    let log = Arc::new(Mutex::new(Vec::new()));
    let inst = ModelInstance::new(Variant::Bushing, "p", Box::new(Sink(log.clone())), false);
    let c: fmi2Component = Box::into_raw(Box::new(inst)).cast();

    let s: fmi2Status = ffi_boundary!(c, "fmi2DoStep", {
        panic!("boom at {}", 42);
    });
    assert_eq!(s, fmi2Status::Fatal);
    // SAFETY: c is the live instance made above; no other reference exists.
    assert_eq!(unsafe { instance_mut(c) }.unwrap().mode(), Mode::Fatal);
    let (level, message) = log.lock().unwrap()[0].clone();
    assert_eq!(level, Level::Fatal);
    assert!(
        message.contains("fmi2DoStep") && message.contains("boom at 42"),
        "{message}"
    );

    // everything but fmi2FreeInstance is refused now
    let mut x = 0.0;
    assert_eq!(fmi2DoStep(c, 0.0, 1e-3, 0), fmi2Status::Error);
    assert_eq!(fmi2Reset(c), fmi2Status::Error);
    assert_eq!(
        fmi2SetDebugLogging(c, 1, 0, std::ptr::null()),
        fmi2Status::Error
    );
    assert_eq!(
        fmi2GetReal(c, std::ptr::null(), 0, &mut x),
        fmi2Status::Error
    );
    assert_eq!(log.lock().unwrap().len(), 5, "each refusal is logged");
    fmi2FreeInstance(c);
}

#[test]
fn a_panic_without_instance_returns_the_type_default() {
    let p: fmi2Component = ffi_boundary!("fmi2Instantiate", {
        panic!("boom");
    });
    assert!(p.is_null());
    let s: *const c_char = ffi_boundary!("fmi2GetVersion", {
        panic!("boom");
    });
    assert!(s.is_null());
    let s: fmi2Status = ffi_boundary!(std::ptr::null_mut(), "fmi2Terminate", {
        panic!("boom");
    });
    assert_eq!(s, fmi2Status::Fatal);
}
