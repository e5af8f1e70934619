//! The checks made after each call: the status and its log message (invariants 1 and 2), an
//! unchanged FMU state after an Error (4, through `state_bytes`), the outcome of an
//! instantiation (7), and finite outputs when they are read with OK (3). Uses `api`, `program`
//! and the messages recorded by `support`.

use super::api::{Api, Handle, St, OK};
use super::program::{reals_of, Inst, Program};
use super::support::{self, LogLine};
use connector_fmu::variables::{table, Causality, Start, Variant};
use std::ffi::c_int;
use std::ptr::null_mut;

/// Index of the mode byte in serialized bytes (after magic, version, id length and id).
fn mode_index(v: Variant) -> usize {
    4 + 2 + 1 + table(v).spec.model_identifier.len()
}

/// The instance's state as bytes with the mode byte and the checksum blanked (None when the
/// state cannot be taken, e.g. after a Fatal).
pub(super) fn state_bytes<A: Api>(inst: &Inst) -> Option<Vec<u8>> {
    let mut s: Handle = null_mut();
    if A::get_state(inst.c, &mut s) != OK {
        return None;
    }
    let mut n: usize = 0;
    let mut out = None;
    if A::state_size(inst.c, s, &mut n) == OK {
        let mut buf = vec![0u8; n];
        if A::serialize(inst.c, s, buf.as_mut_ptr(), n) == OK {
            let m = mode_index(inst.variant);
            buf[m] = 0;
            let len = buf.len();
            buf[len - 8..].fill(0);
            out = Some(buf);
        }
    }
    A::free_state(inst.c, &mut s);
    out
}

impl<A: Api> Program<'_, A> {
    /// Checks invariants 1, 2 (and 4 through `before`) for one call on instance `i`.
    pub(super) fn check(
        &mut self,
        i: usize,
        fname: &str,
        n0: usize,
        s: St,
        before: Option<Vec<u8>>,
    ) {
        let lines = support::log_since(self.env.0, n0);
        let bad: Vec<&LogLine> = lines.iter().filter(|l| l.status != 0).collect();
        if s == St::Fatal {
            self.fail(format!("{fname} returned Fatal: {lines:?}"));
        }
        let logger = self.inst[i].as_ref().is_some_and(|x| x.logger);
        if s == OK {
            if !bad.is_empty() {
                self.fail(format!("{fname} returned OK but logged {bad:?}"));
            }
        } else if logger {
            if bad.len() != 1 {
                self.fail(format!(
                    "{fname} returned {s:?} with {} non-OK messages (want exactly 1): {lines:?}",
                    bad.len()
                ));
            }
            let l = bad[0];
            if l.status != s as c_int {
                self.fail(format!(
                    "{fname} returned {s:?} but logged status {}: {l:?}",
                    l.status
                ));
            }
            let want_cat = if s == St::Warning {
                "logStatusWarning"
            } else {
                "logStatusError"
            };
            if l.category != want_cat || !l.message.contains(fname) {
                self.fail(format!(
                    "{fname}: message does not name the function or has the wrong category: {l:?}"
                ));
            }
        } else if !bad.is_empty() {
            self.fail(format!(
                "{fname}: an instance without logger logged {bad:?}"
            ));
        }
        if s == St::Error {
            if let (Some(b0), Some(inst)) = (before, self.inst[i].as_ref()) {
                if let Some(b1) = state_bytes::<A>(inst) {
                    if b0 != b1 {
                        let at = b0.iter().zip(&b1).position(|(x, y)| x != y);
                        self.fail(format!(
                            "{fname} returned Error but changed the FMU state (first differing byte {at:?}, lengths {} {})",
                            b0.len(),
                            b1.len()
                        ));
                    }
                }
            }
        }
    }

    /// Records an instantiation outcome (invariant 7): `c` NULL or not, `valid` arguments,
    /// log lines since `n0` when a logger was given.
    pub(super) fn instantiated(
        &mut self,
        i: usize,
        fname: &str,
        c: Handle,
        valid: bool,
        n0: usize,
        inst: Inst,
    ) {
        if c.is_null() {
            let lines = support::log_since(self.env.0, n0);
            if valid {
                self.fail(format!("{fname} refused valid arguments: {lines:?}"));
            }
            if inst.logger
                && (lines.len() != 1
                    || lines[0].status != St::Error as c_int
                    || !lines[0].message.contains(fname))
            {
                self.fail(format!(
                    "{fname} refusal must log one error naming the function: {lines:?}"
                ));
            }
        } else {
            if !valid {
                self.fail(format!("{fname} accepted invalid arguments"));
            }
            self.inst[i] = Some(Inst { c, ..inst });
        }
    }

    /// Reads every Real output (invariant 3) and Integer output; returns the Real bits and status.
    pub(super) fn read_outputs(&mut self, i: usize) -> Option<(St, Vec<u64>, Vec<i32>)> {
        let v = self.variant(i)?;
        let vrs = reals_of(v, |x| x.causality == Causality::Output);
        let mut out = vec![f64::NAN; vrs.len()];
        let s = self.call(i, A::GET_REAL, |c| {
            A::get_real(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr())
        });
        if s == OK {
            if let Some(k) = out.iter().position(|x| !x.is_finite()) {
                let name = &table(v).get(vrs[k]).expect("known").name;
                self.fail(format!(
                    "{} returned OK with {name} = {}",
                    A::GET_REAL,
                    out[k]
                ));
            }
        }
        let ivrs: Vec<u32> = table(v)
            .vars
            .iter()
            .filter(|x| x.causality == Causality::Output && matches!(x.start, Start::Integer(_)))
            .map(|x| x.vr)
            .collect();
        let mut iout = vec![i32::MIN; ivrs.len()];
        let si = self.call(i, A::GET_INT, |c| {
            A::get_int(c, ivrs.as_ptr(), ivrs.len(), iout.as_mut_ptr())
        });
        if si != s {
            self.fail(format!(
                "{} {s:?} but {} {si:?} on outputs",
                A::GET_REAL,
                A::GET_INT
            ));
        }
        Some((s, out.iter().map(|x| x.to_bits()).collect(), iout))
    }
}
