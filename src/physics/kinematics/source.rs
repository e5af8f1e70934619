//! Where the dispatch (`geometry_into`) takes the centred triad and REVOLUTE's rotations from
//! (`Triads`): computed (`Computed`, the step), or as the caller says (`TriadSource`: a read or
//! a directional derivative, with what `instance::memo::PointMemo` keeps for its point); and
//! whether a frame is a constant along the seeded direction (`constant`), where either is
//! computed in Real and lifted. Uses `math`, `geometry`'s `Singular`, `triad` and `revolute`.

use super::geometry::Singular;
use super::revolute::{revolute, Revolute};
use super::triad::{centred, centred_with, Centred, TriadTrig};
use crate::physics::math::{Mat3, Real, Scalar};

/// Whether a frame is a constant along the seeded direction (every derivative exactly 0).
#[inline]
pub fn constant<T: Scalar>(m: &Mat3<T>) -> bool {
    m.iter().all(|x| x.eps() == 0.0)
}

/// How `geometry_into` comes by the centred triad at a pose's orientations, and REVOLUTE's
/// rotations: `Computed` (the step), or as a `TriadSource` says (a read, whose triad
/// `instance::memo::PointMemo` computed and keeps; the directional derivatives, which all need
/// the same ones at a point). A type of its own for the step, so that its code has no branch
/// on it.
pub trait Triads<T: Scalar> {
    /// The centred triad at frames `ra`, `rb` and torsion branch `beta` (`fixed`: the frames
    /// are constants along the seeded direction); where one is computed, in `slot`.
    fn centred<'s>(
        self,
        ra: &Mat3<T>,
        rb: &Mat3<T>,
        beta: Real,
        fixed: bool,
        slot: &'s mut Option<Centred<T>>,
    ) -> Result<&'s Centred<T>, Singular>
    where
        Self: 's;

    /// REVOLUTE's rotations at frames `ra`, `rb` and branch `alpha` (`fixed`: the frames are
    /// constants along the seeded direction): computed, unless the source has them.
    #[inline(always)]
    fn revolute(
        &self,
        ra: &Mat3<T>,
        rb: &Mat3<T>,
        alpha: Real,
        fixed: bool,
    ) -> Result<Revolute<T>, Singular> {
        if fixed {
            Ok(revolute(&ra.map(|x| x.re()), &rb.map(|x| x.re()), alpha)?.lift())
        } else {
            revolute(ra, rb, alpha)
        }
    }
}

/// The centred triad computed (in Real and lifted where the frames are constants).
#[inline(always)]
fn computed<T: Scalar>(
    ra: &Mat3<T>,
    rb: &Mat3<T>,
    beta: Real,
    fixed: bool,
) -> Result<Centred<T>, Singular> {
    if fixed {
        Ok(centred(&ra.map(|x| x.re()), &rb.map(|x| x.re()), beta)?.lift())
    } else {
        centred(ra, rb, beta)
    }
}

/// Every triad computed: the step's evaluations.
pub struct Computed;

impl<T: Scalar> Triads<T> for Computed {
    #[inline(always)]
    fn centred<'s>(
        self,
        ra: &Mat3<T>,
        rb: &Mat3<T>,
        beta: Real,
        fixed: bool,
        slot: &'s mut Option<Centred<T>>,
    ) -> Result<&'s Centred<T>, Singular>
    where
        Self: 's,
    {
        Ok(slot.insert(computed(ra, rb, beta, fixed)?))
    }
}

impl<'a, T: Scalar> Triads<T> for TriadSource<'a, T> {
    #[inline(always)]
    fn centred<'s>(
        self,
        ra: &Mat3<T>,
        rb: &Mat3<T>,
        beta: Real,
        fixed: bool,
        slot: &'s mut Option<Centred<T>>,
    ) -> Result<&'s Centred<T>, Singular>
    where
        Self: 's,
    {
        match self {
            TriadSource::Given(c) if fixed || !T::DUAL => Ok(c),
            TriadSource::Trig(trig) if T::DUAL && !fixed => {
                Ok(slot.insert(centred_with(ra, rb, beta, trig)?))
            }
            TriadSource::RecordTrig(record) if T::DUAL && !fixed => {
                let mut trig = TriadTrig::default();
                let c = centred_with(ra, rb, beta, &mut trig)?;
                *record = Some(trig);
                Ok(slot.insert(c))
            }
            _ => Ok(slot.insert(computed(ra, rb, beta, fixed)?)),
        }
    }

    #[inline(always)]
    fn revolute(
        &self,
        ra: &Mat3<T>,
        rb: &Mat3<T>,
        alpha: Real,
        fixed: bool,
    ) -> Result<Revolute<T>, Singular> {
        match self {
            TriadSource::Revolute(rev) if fixed || !T::DUAL => Ok(rev.lift()),
            _ => Computed.revolute(ra, rb, alpha, fixed),
        }
    }
}

/// Where a read or a directional derivative takes the centred triad, or REVOLUTE's rotations,
/// from (`Triads`).
#[derive(Debug)]
pub enum TriadSource<'a, T: Scalar> {
    /// Computed.
    Compute,
    /// The caller has it, computed in Real at these frames and torsion branch: read in Real,
    /// and in `Dual` (as a constant) where the orientations are constants along the seeded
    /// direction (`constant`).
    Given(&'a Centred<T>),
    /// The caller has the values of its libm calls at these frames and branch.
    Trig(&'a TriadTrig),
    /// Computed, and the values of its libm calls handed to the caller.
    RecordTrig(&'a mut Option<TriadTrig>),
    /// No centred triad (REVOLUTE's frames are the nodes'): the caller has REVOLUTE's
    /// rotations, computed in Real at these frames and branch: read in Real, and in `Dual` (as
    /// constants) where the frames are constants along the seeded direction.
    Revolute(&'a Revolute),
}
