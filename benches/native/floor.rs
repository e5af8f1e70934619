//! The floor of a round (docs/benchmarks.md, "Floor"): the physics of Bushing "on" and Planar
//! "on" written directly, as the reference the FMU's round is compared with in the same run.
//!
//! A round is what an importer's round asks for and nothing more: the node inputs copied in
//! (`set`); the step (`step`): both nodes read (quaternions normalised as the FMU does), the
//! number of substeps from the path's turn, per substep the nodes extrapolated along their
//! velocities (exponential map) and the connector evaluated (kinematics, springs, dampers,
//! stops, constraint penalties, friction); the twelve node loads copied out (`get`). It keeps
//! only the state the physics needs (initial positions, angle branches, friction state).
//!
//! What it leaves out, each of which the FMU must do: FMI's checks of the call sequence, value
//! references, types and ranges, the all-or-nothing set and the rollback of a refused step, the
//! path guard of the centred triad (the floor asserts α < π − gap instead), the finite-output
//! check, the component outputs nobody read (CU, CEF, CVF, CSF, CRF, energies, stop status,
//! friction outputs other than its forces), event tracking and location, the output cache.
//!
//! Kinematics and constitutive laws are written out here on plain arrays (no nalgebra, no
//! gradient structures: the rates from the triad's angular velocity, the node moments from the
//! total force and the triad Jacobians). Friction is the crate's `friction::update` (the return
//! map is the same physics in every implementation; the floor includes its cost as it is).
//! Initialization is not timed and uses the crate's `initial_state` (initial positions, angle
//! branches, friction state at t = 0).
//!
//! Uses the crate's physics only, nothing else of the benchmark (`direct.rs` runs and checks it).

use connector_fmu::physics::connector::{Params, Penalty};
use connector_fmu::physics::friction::{self, Eval, FrictionParams, FrictionState};
use connector_fmu::physics::init::initial_state;
use connector_fmu::physics::kinematics::{
    ConnectionType, Node, Rotational, Translational, ALPHA_MAX_GAP,
};
use connector_fmu::physics::math::{Quat, Vec3};
use std::f64::consts::PI;

type V = [f64; 3];

#[inline(always)]
fn dot(a: &V, b: &V) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
#[inline(always)]
fn cross(a: &V, b: &V) -> V {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
#[inline(always)]
fn add(a: &V, b: &V) -> V {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
#[inline(always)]
fn sub(a: &V, b: &V) -> V {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
#[inline(always)]
fn scale(a: &V, s: f64) -> V {
    [a[0] * s, a[1] * s, a[2] * s]
}
/// a·s + b·t
#[inline(always)]
fn lin(a: &V, s: f64, b: &V, t: f64) -> V {
    [
        a[0] * s + b[0] * t,
        a[1] * s + b[1] * t,
        a[2] * s + b[2] * t,
    ]
}

/// A unit quaternion (w, x, y, z).
type Q = [f64; 4];

/// Scalar-first components normalised as the FMU reads them (unit to 4ε: taken as given).
#[inline(always)]
fn normalised(w: f64, x: f64, y: f64, z: f64) -> Q {
    let n = (w * w + x * x + y * y + z * z).sqrt();
    assert!(n.is_finite() && n >= 1e-6, "not a rotation");
    if (n - 1.0).abs() <= 4.0 * f64::EPSILON {
        [w, x, y, z]
    } else {
        [w / n, x / n, y / n, z / n]
    }
}

/// exp(φ)·q: the rotation vector φ as a quaternion (identity below |φ/2| ≤ ε), times q.
#[inline(always)]
fn turned(phi: &V, q: &Q) -> Q {
    let v = scale(phi, 0.5);
    let nn = dot(&v, &v);
    if nn <= f64::EPSILON * f64::EPSILON {
        return *q;
    }
    let n = nn.sqrt();
    let (s, c) = n.sin_cos();
    let k = s / n;
    let (w1, x1, y1, z1) = (c, v[0] * k, v[1] * k, v[2] * k);
    let [w2, x2, y2, z2] = *q;
    [
        w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
        w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
        w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2,
    ]
}

/// The frame's axes e1, e2, e3 (columns of the rotation matrix) of a unit quaternion.
#[inline(always)]
fn axes(q: &Q) -> [V; 3] {
    let [w, i, j, k] = *q;
    let (ww, ii, jj, kk) = (w * w, i * i, j * j, k * k);
    let (ij, wk, wj, ik, jk, wi) = (
        i * j * 2.0,
        w * k * 2.0,
        w * j * 2.0,
        i * k * 2.0,
        j * k * 2.0,
        w * i * 2.0,
    );
    [
        [ww + ii - jj - kk, wk + ij, ik - wj],
        [ij - wk, ww - ii + jj - kk, wi + jk],
        [wj + ik, jk - wi, ww - ii - jj + kk],
    ]
}

/// The continuous branch of an angle (raw + 2πm nearest to prev).
#[inline(always)]
fn branch(raw: f64, prev: f64) -> f64 {
    let two_pi = 2.0 * PI;
    raw + two_pi * ((prev - raw) / two_pi).round()
}

/// Spring, damper and stop force of available component slot `k` at position `x`, rate `v`
/// (initial position `c0`).
#[inline]
fn component_force(p: &FloorParams, k: usize, x: f64, v: f64, c0: f64) -> f64 {
    let (ks, cs) = if k < 3 {
        (p.stop.k, p.stop.c)
    } else {
        (p.stop.k_rot, p.stop.c_rot)
    };
    p.k[k] * (x - c0) + p.c[k] * v + stop(x, v, p.lower[k], p.upper[k], ks, cs)
}

/// One-sided stop penalty force on position c with rate v (never pulls).
#[inline(always)]
fn stop(c: f64, v: f64, lower: f64, upper: f64, k: f64, d: f64) -> f64 {
    if c > upper {
        (k * (c - upper) + d * v).max(0.0)
    } else if c < lower {
        -(k * (lower - c) - d * v).max(0.0)
    } else {
        0.0
    }
}

/// Which physics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Kind {
    /// PROJECTION CARTESIAN + PROJECTION FLEXION-TORSION (centred triad).
    Bushing,
    /// SLIDE-PLANE + REVOLUTE with friction.
    Planar,
}

/// The parameters the floor uses, from the benchmark's (name, value) list.
#[derive(Clone, Copy, Debug)]
pub struct FloorParams {
    k: [f64; 6],
    c: [f64; 6],
    lower: [f64; 6],
    upper: [f64; 6],
    stop: Penalty,
    constraint: Penalty,
    friction: FrictionParams,
}

impl FloorParams {
    /// From the names of the model description; panics on a name it does not know (so that no
    /// parameter of the FMU's scene is silently left out of the floor).
    pub fn from_list(list: &[(String, f64)]) -> FloorParams {
        let d = Params::default();
        let mut p = FloorParams {
            k: d.k,
            c: d.c,
            lower: d.stop_lower,
            upper: d.stop_upper,
            stop: d.stop,
            constraint: d.constraint,
            friction: d.friction,
        };
        for (name, x) in list {
            let x = *x;
            let slot = |prefix: &str| {
                name.strip_prefix(prefix)
                    .and_then(|k| k.parse::<usize>().ok())
                    .map(|k| k - 1)
            };
            if let Some(k) = slot("elasticity.k") {
                p.k[k] = x;
            } else if let Some(k) = slot("damping.c") {
                p.c[k] = x;
            } else if let Some(k) = slot("stop.upper") {
                p.upper[k] = x;
            } else if let Some(k) = slot("stop.lower") {
                p.lower[k] = x;
            } else {
                let f = &mut p.friction;
                match name.as_str() {
                    "stop.stiffness" => p.stop.k = x,
                    "stop.damping" => p.stop.c = x,
                    "stop.rotStiffness" => p.stop.k_rot = x,
                    "stop.rotDamping" => p.stop.c_rot = x,
                    "friction.muStatic" => f.mu_static = x,
                    "friction.muKinetic" => f.mu_kinetic = x,
                    "friction.decay" => f.decay = x,
                    "friction.R" => f.radius = x,
                    "friction.Fint" => f.f_int = x,
                    "friction.Mint" => f.m_int = x,
                    "friction.stickStiffness" => f.k_stick = x,
                    "friction.stickStiffnessR1" => f.k_stick_r1 = x,
                    _ => panic!("the floor does not know parameter {name}"),
                }
            }
        }
        p
    }

    /// The crate's parameters with the same values (for the initial state only).
    fn crate_params(&self) -> Params {
        Params {
            k: self.k,
            c: self.c,
            stop_lower: self.lower,
            stop_upper: self.upper,
            stop: self.stop,
            constraint: self.constraint,
            friction: self.friction,
            ..Params::default()
        }
    }
}

/// A node's 13 pose and twist inputs: r, q (w x y z), v, ω.
type NodeIn = [f64; 13];

/// The floor instance.
pub struct Floor {
    kind: Kind,
    p: FloorParams,
    /// Where each value of a `set` row goes: node·13 + index.
    sel: Vec<usize>,
    inputs: [NodeIn; 2],
    /// Initial component positions.
    c0: [f64; 6],
    /// Torsion β (Bushing) or rotation α (Planar) on its continuous branch.
    angle: f64,
    friction: FrictionState,
    /// fa, ma, fb, mb.
    loads: [f64; 12],
    /// CTF1..3, CTM1..3.
    total: [f64; 6],
}

/// The connection type of a kind (for the initial state).
fn connection(kind: Kind) -> ConnectionType {
    match kind {
        Kind::Bushing => ConnectionType {
            trans: Translational::ProjectionCartesian,
            rot: Rotational::ProjectionFlexionTorsion,
        },
        Kind::Planar => ConnectionType {
            trans: Translational::SlidePlane,
            rot: Rotational::Revolute,
        },
    }
}

impl Floor {
    /// A floor initialized at the inputs `row` (values in the order of `sel`).
    pub fn new(kind: Kind, params: &[(String, f64)], sel: &[usize], row: &[f64]) -> Floor {
        let p = FloorParams::from_list(params);
        let mut f = Floor {
            kind,
            p,
            sel: sel.to_vec(),
            inputs: [[0.0; 13]; 2],
            c0: [0.0; 6],
            angle: 0.0,
            friction: FrictionState::default(),
            loads: [0.0; 12],
            total: [0.0; 6],
        };
        f.inputs[0][3] = 1.0;
        f.inputs[1][3] = 1.0;
        f.set(row);
        let node = |u: &NodeIn| {
            let q = normalised(u[3], u[4], u[5], u[6]);
            Node {
                r: Vec3::new(u[0], u[1], u[2]),
                q: Quat::new_unchecked(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3])),
                v: Vec3::new(u[7], u[8], u[9]),
                w: Vec3::new(u[10], u[11], u[12]),
            }
        };
        let st = initial_state(
            connection(kind),
            &p.crate_params(),
            &node(&f.inputs[0]),
            &node(&f.inputs[1]),
        )
        .expect("regular initial configuration");
        f.c0 = st.c0;
        f.angle = match kind {
            Kind::Bushing => st.branches.beta,
            Kind::Planar => st.branches.alpha,
        };
        f.friction = st.friction;
        f
    }

    /// The node inputs of a round (the values of `sel`).
    #[inline(never)]
    pub fn set(&mut self, row: &[f64]) {
        for (&j, &x) in self.sel.iter().zip(row) {
            self.inputs[j / 13][j % 13] = x;
        }
    }

    /// The node loads fa, ma, fb, mb.
    #[inline(never)]
    pub fn get(&self, out: &mut [f64; 12]) {
        *out = self.loads;
    }

    /// CTF1..3, CTM1..3 of the last step.
    pub fn total(&self) -> [f64; 6] {
        self.total
    }

    /// One communication step of length h from the inputs set.
    #[inline(never)]
    pub fn step(&mut self, h: f64) {
        let [ua, ub] = &self.inputs;
        let qa = normalised(ua[3], ua[4], ua[5], ua[6]);
        let qb = normalised(ub[3], ub[4], ub[5], ub[6]);
        let v3 = |u: &NodeIn, i: usize| [u[i], u[i + 1], u[i + 2]];
        let (ra, va, wa) = (v3(ua, 0), v3(ua, 7), v3(ua, 10));
        let (rb, vb, wb) = (v3(ub, 0), v3(ub, 7), v3(ub, 10));
        // substeps from the turn of the step (≤ 0.25 rad each)
        let turn = (dot(&wa, &wa).sqrt() + dot(&wb, &wb).sqrt()) * h;
        let n = (turn / 0.25).max(1.0).ceil();
        assert!(n <= 100_000.0, "too many substeps");
        let n = n as u32;
        let dt = h / n as f64;
        let mut na = (ra, qa);
        let mut nb = (rb, qb);
        for j in 1..=n {
            let tau = h * j as f64 / n as f64;
            na = (lin(&ra, 1.0, &va, tau), turned(&scale(&wa, tau), &qa));
            nb = (lin(&rb, 1.0, &vb, tau), turned(&scale(&wb, tau), &qb));
            match self.kind {
                Kind::Bushing => self.bushing(&na, &nb, (&va, &wa), (&vb, &wb)),
                Kind::Planar => self.planar(&na, &nb, (&va, &wa), (&vb, &wb), dt),
            }
        }
        // the extrapolated nodes become the inputs (the next set overwrites what it sets)
        let write = |u: &mut NodeIn, (r, q): &(V, Q)| {
            u[..3].copy_from_slice(r);
            u[3..7].copy_from_slice(q);
        };
        write(&mut self.inputs[0], &na);
        write(&mut self.inputs[1], &nb);
    }

    /// PROJECTION CARTESIAN + PROJECTION FLEXION-TORSION at nodes (r, q) with twists (v, ω).
    #[inline(always)]
    fn bushing(&mut self, a: &(V, Q), b: &(V, Q), (va, wa): (&V, &V), (vb, wb): (&V, &V)) {
        let p = &self.p;
        let [e1a, e2a, e3a] = axes(&a.1);
        let [e1b, e2b, e3b] = axes(&b.1);
        // total flexion α, and α·q̂ = (α / sin α)(e3a × e3b)
        let w = cross(&e3a, &e3b);
        let s = dot(&w, &w).sqrt();
        let c = dot(&e3a, &e3b);
        let alpha = s.atan2(c);
        assert!(alpha <= PI - ALPHA_MAX_GAP, "folded shafts");
        let x_over_sin = if alpha < 1e-4 {
            1.0 + alpha * alpha / 6.0
        } else {
            alpha / s
        };
        let phi = scale(&w, x_over_sin);
        // frame a turned by α/2 about q̂ (Rodrigues)
        let th = 0.5 * alpha;
        let (sth, cth) = th.sin_cos();
        let half = |v: &V| {
            if s == 0.0 {
                return *v;
            }
            let q = scale(&w, 1.0 / s);
            let t = lin(v, cth, &cross(&q, v), sth);
            add(&t, &scale(&q, dot(&q, v) * (1.0 - cth)))
        };
        let (h0, h1, t2) = (half(&e1a), half(&e2a), half(&e3a));
        // torsion β on its branch, the triad twisted by β/2 about the bisector
        let beta_raw = (dot(&e2a, &e1b) - dot(&e1a, &e2b)).atan2(dot(&e1a, &e1b) + dot(&e2a, &e2b));
        let beta = branch(beta_raw, self.angle);
        self.angle = beta;
        let (sb, cb) = (0.5 * beta).sin_cos();
        let t0 = lin(&h0, cb, &h1, sb);
        let t1 = lin(&h0, -sb, &h1, cb);
        let a1 = dot(&t0, &phi);
        let a2 = dot(&t1, &phi);
        // K = ∂(α1, α2, β)/∂θ_b (rows k0, k1, k2), ∂/∂θ_a = −K
        let a_s = if th < 1e-4 {
            1.0 + th * th / 6.0
        } else {
            th / sth
        };
        let coef = if alpha < 1e-4 {
            -1.0 / 24.0
        } else {
            (1.0 - a_s) / (alpha * alpha)
        };
        let (m11, m12, m22) = (a_s + coef * a1 * a1, coef * a1 * a2, a_s + coef * a2 * a2);
        let k0 = lin(&t0, m11, &t1, m12);
        let k1 = lin(&t0, m12, &t1, m22);
        let k2 = scale(&t2, 1.0 / cth);
        // the triad turns by δψ = A δθ_a + (I − A) δθ_b, A = ½I + Σ t_i n_iᵀ
        let h1c = if th < 1e-4 {
            0.5 - th * th / 24.0
        } else {
            (1.0 - cth) / (th * th)
        };
        let h2c = if th < 1e-4 {
            1.0 - th * th / 6.0
        } else {
            sth / th
        };
        let n0 = scale(&k2, h2c * a2 * 0.25);
        let n1 = scale(&k2, -h2c * a1 * 0.25);
        let n2 = lin(&k0, -h1c * a2 * 0.25, &k1, h1c * a1 * 0.25);
        let triad = [t0, t1, t2];
        let ns = [n0, n1, n2];
        // A x and Aᵀ y
        let a_x = |x: &V| {
            let mut r = scale(x, 0.5);
            for i in 0..3 {
                r = add(&r, &scale(&triad[i], dot(&ns[i], x)));
            }
            r
        };
        let at_y = |y: &V| {
            let mut r = scale(y, 0.5);
            for i in 0..3 {
                r = add(&r, &scale(&ns[i], dot(&triad[i], y)));
            }
            r
        };
        let d = sub(&b.0, &a.0);
        let dv = sub(vb, va);
        let dw = sub(wb, wa);
        // the triad's angular velocity ω_b + A(ω_a − ω_b)
        let w_tri = sub(wb, &a_x(&dw));
        let pos = [dot(&t0, &d), dot(&t1, &d), dot(&t2, &d), a1, a2, beta];
        let rate = [
            dot(&t0, &dv) + dot(&cross(&t0, &d), &w_tri),
            dot(&t1, &dv) + dot(&cross(&t1, &d), &w_tri),
            dot(&t2, &dv) + dot(&cross(&t2, &d), &w_tri),
            dot(&k0, &dw),
            dot(&k1, &dw),
            dot(&k2, &dw),
        ];
        let mut f = [0.0; 6];
        for k in 0..6 {
            f[k] = component_force(p, k, pos[k], rate[k], self.c0[k]);
        }
        // node loads: force Σ F_i t_i on a, its moment (Σ F_i t_i) × d shared by the triad's
        // Jacobians, the rotational components' moments through K
        let force = add(
            &add(&scale(&t0, f[0]), &scale(&t1, f[1])),
            &scale(&t2, f[2]),
        );
        let m = cross(&force, &d);
        let am = at_y(&m);
        let kf = add(
            &add(&scale(&k0, f[3]), &scale(&k1, f[4])),
            &scale(&k2, f[5]),
        );
        let ma = sub(&kf, &am);
        let mb = scale(&add(&sub(&m, &am), &kf), -1.0);
        self.total = f;
        self.write_loads(&force, &ma, &mb);
    }

    /// SLIDE-PLANE + REVOLUTE with friction, in node a's frame.
    #[inline(always)]
    fn planar(&mut self, a: &(V, Q), b: &(V, Q), (va, wa): (&V, &V), (vb, wb): (&V, &V), dt: f64) {
        let p = &self.p;
        let [e1a, e2a, e3a] = axes(&a.1);
        let [e1b, _, e3b] = axes(&b.1);
        let d = sub(&b.0, &a.0);
        let dv = sub(vb, va);
        let dw = sub(wa, wb);
        // translations x_i = e_ia·d, rates e_ia·(v_b − v_a) + (e_ia × d)·ω_a
        let tri = [e1a, e2a, e3a];
        let mut pos = [0.0; 6];
        let mut rate = [0.0; 6];
        for i in 0..3 {
            pos[i] = dot(&tri[i], &d);
            rate[i] = dot(&tri[i], &dv) + dot(&cross(&tri[i], &d), wa);
        }
        // α = atan2(−e2a·e3b, e3a·e3b) on its branch; constraint rotations −e3a·e1b, e2a·e1b;
        // their gradients g with respect to θ_a (θ_b: −g)
        let y = -dot(&e2a, &e3b);
        let x = dot(&e3a, &e3b);
        let rr = x * x + y * y;
        assert!(rr > 1e-12, "revolute undefined");
        let alpha = branch(y.atan2(x), self.angle);
        self.angle = alpha;
        let dy = scale(&cross(&e2a, &e3b), -1.0);
        let dx = cross(&e3a, &e3b);
        let g = [
            scale(&lin(&dy, x, &dx, -y), 1.0 / rr),
            scale(&cross(&e3a, &e1b), -1.0),
            cross(&e2a, &e1b),
        ];
        pos[3] = alpha;
        pos[4] = -dot(&e3a, &e1b);
        pos[5] = dot(&e2a, &e1b);
        for r in 0..3 {
            rate[3 + r] = dot(&g[r], &dw);
        }
        let mut f = [0.0; 6];
        // constraints: x = x0, φ2 = φ3 = 0
        let con = &p.constraint;
        f[0] = con.k * (pos[0] - self.c0[0]) + con.c * rate[0];
        f[4] = con.k_rot * pos[4] + con.c_rot * rate[4];
        f[5] = con.k_rot * pos[5] + con.c_rot * rate[5];
        for k in 1..4 {
            f[k] = component_force(p, k, pos[k], rate[k], self.c0[k]);
        }
        let fr = friction::update(
            &p.friction,
            &self.friction,
            [f[0], f[4], f[5]],
            [pos[1], pos[2], pos[3]],
            [rate[1], rate[2], rate[3]],
            Eval::Step(dt),
        );
        self.friction = fr.state;
        f[1] += fr.force[0];
        f[2] += fr.force[1];
        f[3] += fr.force[2];
        let force = add(
            &add(&scale(&e1a, f[0]), &scale(&e2a, f[1])),
            &scale(&e3a, f[2]),
        );
        let mr = add(
            &add(&scale(&g[0], f[3]), &scale(&g[1], f[4])),
            &scale(&g[2], f[5]),
        );
        let ma = scale(&add(&cross(&force, &d), &mr), -1.0);
        self.total = f;
        self.write_loads(&force, &ma, &mr);
    }

    #[inline(always)]
    fn write_loads(&mut self, force_on_a: &V, ma: &V, mb: &V) {
        let l = &mut self.loads;
        l[..3].copy_from_slice(force_on_a);
        l[3..6].copy_from_slice(ma);
        l[6..9].copy_from_slice(&scale(force_on_a, -1.0));
        l[9..12].copy_from_slice(mb);
    }
}
