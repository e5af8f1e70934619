//! The FMI 2.0 Co-Simulation C boundary: with `crate::fmi3`, the only module where `unsafe`,
//! `no_mangle` and `extern "C"` appear. `boundary` converts pointers, catches panics and leads
//! every message with the FMI function's name (the FMI 3.0 boundary reuses it); `exports` holds
//! the 34 functions; every decision is `crate::instance::Instance`'s.

#[macro_use]
pub(crate) mod boundary;
pub mod exports;
pub(crate) mod logger;
pub mod types;
