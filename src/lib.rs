//! Abaqus-style connector elements as FMI 2.0 and FMI 3.0 Co-Simulation FMUs.
//!
//! Layers, each depending only on those below it: `fmi2` and `fmi3` (the C boundaries, the only
//! `unsafe` code) → `instance` (FMI state machine, get/set, stepping, derivatives) → `model` (variable
//! tables, value access, the instance's data and its serialized form) → `physics` (pure
//! Rust on plain data: kinematics, constitutive behaviour, friction, stepping).

#![deny(unsafe_code)]

pub mod error;
#[allow(unsafe_code)]
pub mod fmi2;
#[allow(unsafe_code)]
pub mod fmi3;
pub mod instance;
pub mod model;
pub mod model_description;
pub mod physics;

/// The variable tables, at the path tests and tools use.
pub use model::variables;
