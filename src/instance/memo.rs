//! The value-reference list of the last fast-path get or set, or of the last directional
//! derivative's unknowns, resolved: an importer repeats the same list every step (the node
//! inputs in, the node loads out; the same unknowns along every input), and a list equal to
//! the last one needs no look-up per VR (one comparison of the lists instead).

/// A VR list and the slot each VR resolved to (`RealTables::input_index`, `load_index` or
/// `continuous_index`).
#[derive(Default)]
pub(super) struct VrMemo {
    vrs: Vec<u32>,
    slots: Vec<u8>,
}

impl VrMemo {
    /// The slots of `vrs` when it is the remembered list.
    #[inline]
    pub(super) fn slots_of(&self, vrs: &[u32]) -> Option<&[u8]> {
        (self.vrs == vrs).then_some(&self.slots)
    }

    /// The slots of the remembered list.
    #[inline]
    pub(super) fn slots(&self) -> &[u8] {
        &self.slots
    }

    /// Remembers `vrs`, which resolved to `slots` (no allocation once the buffers have grown
    /// to the list's length).
    pub(super) fn remember(&mut self, vrs: &[u32], slots: impl Iterator<Item = u8>) {
        self.vrs.clear();
        self.vrs.extend_from_slice(vrs);
        self.slots.clear();
        self.slots.extend(slots);
    }
}
