//! What the connector FMU (`connector_fmu`, the repository's root crate) and the Body FMU
//! (`body_fmu`, bodies/) share, once: `fmi2` and `fmi3`, the hand-written C types of FMI 2.0 and
//! 3.0 (typedefs, status enums, callback types and structs), and `model_description`, the
//! serde + quick-xml structures that write both versions' `modelDescription.xml` from plain data
//! (a `Model` each crate builds from its own variable table). Uses std, serde and quick-xml;
//! both FMU crates use it (their `fmi2::types` / `fmi3::types` re-export the C types and map
//! their own status levels; their `model_description` modules build the `Model`). No exported
//! symbols and no unsafe code (the `unsafe extern "C" fn` in the callback types is part of
//! their type, not an unsafe block), so both cdylibs can link it.
#![forbid(unsafe_code)]

pub mod fmi2;
pub mod fmi3;
pub mod model_description;
