//! Regression 009 (found by the `fmi_calls` fuzz target on an FMI 3.0 program, a Bushing,
//! after regression 008's fix): the program ends with refused steps, and the harness's
//! invariant 6 restores the state and repeats the refused step. The first read after the
//! refusal returned the outputs cached by an earlier read, the second (after
//! fmi3SetFMUState, which forgets the cache) evaluated the connector afresh: `a.f[2]` differed
//! in its 13th digit. The cause: refusals before the kernel runs (a currentCommunicationPoint
//! that is not the FMU's time, a step size that is not finite and positive) did not pass
//! through the place where a refused step forgets the cache.
//!
//! The input the fuzzer found is replayed through the harness (`fuzz/harness/`), and is also
//! among the committed seeds.

#[path = "../fuzz/harness/mod.rs"]
mod harness;

#[test]
fn reads_after_every_refused_step_repeat_from_a_restored_state() {
    let name = "regression_009_read_after_refused_step";
    let path = format!("{}/fuzz/seeds/fmi_calls/{name}", env!("CARGO_MANIFEST_DIR"));
    let data = std::fs::read(&path).expect("seed");
    let r = std::panic::catch_unwind(|| harness::run(&data));
    assert!(r.is_ok(), "{name} violates an invariant");
}
