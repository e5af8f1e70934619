//! Abaqus-style connector elements as FMI 2.0 Co-Simulation FMUs.
#![deny(unsafe_code)]

pub mod error;
pub mod instance;
pub mod physics;
pub mod variables;
