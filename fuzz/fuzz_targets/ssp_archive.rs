//! libFuzzer target: the native master's archive reader (SSD, SSV, zip) on arbitrary bytes
//! (fuzz/archive_harness.rs). Run: `RUSTC_BOOTSTRAP=1 cargo fuzz run ssp_archive` from fuzz/'s
//! parent, seeded with fuzz/seeds/ssp_archive/.
#![no_main]

#[path = "../archive_harness.rs"]
mod archive_harness;

libfuzzer_sys::fuzz_target!(|data: &[u8]| archive_harness::run(data));
