//! The value-reference list of the last fast-path get or set, or of the last directional
//! derivative's unknowns, resolved: an importer repeats the same list every step (the node
//! inputs in, the node loads out; the same unknowns along every input), and a list equal to
//! the last one needs no look-up per VR (one comparison of the lists instead).
//!
//! A list is also kept as runs of consecutive slots: an importer lists a node's inputs (or
//! the loads) in the order of the model description, so the values move as a few slices
//! (`Run`) instead of one by one through the slot table.
//!
//! Also what a directional derivative's point fixes for every direction (`PointMemo`): the
//! frames of the orientation inputs and the centred triad, or REVOLUTE's rotations.
//!
//! Uses the physics' kinematics and math only; the instance's reads and derivatives use it.

use crate::physics::kinematics::{
    centred_with, frame_of_raw, revolute, Centred, Revolute, Singular, TriadSource, TriadTrig,
};
use crate::physics::math::{Dual, Mat3, Real};

/// Shortest mean run worth moving as slices: a slice copy of unknown length is a call to
/// memcpy, which costs more than a short run's values one by one (callgrind: the four runs of
/// 3–4 node inputs of PROJECTION FLEXION-TORSION, an orientation and an angular velocity per
/// node, cost 46 instructions more per round as slices).
const MIN_RUN: usize = 6;

/// Values `at..at + len` of a remembered list belong to the slots `slot..slot + len`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Run {
    pub slot: usize,
    pub at: usize,
    pub len: usize,
}

/// Copies every run from `from` into `to`: run r's values start at `from_at(r)` in `from` and
/// go to `to_at(r)` in `to` (a set writes the list's values into their slots, a get reads them
/// from their slots into the list's order).
#[inline]
pub(super) fn copy_runs(
    runs: &[Run],
    (to, to_at): (&mut [Real], fn(&Run) -> usize),
    (from, from_at): (&[Real], fn(&Run) -> usize),
) {
    for r in runs {
        let (t, f) = (to_at(r), from_at(r));
        if let (Some(to), Some(from)) = (to.get_mut(t..t + r.len), from.get(f..f + r.len)) {
            to.copy_from_slice(from);
        }
    }
}

/// A VR list and the slot each VR resolved to (`RealTables::input_index`, `load_index` or
/// `continuous_index`), also as runs.
#[derive(Default)]
pub(super) struct VrMemo {
    vrs: Vec<u32>,
    slots: Vec<u8>,
    runs: Vec<Run>,
}

impl VrMemo {
    /// Whether `vrs` is the remembered list.
    #[inline]
    pub(super) fn holds(&self, vrs: &[u32]) -> bool {
        self.vrs == vrs
    }

    /// The slots of the remembered list.
    #[inline]
    pub(super) fn slots(&self) -> &[u8] {
        &self.slots
    }

    /// The remembered list as runs of consecutive slots, in the list's order (a VR listed
    /// twice is written twice, the later value last, as one by one); None where the runs are
    /// short (under `MIN_RUN` values on average), which move faster one value at a time.
    #[inline]
    pub(super) fn runs(&self) -> Option<&[Run]> {
        (self.slots.len() >= MIN_RUN * self.runs.len()).then_some(&self.runs)
    }

    /// Remembers `vrs`, which resolved to `slots` (no allocation once the buffers have grown
    /// to the list's length).
    pub(super) fn remember(&mut self, vrs: &[u32], slots: impl Iterator<Item = u8>) {
        self.vrs.clear();
        self.vrs.extend_from_slice(vrs);
        self.slots.clear();
        self.slots.extend(slots);
        self.runs.clear();
        for (at, &s) in self.slots.iter().enumerate() {
            let slot = s as usize;
            match self.runs.last_mut() {
                Some(r) if r.slot + r.len == slot => r.len += 1,
                _ => self.runs.push(Run { slot, at, len: 1 }),
            }
        }
    }
}

/// What a directional derivative's point fixes, whatever the direction: the frames of its
/// orientation inputs (Real), and at a torsion branch the centred triad (computed in Real,
/// lifted to `Dual`: the triad of every direction that leaves both orientations alone) and
/// the values of its libm calls (which the triad of a direction along an orientation takes
/// instead of calling libm again); for PLANAR, REVOLUTE's rotations (Real: those of every
/// direction that leaves both orientations alone). A linear-implicit master reads the outputs
/// at a point and then asks for the derivatives along every input there, so these are computed
/// once for the read and all of them (`read`; REVOLUTE's rotations are left to the first
/// direction that needs them: keeping them at a read cost the read about a tenth more
/// instructions than they save). Keyed by the bits of the raw quaternion inputs and of the
/// branch: the same bits give the same frames, triad and rotations.
#[derive(Default)]
pub(super) struct PointMemo {
    /// The bits of the quaternion inputs (w, x, y, z of a, then of b) `frames` are of.
    quats: Option<[u64; 8]>,
    frames: [Mat3; 2],
    /// The bits of a torsion branch, and the triad there.
    triad: Option<(u64, Centred<Dual>)>,
    /// The bits of a torsion branch, and the values of the triad's libm calls there.
    trig: Option<(u64, TriadTrig)>,
    /// The triad a read at these inputs computed (`read`): the bits of its torsion branch,
    /// the triad (Real) and the values of its libm calls.
    read: Option<(u64, Centred, TriadTrig)>,
    /// The bits of a REVOLUTE branch α, and REVOLUTE's rotations there (Real).
    revolute: Option<(u64, Revolute)>,
}

/// The bits of the raw quaternion inputs (w, x, y, z of node a, then of node b).
pub(super) fn quat_bits(q: [[Real; 4]; 2]) -> [u64; 8] {
    let mut key = [0u64; 8];
    for (k, x) in key.iter_mut().zip(q.iter().flat_map(|q| q.iter())) {
        *k = x.to_bits();
    }
    key
}

impl PointMemo {
    /// The frames of the raw quaternion inputs `q` of nodes a and b (`kinematics::frame_of_raw`),
    /// from the memo where it holds the same inputs, else computed and remembered (which
    /// forgets the triad of other inputs).
    pub(super) fn frames(&mut self, q: [[Real; 4]; 2]) -> &[Mat3; 2] {
        let key = quat_bits(q);
        if self.quats != Some(key) {
            self.at(key, &[frame_of_raw(&q[0]), frame_of_raw(&q[1])]);
        }
        &self.frames
    }

    /// The memo of the point whose quaternion inputs have the bits `quats` and whose frames
    /// are `frames`: everything of another point forgotten.
    fn at(&mut self, quats: [u64; 8], frames: &[Mat3; 2]) {
        (self.quats, self.frames) = (Some(quats), *frames);
        (self.triad, self.trig, self.read, self.revolute) = (None, None, None, None);
    }

    /// The centred triad (Real) of a read at inputs whose quaternions have the bits `quats`,
    /// of frames `frames` (`Pose::of`'s, the same bits as `frame_of_raw`'s) and torsion branch
    /// `beta`: the one the memo holds, else computed (recording its libm values) and kept for
    /// the directions at that point (`triad`, `trig`). None only where it could not be kept.
    pub(super) fn read(
        &mut self,
        quats: [u64; 8],
        frames: &[Mat3; 2],
        beta: Real,
    ) -> Result<Option<&Centred>, Singular> {
        if self.quats != Some(quats) {
            self.at(quats, frames);
        }
        let key = beta.to_bits();
        if self.read.as_ref().is_none_or(|(k, ..)| *k != key) {
            let mut trig = TriadTrig::default();
            let cen = centred_with(&self.frames[0], &self.frames[1], beta, &mut trig)?;
            self.read = Some((key, cen, trig));
        }
        Ok(self.read.as_ref().map(|(_, cen, _)| cen))
    }

    /// The centred triad of the frames last given (`frames`) at torsion branch `beta`, for a
    /// direction that leaves both orientations alone: lifted from a read's (`read`), else
    /// computed in Real (with the libm values the memo holds, else recording them) and
    /// lifted, unless the memo holds it.
    pub(super) fn triad(&mut self, beta: Real) -> Result<TriadSource<'_, Dual>, Singular> {
        let key = beta.to_bits();
        if self.triad.as_ref().is_none_or(|(k, _)| *k != key) {
            let (ra, rb) = (&self.frames[0], &self.frames[1]);
            let lifted = match (&self.read, &self.trig) {
                (Some((k, cen, _)), _) if *k == key => cen.lift(),
                (_, Some((k, trig))) if *k == key => centred_with(ra, rb, beta, trig)?.lift(),
                _ => {
                    let mut trig = TriadTrig::default();
                    let cen = centred_with(ra, rb, beta, &mut trig)?;
                    self.trig = Some((key, trig));
                    cen.lift()
                }
            };
            self.triad = Some((key, lifted));
        }
        Ok(match &self.triad {
            Some((_, cen)) => TriadSource::Given(cen),
            None => TriadSource::Compute,
        })
    }

    /// The values of the triad's libm calls at the frames last given and branch `beta`, for a
    /// direction along an orientation: where the memo holds them (also from a read), else
    /// recorded into `record` (then given to `remember`).
    pub(super) fn trig<'m>(
        &'m self,
        beta: Real,
        record: &'m mut Option<TriadTrig>,
    ) -> TriadSource<'m, Dual> {
        let key = beta.to_bits();
        match (&self.trig, &self.read) {
            (Some((k, trig)), _) | (_, Some((k, _, trig))) if *k == key => TriadSource::Trig(trig),
            _ => TriadSource::RecordTrig(record),
        }
    }

    /// REVOLUTE's rotations (Real) at the frames last given and branch `alpha`: the ones the
    /// memo holds, else computed and remembered. What every direction that leaves both
    /// orientations alone takes, lifted (`TriadSource::Revolute`).
    pub(super) fn revolute(&mut self, alpha: Real) -> Result<&Revolute, Singular> {
        let key = alpha.to_bits();
        if self.revolute.as_ref().is_none_or(|(k, _)| *k != key) {
            let rev = revolute(&self.frames[0], &self.frames[1], alpha)?;
            self.revolute = Some((key, rev));
        }
        self.revolute
            .as_ref()
            .map(|(_, rev)| rev)
            .ok_or(Singular::NotFinite)
    }

    /// Remembers the libm values recorded at branch `beta` (`trig`), for the frames last given.
    pub(super) fn remember(&mut self, beta: Real, recorded: Option<TriadTrig>) {
        if let Some(trig) = recorded {
            self.trig = Some((beta.to_bits(), trig));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Run, VrMemo};

    #[test]
    fn runs_follow_consecutive_slots_in_the_lists_order() {
        let mut m = VrMemo::default();
        let run = |slot, at, len| Run { slot, at, len };
        m.remember(&[10, 11, 12, 20, 21, 5], [0u8, 1, 2, 19, 20, 7].into_iter());
        assert!(m.holds(&[10, 11, 12, 20, 21, 5]));
        assert!(!m.holds(&[10, 11, 12, 20, 21]));
        assert_eq!(m.runs, [run(0, 0, 3), run(19, 3, 2), run(7, 5, 1)]);
        assert_eq!(m.runs(), None, "2 values per run: one by one");
        // a repeated or reversed slot starts a new run
        m.remember(&[1, 1, 3, 2], [4u8, 4, 6, 5].into_iter());
        let want = [run(4, 0, 1), run(4, 1, 1), run(6, 2, 1), run(5, 3, 1)];
        assert_eq!(m.runs, want);
        // two nodes' 13 inputs (positions, orientation, velocities), each node's in one run
        let vrs: Vec<u32> = (0..26).collect();
        m.remember(&vrs, (0..13u8).chain(19..32));
        assert_eq!(m.runs(), Some(&[run(0, 0, 13), run(19, 13, 13)][..]));
        m.remember(&[], std::iter::empty());
        assert!(m.holds(&[]) && m.runs().is_some_and(|r| r.is_empty()));
    }
}
