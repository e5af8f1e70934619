//! The outputs at the current inputs and committed state, double-buffered.
//!
//! Uses the physics' outputs only; the instance uses it.

use crate::physics::connector::Outputs;

/// The outputs at the current inputs and committed state, in one of two buffers: a step (or
/// a read) evaluates into the spare one, which becomes the cache only when that succeeds. So
/// outputs are never copied, and a failed evaluation leaves the cache as it was.
pub(super) struct OutputCache {
    buf: [Outputs; 2],
    /// The buffer holding the cache.
    cur: usize,
    /// Whether `buf[cur]` holds the outputs (else they are to be computed).
    valid: bool,
}

impl OutputCache {
    pub(super) fn new() -> OutputCache {
        OutputCache {
            buf: [Outputs::default(); 2],
            cur: 0,
            valid: false,
        }
    }

    /// The cached outputs, None when they are to be computed.
    #[inline]
    pub(super) fn get(&self) -> Option<&Outputs> {
        self.valid.then_some(&self.buf[self.cur])
    }

    /// Forgets the outputs (inputs, parameters or state changed).
    #[inline]
    pub(super) fn clear(&mut self) {
        self.valid = false;
    }

    /// The buffer that is not the cache, to evaluate into.
    #[inline]
    pub(super) fn spare(&mut self) -> &mut Outputs {
        &mut self.buf[1 - self.cur]
    }

    /// Makes the spare buffer, just filled, the cache.
    #[inline]
    pub(super) fn commit_spare(&mut self) {
        self.cur = 1 - self.cur;
        self.valid = true;
    }
}
