//! The serialized FMU state: a versioned, checksummed, validated byte format.
//!
//! Layout (little endian): magic `CFMU`, format version (u16), model identifier length (u8)
//! and bytes, mode (u8), time and start time (f64), the variant's parameters in table order
//! (Real f64, Integer i32, Boolean u8), its node inputs in table order (f64), the input
//! derivatives that are set (u32 mask over the 2 × 13 poses and twists, then their f64 values), the
//! connector state, the last step's event record (time f64, count i32), the input history (u8
//! flag, then time and the 12 velocity inputs as f64 when set), the event-function record (u8:
//! 0 none, 1 near, 2 far; then a u32 mask of the functions taking part and their values), the
//! outputs the last step ended with where they are still cached (u8: 0 none; 1 those of the 70
//! Real outputs that differ from a fresh read at the state's inputs, as a u8 count and each a u8
//! index and its f64; 2 all of them, the stop statuses as i8 and the friction statuses as u8;
//! see `encode_outputs`), and an FNV-1a 64 checksum of everything before it. Parameters and
//! inputs are written back through the same checks as fmi2Set*, so a decoded state is one that
//! the setters could have produced.
//!
//! Uses the table, the data (`snapshot`, its output cache), the access rules and the physics'
//! state types and evaluation (the fresh read cached outputs are written against); the
//! instance uses it.

use super::access::{nodes_of, read_int_param, read_real_param, write_int, write_real};
use super::cache::OutputCache;
use super::snapshot::{EventRecord, LastEvent, Mode, Snapshot};
use super::variables::{
    Causality, CompPar, Field, NodeInputs, Start, Table, NODE_INPUTS, POSE_TWIST,
};
use crate::physics::connector::{evaluate, Energy, Outputs, State};
use crate::physics::events::N_EVENTS;
use crate::physics::friction::{Eval, FrictionState, Status};
use crate::physics::kinematics::Branches;
use crate::physics::math::Vec3;

const MAGIC: &[u8; 4] = b"CFMU";
/// Version of the byte format; bump on any layout change.
pub const VERSION: u16 = 5;

struct W(Vec<u8>);

impl W {
    fn f(&mut self, x: f64) {
        self.0.extend_from_slice(&x.to_le_bytes());
    }
    fn fs(&mut self, xs: &[f64]) {
        xs.iter().for_each(|&x| self.f(x));
    }
    fn b(&mut self, x: u8) {
        self.0.push(x);
    }
}

struct R<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> R<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        match end {
            Some(e) => {
                let s = &self.bytes[self.at..e];
                self.at = e;
                Ok(s)
            }
            None => Err(format!(
                "truncated at byte {} of {}",
                self.at,
                self.bytes.len()
            )),
        }
    }
    fn f(&mut self, what: &str) -> Result<f64, String> {
        let mut a = [0u8; 8];
        a.copy_from_slice(self.take(8)?);
        let x = f64::from_le_bytes(a);
        if x.is_finite() {
            Ok(x)
        } else {
            Err(format!("{what} is not finite"))
        }
    }
    fn f_any(&mut self) -> Result<f64, String> {
        let mut a = [0u8; 8];
        a.copy_from_slice(self.take(8)?);
        Ok(f64::from_le_bytes(a))
    }
    fn fs<const N: usize>(&mut self, what: &str) -> Result<[f64; N], String> {
        let mut out = [0.0; N];
        for x in out.iter_mut() {
            *x = self.f(what)?;
        }
        Ok(out)
    }
    fn b(&mut self) -> Result<u8, String> {
        Ok(self.take(1)?[0])
    }
    fn u32(&mut self) -> Result<u32, String> {
        let mut a = [0u8; 4];
        a.copy_from_slice(self.take(4)?);
        Ok(u32::from_le_bytes(a))
    }
}

fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

const MODES: [Mode; 7] = [
    Mode::Instantiated,
    Mode::InitializationMode,
    Mode::StepComplete,
    Mode::StepFailed,
    Mode::StepCanceled,
    Mode::Terminated,
    Mode::Error,
];

/// The snapshot as bytes.
pub fn encode(t: &Table, s: &Snapshot) -> Vec<u8> {
    let mut w = W(Vec::with_capacity(768));
    w.0.extend_from_slice(MAGIC);
    w.0.extend_from_slice(&VERSION.to_le_bytes());
    let id = t.spec.model_identifier.as_bytes();
    w.b(id.len() as u8);
    w.0.extend_from_slice(id);
    w.b(MODES.iter().position(|&m| m == s.mode).unwrap_or(0) as u8);
    w.fs(&[s.time, s.start_time]);
    for v in t
        .vars
        .iter()
        .filter(|v| v.causality == Causality::Parameter)
    {
        match v.start {
            Start::Real(_) => w.f(read_real_param(&s.params, v.field)),
            Start::Integer(_) => {
                w.0.extend_from_slice(&read_int_param(&s.params, v.field).to_le_bytes())
            }
            Start::Boolean(_) => match v.field {
                Field::CompParam { k, .. } => w.b(s.params.ref_given[k as usize] as u8),
                _ => w.b(0),
            },
        }
    }
    for v in &t.vars {
        if let Field::Input { node, idx } = v.field {
            w.f(s.inputs[node as usize][idx as usize]);
        }
    }
    let mut mask = 0u32;
    for n in 0..2 {
        for i in 0..POSE_TWIST {
            if s.input_der_set[n][i] {
                mask |= 1 << (POSE_TWIST * n + i);
            }
        }
    }
    w.0.extend_from_slice(&mask.to_le_bytes());
    for n in 0..2 {
        for i in 0..POSE_TWIST {
            if s.input_der_set[n][i] {
                w.f(s.input_der[n][i]);
            }
        }
    }
    let st = &s.state;
    let br = &st.branches;
    w.fs(&[
        br.beta,
        br.alpha,
        br.e_r_local.x,
        br.e_r_local.y,
        br.e_r_local.z,
    ]);
    w.fs(&st.c0);
    st.stop_status.iter().for_each(|&x| w.b(x as u8));
    let fr = &st.friction;
    w.fs(&[
        fr.slip_plastic[0],
        fr.slip_plastic[1],
        fr.slip_plastic_r1,
        fr.slip_acc,
        fr.slip_acc_r1,
        fr.dissipated,
        fr.mu_rate[0],
        fr.mu_rate[1],
        fr.force[0],
        fr.force[1],
        fr.force[2],
        fr.elastic[0],
        fr.elastic[1],
        fr.elastic[2],
        fr.slip_rate[0],
        fr.slip_rate[1],
        fr.slip_rate[2],
    ]);
    w.b(fr.status as u8);
    w.b(fr.status_r1 as u8);
    let e = &st.dissipated;
    w.fs(&[e.damping, e.stops, st.power[0], st.power[1]]);
    w.f(s.event.time);
    w.0.extend_from_slice(&s.event.count.to_le_bytes());
    match &s.history {
        None => w.b(0),
        Some((t, vel)) => {
            w.b(1);
            w.f(*t);
            vel.iter().for_each(|v| w.fs(v));
        }
    }
    match &s.events {
        None => w.b(0),
        Some(r) => {
            // flag 1 + far, a u32 mask of the functions taking part, then their values
            w.b(1 + u8::from(r.far));
            let v = &r.end;
            let mask = (0..N_EVENTS).fold(0u32, |m, i| m | (u32::from(!v[i].is_nan()) << i));
            w.0.extend_from_slice(&mask.to_le_bytes());
            v.iter().filter(|x| !x.is_nan()).for_each(|&x| w.f(x));
        }
    }
    encode_outputs(&mut w, t, s);
    let sum = fnv(&w.0);
    w.0.extend_from_slice(&sum.to_le_bytes());
    w.0
}

/// Real outputs in `flat`'s order: the eight per-component arrays, the four node loads, the six
/// friction outputs, the four energies.
const N_FLAT: usize = 8 * 6 + 4 * 3 + 6 + 4;

/// The Real outputs of `o` in one array (event.time is the snapshot's, not an output here).
fn flat(o: &Outputs) -> [f64; N_FLAT] {
    let (f, e) = (&o.friction, &o.energy);
    let mut x = [0.0; N_FLAT];
    let arrays = [&o.cp, &o.cu, &o.cv, &o.cef, &o.cvf, &o.csf, &o.crf, &o.ctf];
    let loads = [&o.fa, &o.ma, &o.fb, &o.mb].map(|v| [v.x, v.y, v.z]);
    let rest = [f.cnf, f.cnm1, f.csfc, f.csmc1, f.slip, f.slip_r1];
    let energy = [e.stored, e.damping, e.friction, e.stops];
    let all = arrays.iter().flat_map(|a| a.iter());
    let all = all
        .chain(loads.iter().flatten())
        .chain(&rest)
        .chain(&energy);
    for (x, &v) in x.iter_mut().zip(all) {
        *x = v;
    }
    x
}

/// Writes `x` (in `flat`'s order) into the Real outputs of `o`.
fn unflat(o: &mut Outputs, x: &[f64; N_FLAT]) {
    let mut it = x.iter().copied();
    let mut next = || it.next().unwrap_or(0.0);
    for a in [
        &mut o.cp, &mut o.cu, &mut o.cv, &mut o.cef, &mut o.cvf, &mut o.csf, &mut o.crf, &mut o.ctf,
    ] {
        a.iter_mut().for_each(|v| *v = next());
    }
    for v in [&mut o.fa, &mut o.ma, &mut o.fb, &mut o.mb] {
        *v = Vec3::new(next(), next(), next());
    }
    let f = &mut o.friction;
    for v in [
        &mut f.cnf,
        &mut f.cnm1,
        &mut f.csfc,
        &mut f.csmc1,
        &mut f.slip,
        &mut f.slip_r1,
    ] {
        *v = next();
    }
    let e = &mut o.energy;
    for v in [&mut e.stored, &mut e.damping, &mut e.friction, &mut e.stops] {
        *v = next();
    }
}

/// The outputs a read evaluates at the snapshot's inputs with its committed state (None where
/// they cannot be evaluated there): what the outputs a step ended with are written against.
fn fresh_outputs(t: &Table, s: &Snapshot) -> Option<Outputs> {
    let (a, b) = nodes_of(&s.inputs).ok()?;
    let (mut o, _) = evaluate(t.spec.connection, &s.params, &s.state, &a, &b, Eval::Read).ok()?;
    (o.event_time, o.event_count) = (s.event.time, s.event.count);
    Some(o)
}

/// The outputs the last step ended with (`Snapshot::outputs`), where still cached. They equal a
/// fresh read at the same inputs and state but for a few last bits (`model::cache`), so they
/// are written as the Real outputs that differ from it (flag 1: their count, then index and
/// value each), or whole (flag 2: where no fresh read can be made or its statuses differ).
fn encode_outputs(w: &mut W, t: &Table, s: &Snapshot) {
    let Some(o) = s.outputs.stepped() else {
        return w.b(0);
    };
    let same_statuses = |f: &Outputs| {
        f.cslst == o.cslst
            && (f.friction.status, f.friction.status_r1)
                == (o.friction.status, o.friction.status_r1)
    };
    let x = flat(o);
    match fresh_outputs(t, s).filter(same_statuses) {
        Some(fresh) => {
            let y = flat(&fresh);
            let differ: Vec<usize> = (0..N_FLAT)
                .filter(|&i| x[i].to_bits() != y[i].to_bits())
                .collect();
            w.b(1);
            w.b(differ.len() as u8);
            for i in differ {
                w.b(i as u8);
                w.f(x[i]);
            }
        }
        None => {
            w.b(2);
            w.fs(&x);
            o.cslst.iter().for_each(|&k| w.b(k as i8 as u8));
            w.b(o.friction.status as u8);
            w.b(o.friction.status_r1 as u8);
        }
    }
}

/// The outputs written by `encode_outputs` for the snapshot `s` (decoded up to them): every
/// value finite (NaN never reaches an output), indices in order, statuses in range.
fn decode_outputs(r: &mut R, t: &Table, s: &Snapshot) -> Result<OutputCache, String> {
    let o = match r.b()? {
        0 => return Ok(OutputCache::new()),
        1 => {
            let mut o = fresh_outputs(t, s)
                .ok_or("the cached outputs' reference cannot be evaluated at the state's inputs")?;
            let mut x = flat(&o);
            let n = r.b()? as usize;
            let mut last = None;
            for _ in 0..n {
                let i = r.b()? as usize;
                if i >= N_FLAT || last.is_some_and(|l| i <= l) {
                    return Err(format!("cached output index {i} is out of order or range"));
                }
                x[i] = r.f("cached output")?;
                last = Some(i);
            }
            unflat(&mut o, &x);
            o
        }
        2 => {
            let mut o = Outputs::default();
            let x = r.fs::<N_FLAT>("cached output")?;
            unflat(&mut o, &x);
            for k in o.cslst.iter_mut() {
                *k = match r.b()? {
                    0 => 0,
                    1 => 1,
                    255 => -1,
                    x => return Err(format!("cached stop status {x} is not -1, 0 or 1")),
                };
            }
            o.friction.status = status(r.b()?)?;
            o.friction.status_r1 = status(r.b()?)?;
            (o.event_time, o.event_count) = (s.event.time, s.event.count);
            o
        }
        x => return Err(format!("cached outputs flag {x} is not 0, 1 or 2")),
    };
    Ok(OutputCache::stepped_to(o))
}

fn status(x: u8) -> Result<Status, String> {
    match x {
        0 => Ok(Status::NoNormal),
        1 => Ok(Status::Stick),
        2 => Ok(Status::Slip),
        _ => Err(format!("friction status {x} is not 0, 1 or 2")),
    }
}

/// Decodes and validates bytes written by `encode` for the same variant.
pub fn decode(t: &Table, bytes: &[u8]) -> Result<Snapshot, String> {
    if bytes.len() < 8 + MAGIC.len() {
        return Err(format!(
            "{} bytes are too few for a serialized state",
            bytes.len()
        ));
    }
    let (body, sum) = bytes.split_at(bytes.len() - 8);
    if bytes[..4] != MAGIC[..] {
        return Err("the bytes are not a state of this FMU (bad magic)".into());
    }
    let mut sum_b = [0u8; 8];
    sum_b.copy_from_slice(sum);
    if fnv(body) != u64::from_le_bytes(sum_b) {
        return Err("checksum mismatch: the bytes are corrupt".into());
    }
    let mut r = R { bytes: body, at: 4 };
    let mut v = [0u8; 2];
    v.copy_from_slice(r.take(2)?);
    let version = u16::from_le_bytes(v);
    if version != VERSION {
        return Err(format!(
            "format version {version} is not the supported version {VERSION}"
        ));
    }
    let n = r.b()? as usize;
    let id = r.take(n)?;
    if id != t.spec.model_identifier.as_bytes() {
        return Err(format!(
            "the state belongs to model {:?}, not {}",
            String::from_utf8_lossy(id),
            t.spec.model_identifier
        ));
    }
    let mode = *MODES.get(r.b()? as usize).ok_or("unknown mode")?;
    let time = r.f("time")?;
    let start_time = r.f("start time")?;
    let mut params = crate::physics::connector::Params::default();
    let mut inputs: [NodeInputs; 2] = [[0.0; NODE_INPUTS]; 2];
    inputs[0][3] = 1.0;
    inputs[1][3] = 1.0;
    for v in t
        .vars
        .iter()
        .filter(|v| v.causality == Causality::Parameter)
    {
        let bad = |why: String| format!("parameter {} {why}", v.name);
        match v.start {
            Start::Real(_) => write_real(&mut params, &mut inputs, v, r.f_any()?).map_err(bad)?,
            Start::Integer(_) => {
                let mut a = [0u8; 4];
                a.copy_from_slice(r.take(4)?);
                write_int(&mut params, v, i32::from_le_bytes(a)).map_err(bad)?
            }
            Start::Boolean(_) => match (v.field, r.b()?) {
                (
                    Field::CompParam {
                        par: CompPar::RefGiven,
                        k,
                    },
                    x @ (0 | 1),
                ) => params.ref_given[k as usize] = x == 1,
                _ => return Err(bad("is not a Boolean 0 or 1".to_string())),
            },
        }
    }
    // Cross-parameter rules (stop.lower ≤ stop.upper, μ_k ≤ μ_s, coupling needs R > 0) are
    // checked at fmi2ExitInitializationMode; before it the setters accept each valid value on
    // its own, so a state saved then may legitimately break them (regression 004).
    if !matches!(mode, Mode::Instantiated | Mode::InitializationMode) {
        params
            .check(&t.spec.connection.roles())
            .map_err(|name| format!("invalid parameter {name}"))?;
    }
    for v in &t.vars {
        if let Field::Input { .. } = v.field {
            write_real(&mut params, &mut inputs, v, r.f_any()?)
                .map_err(|why| format!("input {} {why}", v.name))?;
        }
    }
    let mask = r.u32()?;
    if mask >> 26 != 0 {
        return Err("input-derivative mask has unknown bits".into());
    }
    let mut input_der = [[0.0; POSE_TWIST]; 2];
    let mut input_der_set = [[false; POSE_TWIST]; 2];
    for n in 0..2 {
        for i in 0..POSE_TWIST {
            if mask & (1 << (POSE_TWIST * n + i)) != 0 {
                input_der[n][i] = r.f("input derivative")?;
                input_der_set[n][i] = true;
            }
        }
    }
    let [beta, alpha, ex, ey, ez] = r.fs::<5>("angle branch")?;
    let e_r_local = Vec3::new(ex, ey, ez);
    if (e_r_local.norm() - 1.0).abs() > 1e-9 {
        return Err("radial direction is not a unit vector".into());
    }
    let c0 = r.fs::<6>("initial position")?;
    let mut stop_status = [0i8; 6];
    for s in stop_status.iter_mut() {
        *s = match r.b()? {
            0 => 0,
            1 => 1,
            255 => -1,
            x => return Err(format!("stop status {x} is not -1, 0 or 1")),
        };
    }
    let [s0, s1, sr, acc, acc_r, fdiss, mu0, mu1, f2, f3, m1, e2, e3, e4, v2, v3, v4] =
        r.fs::<17>("friction state")?;
    if mu0 < 0.0 || mu1 < 0.0 {
        return Err("friction slip speed is negative".into());
    }
    let (st0, st1) = (status(r.b()?)?, status(r.b()?)?);
    let [damping, stops, p0, p1] = r.fs::<4>("energy")?;
    let event_time = r.f("event time")?;
    let event_count = r.u32()? as i32;
    if event_count < 0 {
        return Err(format!("event count {event_count} is negative"));
    }
    let history = match r.b()? {
        0 => None,
        1 => Some((
            r.f("history time")?,
            [
                r.fs::<6>("history velocity")?,
                r.fs::<6>("history velocity")?,
            ],
        )),
        x => return Err(format!("history flag {x} is not 0 or 1")),
    };
    let events = match r.b()? {
        0 => None,
        flag @ (1 | 2) => {
            let mask = r.u32()?;
            if mask >> N_EVENTS != 0 {
                return Err(format!("event function mask {mask:#x} has unknown bits"));
            }
            let mut end = [f64::NAN; N_EVENTS];
            for (i, x) in end.iter_mut().enumerate() {
                if mask & (1 << i) != 0 {
                    // ±INF is a value (a penetration or force that overflowed far from its
                    // event); NaN marks a function not taking part, never a value
                    *x = r.f_any()?;
                    if x.is_nan() {
                        return Err("event function is NaN".into());
                    }
                }
            }
            Some(EventRecord {
                end,
                far: flag == 2,
            })
        }
        x => return Err(format!("event record flag {x} is not 0, 1 or 2")),
    };
    let event = LastEvent {
        time: event_time,
        count: event_count,
    };
    let mut snapshot = Snapshot {
        variant: t.spec.variant,
        mode,
        time,
        start_time,
        params,
        inputs,
        input_der,
        input_der_set,
        state: State {
            branches: Branches {
                beta,
                alpha,
                e_r_local,
            },
            c0,
            stop_status,
            friction: FrictionState {
                slip_plastic: [s0, s1],
                slip_plastic_r1: sr,
                slip_acc: acc,
                slip_acc_r1: acc_r,
                status: st0,
                status_r1: st1,
                dissipated: fdiss,
                mu_rate: [mu0, mu1],
                force: [f2, f3, m1],
                elastic: [e2, e3, e4],
                slip_rate: [v2, v3, v4],
            },
            dissipated: Energy {
                stored: 0.0,
                damping,
                friction: 0.0,
                stops,
            },
            power: [p0, p1],
        },
        event,
        history,
        events,
        outputs: OutputCache::new(),
    };
    snapshot.outputs = decode_outputs(&mut r, t, &snapshot)?;
    if r.at != body.len() {
        return Err(format!("{} unexpected trailing bytes", body.len() - r.at));
    }
    Ok(snapshot)
}
