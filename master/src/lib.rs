//! A co-simulation master for any system of FMI 2.0 and 3.0 Co-Simulation FMUs: an SSP 1.0
//! archive or a lone FMU in, fixed-step Jacobi or Gauss-Seidel on a grid of integer ticks,
//! every output sampled into a CSV file or memory. The rooms (after libcosim):
//!
//! ```text
//! xml, model_description   reading XML; variables of either FMI version in one form
//! unzip, fmu               unpacking archives safely; importing an FMU (library, description)
//! ffi/                     the FMI C calls, the only unsafe code
//! slave                    one instance behind one interface, either version
//! ssp/                     an SSP archive -> a flat system description; nothing else reads it
//! structure                the checked system: components, start values, connections
//! order                    Gauss-Seidel's order; algebraic loops
//! exchange                 output slots and input sources, what moves between components
//! algorithm/               jacobi, gauss_seidel: one step of each method
//! time                     the grid of integer ticks
//! inputs                   an input file for a lone FMU
//! observer                 what is recorded: CSV file, memory
//! execution                the time loop
//! error                    the one error type, naming element, component, variable, function, time
//! ```
#![deny(missing_docs)]
// An `Error` carries its context (element, component, variable, function, time) by value: it is
// built once, on the way out of a failed run, never on the stepping path.
#![allow(clippy::result_large_err)]

pub mod algorithm;
pub mod cli;
pub mod error;
pub mod exchange;
pub mod execution;
pub mod ffi;
pub mod fmu;
pub mod inputs;
pub mod model_description;
pub mod observer;
pub mod order;
pub mod slave;
pub mod ssp;
pub mod structure;
pub mod time;
pub mod unzip;
pub mod xml;

pub use algorithm::Method;
pub use error::{Error, Result};
pub use execution::{run, Outcome, Settings};
pub use structure::System;
