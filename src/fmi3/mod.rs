//! The FMI 3.0 Co-Simulation C boundary, next to the FMI 2.0 one and over the same instance:
//! with `fmi2`, the only modules where `unsafe`, `no_mangle` and `extern "C"` appear. It reuses
//! the FMI 2.0 boundary's pointer helpers (slices, C strings, FMU state handles); `boundary`
//! adds the panic wrapper, the `fmi3Status` mapping and the FMI 3.0 argument checks; `policy`
//! holds the FMI 3.0 rules that need no pointer (refusals of what this FMU does not have);
//! every other decision is `crate::instance::ModelInstance`'s.

#[macro_use]
pub(crate) mod boundary;
pub mod exports;
mod logger;
mod policy;
pub mod types;

#[cfg(test)]
mod boundary_tests;
