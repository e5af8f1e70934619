//! The connector's constitutive response on top of its kinematics: elasticity, damping,
//! penalty constraints, stops and PLANAR friction, assembled into component forces, node
//! loads (virtual work) and energies.
//!
//! Sign convention (Abaqus): a component force F_k is the force IN the connector, so a
//! stretched spring of positive stiffness gives F_k = k·u_mat > 0; the node loads are
//! −Σ F_k ∇c_k, i.e. the force vector f = Σ F_k e_k acts on node a as +f and on node b as −f.
//!
//! Uses the kinematics, the friction law and the math; the step, events, init and the instance use
//! it.

use super::friction::{self, Eval, FrictionOut, FrictionParams, FrictionState};
use super::kinematics::{
    geometry_into, with_constant_type, Branches, Computed, ConnectionType, Geometry, Node, Pose,
    Role, Singular, Triads,
};
use super::math::{lift, Real, Scalar, Vec3};

/// A penalty pair: translational and rotational stiffness and damping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Penalty {
    /// Translational stiffness (N/m).
    pub k: Real,
    /// Translational damping (N.s/m).
    pub c: Real,
    /// Rotational stiffness (N.m/rad).
    pub k_rot: Real,
    /// Rotational damping (N.m.s/rad).
    pub c_rot: Real,
}

impl Penalty {
    /// Stiffness and damping for component slot `k` (0..2 translational, 3..5 rotational).
    #[inline]
    pub fn for_slot(&self, k: usize) -> (Real, Real) {
        if k < 3 {
            (self.k, self.c)
        } else {
            (self.k_rot, self.c_rot)
        }
    }
}

/// Input extrapolation over a communication step (docs/physics.md, "Stepping").
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Extrapolation {
    /// Nodes stay where the inputs put them at t.
    Hold,
    /// Nodes move along r + ṙ τ, q ← exp(ω τ)·q.
    #[default]
    Linear,
    /// Second order: r + ṙ τ + ½ v̇ τ², q ← exp(ω τ + ½ ω̇ τ²)·q, with v̇ and ω̇ from the input
    /// derivatives of the velocities where given, otherwise from the velocity inputs of the
    /// previous communication point (the input history; FMI 3.0 has no input derivatives).
    Quadratic,
    /// Second order as `Quadratic`, with v̇ and ω̇ the acceleration inputs (a.dv, a.dw, b.dv,
    /// b.dw): the importer gives the path its own bodies follow, in either FMI version.
    Accelerations,
}

/// Connector parameters, per component slot k−1 for the Abaqus component k.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    /// Linear stiffness per component (N/m, N.m/rad).
    pub k: [Real; 6],
    /// Linear damping per component (N.s/m, N.m.s/rad).
    pub c: [Real; 6],
    /// Whether the constitutive reference of a component is given (else the initial position).
    pub ref_given: [bool; 6],
    /// Given constitutive reference l_ref / θ_ref (m, rad).
    pub ref_value: [Real; 6],
    /// Lower stop on the component position (m, rad); −∞ = none.
    pub stop_lower: [Real; 6],
    /// Upper stop on the component position (m, rad); +∞ = none.
    pub stop_upper: [Real; 6],
    /// Stop penalty.
    pub stop: Penalty,
    /// Constraint penalty (PLANAR's SLIDE-PLANE and REVOLUTE constraints).
    pub constraint: Penalty,
    /// PLANAR predefined friction.
    pub friction: FrictionParams,
    /// Input extrapolation.
    pub extrapolation: Extrapolation,
    /// Largest internal substep (s); 0 = chosen from the path alone.
    pub max_substep: Real,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            k: [0.0; 6],
            c: [0.0; 6],
            ref_given: [false; 6],
            ref_value: [0.0; 6],
            stop_lower: [Real::NEG_INFINITY; 6],
            stop_upper: [Real::INFINITY; 6],
            stop: Penalty {
                k: 1e7,
                c: 0.0,
                k_rot: 1e5,
                c_rot: 0.0,
            },
            constraint: Penalty {
                k: 1e7,
                c: 0.0,
                k_rot: 1e5,
                c_rot: 0.0,
            },
            friction: FrictionParams::default(),
            extrapolation: Extrapolation::Linear,
            max_substep: 0.0,
        }
    }
}

impl Params {
    /// Relations between parameters that a connector needs (each value's own range is the
    /// variable table's, checked when it is set): a lower stop not above its upper stop, and
    /// friction's (`FrictionParams::check`). Names the parameters as the model description does.
    pub fn check(&self, roles: &[Role; 6]) -> Result<(), &'static str> {
        const S: [&str; 6] = [
            "stop.lower1 > stop.upper1",
            "stop.lower2 > stop.upper2",
            "stop.lower3 > stop.upper3",
            "stop.lower4 > stop.upper4",
            "stop.lower5 > stop.upper5",
            "stop.lower6 > stop.upper6",
        ];
        for i in 0..6 {
            if roles[i] == Role::Available && self.stop_lower[i] > self.stop_upper[i] {
                return Err(S[i]);
            }
        }
        self.friction.check()
    }
}

/// Energy accounts (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Energy<T: Scalar = Real> {
    /// Stored in springs, penalties, stops and stick springs, at the current configuration.
    pub stored: T,
    /// Dissipated by dampers (components and constraint penalty) since initialization.
    pub damping: T,
    /// Dissipated by friction since initialization.
    pub friction: T,
    /// Dissipated by stops since initialization.
    pub stops: T,
}

/// State that influences the future: committed at the end of each accepted substep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State<T: Scalar = Real> {
    /// Angle branches and the RADIAL-THRUST direction.
    pub branches: Branches,
    /// Component positions at the end of initialization (CU = CP − c0; SLIDE-PLANE x0).
    pub c0: [T; 6],
    /// Stop status per component: −1 lower, 0 free, +1 upper.
    pub stop_status: [i8; 6],
    /// PLANAR friction state.
    pub friction: FrictionState<T>,
    /// Dissipated energy accumulators (`stored` unused here).
    pub dissipated: Energy<T>,
    /// Dissipation power (W) at the end of the last substep: damping, stops.
    pub power: [T; 2],
}

impl<T: Scalar> Default for State<T> {
    fn default() -> Self {
        State {
            branches: Branches::default(),
            c0: [T::zero(); 6],
            stop_status: [0; 6],
            friction: FrictionState::default(),
            dissipated: Energy::default(),
            power: [T::zero(); 2],
        }
    }
}

impl State {
    /// This state in any scalar (its values as constants).
    pub fn lift<T: Scalar>(&self) -> State<T> {
        let e = &self.dissipated;
        State {
            branches: self.branches,
            c0: lift(self.c0),
            stop_status: self.stop_status,
            friction: self.friction.lift(),
            dissipated: Energy {
                stored: T::cst(e.stored),
                damping: T::cst(e.damping),
                friction: T::cst(e.friction),
                stops: T::cst(e.stops),
            },
            power: lift(self.power),
        }
    }
}

/// Everything the connector reports at one instant, per component slot.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Outputs<T: Scalar = Real> {
    /// CP / CPR: component position.
    pub cp: [T; 6],
    /// CU / CUR: motion from the initial state.
    pub cu: [T; 6],
    /// CV / CVR: relative velocity.
    pub cv: [T; 6],
    /// CEF / CEM: elastic force.
    pub cef: [T; 6],
    /// CVF / CVM: viscous force.
    pub cvf: [T; 6],
    /// CSF / CSM: friction force.
    pub csf: [T; 6],
    /// CRF / CRM: constraint and stop reactions.
    pub crf: [T; 6],
    /// CTF / CTM: total.
    pub ctf: [T; 6],
    /// CSLST: stop status.
    pub cslst: [i32; 6],
    /// Force on node a (W).
    pub fa: Vec3<T>,
    /// Moment on node a about x_a (W).
    pub ma: Vec3<T>,
    /// Force on node b (W).
    pub fb: Vec3<T>,
    /// Moment on node b about x_b (W).
    pub mb: Vec3<T>,
    /// PLANAR friction outputs.
    pub friction: FrictionOut<T>,
    /// Energy accounts.
    pub energy: Energy<T>,
    /// event.time: the first event of the last step (set by the instance, not by `evaluate`).
    pub event_time: Real,
    /// event.count: the events of the last step (set by the instance, not by `evaluate`).
    pub event_count: i32,
}

/// Outputs at nodes (a, b) given the committed state, and the state these imply
/// (branches, stop status, friction return map) for the caller to commit.
///
/// `mode`: a substep along the path, a read of the outputs at the current inputs, or the
/// evaluation behind the consistent tangent (see `friction::Eval`).
/// Dissipated energies in the result are the committed ones; `advance` accumulates them.
pub fn evaluate(
    ct: ConnectionType,
    p: &Params,
    st: &State,
    a: &Node,
    b: &Node,
    mode: Eval,
) -> Result<(Outputs, State), Singular> {
    let mut o = Outputs::default();
    let mut next = *st;
    evaluate_into(ct, p, st, a, b, mode, (&mut o, &mut next))?;
    Ok((o, next))
}

/// `evaluate` writing the outputs and the next state in place (the per-step path, where the
/// outputs go straight into the instance's cache instead of being copied there).
///
/// Every field of `o` and `next` is overwritten; on an error their contents are unspecified.
#[inline(always)]
pub fn evaluate_into(
    ct: ConnectionType,
    p: &Params,
    st: &State,
    a: &Node,
    b: &Node,
    mode: Eval,
    out: (&mut Outputs, &mut State),
) -> Result<(), Singular> {
    evaluate_pose(ct, p, st, &Pose::of(a, b), Computed, mode, out)
}

/// `evaluate_into` at a pose, in any scalar: with `Dual` (the inputs seeded along a direction)
/// the outputs carry their exact derivatives along it, the consistent tangent
/// (`ModelInstance::directional_derivative`). `triad`: how the centred triad at this pose is
/// come by (`geometry_into`).
pub fn evaluate_pose<T: Scalar>(
    ct: ConnectionType,
    p: &Params,
    st: &State<T>,
    pose: &Pose<T>,
    triad: impl Triads<T>,
    mode: Eval,
    out: (&mut Outputs<T>, &mut State<T>),
) -> Result<(), Singular> {
    // One copy of the body per connection type of the variants, each with the type a
    // constant: the branches on the type and its roles fold away, and each variant runs only
    // its own code (the per-step path; other pairings take the general copy).
    with_constant_type!(ct, |CT| evaluate_body(CT, p, st, pose, triad, mode, out))
}

/// The body of `evaluate_pose`, inlined into each of its per-type copies.
#[inline(always)]
fn evaluate_body<T: Scalar>(
    ct: ConnectionType,
    p: &Params,
    st: &State<T>,
    pose: &Pose<T>,
    triad: impl Triads<T>,
    mode: Eval,
    (o, next): (&mut Outputs<T>, &mut State<T>),
) -> Result<(), Singular> {
    let roles = ct.roles();
    let mut g = Geometry::blank();
    geometry_into(ct, pose, &st.branches, triad, &mut g)?;
    // `next` field by field (every field is written, none twice): what the evaluation does not
    // change is copied from `st`, the rest is written below
    next.branches = g.branches;
    next.c0 = st.c0;
    next.dissipated = st.dissipated;
    // Every output is written below, from zero where it accumulates (writing the struct
    // as a whole first would cost a memset of all of it on every evaluation).
    let zero = T::zero();
    let rates = g.rates(ct, pose);

    // every slot's component, each call with its slot and role constant (a loop over the
    // slots was not unrolled: every slot paid the dispatch on its role and the indexing)
    let mut sums = Sums {
        stored: zero,
        damping: zero,
        stops: zero,
    };
    macro_rules! slots {
        ($($k:literal),*) => {
            $(component(
                $k,
                roles[$k],
                (g.pos[$k], rates[$k]),
                p,
                st,
                (&mut *o, &mut *next),
                &mut sums,
            );)*
        };
    }
    slots!(0, 1, 2, 3, 4, 5);
    let Sums {
        mut stored,
        damping: p_damp,
        stops: p_stop,
    } = sums;

    // PLANAR friction: normal force and moment from the constraint reactions f1, m2, m3
    // (F_NC and M_NR1 are reported even when μ = 0 turns the friction force off)
    o.csf = [zero; 6];
    o.friction = FrictionOut::default();
    if ct.rot != super::kinematics::Rotational::Revolute {
        next.friction = st.friction;
    } else {
        let fr = friction::update(
            &p.friction,
            &st.friction,
            [o.crf[0], o.crf[4], o.crf[5]],
            [o.cp[1], o.cp[2], o.cp[3]],
            [o.cv[1], o.cv[2], o.cv[3]],
            mode,
        );
        o.csf[1] = fr.force[0];
        o.csf[2] = fr.force[1];
        o.csf[3] = fr.force[2];
        o.friction = fr.out;
        stored += fr.stored;
        next.friction = fr.state;
    }

    for k in 0..6 {
        o.ctf[k] = o.cef[k] + o.cvf[k] + o.csf[k] + o.crf[k];
    }
    // node loads by virtual work: −Σ F_k ∇c_k; f_a = −f_b since ∂c/∂x_a = −∂c/∂x_b
    (o.ma, o.fb, o.mb) = g.loads(ct, pose, &o.ctf);
    o.fa = Vec3::zeros() - o.fb;
    next.power = [p_damp, p_stop];
    o.energy = Energy {
        stored,
        friction: next.friction.dissipated,
        ..st.dissipated
    };
    Ok(())
}

/// What the components add up: stored energy, damping and stop dissipation powers.
struct Sums<T> {
    stored: T,
    damping: T,
    stops: T,
}

/// The outputs of component slot k (role `role`) at position `c` with rate `v`, its stop
/// status in `next`, and its energy and powers added to `sums` (`evaluate_body`).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn component<T: Scalar>(
    k: usize,
    role: Role,
    (c, v): (T, T),
    p: &Params,
    st: &State<T>,
    (o, next): (&mut Outputs<T>, &mut State<T>),
    sums: &mut Sums<T>,
) {
    let zero = T::zero();
    match role {
        Role::Absent => {
            next.stop_status[k] = st.stop_status[k];
            (o.cp[k], o.cu[k], o.cv[k]) = (zero, zero, zero);
            (o.cef[k], o.cvf[k], o.crf[k], o.cslst[k]) = (zero, zero, zero, 0);
        }
        Role::Constrained => {
            (o.cp[k], o.cu[k], o.cv[k]) = (c, c - st.c0[k], v);
            next.stop_status[k] = st.stop_status[k];
            // penalty on the constraint: SLIDE-PLANE x = x0, REVOLUTE φ2 = φ3 = 0
            let target = if k == 0 { st.c0[0] } else { zero };
            let (kp, cp) = p.constraint.for_slot(k);
            let gap = c - target;
            (o.cef[k], o.cvf[k], o.cslst[k]) = (zero, zero, 0);
            o.crf[k] = gap * kp + v * cp;
            sums.stored += gap * (0.5 * kp) * gap;
            sums.damping += v * cp * v;
        }
        Role::Available => {
            (o.cp[k], o.cu[k], o.cv[k]) = (c, c - st.c0[k], v);
            let reference = if p.ref_given[k] {
                T::cst(p.ref_value[k])
            } else {
                st.c0[k]
            };
            let u_mat = c - reference;
            o.cef[k] = u_mat * p.k[k];
            o.cvf[k] = v * p.c[k];
            sums.stored += u_mat * (0.5 * p.k[k]) * u_mat;
            sums.damping += v * p.c[k] * v;
            // stops act on positions, never pull
            let (ks, cs) = p.stop.for_slot(k);
            let (force, status, energy, power) =
                stop_force(c, v, p.stop_lower[k], p.stop_upper[k], ks, cs);
            // 0 + force, as when the reaction accumulated from zero: a stop force of −0
            // reads +0
            o.crf[k] = force + 0.0;
            o.cslst[k] = status as i32;
            next.stop_status[k] = status;
            sums.stored += energy;
            sums.stops += power;
        }
    }
}

/// One-sided stop penalty on position `c` with rate `v`: (force, status, energy, power).
///
/// The force never pulls: it is clipped at zero when the damper would make it adhesive
/// (docs/physics.md, "Stops"). `power` is the dissipation rate (F − k·p)·ṗ ≥ 0, where p is the penetration.
#[inline(always)]
fn stop_force<T: Scalar>(c: T, v: T, lower: Real, upper: Real, k: Real, d: Real) -> (T, i8, T, T) {
    let zero = T::zero();
    if c.re() > upper {
        let pen = c - upper;
        let f = (pen * k + v * d).max(zero);
        (f, 1, pen * (0.5 * k) * pen, (f - pen * k) * v)
    } else if c.re() < lower {
        let pen = -(c - lower);
        let f = (pen * k - v * d).max(zero);
        (-f, -1, pen * (0.5 * k) * pen, (f - pen * k) * (-v))
    } else {
        (zero, 0, zero, zero)
    }
}
