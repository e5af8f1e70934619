//! Exits 0 when a panic inside `catch_unwind` is caught (the unwind runs), 1 when not; with a
//! panic strategy of `abort` the process would end without reaching the check at all.
use std::panic::{catch_unwind, AssertUnwindSafe};

fn main() {
    let caught = catch_unwind(AssertUnwindSafe(|| {
        let v: Vec<u32> = std::hint::black_box(Vec::new());
        v[1] // index out of bounds: panics
    }));
    match caught {
        Err(payload) => {
            let what = payload
                .downcast_ref::<String>()
                .map(String::as_str)
                .unwrap_or("?");
            println!("panic caught: {what}");
        }
        Ok(v) => {
            println!("no panic ({v})");
            std::process::exit(1);
        }
    }
}
