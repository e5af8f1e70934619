//! The FMI 3.0 Co-Simulation C boundary, next to the FMI 2.0 one and over the same instance:
//! with `crate::fmi2`, the only module where `unsafe`, `no_mangle` and `extern "C"` appear. It
//! reuses the FMI 2.0 boundary's panic wall and pointer helpers; `boundary` adds the
//! `fmi3Status` mapping and FMI 3.0's argument checks; `exports` holds the functions provided,
//! `refused` those of what this FMU does not have (all 75 of `fmi3Functions.h` together).

pub(crate) mod boundary;
pub mod exports;
mod logger;
pub mod refused;
pub mod types;
