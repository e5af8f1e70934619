//! The FMI call-sequence fuzz harness, shared by the libFuzzer target
//! (`fuzz/fuzz_targets/fmi_calls.rs`) and its deterministic replay in `cargo test`
//! (`tests/fuzz_smoke.rs`, included there with `#[path]`). Logger, callbacks, GUIDs, the plain
//! fmi2Instantiate and the checksum come from the tests' support module (`tests/common/mod.rs`,
//! included here with `#[path]`).
//! This file holds the program format, the numbered invariants, the entry point `run` and the
//! module list; the other files of `fuzz/harness/` use it only for `support` and `trace_wanted`.
//!
//! The input bytes are a program of FMI 2.0 calls or, when the first byte is 0xE0 or more, of
//! FMI 3.0 calls (that byte is the mode and is skipped; every committed FMI 2.0 seed starts
//! below it). One interpreter serves both versions: `Api` is the version's calls, `Program`
//! decodes and checks. A program is a header that instantiates one variant (or tries a bad
//! GUID/instantiationToken, type, name, eventModeUsed, callback), then a sequence of operations
//! on up to two instances, four FMU-state slots and two serialized-state buffers. Every exported
//! function is reachable, in FMI 3.0 also the ones this FMU refuses (Model Exchange, Scheduled
//! Execution, Event Mode, clocks, configuration, types it has no variables of); values come from
//! a pool of awkward floats (NaN, ±INF, ±1e308, 5e-324, −0.0, raw bits) and from plausible
//! physics (parameter sets, poses, velocities), so both the refusals and the kernel are exercised.
//!
//! Invariants checked after every call (a violation panics, which libFuzzer reports):
//! 1. no fmi2Fatal / fmi3Fatal (the boundary catches panics, but a caught panic is still a bug);
//! 2. a non-OK status is explained by exactly one non-OK log message of that status, whose text
//!    names the function; an OK status logs no non-OK message (FMI 3.0 instances made without a
//!    logger, which FMI 3.0 allows, are exempt);
//! 3. every Real/Float64 output (and directional or adjoint derivative) returned with OK is
//!    finite;
//! 4. a call that returns fmi2Error / fmi3Error leaves the instance's FMU state (parameters,
//!    inputs, input derivatives, time, connector state) byte-identical, apart from the mode;
//! 5. a state that Serialize wrote is accepted by DeSerialize and re-serializes to the same
//!    bytes; a state of another variant is refused by SetFMUstate and SerializeFMUstate alike;
//! 6. restoring an FMU state and repeating a step reproduces status and outputs (and in FMI 3.0
//!    earlyReturn and lastSuccessfulTime) bit for bit;
//! 7. instantiation with valid arguments succeeds, and a refusal is logged when a logger exists;
//! 8. after a DoStep(t, h) that returns OK: in FMI 3.0 eventHandlingNeeded and
//!    terminateSimulation are false; earlyReturn implies earlyReturnAllowed at instantiation and
//!    t < lastSuccessfulTime < t + h; without it lastSuccessfulTime = t + h (within the FMU's time
//!    tolerance 1e-9·max(|t|, 1)); the FMU's time (fmi3 `time`, fmi2LastSuccessfulTime) is then
//!    lastSuccessfulTime, and every step of a program starts at the FMU's time. Where the
//!    variant has the outputs `event.time` and `event.count` (looked up by name; checked only
//!    when present): t < event.time ≤ t + h (event.time = t + h when a denormal h does not
//!    move t), event.count ≥ 0, and after an early return event.time = lastSuccessfulTime and
//!    event.count ≥ 1;
//! 9. the FMI 3.0 functions of interfaces and features this FMU has not (Model Exchange,
//!    Scheduled Execution, Event Mode, clocks, configuration) answer fmi3Error (NULL for the
//!    instantiation functions).
//!
//! The files (each says at its top what it may use):
//! - `api.rs`: `St` (a status of either version), `StepOut` and the `Api` trait, the calls of
//!   one FMI version as the interpreter makes them;
//! - `bytes.rs`: `Bytes`, the program decoder and its value generators (awkward floats, step
//!   sizes, quaternions, plausible parameter values);
//! - `program.rs`: `Program`, the state of one program (instances, state slots, buffers, trace),
//!   `call`, value-reference choice, the instantiation header's fields, `run` and its clean-up;
//! - `invariants.rs`: the checks after each call (invariants 1, 2, 4), after an instantiation
//!   (7) and of the outputs read (3);
//! - `steps.rs`: DoStep from the FMU's time and the checks after an OK step (8);
//! - `states.rs`: serialization round trips (5), de-serialization of mutated bytes and the
//!   restore-and-repeat check (6);
//! - `ops.rs`: the operation decoder shared by both versions (codes 0–31 but the few each
//!   version defines itself) and the value sets it writes (parameters, motion);
//! - `fmi2.rs`: `Fmi2`, the FMI 2.0 calls, header and operations of FMI 2.0 only;
//! - `fmi3.rs`: `Fmi3`, the FMI 3.0 calls, header and dispatch of the FMI 3.0 only operations;
//! - `fmi3_ops.rs`: the FMI 3.0 only operations (adjoint derivatives, absent types, refused
//!   interfaces and features, variable dependencies, other instantiation functions).
#![allow(dead_code, clippy::too_many_lines)]

// The logger, callback struct and value lookups of the tests (one support module for the tests,
// this harness and the benchmark). Each program logs under a componentEnvironment key of its own.
#[path = "../../tests/common/mod.rs"]
mod support;

mod api;
mod bytes;
mod fmi2;
mod fmi3;
mod fmi3_ops;
mod invariants;
mod ops;
mod program;
mod states;
mod steps;

use fmi2::Fmi2;
use fmi3::Fmi3;
use program::Program;

/// First bytes from this value on select an FMI 3.0 program.
pub const FMI3_MODE: u8 = 0xE0;

/// Runs one program (FMI 3.0 when the first byte is FMI3_MODE or more); returns how many of
/// its steps returned early at an event. Panics when an invariant is violated.
pub fn run(data: &[u8]) -> usize {
    match data.first() {
        Some(&m) if m >= FMI3_MODE => Program::<Fmi3>::new(&data[1..]).run(),
        _ => Program::<Fmi2>::new(data).run(),
    }
}

/// `FMI_FUZZ_TRACE=1` prints each program's operations (to read what an input does).
fn trace_wanted() -> bool {
    static WANTED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *WANTED.get_or_init(|| std::env::var_os("FMI_FUZZ_TRACE").is_some())
}
