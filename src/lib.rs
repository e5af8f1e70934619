//! Abaqus-style connector elements as FMI 2.0 Co-Simulation FMUs.
#![deny(unsafe_code)]

pub mod error;
#[allow(unsafe_code)]
pub mod fmi2;
pub mod instance;
pub mod model_description;
pub mod physics;
pub mod state_bytes;
pub mod variables;
