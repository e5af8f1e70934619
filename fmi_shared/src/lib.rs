//! What the connector FMU (`connector_fmu`, the repository's root crate) and the Body FMU
//! (`body_fmu`, bodies/) share: `fmi2` and `fmi3`, the hand-written C types of FMI 2.0 and 3.0
//! (typedefs, status enums, callback types and structs). Uses only std; both FMU crates use it
//! (their `fmi2::types` / `fmi3::types` re-export it and add the mapping of their own status
//! levels). No exported symbols and no unsafe code (the `unsafe extern "C" fn` in the callback
//! types is part of their type, not an unsafe block), so both cdylibs can link it.
#![forbid(unsafe_code)]

pub mod fmi2;
pub mod fmi3;
