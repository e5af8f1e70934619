//! The model below the FMI instance: the variable tables (one row per variable), what each
//! value reference reads and writes, the instance's data (`Snapshot`) and its serialized
//! form. Depends on physics only; the instance layer builds on it.

pub mod access;
pub mod cache;
pub mod slots;
pub mod snapshot;
pub mod state_bytes;
pub mod variables;
