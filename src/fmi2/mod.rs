//! The FMI 2.0 Co-Simulation C boundary: the only module where `unsafe`, `no_mangle` and
//! `extern "C"` appear. `boundary` converts C pointers and enums, catches panics and puts the
//! FMI function's name before every message; `policy` holds the FMI rules that need no
//! pointer; every other decision is `crate::instance::ModelInstance`'s.

#[macro_use]
pub(crate) mod boundary;
pub mod exports;
pub(crate) mod logger;
pub(crate) mod policy;
pub mod types;

#[cfg(test)]
mod boundary_tests;
