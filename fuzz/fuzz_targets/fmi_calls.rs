//! libFuzzer target: the input bytes are a program of FMI 2.0 calls, or of FMI 3.0 calls when
//! the first byte is 0xE0 or more, on the exported C functions of every variant (see
//! `fuzz/harness/mod.rs` for the format and the invariants).
//!
//!     RUSTC_BOOTSTRAP=1 cargo fuzz run fmi_calls -- -max_total_time=60
//!
//! or `scripts/fuzz` for the long run.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../harness/mod.rs"]
mod harness;

fuzz_target!(|data: &[u8]| {
    harness::run(data);
});
