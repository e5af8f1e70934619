//! The FMI 2.0 Co-Simulation C boundary: the only module where `unsafe`, `no_mangle` and
//! `extern "C"` appear. It converts C pointers and enums, catches panics, and leaves every
//! decision to `crate::instance::ModelInstance`.

#[macro_use]
mod boundary;
pub mod exports;
mod logger;
pub mod types;
