//! The outputs at the current inputs and committed state, double-buffered; those a step ended
//! with are part of the FMU state (`Snapshot::outputs`).
//!
//! Why a step's outputs are state, not a memo: they are evaluated on the path's end nodes inside
//! the step's last substep, and a read evaluates the connector afresh at the inputs written back
//! from them, with the committed state. The two agree to round-off only (an end orientation
//! normalised once more when read back; a friction force that a slip step leaves on its limit,
//! re-evaluated there). Were they a memo, what is read would depend on whether the cache still
//! held them: a restore (which had to forget them) or a refused call would read other bits than
//! the run that saved the state (regressions 008 and 009). As part of the state they are saved,
//! restored and serialized with everything else, so what is read is a function of the FMU state
//! and the inputs alone, and a restored state reports what was read at saving. A refused call
//! leaves them as they were, like the rest of the state.
//!
//! Outputs a read computed are a pure memo: the same evaluation at the same inputs and state
//! gives the same bits, so they are neither serialized nor compared, and a read never changes
//! the FMU state.
//!
//! Uses the physics' outputs only; the snapshot holds it, the instance fills and reads it.

use crate::physics::connector::Outputs;
use std::fmt;

/// The outputs at the current inputs and committed state, in one of two buffers: a step (or
/// a read) evaluates into the spare one, which becomes the cache only when that succeeds. So
/// outputs are never copied, and a failed evaluation leaves the cache as it was.
#[derive(Clone)]
pub struct OutputCache {
    buf: [Outputs; 2],
    /// The buffer holding the cache.
    cur: usize,
    /// Whether `buf[cur]` holds the outputs (else they are to be computed).
    valid: bool,
    /// Whether they are those a step ended with (state), not a read's (a memo).
    stepped: bool,
}

impl Default for OutputCache {
    fn default() -> Self {
        OutputCache::new()
    }
}

impl OutputCache {
    /// An empty cache: the outputs are to be computed.
    pub fn new() -> OutputCache {
        OutputCache {
            buf: [Outputs::default(); 2],
            cur: 0,
            valid: false,
            stepped: false,
        }
    }

    /// A cache holding `o`, the outputs a step ended with.
    pub fn stepped_to(o: Outputs) -> OutputCache {
        OutputCache {
            buf: [o, Outputs::default()],
            cur: 0,
            valid: true,
            stepped: true,
        }
    }

    /// The cached outputs, None when they are to be computed.
    #[inline]
    pub fn get(&self) -> Option<&Outputs> {
        self.valid.then_some(&self.buf[self.cur])
    }

    /// The outputs a step ended with, where the cache holds them (the part that is state).
    #[inline]
    pub fn stepped(&self) -> Option<&Outputs> {
        (self.valid && self.stepped).then_some(&self.buf[self.cur])
    }

    /// Forgets the outputs (inputs, parameters or state changed).
    #[inline]
    pub fn clear(&mut self) {
        self.valid = false;
    }

    /// The buffer that is not the cache, to evaluate into.
    #[inline]
    pub fn spare(&mut self) -> &mut Outputs {
        &mut self.buf[1 - self.cur]
    }

    /// Makes the spare buffer, just filled by a step, the cache.
    #[inline]
    pub fn commit_step(&mut self) {
        self.cur = 1 - self.cur;
        (self.valid, self.stepped) = (true, true);
    }

    /// Makes the spare buffer, just filled by a read, the cache.
    #[inline]
    pub fn commit_read(&mut self) {
        self.cur = 1 - self.cur;
        (self.valid, self.stepped) = (true, false);
    }
}

impl PartialEq for OutputCache {
    /// The same outputs of a step, or none: a read's outputs are a memo and the spare buffer is
    /// scratch, neither is state.
    fn eq(&self, other: &Self) -> bool {
        self.stepped() == other.stepped()
    }
}

impl fmt::Debug for OutputCache {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("OutputCache").field(&self.stepped()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::OutputCache;
    use crate::physics::connector::Outputs;

    #[test]
    fn only_a_steps_committed_buffer_is_state() {
        let mut a = OutputCache::new();
        let b = OutputCache::new();
        a.spare().ctf[0] = 1.0;
        assert_eq!(a, b, "an uncommitted spare buffer is scratch");
        a.commit_read();
        assert_eq!(a.get().map(|o| o.ctf[0]), Some(1.0));
        assert_eq!(a, b, "a read's outputs are a memo");
        assert_eq!(a.stepped(), None);
        a.spare().ctf[0] = 2.0;
        a.commit_step();
        assert_ne!(a, b);
        let mut want = Outputs::default();
        want.ctf[0] = 2.0;
        assert_eq!(a, OutputCache::stepped_to(want));
        assert_eq!(a.stepped().map(|o| o.ctf[0]), Some(2.0));
        a.clear();
        assert_eq!(a, b);
        assert_eq!(a.get(), None);
    }
}
