//! FMU states through their bytes: Serialize with buffers of every size and the round trip
//! Serialize → DeSerialize → Serialize (invariant 5), DeSerialize of stored or random bytes,
//! mutated and perhaps re-checksummed, and restore-and-repeat of a step (invariant 6). Uses
//! `api`, `program`, `steps` and the checksum of `support`.

use super::api::{Api, Handle, OK};
use super::program::{reals_of, Program, MAX_STEPS};
use super::support::{self, LogLine};
use connector_fmu::variables::Causality;
use std::ptr::{null, null_mut};

/// Rewrites the checksum trailer of serialized state bytes (FNV-1a 64): lets mutated bytes
/// pass the checksum so that the field validation behind it is exercised.
fn fix_checksum(bytes: &mut [u8]) {
    if bytes.len() >= 8 {
        let n = bytes.len() - 8;
        let sum = support::fnv1a(&bytes[..n]);
        bytes[n..].copy_from_slice(&sum.to_le_bytes());
    }
}

impl<A: Api> Program<'_, A> {
    /// Serializes a slot through instance i; on success checks invariant 5 and stores the bytes.
    pub(super) fn serialize(&mut self, i: usize, k: usize) {
        let Some(v) = self.variant(i) else { return };
        let slot = self.slots[k];
        let mut n: usize = 0;
        let s = self.call(i, A::STATE_SIZE, |c| A::state_size(c, slot.s, &mut n));
        if s == OK && !slot.s.is_null() && slot.variant != v {
            self.fail(format!(
                "{} accepted a state of {:?} in a {v:?} instance",
                A::STATE_SIZE,
                slot.variant
            ));
        }
        if s != OK {
            n = 0;
        }
        // sometimes a buffer that is too small, or larger than needed
        let size = match self.b.u8() % 8 {
            0 => n.saturating_sub(1),
            1 => n + 16,
            2 => 0,
            _ => n,
        };
        let mut buf = vec![0u8; size.max(1)];
        let p = if size == 0 && self.b.u8().is_multiple_of(2) {
            null_mut()
        } else {
            buf.as_mut_ptr()
        };
        let s2 = self.call(i, A::SERIALIZE, |c| A::serialize(c, slot.s, p, size));
        if s2 == OK && !slot.s.is_null() && slot.variant != v {
            self.fail(format!(
                "{} accepted a state of {:?} in a {v:?} instance",
                A::SERIALIZE,
                slot.variant
            ));
        }
        if s2 == OK && s == OK && size >= n && n > 0 {
            buf.truncate(n);
            // invariant 5: the bytes are accepted and re-serialize identically
            let mut back: Handle = null_mut();
            let n_log = support::log_len(self.env.0);
            let s3 = self.call(i, A::DESERIALIZE, |c| {
                A::deserialize(c, buf.as_ptr(), n, &mut back)
            });
            if s3 != OK {
                let why: Vec<LogLine> = support::log_since(self.env.0, n_log)
                    .into_iter()
                    .filter(|l| l.status != 0)
                    .collect();
                self.fail(format!(
                    "{} refused bytes {} wrote: {s3:?} {why:?}",
                    A::DESERIALIZE,
                    A::SERIALIZE
                ));
            }
            let mut n2: usize = 0;
            let mut again = vec![0u8; n];
            let s4 = self.call(i, A::STATE_SIZE, |c| A::state_size(c, back, &mut n2));
            let s5 = self.call(i, A::SERIALIZE, |c| {
                A::serialize(c, back, again.as_mut_ptr(), n)
            });
            if s4 != OK || s5 != OK || n2 != n || again != buf {
                self.fail("serialize → deserialize → serialize is not the identity".into());
            }
            self.call(i, A::FREE_STATE, |c| A::free_state(c, &mut back));
            if self.bufs.len() >= 2 {
                self.bufs.remove(0);
            }
            self.bufs.push((buf, v));
        }
    }

    /// De-serializes (mutated) bytes into a slot.
    pub(super) fn deserialize(&mut self, i: usize, k: usize) {
        let Some(v) = self.variant(i) else { return };
        let (mut bytes, from) = match (self.b.u8() % 4, self.bufs.is_empty()) {
            (0, _) | (_, true) => {
                let n = self.b.u8() as usize * 4;
                ((0..n).map(|_| self.b.u8()).collect::<Vec<u8>>(), None)
            }
            _ => {
                let j = self.b.u8() as usize % self.bufs.len();
                let (b, src) = self.bufs[j].clone();
                (b, Some(src))
            }
        };
        let mut mutated = false;
        let nmut = self.b.u8() % 4;
        for _ in 0..nmut {
            if bytes.is_empty() {
                break;
            }
            mutated = true;
            match self.b.u8() % 5 {
                0 => {
                    let at = self.b.u16() as usize % bytes.len();
                    bytes[at] ^= self.b.u8().max(1);
                }
                1 => {
                    let at = self.b.u16() as usize % bytes.len();
                    bytes.truncate(at);
                }
                2 => {
                    let n = self.b.u8() % 16;
                    for _ in 0..n {
                        bytes.push(self.b.u8());
                    }
                }
                _ => {
                    // an awkward f64 over 8 bytes at an arbitrary offset
                    let x = self.b.real().to_le_bytes();
                    let at = self.b.u16() as usize % bytes.len();
                    for (j, b) in x.iter().enumerate() {
                        if let Some(slot) = bytes.get_mut(at + j) {
                            *slot = *b;
                        }
                    }
                }
            }
        }
        if !self.b.u8().is_multiple_of(4) {
            fix_checksum(&mut bytes);
        }
        let size = if self.b.u8().is_multiple_of(16) {
            bytes.len() + 1 + self.b.u8() as usize // announced longer than given: only for NULL
        } else {
            bytes.len()
        };
        let p: *const u8 = if size != bytes.len() {
            null()
        } else {
            bytes.as_ptr()
        };
        self.trace.push(format!(
            "deserialize[{i}] -> slot {k} (len {size}, from {from:?}, mutated {mutated})"
        ));
        let mut slot = self.slots[k];
        let s = self.call(i, A::DESERIALIZE, |c| {
            A::deserialize(c, p, size, &mut slot.s)
        });
        if s == OK {
            slot.variant = v;
            if !mutated && from.is_some_and(|f| f != v) {
                self.fail(format!(
                    "{} accepted a {from:?} state in {v:?}",
                    A::DESERIALIZE
                ));
            }
        }
        self.slots[k] = slot;
    }

    /// Invariant 6: restore a state, repeat a step, compare.
    pub(super) fn replay(&mut self, i: usize) {
        let Some(_) = self.variant(i) else { return };
        if self.steps + 2 > MAX_STEPS {
            return;
        }
        self.steps += 2;
        let mut s: Handle = null_mut();
        if self.call(i, A::GET_STATE, |c| A::get_state(c, &mut s)) != OK {
            return;
        }
        let h = self.b.step();
        let t = self.fmu_time(i);
        self.trace.push(format!("replay[{i}] t={t:e} h={h:e}"));
        let (s1, o1) = self.step_checked(i, t, h);
        let y1 = self.read_outputs(i);
        let r = self.call(i, A::SET_STATE, |c| A::set_state(c, s));
        if r != OK {
            self.fail(format!(
                "{} of its own fresh state failed: {r:?}",
                A::SET_STATE
            ));
        }
        let (s2, o2) = self.step_checked(i, t, h);
        let y2 = self.read_outputs(i);
        if s1 != s2 || y1 != y2 || o1 != o2 {
            // where the outputs differ: the read statuses, or the first differing value
            let diff = match (&y1, &y2) {
                (Some((r1, x1, n1)), Some((r2, x2, n2))) if r1 == r2 => {
                    let vrs = reals_of(self.variant(i).expect("live"), |x| {
                        x.causality == Causality::Output
                    });
                    match x1.iter().zip(x2).position(|(a, b)| a != b) {
                        Some(k) => format!(
                            "vr {}: {} vs {}",
                            vrs[k],
                            f64::from_bits(x1[k]),
                            f64::from_bits(x2[k])
                        ),
                        None => format!("integers {n1:?} vs {n2:?}"),
                    }
                }
                (a, b) => format!(
                    "reads {:?} vs {:?}",
                    a.as_ref().map(|x| x.0),
                    b.as_ref().map(|x| x.0)
                ),
            };
            self.fail(format!(
                "repeating a step after {} differs: {s1:?} vs {s2:?}, {o1:?} vs {o2:?}, outputs: {diff}",
                A::SET_STATE
            ));
        }
        self.call(i, A::FREE_STATE, |c| A::free_state(c, &mut s));
    }
}
