//! The variants and their driven scenes: `VARIANTS` in the order the tables list them, the
//! communication step `H` and the `PERIOD` of every path, node b's smooth path (`smooth`) and
//! PLANAR's sliding path (`planar`), the parameter sets and paths shared with tests/python
//! (`shared`: tests/data/parameter_sets.json), a variant's node inputs and node-load outputs
//! (`interface`) with its path over one period (`path_of`), and its continuous outputs. Uses the
//! crate's variable tables only, nothing else of the benchmark.

use connector_fmu::variables::{table, Causality, Field, Variant};

/// Every variant, in the order the tables and files list them.
pub const VARIANTS: [Variant; 5] = [
    Variant::Planar,
    Variant::ProjectionCartesian,
    Variant::ProjectionFlexionTorsion,
    Variant::Bushing,
    Variant::RadialThrust,
];

/// A variant's model identifier, as the tables and labels name it.
pub fn name_of(v: Variant) -> &'static str {
    v.spec().model_identifier
}

/// Communication step (s).
pub const H: f64 = 1e-3;
/// Steps per period of every path (2 s).
pub const PERIOD: usize = 2000;
/// Node inputs per node: r(3), q w x y z (4), v(3), ω(3).
pub const PER_NODE: usize = 13;

/// Both nodes' 26 poses and twists at t, node a then node b, in the order of `Field::Input { node, idx }`.
type Pose = [f64; 2 * PER_NODE];

fn node_a_at_rest(p: &mut Pose) {
    p[..PER_NODE].copy_from_slice(&[
        0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
    ]);
}

/// Node a at rest at the origin; node b translates on a Lissajous path and rotates about the
/// fixed axis n = (2, 1, 2)/3 by φ = 0.3 sin ωt (so α1, α2 and β all vary), ω = 2π rad/s.
fn smooth(t: f64) -> Pose {
    let om = 2.0 * std::f64::consts::PI;
    let (s, c) = (om * t).sin_cos();
    let (s2, c2) = (2.0 * om * t).sin_cos();
    let phi = 0.3 * s;
    let dphi = 0.3 * om * c;
    let n = [2.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0];
    let (sh, ch) = (0.5 * phi).sin_cos();
    let mut p = [0.0; 26];
    node_a_at_rest(&mut p);
    let b = &mut p[PER_NODE..];
    b[0..3].copy_from_slice(&[0.05 + 0.01 * s, -0.03 + 0.008 * s2, 0.10 + 0.01 * c]);
    b[3..7].copy_from_slice(&[ch, sh * n[0], sh * n[1], sh * n[2]]);
    b[7..10].copy_from_slice(&[0.01 * om * c, 0.016 * om * c2, -0.01 * om * s]);
    b[10..13].copy_from_slice(&[dphi * n[0], dphi * n[1], dphi * n[2]]);
    p
}

/// The parameter sets and paths shared with tests/python (tests/data/parameter_sets.json).
#[derive(serde::Deserialize)]
pub struct Shared {
    pub spring_damper: SpringDamper,
    pub planar_friction: PlanarFriction,
    planar_slide: PlanarSlide,
}

#[derive(serde::Deserialize)]
pub struct SpringDamper {
    pub k_translational: [f64; 3],
    pub k_rotational: [f64; 3],
    pub c_translational: [f64; 3],
    pub c_rotational: [f64; 3],
}

#[derive(serde::Deserialize)]
pub struct PlanarFriction {
    pub values: Vec<(String, f64)>,
}

#[derive(serde::Deserialize)]
#[allow(non_snake_case)]
struct PlanarSlide {
    X0: f64,
    Y0: f64,
    Z0: f64,
    A: f64,
    B: f64,
    PSI0: f64,
    PS: f64,
}

pub fn shared() -> &'static Shared {
    static SHARED: std::sync::OnceLock<Shared> = std::sync::OnceLock::new();
    SHARED.get_or_init(|| {
        serde_json::from_str(include_str!("../../tests/data/parameter_sets.json"))
            .expect("tests/data/parameter_sets.json")
    })
}

/// PLANAR (`planar_slide` of tests/data/parameter_sets.json, as tests/python PlanarSlide): node
/// a at rest; node b slides in a's 2–3 plane along a parabolic arc b = (X0, Y0 + A s, Z0 + B s²),
/// s = sin ωt (the sliding direction turns, both rates vanish at the ends so the friction sticks
/// there) and spins about e1 by ψ = PSI0 + PS sin 1.5ωt.
fn planar(t: f64) -> Pose {
    let PlanarSlide {
        X0,
        Y0,
        Z0,
        A,
        B,
        PSI0,
        PS,
    } = shared().planar_slide;
    let om = 2.0 * std::f64::consts::PI;
    let (s, c) = (om * t).sin_cos();
    let ds = om * c;
    let psi = PSI0 + PS * (1.5 * om * t).sin();
    let dpsi = 1.5 * om * PS * (1.5 * om * t).cos();
    let (sh, ch) = (0.5 * psi).sin_cos();
    let mut p = [0.0; 26];
    node_a_at_rest(&mut p);
    let b = &mut p[PER_NODE..];
    b[0..3].copy_from_slice(&[X0, Y0 + A * s, Z0 + B * s * s]);
    b[3..7].copy_from_slice(&[ch, sh, 0.0, 0.0]);
    b[7..10].copy_from_slice(&[0.0, A * ds, 2.0 * B * s * ds]);
    b[10..13].copy_from_slice(&[dpsi, 0.0, 0.0]);
    p
}

/// Inputs (value references, index into Pose) and node-load outputs of a variant.
pub fn interface(v: Variant) -> (Vec<u32>, Vec<usize>, Vec<u32>) {
    let (mut vin, mut sel, mut vout) = (vec![], vec![], vec![]);
    for x in &table(v).vars {
        match x.field {
            // the poses and twists (the acceleration inputs only matter with extrapolation 3)
            Field::Input { node, idx } if (idx as usize) < PER_NODE => {
                vin.push(x.vr);
                sel.push(node as usize * PER_NODE + idx as usize);
            }
            Field::Load { .. } if x.causality == Causality::Output => vout.push(x.vr),
            _ => {}
        }
    }
    (vin, sel, vout)
}

pub fn path_of(v: Variant, sel: &[usize]) -> Vec<f64> {
    let pose = if v == Variant::Planar { planar } else { smooth };
    let mut path = Vec::with_capacity(PERIOD * sel.len());
    for i in 0..PERIOD {
        let p = pose(i as f64 * H);
        path.extend(sel.iter().map(|&j| p[j]));
    }
    path
}

/// The VRs of a variant's continuous Real outputs (the unknowns of a directional derivative).
pub fn continuous_outputs(v: Variant) -> Vec<u32> {
    table(v)
        .vars
        .iter()
        .filter(|x| x.causality == Causality::Output)
        .filter(|x| x.variability == connector_fmu::variables::Variability::Continuous)
        .map(|x| x.vr)
        .collect()
}
