//! The analytic tangent (`directional_derivative`, one evaluation in dual numbers) against an
//! eighth-order central difference of the same outputs, on every variant and behaviour: springs,
//! dampers, stops in contact, constraint penalties with dampers, friction in stick, sliding slip,
//! spin slip, the coupled mode's disc flow, μ decaying with slip speed, stick dampers, aligned
//! shafts (α = 0, where the triad's axis of flexion is undefined), RADIAL-THRUST off its axis,
//! and initialization mode (the initial positions move with the inputs).
//!
//! The reference evaluates the kernel in `Real` at u ± jε, j = 1..4, on the same friction branch
//! (`Eval::Tangent` with the status at u), with ε = 2e-5·max(1, |u_i|) per input (4e-6 for the
//! coupled disc flow, whose slip angle bends over shorter distances): its truncation is
//! O((ε/ℓ)⁸) for the smallest length ℓ over which an output bends (the scenes keep elastic slips,
//! stop penetrations, constraint gaps and tilts at mm and 10 mrad, so that ℓ ≫ 4ε), its round-off
//! ≈ 1e-15·|y|/ε, which is allowed on top. Each entry must agree to 1e-10 of the largest entry
//! of its output's row (the row's scale in the output's
//! unit: a position's derivative is not measured against a force's).
//!
//! Uses the instance (mod.rs), the model's access rules and table, and the physics (tests only).

use super::{LogSink, ModelInstance};
use crate::error::{Category, Level};
use crate::model::access::read_output;
use crate::model::variables::{Causality, Field, Variability, Variant};
use crate::physics::friction::Eval;
use crate::physics::math::Real;

struct Quiet;
impl LogSink for Quiet {
    fn log(&self, _: Level, _: Category, _: &str) {}
}

/// A point at which the tangent is checked: a variant, its parameters, the nodes' inputs and
/// how many steps of 1 ms are taken before (None: checked in initialization mode).
struct Case {
    name: &'static str,
    variant: Variant,
    params: Vec<(&'static str, Real)>,
    integers: Vec<(&'static str, i32)>,
    /// (name, value) of node inputs set before initialization.
    inputs: Vec<(&'static str, Real)>,
    steps: Option<usize>,
    /// The difference's step relative to max(1, |u_i|).
    step: Real,
}

fn vr(inst: &ModelInstance, name: &str) -> u32 {
    inst.table
        .vars
        .iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .vr
}

fn quat(phi: [Real; 3]) -> [Real; 4] {
    let n = (phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]).sqrt();
    let (s, c) = (0.5 * n).sin_cos();
    [c, s * phi[0] / n, s * phi[1] / n, s * phi[2] / n]
}

/// Inputs of a node: position, orientation (rotation vector), velocity, angular velocity.
fn node(
    which: &'static str,
    r: [Real; 3],
    phi: [Real; 3],
    v: [Real; 3],
    w: [Real; 3],
) -> Vec<(&'static str, Real)> {
    let names: [&'static str; 13] = if which == "a" {
        [
            "a.r[1]", "a.r[2]", "a.r[3]", "a.q.w", "a.q.x", "a.q.y", "a.q.z", "a.v[1]", "a.v[2]",
            "a.v[3]", "a.w[1]", "a.w[2]", "a.w[3]",
        ]
    } else {
        [
            "b.r[1]", "b.r[2]", "b.r[3]", "b.q.w", "b.q.x", "b.q.y", "b.q.z", "b.v[1]", "b.v[2]",
            "b.v[3]", "b.w[1]", "b.w[2]", "b.w[3]",
        ]
    };
    let q = if phi == [0.0; 3] {
        [1.0, 0.0, 0.0, 0.0]
    } else {
        quat(phi)
    };
    let x = [
        r[0], r[1], r[2], q[0], q[1], q[2], q[3], v[0], v[1], v[2], w[0], w[1], w[2],
    ];
    names.into_iter().zip(x).collect()
}

/// The instance at the case's point.
fn instance(c: &Case) -> ModelInstance {
    let mut inst = ModelInstance::new(c.variant, c.name, Box::new(Quiet), false);
    inst.enter_initialization_mode().expect("init");
    let known: Vec<_> = c
        .params
        .iter()
        .chain(&c.inputs)
        .filter(|(n, _)| inst.table.vars.iter().any(|v| v.name == *n))
        .copied()
        .collect();
    for (n, x) in known {
        let r = vr(&inst, n);
        inst.set_real(&[r], &[x]).expect(n);
    }
    for &(n, x) in &c.integers {
        let r = vr(&inst, n);
        inst.set_integer(&[r], &[x]).expect(n);
    }
    if let Some(n) = c.steps {
        inst.exit_initialization_mode().expect("exit init");
        for i in 0..n {
            inst.do_step(i as Real * 1e-3, 1e-3).expect("step");
        }
    }
    inst
}

/// Largest deviation of the analytic tangent from the eighth-order central difference, relative
/// to each output row's largest entry, over every input of the case; and the row scales.
fn deviation(c: &Case) -> Real {
    let mut inst = instance(c);
    let outs: Vec<_> = inst
        .table
        .vars
        .iter()
        .filter(|v| v.causality == Causality::Output && v.variability == Variability::Continuous)
        .map(|v| (v.vr, v.field, v.name.clone()))
        .collect();
    let ins: Vec<_> = inst
        .table
        .vars
        .iter()
        .filter_map(|v| match v.field {
            Field::Input { node, idx } => Some((v.vr, node as usize, idx as usize)),
            _ => None,
        })
        .collect();
    let unknowns: Vec<u32> = outs.iter().map(|o| o.0).collect();
    let here = inst.outputs().expect("outputs").friction;
    let mode = Eval::Tangent([here.status, here.status_r1]);
    // rows with a kink at a committed point: the accumulated slips |Δs| and the plastic work
    // max(0, ·) (`friction::update`); their difference carries an artefact of the kink,
    // a series in ε from its O(ε) term on, removed by Richardson extrapolation of the differences
    // at ε, ε/2, ε/4 (the O(ε) and O(ε²) terms). A kink has no derivative: the tangent takes
    // the central difference's value there, and what is checked is that the extrapolated one is
    // within 1e-4 of the row's scale (measured: 6e-4 → 1e-8 → 2e-9 of 0.01 per level on the
    // sliding slip; 4e-7 of 0.01 left on the coupled spin, whose Δs at the point is the disc
    // return's round-off)
    let kinked = |name: &str| {
        matches!(
            name,
            "friction.slip" | "friction.slipR1" | "energy.friction"
        )
    };
    let (mut analytic, mut reference, mut noise) = (vec![], vec![], vec![]);
    for &(k, node, idx) in &ins {
        let mut col = vec![0.0; outs.len()];
        inst.directional_derivative(&unknowns, &[k], &[1.0], &mut col)
            .expect("directional derivative");
        analytic.push(col);
        let u0 = inst.s.inputs;
        let difference = |eps: Real| {
            const W: [Real; 4] = [4.0 / 5.0, -1.0 / 5.0, 4.0 / 105.0, -1.0 / 280.0];
            let (mut fd, mut size) = (vec![0.0; outs.len()], vec![0.0; outs.len()]);
            for (j, w) in W.iter().enumerate() {
                let at = |sign: Real| {
                    let mut u = u0;
                    u[node][idx] += sign * (j + 1) as Real * eps;
                    inst.evaluate_at(&u, mode)
                        .expect("evaluation near the point")
                };
                let (p, m) = (at(1.0), at(-1.0));
                for (i, o) in outs.iter().enumerate() {
                    let (yp, ym): (Real, Real) = (read_output(&p, o.1), read_output(&m, o.1));
                    fd[i] += w * (yp - ym) / eps;
                    size[i] = Real::max(size[i], yp.abs().max(ym.abs()));
                }
            }
            (fd, size)
        };
        let eps = c.step * u0[node][idx].abs().max(1.0);
        let ((fd, size), (half, _), (quarter, _)) = (
            difference(eps),
            difference(0.5 * eps),
            difference(0.25 * eps),
        );
        let mut r = fd;
        let mut n = vec![0.0; outs.len()];
        for (i, o) in outs.iter().enumerate() {
            // the difference's own round-off: ≈ 2e-16·|y|/ε per evaluation, weights summing to 2
            n[i] = 1e-15 * size[i] / eps;
            if kinked(&o.2) {
                let (r1, r2) = (2.0 * half[i] - r[i], 2.0 * quarter[i] - half[i]);
                (r[i], n[i]) = ((4.0 * r2 - r1) / 3.0, 30.0 * n[i]);
            }
        }
        reference.push(r);
        noise.push(n);
    }
    let mut worst: Real = 0.0;
    for (i, o) in outs.iter().enumerate() {
        let scale = reference
            .iter()
            .map(|col| col[i].abs())
            .fold(0.0, Real::max);
        // rows whose every derivative is below 0.01 (SI units per unit of input) are held to
        // 1e-12 absolute: there the difference's round-off (≈ 1e-12·|y|) is their size
        let scale = scale.max(0.01);
        let tolerance = if kinked(&o.2) { 1e-4 } else { 1e-10 };
        for (j, (a, r)) in analytic.iter().zip(&reference).enumerate() {
            let dev = ((a[i] - r[i]).abs() - noise[j][i]).max(0.0) / scale;
            if !kinked(&o.2) {
                worst = worst.max(dev);
            }
            assert!(
                dev <= tolerance,
                "{}: d{}/d input {j}: analytic {:e}, 8th-order difference {:e} (row scale {scale:e}, its round-off {:e})",
                c.name,
                o.2,
                a[i],
                r[i],
                noise[j][i]
            );
        }
    }
    worst
}

fn general_nodes(b_r: [Real; 3]) -> Vec<(&'static str, Real)> {
    let mut x = node(
        "a",
        [0.01, -0.02, 0.03],
        [0.2, -0.1, 0.3],
        [0.05, 0.02, -0.03],
        [0.3, -0.2, 0.1],
    );
    x.extend(node(
        "b",
        b_r,
        [0.5, 0.3, -0.4],
        [0.2, -0.1, 0.15],
        [-0.4, 0.6, 0.25],
    ));
    x
}

fn springs_dampers(components: &[usize]) -> Vec<(&'static str, Real)> {
    const K: [&str; 6] = [
        "elasticity.k1",
        "elasticity.k2",
        "elasticity.k3",
        "elasticity.k4",
        "elasticity.k5",
        "elasticity.k6",
    ];
    const C: [&str; 6] = [
        "damping.c1",
        "damping.c2",
        "damping.c3",
        "damping.c4",
        "damping.c5",
        "damping.c6",
    ];
    let mut p = vec![];
    for &k in components {
        let rot = k > 3;
        p.push((
            K[k - 1],
            if rot {
                300.0 + 50.0 * k as Real
            } else {
                2e4 * k as Real
            },
        ));
        p.push((
            C[k - 1],
            if rot {
                2.0 + k as Real
            } else {
                30.0 * k as Real
            },
        ));
    }
    p.extend([
        ("stop.stiffness", 1e6),
        ("stop.damping", 200.0),
        ("stop.rotStiffness", 2e3),
        ("stop.rotDamping", 3.0),
    ]);
    p
}

fn planar(friction: Vec<(&'static str, Real)>, b_v: [Real; 3], b_w: [Real; 3]) -> Case {
    let mut params = springs_dampers(&[2, 3, 4]);
    params.extend([
        ("constraint.stiffness", 1e5),
        ("constraint.rotStiffness", 1e3),
        ("constraint.damping", 50.0),
        ("constraint.rotDamping", 0.5),
        ("friction.Fint", 20.0),
        ("friction.R", 0.05),
        // elastic ranges of mm and 10 mrad, far above the differences' steps
        ("friction.stickStiffness", 1e4),
        ("friction.stickStiffnessR1", 100.0),
    ]);
    params.extend(friction);
    let mut inputs = node("a", [0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
    // b tilted and moving off the slide plane, so that the constraint penalties react (by
    // more than the differences' steps: |f1| and |(m2, m3)| bend at their zeros)
    inputs.extend(node("b", [0.0, 0.02, -0.01], [0.01, -0.015, 0.0], b_v, b_w));
    Case {
        name: "planar",
        variant: Variant::Planar,
        params,
        integers: vec![],
        inputs,
        steps: Some(4),
        step: 2e-5,
    }
}

/// PLANAR in stick: a limit of about 260 N (F_NC ≈ 520 N: 200 N off-plane penalty, 20 N
/// internal, 300 N from the bending moment), elastic range 26 mm; 1.4 mm of in-plane motion and
/// 16 mrad of spin in 4 ms.
const STICK: [(&str, Real); 2] = [("friction.muStatic", 0.5), ("friction.muKinetic", 0.4)];
const STICK_V: [Real; 3] = [0.5, 0.3, -0.2];
const STICK_W: [Real; 3] = [4.0, 0.0, 0.0];
/// PLANAR slipping: μ a tenth, 14 mm of in-plane motion and 40 mrad of spin in 4 ms.
const SLIP: [(&str, Real); 2] = [("friction.muStatic", 0.05), ("friction.muKinetic", 0.04)];
const SLIP_V: [Real; 3] = [0.5, 3.0, -2.0];
const SLIP_W: [Real; 3] = [10.0, 0.0, 0.0];

#[test]
fn analytic_tangent_equals_an_eighth_order_difference_on_every_variant_and_behaviour() {
    let mut cases = vec![];
    // Bushing, everything on, a translational stop (upper 1) and a rotational one (lower 6) in
    // contact
    let mut p = springs_dampers(&[1, 2, 3, 4, 5, 6]);
    p.extend([("stop.upper1", 0.02), ("stop.lower6", 0.1)]);
    cases.push(Case {
        name: "Bushing on, stops in contact",
        variant: Variant::Bushing,
        params: p.clone(),
        integers: vec![],
        inputs: general_nodes([0.1, 0.03, -0.05]),
        steps: Some(5),
        step: 2e-5,
    });
    cases.push(Case {
        name: "Bushing on, initialization mode",
        steps: None,
        params: p,
        inputs: general_nodes([0.1, 0.03, -0.05]),
        integers: vec![],
        variant: Variant::Bushing,
        step: 2e-5,
    });
    // aligned shafts: α = 0 exactly (the identity on both nodes), b offset and moving
    let mut aligned = node("a", [0.0; 3], [0.0; 3], [0.0; 3], [0.0; 3]);
    aligned.extend(node("b", [0.05, -0.02, 0.1], [0.0; 3], [0.0; 3], [0.0; 3]));
    cases.push(Case {
        name: "Bushing, shafts aligned",
        variant: Variant::Bushing,
        params: springs_dampers(&[1, 2, 3, 4, 5, 6]),
        integers: vec![],
        inputs: aligned,
        steps: Some(0),
        step: 2e-5,
    });
    let mut p = springs_dampers(&[1, 2, 3]);
    p.push(("stop.lower2", 0.05));
    cases.push(Case {
        name: "ProjectionCartesian on, stop in contact",
        variant: Variant::ProjectionCartesian,
        params: p,
        integers: vec![],
        inputs: general_nodes([0.1, 0.03, -0.05]),
        steps: Some(5),
        step: 2e-5,
    });
    let mut p = springs_dampers(&[4, 5, 6]);
    p.push(("stop.upper5", -0.05));
    cases.push(Case {
        name: "ProjectionFlexionTorsion on, stop in contact",
        variant: Variant::ProjectionFlexionTorsion,
        params: p,
        integers: vec![],
        inputs: general_nodes([0.1, 0.03, -0.05]),
        steps: Some(5),
        step: 2e-5,
    });
    let mut p = springs_dampers(&[1, 3]);
    p.extend([("stop.upper1", 0.02), ("stop.lower3", 0.1)]);
    cases.push(Case {
        name: "RadialThrust on, stops in contact",
        variant: Variant::RadialThrust,
        params: p,
        integers: vec![],
        inputs: general_nodes([0.1, 0.03, 0.05]),
        steps: Some(5),
        step: 2e-5,
    });
    // PLANAR: stick, sliding slip, spin slip, the coupled disc flow, decay with stick dampers
    cases.push(Case {
        name: "Planar, stick",
        ..planar(STICK.to_vec(), STICK_V, STICK_W)
    });
    let slip = SLIP.to_vec();
    cases.push(Case {
        name: "Planar, sliding and spinning slip",
        ..planar(slip.clone(), SLIP_V, SLIP_W)
    });
    let mut coupled = planar(slip.clone(), SLIP_V, SLIP_W);
    coupled.name = "Planar, coupled slip (disc flow)";
    coupled.integers = vec![("friction.coupling", 1)];
    // the disc's slip angle bends over shorter distances: a fifth of the step
    coupled.step = 4e-6;
    cases.push(coupled);
    let mut decay = slip.clone();
    decay.extend([
        ("friction.decay", 3.0),
        ("friction.stickDamping", 40.0),
        ("friction.stickDampingR1", 0.02),
    ]);
    cases.push(Case {
        name: "Planar, slip with decay and stick dampers",
        ..planar(decay, SLIP_V, SLIP_W)
    });
    cases.push(Case {
        name: "Planar, initialization mode",
        steps: None,
        ..planar(slip, SLIP_V, SLIP_W)
    });
    for c in &cases {
        let worst = deviation(c);
        eprintln!("{}: largest deviation {worst:.1e}", c.name);
    }
}

#[test]
fn the_cases_meet_the_behaviours_they_name() {
    // the friction cases really stick and slip where they say (status 1 stick, 2 slip)
    let status = |c: &Case| {
        let mut inst = instance(c);
        let f = inst.outputs().expect("outputs").friction;
        (f.status as i32, f.status_r1 as i32)
    };
    assert_eq!(status(&planar(STICK.to_vec(), STICK_V, STICK_W)), (1, 1));
    let mut slip = planar(SLIP.to_vec(), SLIP_V, SLIP_W);
    assert_eq!(status(&slip), (2, 2));
    slip.integers = vec![("friction.coupling", 1)];
    assert_eq!(status(&slip), (2, 2));
}
