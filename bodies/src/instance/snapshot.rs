//! The FMU state (`Snapshot`: a copy of the instance's data, plain data) and its serialized
//! bytes: a magic, a format version, the fields in a fixed order (little endian) and an
//! FNV-1a checksum. Bytes are decoded only through the checks the setters make (every value
//! finite and in its variable's range, the parameters fitting together once initialized), so
//! corrupt or foreign bytes never become a state. Uses `super::data`, `crate::variables` and
//! `crate::physics`.

use super::data::{Data, Mode};
use crate::physics::{self, Body};
use crate::variables::{fnv1a, int, real, Slot, VARS};

/// The first bytes of every serialized state.
pub const MAGIC: &[u8; 8] = b"BODYFMU\0";
/// The format version; bytes of another version are refused.
pub const FORMAT_VERSION: u32 = 2;
/// The FNV-1a offset basis of the checksum.
const CHECKSUM_SEED: u64 = 0xcbf2_9ce4_8422_2325;
/// Number of f64 in the body.
const BODY_LEN: usize = 16;
/// Length of a serialized state.
pub const LEN: usize = 8 + 4 + 1 + 8 * (2 + real::N + BODY_LEN) + 4 * int::N + 8;

/// An FMU state: what `GetFMUState` saves and `SetFMUState` restores.
#[derive(Clone, Debug, PartialEq)]
pub struct Snapshot(Data);

fn body_values(b: &Body) -> [f64; BODY_LEN] {
    let mut x = [0.0; BODY_LEN];
    let parts: [&[f64]; 5] = [&b.r, &b.q, &b.v, &b.w, &b.angle];
    for (dst, src) in x.iter_mut().zip(parts.into_iter().flatten()) {
        *dst = *src;
    }
    x
}

fn body_of(x: &[f64; BODY_LEN]) -> Body {
    let v3 = |i: usize| [x[i], x[i + 1], x[i + 2]];
    Body {
        r: v3(0),
        q: [x[3], x[4], x[5], x[6]],
        v: v3(7),
        w: v3(10),
        angle: v3(13),
    }
}

/// Reads fixed-size fields from the front of a byte slice (the length was checked first).
struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn take<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0; N];
        let (head, rest) = self.0.split_at(N.min(self.0.len()));
        out[..head.len()].copy_from_slice(head);
        self.0 = rest;
        out
    }

    fn f64(&mut self) -> f64 {
        f64::from_le_bytes(self.take())
    }
}

impl Snapshot {
    /// A copy of `data`.
    pub(super) fn of(data: &Data) -> Self {
        Snapshot(*data)
    }

    /// The data it holds.
    pub(super) fn data(&self) -> &Data {
        &self.0
    }

    /// The serialized bytes (`LEN` of them).
    pub fn to_bytes(&self) -> Vec<u8> {
        let d = &self.0;
        let mut b = Vec::with_capacity(LEN);
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
        b.push(d.mode.to_byte());
        let reals = [d.time, d.start_time]
            .into_iter()
            .chain(d.reals)
            .chain(body_values(&d.body));
        for x in reals {
            b.extend_from_slice(&x.to_le_bytes());
        }
        for i in d.ints {
            b.extend_from_slice(&i.to_le_bytes());
        }
        let sum = fnv1a(&b, CHECKSUM_SEED);
        b.extend_from_slice(&sum.to_le_bytes());
        b
    }

    /// A state from serialized bytes; Err says why they are not one.
    pub fn from_bytes(bytes: &[u8]) -> Result<Snapshot, String> {
        if bytes.len() != LEN {
            return Err(format!(
                "serialized state of {} bytes, expected {LEN} (not a Body FMU state of format version {FORMAT_VERSION})",
                bytes.len()
            ));
        }
        if &bytes[..8] != MAGIC {
            return Err("the bytes are not a serialized Body FMU state (wrong magic)".into());
        }
        let (payload, sum) = bytes.split_at(LEN - 8);
        let mut r = Reader(&payload[8..]);
        let version = u32::from_le_bytes(r.take());
        if version != FORMAT_VERSION {
            return Err(format!(
                "serialized state of format version {version}; this FMU reads version {FORMAT_VERSION}"
            ));
        }
        if fnv1a(payload, CHECKSUM_SEED).to_le_bytes() != sum {
            return Err("serialized state is corrupt (checksum mismatch)".into());
        }
        let [mode] = r.take::<1>();
        let mode = Mode::from_byte(mode).ok_or(format!("unknown mode byte {mode}"))?;
        let time = r.f64();
        let start_time = r.f64();
        let reals: [f64; real::N] = std::array::from_fn(|_| r.f64());
        let body = body_of(&std::array::from_fn(|_| r.f64()));
        let ints: [i32; int::N] = std::array::from_fn(|_| i32::from_le_bytes(r.take()));
        let data = Data {
            mode,
            time,
            start_time,
            reals,
            ints,
            body,
        };
        check(&data)?;
        Ok(Snapshot(data))
    }
}

/// The setters' checks on decoded data: everything finite, every parameter in its range, and
/// once initialized the parameters fitting together.
fn check(d: &Data) -> Result<(), String> {
    let finite = |what: &str, x: &[f64]| match x.iter().all(|x| x.is_finite()) {
        true => Ok(()),
        false => Err(format!(
            "serialized state holds a {what} that is not finite"
        )),
    };
    finite("time", &[d.time, d.start_time])?;
    finite(
        "body position, orientation or velocity",
        &body_values(&d.body),
    )?;
    for v in &VARS {
        let x = match v.slot {
            Slot::Real(i) => d.reals[i],
            Slot::Int(i) => f64::from(d.ints[i]),
            Slot::Out(_) => continue,
        };
        finite(v.name, &[x])?;
        v.check_range(x)
            .map_err(|e| format!("serialized state: {e}"))?;
    }
    if matches!(d.mode, Mode::Step | Mode::Terminated) {
        physics::check(&d.params()).map_err(|e| format!("serialized state: {e}"))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_round_trip_and_damage_is_refused() {
        let mut d = Data::new();
        d.mode = Mode::Step;
        d.time = 0.25;
        d.body.q = [1.0, 0.0, 0.0, 0.0];
        d.body.v = [1.0, -2.0, 3.5];
        let s = Snapshot::of(&d);
        let bytes = s.to_bytes();
        assert_eq!(bytes.len(), LEN);
        assert_eq!(Snapshot::from_bytes(&bytes), Ok(s));
        for i in [0, 9, 12, 40, LEN - 1] {
            let mut bad = bytes.clone();
            bad[i] ^= 0x10;
            assert!(Snapshot::from_bytes(&bad).is_err(), "byte {i}");
        }
        assert!(Snapshot::from_bytes(&bytes[..LEN - 1]).is_err());
    }

    #[test]
    fn a_state_with_a_value_out_of_range_is_refused_even_with_a_good_checksum() {
        let mut d = Data::new();
        d.reals[real::MASS] = -1.0;
        let e = Snapshot::from_bytes(&Snapshot::of(&d).to_bytes()).unwrap_err();
        assert!(e.contains("mass"), "{e}");
    }
}
