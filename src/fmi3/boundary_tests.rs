//! Tests of the FMI 3.0 boundary through the exported functions: a panic caught by the
//! wrapper is fmi3Fatal, logged, and leaves the instance refusing everything but
//! fmi3FreeInstance; without an instance the wrapper returns the type's default. A file of
//! its own because it uses both `boundary` and `exports` (which uses `boundary`).

use super::exports::{fmi3DoStep, fmi3FreeInstance, fmi3GetFloat64, fmi3Reset};
use super::types::fmi3Instance;
use super::types::fmi3Status;
use crate::error::{Category, Level};
use crate::fmi2::boundary::instance_mut;
use crate::instance::Mode;
use crate::instance::{FmiVersion, LogSink, ModelInstance};
use crate::variables::Variant;
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
    let inst = ModelInstance::new(Variant::Bushing, "p", Box::new(Sink(log.clone())), false)
        .with_version(FmiVersion::V3);
    let c: fmi3Instance = Box::into_raw(Box::new(inst)).cast();

    let s: fmi3Status = ffi3!(c, "fmi3DoStep", {
        panic!("boom at {}", 42);
    });
    assert_eq!(s, fmi3Status::Fatal);
    // SAFETY: c is the live instance made above; no other reference exists.
    assert_eq!(unsafe { instance_mut(c) }.unwrap().mode(), Mode::Fatal);
    let (level, message) = log.lock().unwrap()[0].clone();
    assert_eq!(level, Level::Fatal);
    assert!(
        message.starts_with("fmi3DoStep: ") && message.contains("boom at 42"),
        "{message}"
    );

    // everything but fmi3FreeInstance is refused now
    let (mut b, mut t) = (0u8, 0.0);
    let s = fmi3DoStep(
        c,
        0.0,
        1e-3,
        0,
        &mut b,
        &mut b.clone(),
        &mut b.clone(),
        &mut t,
    );
    assert_eq!(s, fmi3Status::Error);
    assert_eq!(fmi3Reset(c), fmi3Status::Error);
    assert_eq!(
        fmi3GetFloat64(c, std::ptr::null(), 0, std::ptr::null_mut(), 0),
        fmi3Status::Error
    );
    assert_eq!(log.lock().unwrap().len(), 4, "each refusal is logged");
    fmi3FreeInstance(c);
}

#[test]
fn a_panic_without_instance_returns_the_type_default() {
    let p: fmi3Instance = ffi3!("fmi3InstantiateCoSimulation", {
        panic!("boom");
    });
    assert!(p.is_null());
    let s: fmi3Status = ffi3!(std::ptr::null_mut(), "fmi3Terminate", {
        panic!("boom");
    });
    assert_eq!(s, fmi3Status::Fatal);
}
