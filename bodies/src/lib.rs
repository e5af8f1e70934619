//! The Body FMU: a rigid body as an FMI 2.0 and FMI 3.0 Co-Simulation FMU, to couple with the
//! connector FMUs in third-party masters (docs/body.md). Its per-step update equals the body
//! update of the project's own master's zero-order-hold method (scripts/cosim/master.py).
//!
//! Layers, each using only those below it: `fmi2` and `fmi3` (the C boundaries, the only
//! `unsafe` code) → `instance` (FMI state machine, get/set, stepping, FMU state bytes) →
//! `variables` (the one table of variables) and `physics` (pure Rust on plain data);
//! `model_description` writes the XML from the table; `error` is shared by all. This crate
//! does not depend on `connector_fmu`: both export the fmi2*/fmi3* symbols.

#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod error;
#[allow(unsafe_code)]
pub mod fmi2;
#[allow(unsafe_code)]
pub mod fmi3;
pub mod instance;
pub mod model_description;
pub mod physics;
pub mod variables;
