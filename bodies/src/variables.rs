//! THE variable table of the Body FMU: every variable once — name, value reference, causality,
//! variability, type, start, unit, min/max, description and where its value lives. The model
//! descriptions of both FMI versions, the start values, the setters' range checks and the
//! GUID all come from here. Edit a row, then regenerate the committed XML with
//! `cargo run --bin gen_body_model_description`. Uses nothing else of the crate; from
//! `fmi_shared`, the causality and variability enums and the value reference of FMI 3.0's
//! `time`.

use std::sync::OnceLock;

/// modelIdentifier and modelName.
pub const MODEL_IDENTIFIER: &str = "Body";
/// The model description's `description`.
pub const DESCRIPTION: &str = "Body: a rigid body under gravity, a force and a moment, integrated per communication step as the project's zero-order-hold master does (model 0: exact per world axis; model 1: free 3-D rigid body, RK4)";

/// Causality and variability (parameters are fixed, inputs and outputs continuous; the Body
/// uses no other variability), the same enums as the connector FMU's (`fmi_shared`).
pub use fmi_shared::model_description::{Causality, Variability};

/// An output, computed from the body's state when read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Out {
    /// position r[i] (m, W)
    R(usize),
    /// orientation quaternion component (0 = w, 1..3 = x, y, z)
    Q(usize),
    /// velocity v[i] (m/s, W)
    V(usize),
    /// angular velocity w[i] (rad/s, W)
    W(usize),
    /// port k's (0-based) point r[i] (m, W)
    PortR(usize, usize),
    /// port k's frame orientation component (port → W; 0 = w, 1..3 = x, y, z)
    PortQ(usize, usize),
    /// port k's point velocity v[i] (m/s, W)
    PortV(usize, usize),
    /// port k's angular velocity w[i] (rad/s, W): the body's
    PortW(usize, usize),
    /// kinetic energy (J)
    Kinetic,
    /// potential energy (J)
    Potential,
}

/// Where a variable's value lives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// a Real parameter or input: index into the instance's Real values (`real::*`)
    Real(usize),
    /// an Integer parameter: index into the instance's Integer values (`int::*`)
    Int(usize),
    /// an output
    Out(Out),
}

/// One row of the table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Var {
    /// valueReference
    pub vr: u32,
    /// name
    pub name: &'static str,
    /// causality
    pub causality: Causality,
    /// variability
    pub variability: Variability,
    /// storage (and with it the type: `Slot::Int` is Integer, the others Real)
    pub slot: Slot,
    /// start value (parameters and inputs; an Integer's is integral); None for outputs
    pub start: Option<f64>,
    /// unit ("" = none)
    pub unit: &'static str,
    /// smallest accepted value, inclusive (FMI `min`)
    pub min: Option<f64>,
    /// largest accepted value, inclusive (FMI `max`)
    pub max: Option<f64>,
    /// description
    pub description: &'static str,
}

impl Var {
    /// True for an Integer variable.
    pub fn is_integer(&self) -> bool {
        matches!(self.slot, Slot::Int(_))
    }

    /// Ok when `x` lies in [min, max]; otherwise the message naming the variable and bound.
    pub fn check_range(&self, x: f64) -> Result<(), String> {
        let show = |x: f64| match self.is_integer() {
            true => format!("{}", x as i64),
            false => format!("{x:?}"),
        };
        let bound = match (self.min, self.max) {
            (Some(min), _) if x < min && min == POSITIVE => "> 0".to_string(),
            (Some(min), _) if x < min => format!(">= {}", show(min)),
            (_, Some(max)) if x > max => format!("<= {}", show(max)),
            _ => return Ok(()),
        };
        Err(format!(
            "{} = {} is refused: it must be {bound}",
            self.name,
            show(x)
        ))
    }
}

/// Slots of the Real parameters and inputs.
pub mod real {
    /// mass
    pub const MASS: usize = 0;
    /// inertia[1..3]
    pub const INERTIA: usize = 1;
    /// gravity[1..3]
    pub const GRAVITY: usize = 4;
    /// spring.k[1..3]
    pub const SPRING: usize = 7;
    /// start.r[1..3]
    pub const START_R: usize = 10;
    /// start.q.w, .x, .y, .z
    pub const START_Q: usize = 13;
    /// start.v[1..3]
    pub const START_V: usize = 17;
    /// start.w[1..3]
    pub const START_W: usize = 20;
    /// rigid.maxTurn
    pub const MAX_TURN: usize = 23;
    /// f[1..3] (input)
    pub const F: usize = 24;
    /// m[1..3] (input)
    pub const M: usize = 27;
    /// port 1's first slot; port k (1-based) starts at PORT + (k − 1)·PORT_LEN
    pub const PORT: usize = 30;
    /// within a port: offset.r[1..3]
    pub const PORT_OFFSET_R: usize = 0;
    /// within a port: offset.q.w, .x, .y, .z
    pub const PORT_OFFSET_Q: usize = 3;
    /// within a port: f[1..3] (input)
    pub const PORT_F: usize = 7;
    /// within a port: m[1..3] (input)
    pub const PORT_M: usize = 10;
    /// slots per port
    pub const PORT_LEN: usize = 13;
    /// number of Real slots
    pub const N: usize = PORT + super::PORTS * PORT_LEN;
}

/// Number of load ports, `port[1]` … `port[4]`.
pub const PORTS: usize = 4;

/// Slots of the Integer parameters.
pub mod int {
    /// model
    pub const MODEL: usize = 0;
    /// dof.r[1..3]
    pub const DOF_R: usize = 1;
    /// dof.w[1..3]
    pub const DOF_W: usize = 4;
    /// number of Integer slots
    pub const N: usize = 7;
}

/// FMI 3.0's independent variable `time` (no row uses value reference 0; the model description
/// declares it as `fmi_shared` does).
pub const TIME_VR: u32 = fmi_shared::model_description::fmi3::TIME_VR;

/// `min` of a quantity that must be > 0: the smallest positive double (0 itself is refused).
pub const POSITIVE: f64 = f64::from_bits(1);

type Range = (Option<f64>, Option<f64>);
const ANY: Range = (None, None);
const GT0: Range = (Some(POSITIVE), None);
const GE0: Range = (Some(0.0), None);
const DOF: Range = (Some(0.0), Some(2.0));

const fn par(
    vr: u32,
    name: &'static str,
    slot: usize,
    start: f64,
    unit: &'static str,
    range: Range,
    description: &'static str,
) -> Var {
    Var {
        vr,
        name,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        slot: Slot::Real(slot),
        start: Some(start),
        unit,
        min: range.0,
        max: range.1,
        description,
    }
}

const fn ipar(
    vr: u32,
    name: &'static str,
    slot: usize,
    start: i32,
    range: Range,
    d: &'static str,
) -> Var {
    Var {
        slot: Slot::Int(slot),
        start: Some(start as f64),
        ..par(vr, name, 0, 0.0, "", range, d)
    }
}

const fn input(
    vr: u32,
    name: &'static str,
    slot: usize,
    unit: &'static str,
    d: &'static str,
) -> Var {
    Var {
        causality: Causality::Input,
        variability: Variability::Continuous,
        ..par(vr, name, slot, 0.0, unit, ANY, d)
    }
}

const fn output(vr: u32, name: &'static str, out: Out, unit: &'static str, d: &'static str) -> Var {
    Var {
        causality: Causality::Output,
        variability: Variability::Continuous,
        slot: Slot::Out(out),
        start: None,
        ..par(vr, name, 0, 0.0, unit, ANY, d)
    }
}

use real::*;

/// Rows of the body's own variables (value references 1–551).
const BODY_ROWS: usize = 52;
/// Rows of one port.
const PORT_ROWS: usize = 26;

/// The 26 rows of port `$k` (1-based), value references `$base` + 1…6 (inputs f, m), + 101…113
/// (outputs r, q, v, w), + 501…507 (parameters offset.r, offset.q): the body's own numbering
/// moved up by `$base`.
#[rustfmt::skip]
macro_rules! port_rows {
    ($k:literal, $base:literal) => {{
        const S: usize = real::PORT + ($k - 1) * real::PORT_LEN;
        const K: usize = $k - 1;
        const FF: usize = S + real::PORT_F;
        const MM: usize = S + real::PORT_M;
        const OR: usize = S + real::PORT_OFFSET_R;
        const OQ: usize = S + real::PORT_OFFSET_Q;
        [
            input($base + 1, concat!("port[", $k, "].f[1]"), FF, "N", concat!("force on the body at port ", $k, "'s point, world x")),
            input($base + 2, concat!("port[", $k, "].f[2]"), FF + 1, "N", concat!("force on the body at port ", $k, "'s point, world y")),
            input($base + 3, concat!("port[", $k, "].f[3]"), FF + 2, "N", concat!("force on the body at port ", $k, "'s point, world z")),
            input($base + 4, concat!("port[", $k, "].m[1]"), MM, "N.m", concat!("moment on the body at port ", $k, ", world x")),
            input($base + 5, concat!("port[", $k, "].m[2]"), MM + 1, "N.m", concat!("moment on the body at port ", $k, ", world y")),
            input($base + 6, concat!("port[", $k, "].m[3]"), MM + 2, "N.m", concat!("moment on the body at port ", $k, ", world z")),
            output($base + 101, concat!("port[", $k, "].r[1]"), Out::PortR(K, 0), "m", concat!("position of port ", $k, "'s point, world x")),
            output($base + 102, concat!("port[", $k, "].r[2]"), Out::PortR(K, 1), "m", concat!("position of port ", $k, "'s point, world y")),
            output($base + 103, concat!("port[", $k, "].r[3]"), Out::PortR(K, 2), "m", concat!("position of port ", $k, "'s point, world z")),
            output($base + 104, concat!("port[", $k, "].q.w"), Out::PortQ(K, 0), "", concat!("orientation port ", $k, " -> world, unit quaternion, scalar part")),
            output($base + 105, concat!("port[", $k, "].q.x"), Out::PortQ(K, 1), "", concat!("orientation port ", $k, " -> world, unit quaternion, x")),
            output($base + 106, concat!("port[", $k, "].q.y"), Out::PortQ(K, 2), "", concat!("orientation port ", $k, " -> world, unit quaternion, y")),
            output($base + 107, concat!("port[", $k, "].q.z"), Out::PortQ(K, 3), "", concat!("orientation port ", $k, " -> world, unit quaternion, z")),
            output($base + 108, concat!("port[", $k, "].v[1]"), Out::PortV(K, 0), "m/s", concat!("velocity of port ", $k, "'s point, world x")),
            output($base + 109, concat!("port[", $k, "].v[2]"), Out::PortV(K, 1), "m/s", concat!("velocity of port ", $k, "'s point, world y")),
            output($base + 110, concat!("port[", $k, "].v[3]"), Out::PortV(K, 2), "m/s", concat!("velocity of port ", $k, "'s point, world z")),
            output($base + 111, concat!("port[", $k, "].w[1]"), Out::PortW(K, 0), "rad/s", concat!("angular velocity of port ", $k, " (the body's), world x")),
            output($base + 112, concat!("port[", $k, "].w[2]"), Out::PortW(K, 1), "rad/s", concat!("angular velocity of port ", $k, " (the body's), world y")),
            output($base + 113, concat!("port[", $k, "].w[3]"), Out::PortW(K, 2), "rad/s", concat!("angular velocity of port ", $k, " (the body's), world z")),
            par($base + 501, concat!("port[", $k, "].offset.r[1]"), OR, 0.0, "m", ANY, concat!("port ", $k, "'s point in the body frame (from the centre of mass), axis 1")),
            par($base + 502, concat!("port[", $k, "].offset.r[2]"), OR + 1, 0.0, "m", ANY, concat!("port ", $k, "'s point in the body frame (from the centre of mass), axis 2")),
            par($base + 503, concat!("port[", $k, "].offset.r[3]"), OR + 2, 0.0, "m", ANY, concat!("port ", $k, "'s point in the body frame (from the centre of mass), axis 3")),
            par($base + 504, concat!("port[", $k, "].offset.q.w"), OQ, 1.0, "", ANY, concat!("port ", $k, "'s frame -> body frame (normalised), scalar part")),
            par($base + 505, concat!("port[", $k, "].offset.q.x"), OQ + 1, 0.0, "", ANY, concat!("port ", $k, "'s frame -> body frame (normalised), x")),
            par($base + 506, concat!("port[", $k, "].offset.q.y"), OQ + 2, 0.0, "", ANY, concat!("port ", $k, "'s frame -> body frame (normalised), y")),
            par($base + 507, concat!("port[", $k, "].offset.q.z"), OQ + 3, 0.0, "", ANY, concat!("port ", $k, "'s frame -> body frame (normalised), z")),
        ]
    }};
}

/// Every variable, in value-reference order (the order of the model descriptions): the body's
/// own, then port 1's (value references 1001–1507), port 2's (2001–2507), … port 4's.
pub static VARS: [Var; BODY_ROWS + PORTS * PORT_ROWS] = join(
    &BODY,
    &[
        port_rows!(1, 1000),
        port_rows!(2, 2000),
        port_rows!(3, 3000),
        port_rows!(4, 4000),
    ],
);

/// The body's own rows followed by the ports' (a const copy: the table stays one static).
const fn join(
    body: &[Var; BODY_ROWS],
    ports: &[[Var; PORT_ROWS]; PORTS],
) -> [Var; BODY_ROWS + PORTS * PORT_ROWS] {
    let mut out = [body[0]; BODY_ROWS + PORTS * PORT_ROWS];
    let mut i = 0;
    while i < BODY_ROWS {
        out[i] = body[i];
        i += 1;
    }
    let mut k = 0;
    while k < PORTS {
        let mut j = 0;
        while j < PORT_ROWS {
            out[BODY_ROWS + k * PORT_ROWS + j] = ports[k][j];
            j += 1;
        }
        k += 1;
    }
    out
}

/// The body's own rows: centre-of-mass load, state outputs, energies, parameters.
const BODY: [Var; BODY_ROWS] = [
    input(1, "f[1]", F, "N", "force on the body at its centre of mass, world x"),
    input(2, "f[2]", F + 1, "N", "force on the body at its centre of mass, world y"),
    input(3, "f[3]", F + 2, "N", "force on the body at its centre of mass, world z"),
    input(4, "m[1]", M, "N.m", "moment on the body about its centre of mass, world x"),
    input(5, "m[2]", M + 1, "N.m", "moment on the body about its centre of mass, world y"),
    input(6, "m[3]", M + 2, "N.m", "moment on the body about its centre of mass, world z"),
    output(101, "r[1]", Out::R(0), "m", "position of the centre of mass, world x"),
    output(102, "r[2]", Out::R(1), "m", "position of the centre of mass, world y"),
    output(103, "r[3]", Out::R(2), "m", "position of the centre of mass, world z"),
    output(104, "q.w", Out::Q(0), "", "orientation body -> world, unit quaternion, scalar part"),
    output(105, "q.x", Out::Q(1), "", "orientation body -> world, unit quaternion, x"),
    output(106, "q.y", Out::Q(2), "", "orientation body -> world, unit quaternion, y"),
    output(107, "q.z", Out::Q(3), "", "orientation body -> world, unit quaternion, z"),
    output(108, "v[1]", Out::V(0), "m/s", "velocity of the centre of mass, world x"),
    output(109, "v[2]", Out::V(1), "m/s", "velocity of the centre of mass, world y"),
    output(110, "v[3]", Out::V(2), "m/s", "velocity of the centre of mass, world z"),
    output(111, "w[1]", Out::W(0), "rad/s", "angular velocity, world x"),
    output(112, "w[2]", Out::W(1), "rad/s", "angular velocity, world y"),
    output(113, "w[3]", Out::W(2), "rad/s", "angular velocity, world z"),
    output(121, "energy.kinetic", Out::Kinetic, "J", "kinetic energy: translation and rotation"),
    output(122, "energy.potential", Out::Potential, "J", "potential energy: -mass gravity.r + sum of spring.k[i] r[i]^2/2"),
    par(501, "mass", MASS, 1.0, "kg", GT0, "mass, > 0"),
    par(502, "inertia[1]", INERTIA, 1.0, "kg.m2", GT0, "principal moment of inertia about body axis 1, > 0 (model 0: about world x)"),
    par(503, "inertia[2]", INERTIA + 1, 1.0, "kg.m2", GT0, "principal moment of inertia about body axis 2, > 0 (model 0: about world y)"),
    par(504, "inertia[3]", INERTIA + 2, 1.0, "kg.m2", GT0, "principal moment of inertia about body axis 3, > 0 (model 0: about world z)"),
    par(505, "gravity[1]", GRAVITY, 0.0, "m/s2", ANY, "gravitational acceleration, world x"),
    par(506, "gravity[2]", GRAVITY + 1, 0.0, "m/s2", ANY, "gravitational acceleration, world y"),
    par(507, "gravity[3]", GRAVITY + 2, 0.0, "m/s2", ANY, "gravitational acceleration, world z"),
    ipar(511, "model", int::MODEL, 0, (Some(0.0), Some(1.0)), "0 axes: each degree of freedom along or about a world axis, integrated exactly; 1 rigid: free 3-D rigid body, RK4"),
    ipar(512, "dof.r[1]", int::DOF_R, 1, DOF, "model 0, translation along world x: 0 fixed at its start value, 1 free, 2 prescribed: moves at its start velocity"),
    ipar(513, "dof.r[2]", int::DOF_R + 1, 1, DOF, "model 0, translation along world y: 0 fixed at its start value, 1 free, 2 prescribed: moves at its start velocity"),
    ipar(514, "dof.r[3]", int::DOF_R + 2, 1, DOF, "model 0, translation along world z: 0 fixed at its start value, 1 free, 2 prescribed: moves at its start velocity"),
    ipar(515, "dof.w[1]", int::DOF_W, 0, DOF, "model 0, rotation about world x (at most one rotation not fixed): 0 fixed at its start value, 1 free, 2 prescribed: turns at its start angular velocity"),
    ipar(516, "dof.w[2]", int::DOF_W + 1, 0, DOF, "model 0, rotation about world y (at most one rotation not fixed): 0 fixed at its start value, 1 free, 2 prescribed: turns at its start angular velocity"),
    ipar(517, "dof.w[3]", int::DOF_W + 2, 0, DOF, "model 0, rotation about world z (at most one rotation not fixed): 0 fixed at its start value, 1 free, 2 prescribed: turns at its start angular velocity"),
    par(521, "spring.k[1]", SPRING, 0.0, "N/m", GE0, "model 0: spring from the world origin along world x, force -spring.k[1] r[1], >= 0"),
    par(522, "spring.k[2]", SPRING + 1, 0.0, "N/m", GE0, "model 0: spring from the world origin along world y, force -spring.k[2] r[2], >= 0"),
    par(523, "spring.k[3]", SPRING + 2, 0.0, "N/m", GE0, "model 0: spring from the world origin along world z, force -spring.k[3] r[3], >= 0"),
    par(531, "start.r[1]", START_R, 0.0, "m", ANY, "position at the start time, world x"),
    par(532, "start.r[2]", START_R + 1, 0.0, "m", ANY, "position at the start time, world y"),
    par(533, "start.r[3]", START_R + 2, 0.0, "m", ANY, "position at the start time, world z"),
    par(534, "start.q.w", START_Q, 1.0, "", ANY, "orientation at the start time (normalised), scalar part"),
    par(535, "start.q.x", START_Q + 1, 0.0, "", ANY, "orientation at the start time (normalised), x"),
    par(536, "start.q.y", START_Q + 2, 0.0, "", ANY, "orientation at the start time (normalised), y"),
    par(537, "start.q.z", START_Q + 3, 0.0, "", ANY, "orientation at the start time (normalised), z"),
    par(538, "start.v[1]", START_V, 0.0, "m/s", ANY, "velocity at the start time, world x"),
    par(539, "start.v[2]", START_V + 1, 0.0, "m/s", ANY, "velocity at the start time, world y"),
    par(540, "start.v[3]", START_V + 2, 0.0, "m/s", ANY, "velocity at the start time, world z"),
    par(541, "start.w[1]", START_W, 0.0, "rad/s", ANY, "angular velocity at the start time, world x"),
    par(542, "start.w[2]", START_W + 1, 0.0, "rad/s", ANY, "angular velocity at the start time, world y"),
    par(543, "start.w[3]", START_W + 2, 0.0, "rad/s", ANY, "angular velocity at the start time, world z"),
    par(551, "rigid.maxTurn", MAX_TURN, 0.05, "rad", GT0, "model 1: largest turn of the body per RK4 substep, > 0"),
];

/// The row of value reference `vr`: one look-up in an index built once (the body's rows are
/// numbered below 1000 and port k's 1000·k above them, so the index has a few thousand entries;
/// a master that reads every output every step pays no search through the table).
pub fn by_vr(vr: u32) -> Option<&'static Var> {
    static INDEX: OnceLock<Vec<u16>> = OnceLock::new();
    let index = INDEX.get_or_init(|| {
        let top = VARS.iter().map(|v| v.vr as usize).max().unwrap_or(0);
        let mut at = vec![u16::MAX; top + 1];
        for (row, v) in VARS.iter().enumerate() {
            at[v.vr as usize] = row as u16;
        }
        at
    });
    let row = *index.get(vr as usize)?;
    VARS.get(row as usize)
}

/// The row named `name`.
pub fn by_name(name: &str) -> Option<&'static Var> {
    VARS.iter().find(|v| v.name == name)
}

/// The start values of the Real and Integer slots.
pub fn start_values() -> ([f64; real::N], [i32; int::N]) {
    let mut reals = [0.0; real::N];
    let mut ints = [0; int::N];
    for v in &VARS {
        match (v.slot, v.start) {
            (Slot::Real(i), Some(s)) => reals[i] = s,
            (Slot::Int(i), Some(s)) => ints[i] = s as i32,
            _ => {}
        }
    }
    (reals, ints)
}

/// The GUID (FMI 2.0) and instantiationToken (FMI 3.0): a hash of the interface the model
/// description shows (every row's name, value reference, type, causality, variability, start,
/// unit and range), so that an XML and a binary from different interfaces do not match.
pub fn guid() -> &'static str {
    static GUID: OnceLock<String> = OnceLock::new();
    GUID.get_or_init(|| {
        let mut text = format!("{MODEL_IDENTIFIER};");
        for v in &VARS {
            text += &format!(
                "{}|{}|{}|{:?}|{:?}|{:?}|{}|{:?}|{:?};",
                v.name,
                v.vr,
                v.is_integer(),
                v.causality,
                v.variability,
                v.start,
                v.unit,
                v.min,
                v.max
            );
        }
        let a = fnv1a(text.as_bytes(), 0xcbf2_9ce4_8422_2325);
        let b = fnv1a(text.as_bytes(), 0x6c62_272e_07bb_0142);
        format!(
            "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
            a >> 32,
            (a >> 16) & 0xffff,
            a & 0xffff,
            b >> 48,
            b & 0xffff_ffff_ffff
        )
    })
}

/// FNV-1a (64 bit) of `bytes` from the offset basis `seed`.
pub fn fnv1a(bytes: &[u8], seed: u64) -> u64 {
    bytes.iter().fold(seed, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// A Real as the model description spells it (shortest round trip).
pub fn xml_real(x: f64) -> String {
    format!("{x:?}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_references_and_names_are_unique_and_ordered() {
        for w in VARS.windows(2) {
            assert!(w[0].vr < w[1].vr, "{} before {}", w[0].name, w[1].name);
        }
        for v in &VARS {
            assert_eq!(by_name(v.name).map(|x| x.vr), Some(v.vr));
        }
    }

    #[test]
    fn every_slot_is_used_once_and_starts_in_range() {
        let (mut reals, mut ints) = ([0; real::N], [0; int::N]);
        for v in &VARS {
            match v.slot {
                Slot::Real(i) => reals[i] += 1,
                Slot::Int(i) => ints[i] += 1,
                Slot::Out(_) => assert!(v.start.is_none()),
            }
            if let Some(s) = v.start {
                assert_eq!(v.check_range(s), Ok(()), "{}", v.name);
            }
        }
        assert!(reals.iter().chain(ints.iter()).all(|&n| n == 1));
    }

    #[test]
    fn ranges_name_the_variable_and_bound() {
        let mass = by_name("mass").unwrap();
        assert_eq!(
            mass.check_range(0.0).unwrap_err(),
            "mass = 0.0 is refused: it must be > 0"
        );
        let dof = by_name("dof.w[2]").unwrap();
        assert!(dof
            .check_range(3.0)
            .unwrap_err()
            .contains("dof.w[2] = 3 is refused: it must be <= 2"));
        assert!(guid().starts_with('{') && guid().len() == 38);
    }
}
