//! The FMI call-sequence fuzz harness, shared by the libFuzzer target
//! (`fuzz/fuzz_targets/fmi_calls.rs`) and its deterministic replay in `cargo test`
//! (`tests/fuzz_smoke.rs`, included there with `#[path]`). Logger, callbacks and the checksum
//! come from the tests' support module (`tests/common/mod.rs`, included here with `#[path]`).
//!
//! The input bytes are a program: a header that instantiates one variant (or tries a bad
//! GUID, type, name or callback struct), then a sequence of operations on up to two instances,
//! four FMU-state slots and two serialized-state buffers. Every exported function is reachable;
//! values come from a pool of awkward floats (NaN, ±INF, ±1e308, 5e-324, −0.0, raw bits) and
//! from plausible physics (parameter sets, poses, velocities), so both the refusals and the
//! kernel are exercised.
//!
//! Invariants checked after every call (a violation panics, which libFuzzer reports):
//! 1. no fmi2Fatal (the boundary catches panics, but a caught panic is still a bug);
//! 2. a non-OK status is explained by exactly one non-OK log message of that status, whose text
//!    names the function; an OK status logs no non-OK message;
//! 3. every Real output (and directional derivative) returned with fmi2OK is finite;
//! 4. a call that returns fmi2Error leaves the instance's FMU state (parameters, inputs, input
//!    derivatives, time, connector state) byte-identical, apart from the mode;
//! 5. a state that fmi2SerializeFMUstate wrote is accepted by fmi2DeSerializeFMUstate and
//!    re-serializes to the same bytes; a state of another variant is refused by fmi2SetFMUstate
//!    and fmi2SerializeFMUstate alike;
//! 6. restoring an FMU state and repeating a step reproduces status and outputs bit for bit;
//! 7. fmi2Instantiate with valid arguments succeeds, and a refusal is logged when a logger exists.
#![allow(dead_code, clippy::too_many_lines)]

use connector_fmu::fmi2::exports::*;
use connector_fmu::fmi2::types::*;
use connector_fmu::variables::{table, Causality, Start, Variability, Variant, VARIANTS};
use std::ffi::{c_char, c_int, CString};
use std::ptr::{null, null_mut};

// ------------------------------------------------------------------ logger

// The logger, callback struct and value lookups of the tests (one support module for the tests,
// this harness and the benchmark). Each program logs under a componentEnvironment key of its own.
#[path = "../tests/common/mod.rs"]
mod support;
use support::{LogLine, CO_SIMULATION};

/// The callback struct of program `env`, with or without a logger.
fn callbacks(env: usize, with_logger: bool) -> fmi2CallbackFunctions {
    let cb = support::callbacks(env);
    fmi2CallbackFunctions {
        logger: cb.logger.filter(|_| with_logger),
        ..cb
    }
}

// ------------------------------------------------------------------ input decoding

/// The program bytes; reads past the end yield zeros.
pub struct Bytes<'a> {
    d: &'a [u8],
    i: usize,
}

impl<'a> Bytes<'a> {
    pub fn new(d: &'a [u8]) -> Self {
        Bytes { d, i: 0 }
    }
    fn done(&self) -> bool {
        self.i >= self.d.len()
    }
    fn u8(&mut self) -> u8 {
        let b = self.d.get(self.i).copied().unwrap_or(0);
        self.i += 1;
        b
    }
    fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }
    fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    fn u64(&mut self) -> u64 {
        (self.u32() as u64) | ((self.u32() as u64) << 32)
    }
    /// A signed value in [−1, 1).
    fn unit(&mut self) -> f64 {
        (self.u16() as i16) as f64 / 32768.0
    }

    /// A float from the pool of awkward and ordinary values.
    fn real(&mut self) -> f64 {
        match self.u8() % 24 {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            3 => 1e308,
            4 => -1e308,
            5 => 5e-324,
            6 => -0.0,
            7 => 0.0,
            8 => 1.0,
            9 => -1.0,
            10 => f64::MAX,
            11 => f64::MIN_POSITIVE,
            12 => f64::from_bits(self.u64()),
            13 => std::f64::consts::PI * (self.u8() as i8) as f64 / 16.0,
            14 => 1e-12 * self.unit(),
            15 => 1e6 * self.unit(),
            16 => -5e-324,
            17 => 1e154 * self.unit(),
            _ => 10.0 * self.unit(),
        }
    }

    /// A step size: zero, negative, non-finite, huge, denormal, ordinary.
    fn step(&mut self) -> f64 {
        match self.u8() % 16 {
            0 => 0.0,
            1 => -1e-3,
            2 => f64::NAN,
            3 => f64::INFINITY,
            4 => 1e300,
            5 => 5e-324,
            6 => 1.0,
            7 => 1e-6,
            8 => 0.1 * (1.0 + self.unit()),
            9 => self.real(),
            _ => 1e-3 * (1.0 + 4.0 * (self.u8() as f64 / 255.0)),
        }
    }

    /// Four quaternion components (w, x, y, z).
    fn quat(&mut self) -> [f64; 4] {
        let axis_angle = |b: &mut Self, angle: f64| {
            let mut ax = [b.unit(), b.unit(), b.unit()];
            let n = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
            if n < 1e-3 {
                ax = [1.0, 0.0, 0.0];
            } else {
                ax.iter_mut().for_each(|x| *x /= n);
            }
            let (s, c) = (angle / 2.0).sin_cos();
            [c, s * ax[0], s * ax[1], s * ax[2]]
        };
        let about_x = |angle: f64| {
            let (s, c) = (angle / 2.0).sin_cos();
            [c, s, 0.0, 0.0]
        };
        let pi = std::f64::consts::PI;
        match self.u8() % 16 {
            0 => [0.0; 4],
            1 => [1e-7, 0.0, 0.0, 0.0],
            2 => [1e200, 0.0, 0.0, 1e200],
            3 => [f64::NAN, 0.0, 0.0, 1.0],
            4 => [1.0, f64::INFINITY, 0.0, 0.0],
            5 => [5e-324, 5e-324, 0.0, 0.0],
            6 => [self.real(), self.real(), self.real(), self.real()],
            7 => about_x(pi),
            8 => about_x(pi - 1e-3 * self.u8() as f64 / 128.0),
            9 => {
                let s = 1e-6 * (1.0 + self.unit());
                let q = about_x(self.unit() * pi);
                q.map(|x| x * s)
            }
            10 => {
                let s = 1e150;
                about_x(self.unit() * pi).map(|x| x * s)
            }
            _ => {
                let angle = pi * self.unit() * (1 + self.u8() % 2) as f64;
                axis_angle(self, angle)
            }
        }
    }

    /// A plausible parameter value for a parameter named `name`.
    fn param_value(&mut self, name: &str) -> f64 {
        if self.u8().is_multiple_of(8) {
            return self.real();
        }
        let u = self.unit();
        if name.starts_with("stop.lower") {
            -0.2 * u.abs()
        } else if name.starts_with("stop.upper") {
            0.2 * u.abs()
        } else if name.starts_with("reference.value") || name.ends_with("int") {
            u
        } else if name.contains("mu") {
            u.abs()
        } else if name.contains("R") && name.starts_with("friction.") && !name.contains("R1") {
            0.05 * u.abs()
        } else {
            10f64.powf(6.0 * u.abs()) - 1.0
        }
    }
}

// ------------------------------------------------------------------ the program state

const OK: fmi2Status = fmi2Status::OK;
/// Upper bound of DoStep calls per program (each can take up to MAX_SUBSTEPS substeps).
const MAX_STEPS: usize = 24;
/// Upper bound of operations per program.
const MAX_OPS: usize = 400;

struct Inst {
    c: fmi2Component,
    variant: Variant,
}

/// A state slot and the variant of the instance that produced it.
#[derive(Clone, Copy)]
struct Slot {
    s: fmi2FMUstate,
    variant: Variant,
}

/// The componentEnvironment key a program's instances log under; its messages are dropped with it.
struct Env(usize);

impl Drop for Env {
    fn drop(&mut self) {
        support::forget_log(self.0);
    }
}

struct Program<'a> {
    env: Env,
    b: Bytes<'a>,
    inst: [Option<Inst>; 2],
    slots: [Slot; 4],
    bufs: Vec<(Vec<u8>, Variant)>,
    steps: usize,
    trace: Vec<String>,
}

fn variant_of(i: usize) -> Variant {
    VARIANTS[i % VARIANTS.len()].variant
}

/// Rewrites the checksum trailer of serialized state bytes (FNV-1a 64): lets mutated bytes
/// pass the checksum so that the field validation behind it is exercised.
fn fix_checksum(bytes: &mut [u8]) {
    if bytes.len() >= 8 {
        let n = bytes.len() - 8;
        let sum = support::fnv1a(&bytes[..n]);
        bytes[n..].copy_from_slice(&sum.to_le_bytes());
    }
}

/// Index of the mode byte in serialized bytes (after magic, version, id length and id).
fn mode_index(v: Variant) -> usize {
    4 + 2 + 1 + table(v).spec.model_identifier.len()
}

/// The instance's state as bytes with the mode byte and the checksum blanked (None when the
/// state cannot be taken, e.g. after fmi2Fatal).
fn state_bytes(inst: &Inst) -> Option<Vec<u8>> {
    let mut s: fmi2FMUstate = null_mut();
    if fmi2GetFMUstate(inst.c, &mut s) != OK {
        return None;
    }
    let mut n: usize = 0;
    let mut out = None;
    if fmi2SerializedFMUstateSize(inst.c, s, &mut n) == OK {
        let mut buf = vec![0u8; n];
        if fmi2SerializeFMUstate(inst.c, s, buf.as_mut_ptr().cast(), n) == OK {
            let m = mode_index(inst.variant);
            buf[m] = 0;
            let len = buf.len();
            buf[len - 8..].fill(0);
            out = Some(buf);
        }
    }
    fmi2FreeFMUstate(inst.c, &mut s);
    out
}

fn reals_of(v: Variant, pred: impl Fn(&connector_fmu::variables::VarSpec) -> bool) -> Vec<u32> {
    table(v)
        .vars
        .iter()
        .filter(|x| matches!(x.start, Start::Real(_)) && pred(x))
        .map(|x| x.vr)
        .collect()
}

fn is_real_output(v: Variant, vr: u32) -> bool {
    table(v)
        .get(vr)
        .is_some_and(|x| x.causality == Causality::Output && matches!(x.start, Start::Real(_)))
}

impl<'a> Program<'a> {
    fn fail(&self, what: String) -> ! {
        if trace_wanted() {
            eprintln!("full program trace: {:#?}", self.trace);
        }
        panic!(
            "invariant violated: {what}\nprogram trace (last 40 ops): {:#?}",
            &self.trace[self.trace.len().saturating_sub(40)..]
        );
    }

    /// Checks invariants 1, 2 (and 4 through `before`) for one call on instance `i`.
    fn check(&mut self, i: usize, fname: &str, n0: usize, s: fmi2Status, before: Option<Vec<u8>>) {
        let lines = support::log_since(self.env.0, n0);
        let bad: Vec<&LogLine> = lines.iter().filter(|l| l.status != 0).collect();
        if s == fmi2Status::Fatal {
            self.fail(format!("{fname} returned fmi2Fatal: {lines:?}"));
        }
        if s == OK {
            if !bad.is_empty() {
                self.fail(format!("{fname} returned OK but logged {bad:?}"));
            }
        } else {
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
            let want_cat = if s == fmi2Status::Warning {
                "logStatusWarning"
            } else {
                "logStatusError"
            };
            if l.category != want_cat || !l.message.contains(fname) {
                self.fail(format!(
                    "{fname}: message does not name the function or has the wrong category: {l:?}"
                ));
            }
        }
        if s == fmi2Status::Error {
            if let (Some(b0), Some(inst)) = (before, self.inst[i].as_ref()) {
                if let Some(b1) = state_bytes(inst) {
                    if b0 != b1 {
                        let at = b0.iter().zip(&b1).position(|(x, y)| x != y);
                        self.fail(format!(
                            "{fname} returned fmi2Error but changed the FMU state (first differing byte {at:?}, lengths {} {})",
                            b0.len(),
                            b1.len()
                        ));
                    }
                }
            }
        }
    }

    /// Runs one call on instance i with invariant checks (state compared on fmi2Error).
    fn call(
        &mut self,
        i: usize,
        fname: &str,
        f: impl FnOnce(fmi2Component) -> fmi2Status,
    ) -> fmi2Status {
        let Some(inst) = self.inst[i].as_ref() else {
            return fmi2Status::Error;
        };
        let c = inst.c;
        let before = state_bytes(inst);
        let n0 = support::log_len(self.env.0);
        let s = f(c);
        self.check(i, fname, n0, s, before);
        s
    }

    fn variant(&self, i: usize) -> Option<Variant> {
        self.inst[i].as_ref().map(|x| x.variant)
    }

    /// A value reference: mostly one of the variant's variables of the wanted type, sometimes
    /// any variable of the variant, sometimes an arbitrary u32.
    fn vr(&mut self, v: Variant, ty: u8) -> u32 {
        let t = table(v);
        match self.b.u8() % 8 {
            0 => match self.b.u8() % 4 {
                0 => 0,
                1 => u32::MAX,
                2 => self.b.u16() as u32 % 512,
                _ => self.b.u32(),
            },
            1 => {
                let k = self.b.u8() as usize % t.vars.len();
                t.vars[k].vr
            }
            _ => {
                let want: Vec<u32> = t
                    .vars
                    .iter()
                    .filter(|x| match ty {
                        0 => matches!(x.start, Start::Real(_)),
                        1 => matches!(x.start, Start::Integer(_)),
                        _ => matches!(x.start, Start::Boolean(_)),
                    })
                    .map(|x| x.vr)
                    .collect();
                if want.is_empty() {
                    self.b.u32()
                } else {
                    want[self.b.u8() as usize % want.len()]
                }
            }
        }
    }

    fn instantiate(&mut self, i: usize) {
        let sel = self.b.u8();
        let flags = self.b.u8();
        let variant = variant_of(sel as usize);
        let mut valid = true;
        let guid = match sel % 16 {
            14 => {
                valid = false;
                let n = self.b.u8() % 40;
                let bytes: Vec<u8> = (0..n).map(|_| self.b.u8().max(1)).collect();
                Some(CString::new(bytes).expect("no NUL"))
            }
            15 => {
                valid = false;
                None
            }
            _ => Some(CString::new(table(variant).guid.clone()).expect("no NUL")),
        };
        let name = match flags % 16 {
            13 => {
                valid = false;
                Some(CString::new("").expect("no NUL"))
            }
            14 => {
                valid = false;
                None
            }
            15 => {
                // random bytes (perhaps not UTF-8)
                let n = 1 + self.b.u8() % 12;
                let bytes: Vec<u8> = (0..n).map(|_| self.b.u8().max(1)).collect();
                valid &= std::str::from_utf8(&bytes).is_ok();
                Some(CString::new(bytes).expect("no NUL"))
            }
            _ => Some(CString::new(format!("fuzz{i}")).expect("no NUL")),
        };
        let fmu_type = match (flags >> 4) % 8 {
            6 => {
                valid = false;
                0
            }
            7 => {
                let t = self.b.u32() as c_int;
                valid &= t == CO_SIMULATION;
                t
            }
            _ => CO_SIMULATION,
        };
        let logging_on = (flags >> 7) & 1;
        let cb_kind = self.b.u8() % 16;
        let cb = callbacks(self.env.0, cb_kind != 15);
        let cb_ptr: *const fmi2CallbackFunctions = if cb_kind == 14 { null() } else { &cb };
        let has_logger = cb_kind < 14;
        valid &= has_logger;
        let ptr = |s: &Option<CString>| s.as_ref().map_or(null(), |s| s.as_ptr());
        let n0 = support::log_len(self.env.0);
        let c = fmi2Instantiate(
            ptr(&name),
            fmu_type,
            ptr(&guid),
            null(),
            cb_ptr,
            fmi2False,
            logging_on as fmi2Boolean,
        );
        self.trace.push(format!(
            "instantiate[{i}] {variant:?} valid={valid} type={fmu_type} logging={logging_on} cb={cb_kind} -> {}",
            !c.is_null()
        ));
        if c.is_null() {
            if valid {
                self.fail(format!(
                    "fmi2Instantiate refused valid arguments: {:?}",
                    support::log_since(self.env.0, n0)
                ));
            }
            let lines = support::log_since(self.env.0, n0);
            if has_logger && (lines.len() != 1 || lines[0].status != fmi2Status::Error as c_int) {
                self.fail(format!(
                    "fmi2Instantiate refusal must log one error: {lines:?}"
                ));
            }
        } else {
            if !valid {
                self.fail("fmi2Instantiate accepted invalid arguments".into());
            }
            self.inst[i] = Some(Inst { c, variant });
        }
    }

    fn free_instance(&mut self, i: usize) {
        if let Some(inst) = self.inst[i].take() {
            fmi2FreeInstance(inst.c);
        }
    }

    /// Reads every Real output (invariant 3) and Integer output; returns the Real bits and status.
    fn read_outputs(&mut self, i: usize) -> Option<(fmi2Status, Vec<u64>, Vec<i32>)> {
        let v = self.variant(i)?;
        let vrs = reals_of(v, |x| x.causality == Causality::Output);
        let mut out = vec![f64::NAN; vrs.len()];
        let s = self.call(i, "fmi2GetReal", |c| {
            fmi2GetReal(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr())
        });
        if s == OK {
            if let Some(k) = out.iter().position(|x| !x.is_finite()) {
                let name = &table(v).get(vrs[k]).expect("known").name;
                self.fail(format!("fmi2GetReal returned OK with {name} = {}", out[k]));
            }
        }
        let ivrs: Vec<u32> = table(v)
            .vars
            .iter()
            .filter(|x| x.causality == Causality::Output && matches!(x.start, Start::Integer(_)))
            .map(|x| x.vr)
            .collect();
        let mut iout = vec![i32::MIN; ivrs.len()];
        let si = self.call(i, "fmi2GetInteger", |c| {
            fmi2GetInteger(c, ivrs.as_ptr(), ivrs.len(), iout.as_mut_ptr())
        });
        if si != s {
            self.fail(format!(
                "fmi2GetReal {s:?} but fmi2GetInteger {si:?} on outputs"
            ));
        }
        Some((s, out.iter().map(|x| x.to_bits()).collect(), iout))
    }

    /// The FMU's current time when it can tell, else 0.
    fn fmu_time(&mut self, i: usize) -> f64 {
        let mut t = 0.0;
        let s = self.call(i, "fmi2GetRealStatus", |c| fmi2GetRealStatus(c, 2, &mut t));
        if s == OK {
            t
        } else {
            0.0
        }
    }

    fn do_step(&mut self, i: usize) -> Option<fmi2Status> {
        if self.steps >= MAX_STEPS {
            return None;
        }
        self.steps += 1;
        let h = self.b.step();
        let t = if self.b.u8().is_multiple_of(8) {
            self.b.real()
        } else {
            self.fmu_time(i)
        };
        self.trace.push(format!("doStep[{i}] t={t:e} h={h:e}"));
        let s = self.call(i, "fmi2DoStep", |c| fmi2DoStep(c, t, h, fmi2False));
        self.trace.push(format!("  -> {s:?}"));
        Some(s)
    }

    /// Serializes a slot through instance i; on success checks invariant 5 and stores the bytes.
    fn serialize(&mut self, i: usize, k: usize) {
        let Some(v) = self.variant(i) else { return };
        let slot = self.slots[k];
        let mut n: usize = 0;
        let s = self.call(i, "fmi2SerializedFMUstateSize", |c| {
            fmi2SerializedFMUstateSize(c, slot.s, &mut n)
        });
        if s == OK && !slot.s.is_null() && slot.variant != v {
            self.fail(format!(
                "fmi2SerializedFMUstateSize accepted a state of {:?} in a {v:?} instance",
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
            buf.as_mut_ptr().cast::<fmi2Byte>()
        };
        let s2 = self.call(i, "fmi2SerializeFMUstate", |c| {
            fmi2SerializeFMUstate(c, slot.s, p, size)
        });
        if s2 == OK && !slot.s.is_null() && slot.variant != v {
            self.fail(format!(
                "fmi2SerializeFMUstate accepted a state of {:?} in a {v:?} instance",
                slot.variant
            ));
        }
        if s2 == OK && s == OK && size >= n && n > 0 {
            buf.truncate(n);
            // invariant 5: the bytes are accepted and re-serialize identically
            let mut back: fmi2FMUstate = null_mut();
            let n_log = support::log_len(self.env.0);
            let s3 = self.call(i, "fmi2DeSerializeFMUstate", |c| {
                fmi2DeSerializeFMUstate(c, buf.as_ptr().cast(), n, &mut back)
            });
            if s3 != OK {
                let why: Vec<LogLine> = support::log_since(self.env.0, n_log)
                    .into_iter()
                    .filter(|l| l.status != 0)
                    .collect();
                self.fail(format!(
                    "fmi2DeSerializeFMUstate refused bytes fmi2SerializeFMUstate wrote: {s3:?} {why:?}"
                ));
            }
            let mut n2: usize = 0;
            let mut again = vec![0u8; n];
            let s4 = self.call(i, "fmi2SerializedFMUstateSize", |c| {
                fmi2SerializedFMUstateSize(c, back, &mut n2)
            });
            let s5 = self.call(i, "fmi2SerializeFMUstate", |c| {
                fmi2SerializeFMUstate(c, back, again.as_mut_ptr().cast(), n)
            });
            if s4 != OK || s5 != OK || n2 != n || again != buf {
                self.fail("serialize → deserialize → serialize is not the identity".into());
            }
            self.call(i, "fmi2FreeFMUstate", |c| fmi2FreeFMUstate(c, &mut back));
            if self.bufs.len() >= 2 {
                self.bufs.remove(0);
            }
            self.bufs.push((buf, v));
        }
    }

    /// De-serializes (mutated) bytes into a slot.
    fn deserialize(&mut self, i: usize, k: usize) {
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
        let p: *const fmi2Byte = if size != bytes.len() {
            null()
        } else {
            bytes.as_ptr().cast()
        };
        self.trace.push(format!(
            "deserialize[{i}] -> slot {k} (len {size}, from {from:?}, mutated {mutated})"
        ));
        let mut slot = self.slots[k];
        let s = self.call(i, "fmi2DeSerializeFMUstate", |c| {
            fmi2DeSerializeFMUstate(c, p, size, &mut slot.s)
        });
        if s == OK {
            slot.variant = v;
            if !mutated && from.is_some_and(|f| f != v) {
                self.fail(format!(
                    "fmi2DeSerializeFMUstate accepted a {from:?} state in {v:?}"
                ));
            }
        }
        self.slots[k] = slot;
    }

    /// Invariant 6: restore a state, repeat a step, compare.
    fn replay(&mut self, i: usize) {
        let Some(_) = self.variant(i) else { return };
        if self.steps + 2 > MAX_STEPS {
            return;
        }
        self.steps += 2;
        let mut s: fmi2FMUstate = null_mut();
        if self.call(i, "fmi2GetFMUstate", |c| fmi2GetFMUstate(c, &mut s)) != OK {
            return;
        }
        let h = self.b.step();
        let t = self.fmu_time(i);
        self.trace.push(format!("replay[{i}] t={t:e} h={h:e}"));
        let s1 = self.call(i, "fmi2DoStep", |c| fmi2DoStep(c, t, h, fmi2False));
        let y1 = self.read_outputs(i);
        let r = self.call(i, "fmi2SetFMUstate", |c| fmi2SetFMUstate(c, s));
        if r != OK {
            self.fail(format!(
                "fmi2SetFMUstate of its own fresh state failed: {r:?}"
            ));
        }
        let s2 = self.call(i, "fmi2DoStep", |c| fmi2DoStep(c, t, h, fmi2False));
        let y2 = self.read_outputs(i);
        if s1 != s2 || y1 != y2 {
            self.fail(format!(
                "repeating a step after fmi2SetFMUstate differs: {s1:?} vs {s2:?}, outputs equal: {}",
                y1 == y2
            ));
        }
        self.call(i, "fmi2FreeFMUstate", |c| fmi2FreeFMUstate(c, &mut s));
    }

    fn set_reals(&mut self, i: usize, v: Variant) {
        let n = 1 + self.b.u8() as usize % 4;
        let mut vrs = Vec::with_capacity(n);
        let mut xs = Vec::with_capacity(n);
        for _ in 0..n {
            vrs.push(self.vr(v, 0));
            xs.push(self.b.real());
        }
        self.trace.push(format!("setReal[{i}] {vrs:?} {xs:?}"));
        self.call(i, "fmi2SetReal", |c| {
            fmi2SetReal(c, vrs.as_ptr(), n, xs.as_ptr())
        });
    }

    /// A coherent parameter set: each parameter of the variant set (or not) to a plausible
    /// value, sometimes an awkward one; Integer parameters 0/1.
    fn param_set(&mut self, i: usize, v: Variant) {
        let mut vrs = Vec::new();
        let mut xs = Vec::new();
        let mut ivrs = Vec::new();
        let mut ixs = Vec::new();
        for var in &table(v).vars {
            if var.causality != Causality::Parameter || self.b.u8() < 100 {
                continue;
            }
            match var.start {
                Start::Real(_) => {
                    vrs.push(var.vr);
                    xs.push(self.b.param_value(&var.name));
                }
                Start::Integer(_) => {
                    ivrs.push(var.vr);
                    ixs.push((self.b.u8() % 3) as i32);
                }
                Start::Boolean(_) => {}
            }
        }
        self.trace
            .push(format!("paramSet[{i}] {vrs:?} {xs:?} int {ivrs:?} {ixs:?}"));
        self.call(i, "fmi2SetReal", |c| {
            fmi2SetReal(c, vrs.as_ptr(), vrs.len(), xs.as_ptr())
        });
        self.call(i, "fmi2SetInteger", |c| {
            fmi2SetInteger(c, ivrs.as_ptr(), ivrs.len(), ixs.as_ptr())
        });
    }

    /// A plausible motion: positions, orientations, velocities, angular velocities.
    fn motion(&mut self, i: usize, v: Variant) {
        let mut vrs = Vec::new();
        let mut xs = Vec::new();
        let scale = [0.01, 0.1, 1.0, 10.0][self.b.u8() as usize % 4];
        for node in ["a", "b"] {
            let q = self.b.quat();
            for var in &table(v).vars {
                if var.causality != Causality::Input || !var.name.starts_with(node) {
                    continue;
                }
                let x = match &var.name[2..] {
                    "q.w" => q[0],
                    "q.x" => q[1],
                    "q.y" => q[2],
                    "q.z" => q[3],
                    _ => scale * self.b.unit(),
                };
                vrs.push(var.vr);
                xs.push(x);
            }
        }
        self.trace.push(format!("motion[{i}] {xs:?}"));
        self.call(i, "fmi2SetReal", |c| {
            fmi2SetReal(c, vrs.as_ptr(), vrs.len(), xs.as_ptr())
        });
    }

    fn op(&mut self) {
        let i = (self.b.u8() & 1) as usize;
        if self.inst[i].is_none() {
            // an instance slot that is empty: make one (or stop trying when it is refused)
            self.instantiate(i);
            return;
        }
        let v = self.variant(i).expect("live");
        let op = self.b.u8() % 32;
        match op {
            0..=2 => self.set_reals(i, v),
            3 => {
                let vr = self.vr(v, 1);
                let x = match self.b.u8() % 6 {
                    0 => i32::MIN,
                    1 => i32::MAX,
                    2 => -1,
                    _ => (self.b.u8() % 3) as i32,
                };
                self.trace.push(format!("setInteger[{i}] {vr} {x}"));
                self.call(i, "fmi2SetInteger", |c| fmi2SetInteger(c, &vr, 1, &x));
            }
            4 => {
                let vr = self.vr(v, 2);
                let x = [0, 1, 2, -1][self.b.u8() as usize % 4];
                self.trace.push(format!("setBoolean[{i}] {vr} {x}"));
                self.call(i, "fmi2SetBoolean", |c| fmi2SetBoolean(c, &vr, 1, &x));
            }
            5 => {
                let node = if self.b.u8().is_multiple_of(2) {
                    "a"
                } else {
                    "b"
                };
                let q = self.b.quat();
                let vrs: Vec<u32> = ["w", "x", "y", "z"]
                    .iter()
                    .filter_map(|c| {
                        let name = format!("{node}.q.{c}");
                        table(v).vars.iter().find(|x| x.name == name).map(|x| x.vr)
                    })
                    .collect();
                if vrs.len() == 4 {
                    self.trace.push(format!("setQuat[{i}] {node} {q:?}"));
                    self.call(i, "fmi2SetReal", |c| {
                        fmi2SetReal(c, vrs.as_ptr(), 4, q.as_ptr())
                    });
                }
            }
            6 => self.param_set(i, v),
            7 => self.motion(i, v),
            8 => {
                let start = if self.b.u8().is_multiple_of(4) {
                    self.b.real()
                } else {
                    0.0
                };
                let stop_def = self.b.u8() % 2;
                let stop = self.b.real();
                self.trace.push(format!("setup[{i}] {start:e}"));
                self.call(i, "fmi2SetupExperiment", |c| {
                    fmi2SetupExperiment(c, fmi2False, 0.0, start, stop_def as fmi2Boolean, stop)
                });
            }
            9 => {
                self.trace.push(format!("enterInit[{i}]"));
                self.call(i, "fmi2EnterInitializationMode", |c| {
                    fmi2EnterInitializationMode(c)
                });
            }
            10 => {
                let s = self.call(i, "fmi2ExitInitializationMode", |c| {
                    fmi2ExitInitializationMode(c)
                });
                self.trace.push(format!("exitInit[{i}] -> {s:?}"));
            }
            11..=13 => {
                self.do_step(i);
            }
            14 => {
                self.trace.push(format!("readOutputs[{i}]"));
                self.read_outputs(i);
            }
            15 => {
                // random reads of any type
                let ty = self.b.u8() % 3;
                let n = self.b.u8() as usize % 5;
                let vrs: Vec<u32> = (0..n).map(|_| self.vr(v, ty)).collect();
                self.trace.push(format!("get[{i}] type {ty} {vrs:?}"));
                match ty {
                    0 => {
                        let mut out = vec![0.0; n];
                        let s = self.call(i, "fmi2GetReal", |c| {
                            fmi2GetReal(c, vrs.as_ptr(), n, out.as_mut_ptr())
                        });
                        if s == OK {
                            for (vr, x) in vrs.iter().zip(&out) {
                                if is_real_output(v, *vr) && !x.is_finite() {
                                    self.fail(format!("fmi2GetReal OK with output vr {vr} = {x}"));
                                }
                            }
                        }
                    }
                    1 => {
                        let mut out = vec![0; n];
                        self.call(i, "fmi2GetInteger", |c| {
                            fmi2GetInteger(c, vrs.as_ptr(), n, out.as_mut_ptr())
                        });
                    }
                    _ => {
                        let mut out = vec![0; n];
                        self.call(i, "fmi2GetBoolean", |c| {
                            fmi2GetBoolean(c, vrs.as_ptr(), n, out.as_mut_ptr())
                        });
                    }
                }
            }
            16 => {
                let k = self.b.u8() as usize % 4;
                self.trace.push(format!("getState[{i}] -> slot {k}"));
                let mut slot = self.slots[k];
                if self.call(i, "fmi2GetFMUstate", |c| fmi2GetFMUstate(c, &mut slot.s)) == OK {
                    slot.variant = v;
                }
                self.slots[k] = slot;
            }
            17 => {
                let k = self.b.u8() as usize % 4;
                let slot = self.slots[k];
                self.trace
                    .push(format!("setState[{i}] <- slot {k} ({:?})", slot.variant));
                let s = self.call(i, "fmi2SetFMUstate", |c| fmi2SetFMUstate(c, slot.s));
                if s == OK && slot.variant != v {
                    self.fail(format!(
                        "fmi2SetFMUstate accepted a {:?} state in {v:?}",
                        slot.variant
                    ));
                }
            }
            18 => {
                let k = self.b.u8() as usize % 4;
                self.trace.push(format!("freeState[{i}] slot {k}"));
                let mut slot = self.slots[k];
                self.call(i, "fmi2FreeFMUstate", |c| fmi2FreeFMUstate(c, &mut slot.s));
                if !slot.s.is_null() {
                    self.fail("fmi2FreeFMUstate did not set the handle to NULL".into());
                }
                self.slots[k] = slot;
            }
            19 => {
                let k = self.b.u8() as usize % 4;
                self.trace.push(format!("serialize[{i}] slot {k}"));
                self.serialize(i, k);
            }
            20 => {
                let k = self.b.u8() as usize % 4;
                self.deserialize(i, k);
            }
            21 => {
                self.trace.push(format!("reset[{i}]"));
                self.call(i, "fmi2Reset", |c| fmi2Reset(c));
            }
            22 => {
                self.trace.push(format!("terminate[{i}]"));
                self.call(i, "fmi2Terminate", |c| fmi2Terminate(c));
            }
            23 => {
                // directional derivative of outputs w.r.t. inputs (sometimes anything)
                let outs = reals_of(v, |x| {
                    x.causality == Causality::Output && x.variability == Variability::Continuous
                });
                let ins = reals_of(v, |x| x.causality == Causality::Input);
                let nu = self.b.u8() as usize % 6;
                let nk = self.b.u8() as usize % 6;
                let unknowns: Vec<u32> = (0..nu)
                    .map(|_| {
                        if self.b.u8().is_multiple_of(8) {
                            self.vr(v, 0)
                        } else {
                            outs[self.b.u8() as usize % outs.len()]
                        }
                    })
                    .collect();
                let knowns: Vec<u32> = (0..nk)
                    .map(|_| {
                        if self.b.u8().is_multiple_of(8) {
                            self.vr(v, 0)
                        } else {
                            ins[self.b.u8() as usize % ins.len()]
                        }
                    })
                    .collect();
                let seeds: Vec<f64> = (0..nk)
                    .map(|_| {
                        if self.b.u8().is_multiple_of(2) {
                            self.b.real()
                        } else {
                            self.b.unit()
                        }
                    })
                    .collect();
                let mut out = vec![f64::NAN; nu];
                self.trace
                    .push(format!("dirDer[{i}] {unknowns:?} {knowns:?} {seeds:?}"));
                let s = self.call(i, "fmi2GetDirectionalDerivative", |c| {
                    fmi2GetDirectionalDerivative(
                        c,
                        unknowns.as_ptr(),
                        nu,
                        knowns.as_ptr(),
                        nk,
                        seeds.as_ptr(),
                        out.as_mut_ptr(),
                    )
                });
                if s == OK {
                    if let Some(x) = out.iter().find(|x| !x.is_finite()) {
                        self.fail(format!("fmi2GetDirectionalDerivative OK with a value {x}"));
                    }
                }
            }
            24 => {
                let n = 1 + self.b.u8() as usize % 4;
                let vrs: Vec<u32> = (0..n).map(|_| self.vr(v, 0)).collect();
                let orders: Vec<c_int> = (0..n)
                    .map(|_| [1, 1, 1, 0, 2, -1][self.b.u8() as usize % 6])
                    .collect();
                let xs: Vec<f64> = (0..n).map(|_| self.b.real()).collect();
                self.trace
                    .push(format!("inputDer[{i}] {vrs:?} {orders:?} {xs:?}"));
                self.call(i, "fmi2SetRealInputDerivatives", |c| {
                    fmi2SetRealInputDerivatives(c, vrs.as_ptr(), n, orders.as_ptr(), xs.as_ptr())
                });
            }
            25 => {
                let on = self.b.u8() % 2;
                let n = self.b.u8() as usize % 4;
                let names: Vec<CString> = (0..n)
                    .map(|_| match self.b.u8() % 6 {
                        0 => c"logEvents".to_owned(),
                        1 => c"logAll".to_owned(),
                        2 => c"logStatusError".to_owned(),
                        3 => c"logStatusWarning".to_owned(),
                        _ => {
                            let k = self.b.u8() % 10;
                            let bytes: Vec<u8> = (0..k).map(|_| self.b.u8().max(1)).collect();
                            CString::new(bytes).expect("no NUL")
                        }
                    })
                    .collect();
                let ptrs: Vec<*const c_char> = names.iter().map(|s| s.as_ptr()).collect();
                let p = if n == 0 && self.b.u8().is_multiple_of(2) {
                    null()
                } else {
                    ptrs.as_ptr()
                };
                self.trace.push(format!("debugLogging[{i}] {on} {names:?}"));
                self.call(i, "fmi2SetDebugLogging", |c| {
                    fmi2SetDebugLogging(c, on as fmi2Boolean, n, p)
                });
            }
            26 => {
                let kind = [0, 1, 2, 3, -1, 99][self.b.u8() as usize % 6];
                let which = self.b.u8() % 5;
                self.trace
                    .push(format!("status[{i}] fn {which} kind {kind}"));
                match which {
                    0 => {
                        let mut x = OK;
                        self.call(i, "fmi2GetStatus", |c| fmi2GetStatus(c, kind, &mut x));
                    }
                    1 => {
                        let mut x = 0.0;
                        let s = self.call(i, "fmi2GetRealStatus", |c| {
                            fmi2GetRealStatus(c, kind, &mut x)
                        });
                        if s == OK && !x.is_finite() {
                            self.fail(format!("fmi2GetRealStatus OK with {x}"));
                        }
                    }
                    2 => {
                        let mut x = 0;
                        self.call(i, "fmi2GetIntegerStatus", |c| {
                            fmi2GetIntegerStatus(c, kind, &mut x)
                        });
                    }
                    3 => {
                        let mut x = 0;
                        self.call(i, "fmi2GetBooleanStatus", |c| {
                            fmi2GetBooleanStatus(c, kind, &mut x)
                        });
                    }
                    _ => {
                        let mut x: fmi2String = null();
                        self.call(i, "fmi2GetStringStatus", |c| {
                            fmi2GetStringStatus(c, kind, &mut x)
                        });
                    }
                }
            }
            27 => {
                self.trace.push(format!("cancel/outputDer/strings[{i}]"));
                self.call(i, "fmi2CancelStep", |c| fmi2CancelStep(c));
                let vr = self.vr(v, 0);
                let order = 1;
                let mut x = 0.0;
                let n = self.b.u8() as usize % 2;
                self.call(i, "fmi2GetRealOutputDerivatives", |c| {
                    fmi2GetRealOutputDerivatives(c, &vr, n, &order, &mut x)
                });
                let mut sx: fmi2String = null();
                self.call(i, "fmi2GetString", |c| fmi2GetString(c, &vr, n, &mut sx));
                let val = c"x".as_ptr();
                self.call(i, "fmi2SetString", |c| fmi2SetString(c, &vr, n, &val));
            }
            28 => {
                // NULL arrays with a count (refused) and (NULL, 0) (legal)
                let n = self.b.u8() as usize % 3;
                self.trace.push(format!("nullArrays[{i}] n={n}"));
                self.call(i, "fmi2SetReal", |c| fmi2SetReal(c, null(), n, null()));
                self.call(i, "fmi2GetReal", |c| fmi2GetReal(c, null(), n, null_mut()));
                self.call(i, "fmi2SetRealInputDerivatives", |c| {
                    fmi2SetRealInputDerivatives(c, null(), n, null(), null())
                });
                self.call(i, "fmi2GetFMUstate", |c| fmi2GetFMUstate(c, null_mut()));
            }
            29 => self.replay(i),
            30 => {
                self.trace.push(format!("free[{i}]"));
                self.free_instance(i);
            }
            _ => {
                // a short run of plain steps: drives the friction and stop state
                let n = 1 + self.b.u8() % 4;
                for _ in 0..n {
                    if self.do_step(i).is_none() {
                        break;
                    }
                }
                self.read_outputs(i);
            }
        }
    }
}

/// Runs one program. Panics when an invariant is violated.
pub fn run(data: &[u8]) {
    let mut p = Program {
        env: Env(support::new_env()),
        b: Bytes::new(data),
        inst: [None, None],
        slots: [Slot {
            s: null_mut(),
            variant: Variant::Bushing,
        }; 4],
        bufs: Vec::new(),
        steps: 0,
        trace: Vec::new(),
    };
    p.instantiate(0);
    let mut ops = 0;
    while !p.b.done() && ops < MAX_OPS {
        p.op();
        ops += 1;
    }
    // release every state through a live instance (making one when none is left), then the
    // instances: nothing may leak (LeakSanitizer checks under cargo fuzz)
    if p.slots.iter().any(|s| !s.s.is_null()) && p.inst.iter().all(Option::is_none) {
        let cb = callbacks(p.env.0, true);
        let guid = CString::new(table(Variant::Bushing).guid.clone()).expect("no NUL");
        let c = fmi2Instantiate(
            c"cleanup".as_ptr(),
            CO_SIMULATION,
            guid.as_ptr(),
            null(),
            &cb,
            fmi2False,
            fmi2False,
        );
        assert!(!c.is_null(), "cleanup instance");
        p.inst[0] = Some(Inst {
            c,
            variant: Variant::Bushing,
        });
    }
    let c = p.inst.iter().flatten().next().map(|x| x.c);
    for k in 0..4 {
        if let Some(c) = c {
            let mut s = p.slots[k].s;
            assert_eq!(fmi2FreeFMUstate(c, &mut s), OK, "free state {k}");
            p.slots[k].s = s;
        }
    }
    p.free_instance(0);
    p.free_instance(1);
    if trace_wanted() {
        eprintln!("program of {} bytes: {:#?}", data.len(), p.trace);
    }
}

/// `FMI_FUZZ_TRACE=1` prints each program's operations (to read what an input does).
fn trace_wanted() -> bool {
    static WANTED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    *WANTED.get_or_init(|| std::env::var_os("FMI_FUZZ_TRACE").is_some())
}
