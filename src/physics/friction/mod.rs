//! PLANAR predefined friction (Abaqus Analysis User's Guide §31.1.5, PLANAR; docs/physics.md,
//! "Friction"): sliding in the local 2–3 plane and spin
//! about the local 1-direction, each an elastic stick spring with a return map onto the
//! friction limit; optionally coupled through an ellipsoidal limit surface with the flow rule of
//! a uniformly loaded disc (Contensou; `disc`).

use super::disc::disc_law;
use super::math::{lift, norm2, Real, Scalar};
use std::f64::consts::FRAC_PI_2;

/// What an evaluation of the connector is for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Eval {
    /// A substep of this length (s) along the path: friction takes its μ afresh from the
    /// committed status, and the stick dampers see the plastic slip rate over the substep.
    Step(Real),
    /// The outputs at the current inputs: the μ of the last committed return map.
    Read,
    /// The consistent tangent: as `Read`, each effect (sliding, spin) on the branch of the
    /// return map of its status at the point where the derivative is taken: a slipping one stays
    /// on its limit, a sticking one stays elastic (also on the limit at rest), so that the
    /// derivative does not straddle the stick/slip kink there.
    Tangent([Status; 2]),
    /// The start of the run (end of initialization), from a state with no elastic slip: the
    /// stick dampers see the initial rates; where their force exceeds the friction limit the
    /// excess is a plastic slip *rate* (the limit of a substep h → 0: no slip is taken, no
    /// energy dissipated). The state it commits is on the limit, so `Read` there reproduces it.
    Start,
}

/// Friction parameters (the `friction.*` variables).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionParams {
    /// Static coefficient μ_s (1).
    pub mu_static: Real,
    /// Kinetic coefficient μ_k (1), μ_k ≤ μ_s.
    pub mu_kinetic: Real,
    /// Decay d_c of μ with slip rate (s/m): μ = μ_k + (μ_s − μ_k)·exp(−d_c·rate).
    pub decay: Real,
    /// Characteristic puck radius R (m); 0 drops the bending and spin-from-f1 terms.
    pub radius: Real,
    /// Internal contact force F_C^int (N).
    pub f_int: Real,
    /// Internal contact moment M_R1^int (N.m).
    pub m_int: Real,
    /// Stick stiffness of sliding (N/m).
    pub k_stick: Real,
    /// Stick stiffness of spin (N.m/rad).
    pub k_stick_r1: Real,
    /// Stick damping of sliding (N.s/m), in parallel with the stick spring (0: Abaqus).
    pub c_stick: Real,
    /// Stick damping of spin (N.m.s/rad).
    pub c_stick_r1: Real,
    /// Cap on the tangential friction force (N); +∞ = none.
    pub max_force: Real,
    /// 0: the two effects separate (Abaqus); 1: coupled through the ellipsoidal limit surface
    /// |(f2, f3, m1/ρ)| ≤ μF_NC, ρ = 2R/3, with the uniform disc's flow rule.
    pub coupling: i32,
}

impl Default for FrictionParams {
    fn default() -> Self {
        FrictionParams {
            mu_static: 0.0,
            mu_kinetic: 0.0,
            decay: 0.0,
            radius: 0.0,
            f_int: 0.0,
            m_int: 0.0,
            k_stick: 1e6,
            k_stick_r1: 1e4,
            c_stick: 0.0,
            c_stick_r1: 0.0,
            max_force: Real::INFINITY,
            coupling: 0,
        }
    }
}

impl FrictionParams {
    /// Whether friction acts at all (μ = 0 turns it off).
    #[inline]
    pub fn enabled(&self) -> bool {
        self.mu_static > 0.0 || self.mu_kinetic > 0.0
    }

    /// Relations between friction parameters (each value's own range is the variable
    /// table's): μ_k ≤ μ_s, and the coupled mode needs a radius. Named as in the model
    /// description.
    pub fn check(&self) -> Result<(), &'static str> {
        if self.mu_kinetic > self.mu_static {
            return Err("friction.muKinetic > friction.muStatic");
        }
        if self.coupling == 1 && self.radius <= 0.0 {
            return Err("friction.coupling = 1 needs friction.R > 0");
        }
        Ok(())
    }

    /// μ at a slip rate (m/s).
    #[inline]
    pub fn mu<T: Scalar>(&self, rate: T) -> T {
        if self.decay == 0.0 {
            return T::cst(self.mu_static);
        }
        if rate.re() == 0.0 {
            // exp(−0) = 1 without calling exp (every step of a sticking contact); the rate is
            // a speed, so 0 is its kink and has no derivative (the central difference's 0)
            return T::cst(self.mu_kinetic + (self.mu_static - self.mu_kinetic));
        }
        (rate * -self.decay).exp() * (self.mu_static - self.mu_kinetic) + self.mu_kinetic
    }
}

/// Stick/slip status of one friction effect (exposed as Integer 0, 1, 2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Status {
    /// No friction-producing normal force.
    #[default]
    NoNormal = 0,
    /// Stick: the trial force is inside the limit.
    Stick = 1,
    /// Slip: the force is on the limit and plastic slip grows.
    Slip = 2,
}

/// Friction state per effect, saved with the FMU state.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FrictionState<T: Scalar = Real> {
    /// Plastic slip of sliding in the 2–3 plane (m); elastic slip = (y, z) − this.
    pub slip_plastic: [T; 2],
    /// Plastic spin slip about 1 (rad).
    pub slip_plastic_r1: T,
    /// Accumulated sliding slip (m).
    pub slip_acc: T,
    /// Accumulated spin slip (rad).
    pub slip_acc_r1: T,
    /// Sliding status.
    pub status: Status,
    /// Spin status.
    pub status_r1: Status,
    /// Energy dissipated by friction (J).
    pub dissipated: T,
    /// Slip speeds (m/s) at which μ was taken in the last return map, sliding (or coupled)
    /// and spin; 0 (μ = μ_s) when the effect entered it sticking.
    pub mu_rate: [T; 2],
    /// Friction force and moment of the last return map (f2, f3, m1).
    pub force: [T; 3],
    /// Elastic slip of the stick springs after the last return map (y, z, α parts; m, rad).
    pub elastic: [T; 3],
    /// Plastic slip rate over the last substep (m/s, rad/s): the stick dampers act on the
    /// elastic slip rate, the relative rate minus this.
    pub slip_rate: [T; 3],
}

impl FrictionState {
    /// This state in any scalar (its values as constants).
    #[inline(always)]
    pub fn lift<T: Scalar>(&self) -> FrictionState<T> {
        FrictionState {
            slip_plastic: lift(self.slip_plastic),
            slip_plastic_r1: T::cst(self.slip_plastic_r1),
            slip_acc: T::cst(self.slip_acc),
            slip_acc_r1: T::cst(self.slip_acc_r1),
            status: self.status,
            status_r1: self.status_r1,
            dissipated: T::cst(self.dissipated),
            mu_rate: lift(self.mu_rate),
            force: lift(self.force),
            elastic: lift(self.elastic),
            slip_rate: lift(self.slip_rate),
        }
    }
}

/// Friction outputs (CNF, CNM1, CSFC, CSMC1, accumulated slip, status per effect).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FrictionOut<T: Scalar = Real> {
    /// CNF = F_NC (N).
    pub cnf: T,
    /// CNM1 = M_NR1 (N.m).
    pub cnm1: T,
    /// CSFC: magnitude of the sliding friction force (N).
    pub csfc: T,
    /// CSMC1: magnitude of the spin friction moment (N.m).
    pub csmc1: T,
    /// Accumulated sliding slip (m).
    pub slip: T,
    /// Accumulated spin slip (rad).
    pub slip_r1: T,
    /// Sliding status.
    pub status: Status,
    /// Spin status.
    pub status_r1: Status,
}

/// Result of one friction update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionResult<T: Scalar = Real> {
    /// Friction forces on components 2, 3 (N) and moment on 4 (N.m): CSF2, CSF3, CSM1.
    pub force: [T; 3],
    /// Outputs.
    pub out: FrictionOut<T>,
    /// Energy stored in the stick springs (J).
    pub stored: T,
    /// State after the return map.
    pub state: FrictionState<T>,
}

/// F_NC and M_NR1 from the constraint reactions f1, m2, m3 (the manual's PLANAR friction
/// formulas; docs/physics.md, "Friction").
#[inline]
pub fn normal_loads<T: Scalar>(p: &FrictionParams, f1: T, m2: T, m3: T) -> (T, T) {
    let m_bend = norm2(m2, m3);
    let f1 = f1.abs();
    // "If R is 0.0, M_bend is ignored" (F_C) and "M_1 is ignored" (M_R1)
    let (f_c, m_1) = if p.radius > 0.0 {
        (f1 + m_bend / p.radius, f1 * (2.0 / 3.0 * p.radius))
    } else {
        (f1, T::zero())
    };
    let m_r1 = m_1 + m_bend;
    ((f_c + p.f_int).abs(), (m_r1 + p.m_int).abs())
}

/// Return map of both friction effects from the committed state `st`.
///
/// `reaction` = (f1, m2, m3), `pos` = (y, z, α), `rate` = (ẏ, ż, α̇).
///
/// Each effect is a stick spring k with a stick damper c in parallel, in series with the
/// friction slider: f = k e + c ė with e = position − plastic slip (elastic slip),
/// ė = rate − plastic slip rate, and |f| ≤ limit. A substep of length h first tries stick (no
/// plastic flow, ė = rate); when that force lies outside the limit it returns onto the limit
/// with the plastic slip Δs taken by backward Euler (plastic rate Δs/h), that is with the
/// stiffness k + c/h. Outside a substep (read, tangent) the committed plastic rate is kept, so
/// that evaluating again where a step ended reproduces its forces, and a return uses k alone.
/// c = 0 (the default) is Abaqus' elastic stick.
///
/// μ: while an effect's committed status is stick, μ = μ_s (breakaway happens at μ_s N, and
/// the elastic motion of a stuck stick spring does not lower μ and make the contact chatter);
/// while it slips, μ = μ(relative slip speed). `Eval::Step` takes that choice afresh (a
/// substep of the path); otherwise the speed of the last committed return map is reused, so
/// that evaluating the connector again where a step ended reproduces that step's forces.
pub fn update<T: Scalar>(
    p: &FrictionParams,
    st: &FrictionState<T>,
    reaction: [T; 3],
    pos: [T; 3],
    rate: [T; 3],
    mode: Eval,
) -> FrictionResult<T> {
    let h = match mode {
        Eval::Step(h) => h,
        _ => Real::INFINITY,
    };
    let stepping = h.is_finite();
    let start = mode == Eval::Start;
    // the slip branch of the return map, for the consistent tangent of a slipping effect
    let on_limit = |effect: usize| match mode {
        Eval::Tangent(branch) => Some(branch[effect]),
        _ => None,
    };
    let (f_nc, m_nr1) = normal_loads(p, reaction[0], reaction[1], reaction[2]);
    let mut next = *st;
    let zero = T::zero();
    if !p.enabled() {
        // friction off: no force, slip follows the motion, no stored energy
        next.slip_plastic = [pos[0], pos[1]];
        next.slip_plastic_r1 = pos[2];
        next.status = Status::NoNormal;
        next.status_r1 = Status::NoNormal;
        next.mu_rate = [zero; 2];
        next.force = [zero; 3];
        next.elastic = [zero; 3];
        next.slip_rate = [zero; 3];
        return FrictionResult {
            force: [zero; 3],
            out: outputs(&next, f_nc, m_nr1, zero, zero),
            stored: zero,
            state: next,
        };
    }
    // trial forces: stick springs and stick dampers with the plastic rates assumed (none in a
    // substep, the committed ones otherwise)
    let rate_p = if stepping { [zero; 3] } else { st.slip_rate };
    let damper = |rate_p: [T; 3]| damper(p, rate, rate_p);
    let elastic = |st: &FrictionState<T>| elastic(st, pos);
    let [f_tr0, f_tr1, m_tr] = trial(p, st, pos, rate, rate_p);
    let f_tr = [f_tr0, f_tr1];
    // stiffness of the return: the spring and the damper over the substep; at the start the
    // dampers alone, per unit of plastic slip rate
    let k_ret = if start {
        [p.c_stick, p.c_stick_r1]
    } else {
        [p.k_stick + p.c_stick / h, p.k_stick_r1 + p.c_stick_r1 / h]
    };
    // effective spin radius ρ = 2R/3 turns the spin rate into a slip speed (1 m when R = 0)
    let rho = if p.radius > 0.0 {
        2.0 / 3.0 * p.radius
    } else {
        1.0
    };
    let slide = norm2(rate[0], rate[1]);
    let spin = rate[2].abs() * rho;
    let speed_for = |status: Status, v: T, committed: T| match (stepping, status) {
        (_, Status::Slip) => v,
        (true, _) => zero,
        (false, _) => committed,
    };
    // A breakaway in this substep or at the start (stick or no normal force before it, slip
    // after it, μ decaying with speed): the decision is taken at μ_s, and the force returns onto the limit
    // at the current slip speed, where a slip goes on from and where a read here takes μ from
    // (so that a step ending at the breakaway reports the right limit, as a read there does).
    let breakaway = |now: Status, before: Status, v: T| {
        ((stepping || start) && p.decay > 0.0 && now == Status::Slip && before != Status::Slip)
            .then_some(v)
    };

    let (f, m) = if p.coupling == 1 {
        // ellipsoidal limit surface |(f2, f3, m1/ρ)| ≤ μ F_NC, the disc's flow rule
        let v = speed_for(st.status, norm2(slide, spin), st.mu_rate[0]);
        next.mu_rate = [v, v];
        let limit = (p.mu(v) * f_nc).min(T::cst(p.max_force));
        let norm = (f_tr[0] * f_tr[0] + f_tr[1] * f_tr[1] + (m_tr / rho) * (m_tr / rho)).sqrt();
        let load = loading(st, pos, [f_tr[0], f_tr[1], m_tr]);
        let flowing = on_limit_slips(stepping, (load[0] + load[1]).re(), st.status);
        let (scale, status) = return_status(norm, limit, f_nc, (on_limit(0), flowing));
        next.status = status;
        next.status_r1 = status;
        let (limit, scale) = match breakaway(status, st.status, norm2(slide, spin)) {
            Some(v) => {
                next.mu_rate = [v, v];
                let kinetic = (p.mu(v) * f_nc).min(T::cst(p.max_force));
                (kinetic, kinetic / norm)
            }
            None => (limit, scale),
        };
        if scale.re() == 1.0 {
            (f_tr, m_tr)
        } else if start {
            // onto the ellipsoid along the trial's direction: the start only needs a point of
            // the limit; the disc's flow takes over at the first substep
            ([f_tr[0] * scale, f_tr[1] * scale], m_tr * scale)
        } else {
            let f_abs = norm2(f_tr[0], f_tr[1]);
            let (f, m) = disc_flow_return(p.radius, rho, k_ret, f_abs, m_tr.abs(), limit);
            let a = if f_abs.re() > 0.0 { f / f_abs } else { zero };
            ([f_tr[0] * a, f_tr[1] * a], m.copysign(m_tr))
        }
    } else {
        // sliding: radial return in the 2–3 plane; spin: scalar return
        let v = speed_for(st.status, slide, st.mu_rate[0]);
        let v_r = speed_for(st.status_r1, spin, st.mu_rate[1]);
        next.mu_rate = [v, v_r];
        let limit = (p.mu(v) * f_nc).min(T::cst(p.max_force));
        let load = loading(st, pos, [f_tr[0], f_tr[1], m_tr]);
        let flowing = on_limit_slips(stepping, load[0].re(), st.status);
        let f_abs = norm2(f_tr[0], f_tr[1]);
        let (mut scale, status) = return_status(f_abs, limit, f_nc, (on_limit(0), flowing));
        let flowing_r = on_limit_slips(stepping, load[1].re(), st.status_r1);
        let (mut scale_r, status_r) = return_status(
            m_tr.abs(),
            p.mu(v_r) * m_nr1,
            m_nr1,
            (on_limit(1), flowing_r),
        );
        if let Some(v) = breakaway(status, st.status, slide) {
            next.mu_rate[0] = v;
            scale = (p.mu(v) * f_nc).min(T::cst(p.max_force)) / f_abs;
        }
        if let Some(v) = breakaway(status_r, st.status_r1, spin) {
            next.mu_rate[1] = v;
            scale_r = p.mu(v) * m_nr1 / m_tr.abs();
        }
        next.status = status;
        next.status_r1 = status_r;
        ([f_tr[0] * scale, f_tr[1] * scale], m_tr * scale_r)
    };
    // plastic slip Δs = (trial − returned)/(k + c/h), its rate, accumulation and dissipation
    let mut excess = [f_tr[0] - f[0], f_tr[1] - f[1], m_tr - m];
    // With a stick damper, a slipping substep's elastic slip follows the damped spring,
    // c ė + k e = f, under the force ramping from the committed one to the returned one
    // (`damped_elastic`: exact for that ramp, so second order and L-stable); its plastic slip
    // is then what the elastic slip does not take, and the plastic rate kept for the force at
    // the end is rate − ė (`relaxed`). (Backward Euler with the rate at the substep's end, as
    // the return map's stiffness k + c/h alone gives, let the damper carry c·a·h/2 of the force
    // while the slip decelerates at a: an O(h) error in the elastic slip that the plastic slip
    // kept at the next re-stick.) Coupled, the disc's flow rule keeps its own return.
    let mut relaxed: [Option<(T, T)>; 3] = [None; 3];
    if stepping && p.coupling != 1 {
        let slips = [next.status, next.status, next.status_r1].map(|s| s == Status::Slip);
        let (k, c) = (
            [p.k_stick, p.k_stick, p.k_stick_r1],
            [p.c_stick, p.c_stick, p.c_stick_r1],
        );
        let et = elastic(st);
        let f1 = [f[0], f[1], m];
        for i in 0..3 {
            if slips[i] && c[i] > 0.0 {
                let e1 = damped_elastic(k[i], c[i], h, st.elastic[i], st.force[i], f1[i]);
                excess[i] = (et[i] - e1) * k_ret[if i == 2 { 1 } else { 0 }];
                relaxed[i] = Some((e1, rate[i] - (f1[i] - e1 * k[i]) / c[i]));
            }
        }
    }
    if start {
        // the excess over the limit is a plastic rate, (trial − returned)/c (a return happens
        // only with a damper: the trial of an unstretched spring alone is zero)
        let per = |x: T, c: Real| if x.re() == 0.0 { zero } else { x / c };
        next.slip_rate = [
            per(excess[0], k_ret[0]),
            per(excess[1], k_ret[0]),
            per(excess[2], k_ret[1]),
        ];
    }
    let (ds, ds_r) = if start {
        ([zero; 2], zero)
    } else {
        (
            [excess[0] / k_ret[0], excess[1] / k_ret[0]],
            excess[2] / k_ret[1],
        )
    };
    // Where a step ended, a read's plastic increment is zero up to round-off (the trial is back
    // on the limit): there the accumulated slip |Δs| and the plastic work max(0, ·) have their
    // kinks, and their derivative is taken as the central difference's there (`Real`: no change)
    let kink = |x: T, f: T| !stepping && x.re().abs() <= ON_LIMIT * f.re().abs();
    let at_kink = [
        kink(norm2(excess[0], excess[1]), norm2(f[0], f[1])),
        kink(excess[2], m),
    ];
    // |Δs| at Δs = 0: the central difference's derivative is 0
    let flat = |x: T, k: bool| if k { x.with_eps(0.0) } else { x };
    next.slip_plastic[0] += ds[0];
    next.slip_plastic[1] += ds[1];
    next.slip_plastic_r1 += ds_r;
    next.slip_acc += flat(norm2(ds[0], ds[1]), at_kink[0]);
    next.slip_acc_r1 += flat(ds_r.abs(), at_kink[1]);
    if stepping {
        let rate_of = |x: T, r: Option<(T, T)>| r.map_or(x / h, |(_, rate)| rate);
        next.slip_rate = [
            rate_of(ds[0], relaxed[0]),
            rate_of(ds[1], relaxed[1]),
            rate_of(ds_r, relaxed[2]),
        ];
    }
    // The force as spring and damper give it from the new plastic slip and rate: the same
    // expression a later evaluation at this point starts from, so both report the same bits.
    let (e1, d1) = (elastic(&next), damper(next.slip_rate));
    let spring = [e1[0] * p.k_stick, e1[1] * p.k_stick, e1[2] * p.k_stick_r1];
    let force = [spring[0] + d1[0], spring[1] + d1[1], spring[2] + d1[2]];
    next.dissipated += dissipation(p, st, &force, ([ds[0], ds[1], ds_r], at_kink), e1);
    next.force = force;
    next.elastic = e1;
    let csfc = norm2(force[0], force[1]);
    FrictionResult {
        force,
        out: outputs(&next, f_nc, m_nr1, csfc, force[2].abs()),
        stored: ((spring[0] * spring[0] + spring[1] * spring[1]) / p.k_stick
            + spring[2] * spring[2] / p.k_stick_r1)
            * 0.5,
        state: next,
    }
}

/// The elastic slip at the end of a slipping substep of length `h` with a stick damper: the
/// solution of c ė + k e = f(τ), f ramping from `f0` to `f1`, from `e0`:
/// e(h) = [f1 + (k e0 − f0) E + (f1 − f0) φ(kh/c)] / k, E = exp(−kh/c), φ(x) = (E − 1)/x
/// (its series below x = 1e-3, where E − 1 would lose digits).
#[inline]
fn damped_elastic<T: Scalar>(k: Real, c: Real, h: Real, e0: T, f0: T, f1: T) -> T {
    let x = k * h / c;
    let big_e = (-x).exp();
    let phi = if x < 1e-3 {
        -1.0 + x * (0.5 - x * (1.0 / 6.0 - x / 24.0))
    } else {
        (big_e - 1.0) / x
    };
    (f1 + (e0 * k - f0) * big_e + (f1 - f0) * phi) / k
}

/// Elastic slip (y, z, α parts) at positions `pos` from the plastic slip of `st`.
#[inline]
fn elastic<T: Scalar>(st: &FrictionState<T>, pos: [T; 3]) -> [T; 3] {
    [
        pos[0] - st.slip_plastic[0],
        pos[1] - st.slip_plastic[1],
        pos[2] - st.slip_plastic_r1,
    ]
}

/// Stick damper forces at the relative rates `rate` with the plastic rates `rate_p`.
#[inline]
fn damper<T: Scalar>(p: &FrictionParams, rate: [T; 3], rate_p: [T; 3]) -> [T; 3] {
    [
        (rate[0] - rate_p[0]) * p.c_stick,
        (rate[1] - rate_p[1]) * p.c_stick,
        (rate[2] - rate_p[2]) * p.c_stick_r1,
    ]
}

/// Trial friction force and moment (f2, f3, m1): stick springs on the elastic slip from the
/// plastic slip of `st`, stick dampers with the plastic rates `rate_p`.
#[inline]
pub fn trial<T: Scalar>(
    p: &FrictionParams,
    st: &FrictionState<T>,
    pos: [T; 3],
    rate: [T; 3],
    rate_p: [T; 3],
) -> [T; 3] {
    let (e, d) = (elastic(st, pos), damper(p, rate, rate_p));
    [
        e[0] * p.k_stick + d[0],
        e[1] * p.k_stick + d[1],
        e[2] * p.k_stick_r1 + d[2],
    ]
}

/// The stick → slip event functions of a substep that starts sticking from `st`: the trial
/// force minus its limit, sliding (or the coupled ellipsoid) and spin, at positions `pos`,
/// rates `rate` and normal loads F_NC, M_NR1. Exactly what `update` compares in that substep
/// (no plastic rate, μ at zero slip speed): ≥ 0 is where the effect slips.
pub fn stick_slip_function(
    p: &FrictionParams,
    st: &FrictionState,
    pos: [Real; 3],
    rate: [Real; 3],
    normals: (Real, Real),
) -> [Real; 2] {
    trial_minus_limit(p, st, pos, rate, normals, [0.0; 2])
}

/// The slip speeds μ is taken at (m/s): sliding, spin at the effective radius ρ = 2R/3 (|α̇|
/// when R = 0), and coupled, the two together, as `update` takes them.
#[inline]
pub fn slip_speeds(p: &FrictionParams, rate: [Real; 3]) -> [Real; 2] {
    let rho = if p.radius > 0.0 {
        2.0 / 3.0 * p.radius
    } else {
        1.0
    };
    let (slide, spin) = (norm2(rate[0], rate[1]), rate[2].abs() * rho);
    if p.coupling == 1 {
        let v = norm2(slide, spin);
        [v, v]
    } else {
        [slide, spin]
    }
}

/// The slip → stick event functions of a substep that starts slipping from `st` with a stick
/// damper (`damped` per effect): the trial force minus its limit with μ at the current slip
/// speeds, which is what `update` compares at the substep's end (> 0: the plastic slip goes
/// on; it stops where the trial falls inside the limit, before the relative slip reverses
/// when the damper carries part of the force or μ rises as the slip slows).
pub fn slip_stick_function(
    p: &FrictionParams,
    st: &FrictionState,
    pos: [Real; 3],
    rate: [Real; 3],
    normals: (Real, Real),
) -> [Real; 2] {
    trial_minus_limit(p, st, pos, rate, normals, slip_speeds(p, rate))
}

/// The trial force (no plastic rate) minus its limit with μ at the slip speeds `speed`,
/// sliding (or the coupled ellipsoid) and spin.
fn trial_minus_limit(
    p: &FrictionParams,
    st: &FrictionState,
    pos: [Real; 3],
    rate: [Real; 3],
    (f_nc, m_nr1): (Real, Real),
    speed: [Real; 2],
) -> [Real; 2] {
    let [f2, f3, m1] = trial(p, st, pos, rate, [0.0; 3]);
    let limit = (p.mu(speed[0]) * f_nc).min(p.max_force);
    if p.coupling == 1 {
        let rho = 2.0 / 3.0 * p.radius;
        let phi = (f2 * f2 + f3 * f3 + (m1 / rho) * (m1 / rho)).sqrt() - limit;
        [phi, phi]
    } else {
        [norm2(f2, f3) - limit, m1.abs() - p.mu(speed[1]) * m_nr1]
    }
}

/// Energy dissipated from the committed state `st` to the new force `f1`, plastic slip
/// increment `ds` and elastic slip `e1`, by the trapezoidal rule: the work of the force on the
/// plastic slip, ½(f0 + f1)·Δs (never negative), and with stick dampers their work on the
/// elastic slip, ½(d0 + d1)·Δe with d = f − k e. With the stick springs' energy ½k e² this
/// closes work = Δstored + dissipated exactly for the trapezoidal work ½(f0 + f1)·Δposition,
/// also where μ changes from step to step (static → kinetic).
///
/// `at_kink`: per effect (sliding, spin), whether its plastic increment is the round-off of a
/// read where a step ended. When both are, the plastic work is at the kink of max(0, ·), whose
/// derivative is taken as the central difference's there: half the work's.
fn dissipation<T: Scalar>(
    p: &FrictionParams,
    st: &FrictionState<T>,
    f1: &[T; 3],
    (ds, at_kink): ([T; 3], [bool; 2]),
    e1: [T; 3],
) -> T {
    let f0 = &st.force;
    let plastic =
        ((f0[0] + f1[0]) * ds[0] + (f0[1] + f1[1]) * ds[1] + (f0[2] + f1[2]) * ds[2]) * 0.5;
    let mut w = plastic.max(T::zero());
    if at_kink[0] && at_kink[1] {
        w = w.with_eps(0.5 * plastic.eps());
    }
    let k = [p.k_stick, p.k_stick, p.k_stick_r1];
    let c = [p.c_stick, p.c_stick, p.c_stick_r1];
    for i in 0..3 {
        if c[i] > 0.0 {
            let e0 = st.elastic[i];
            let (d0, d1) = (f0[i] - e0 * k[i], f1[i] - e1[i] * k[i]);
            w += (d0 + d1) * 0.5 * (e1[i] - e0);
        }
    }
    w
}

fn outputs<T: Scalar>(st: &FrictionState<T>, cnf: T, cnm1: T, csfc: T, csmc1: T) -> FrictionOut<T> {
    FrictionOut {
        cnf,
        cnm1,
        csfc,
        csmc1,
        slip: st.slip_acc,
        slip_r1: st.slip_acc_r1,
        status: st.status,
        status_r1: st.status_r1,
    }
}

/// Return onto the ellipsoid |(f, m/ρ)| = L with the uniform disc's flow rule (`disc`);
/// `k_s`, `k_r`: the stiffnesses of the return (stick springs and dampers).
///
/// The plastic slip increments (Δs along f_tr, Δθ about 1) are written λ(cos χ, sin χ/R), so
/// that ε = Δs/(RΔθ) = cot χ is the disc's slip ratio; the returned force is the point of the
/// ellipsoid whose direction is the disc's, tan ψ = (R M̂(ε)/ρ)/F̂(ε):
/// f = L cos ψ, m = ρ L sin ψ. Then m/f = R M̂/F̂ exactly as for the disc, so a disc of
/// inertia mR²/2 keeps v/(Rω) = 0.653 while it stops; the magnitude is the ellipsoid's, within
/// 7 % of the disc's. The stick springs give F − f = k_s λ cos χ and M − m = k_r λ sin χ/R
/// (F = |f_tr|, M = |m_tr|), so χ is a root of
/// h(χ) = (F − f(χ)) k_r sin χ − (M − m(χ)) R k_s cos χ, with h(0) = −M R k_s ≤ 0 and
/// h(π/2) = F k_r ≥ 0: a bracket, solved by the Illinois variant of false position.
/// λ > 0 exactly when the trial lies outside the (convex) ellipsoid. Returns (f, m).
///
/// With `Dual` inputs the root is found on their values, and its derivative is the implicit
/// function's, dχ = −(∂h/∂inputs·δ)/(∂h/∂χ), both exact (the iteration's own derivative is not
/// taken).
fn disc_flow_return<T: Scalar>(
    r: Real,
    rho: Real,
    k_ret: [Real; 2],
    f_tr: T,
    m_tr: T,
    limit: T,
) -> (T, T) {
    let (fr, mr, lr) = (f_tr.re(), m_tr.re(), limit.re());
    let h = |chi: Real| disc_h(r, rho, k_ret, chi, (fr, mr, lr));
    let (mut a, mut ha) = (0.0, h(0.0));
    let (mut b, mut hb) = (FRAC_PI_2, h(FRAC_PI_2));
    let chi = if ha >= 0.0 {
        0.0
    } else if hb <= 0.0 {
        FRAC_PI_2
    } else {
        let mut x = b;
        for _ in 0..100 {
            x = (a * hb - b * ha) / (hb - ha);
            let hx = h(x);
            if hx == 0.0 {
                break;
            }
            if (hx > 0.0) == (hb > 0.0) {
                ha *= 0.5; // Illinois: the retained end's value halved
            } else {
                (a, ha) = (b, hb);
            }
            (b, hb) = (x, hx);
            if (b - a).abs() <= 4.0 * Real::EPSILON {
                break;
            }
        }
        x
    };
    let mut chi_t = T::cst(chi);
    if T::DUAL && chi > 0.0 && chi < FRAC_PI_2 {
        let along = disc_h(r, rho, k_ret, chi_t, (f_tr, m_tr, limit)).eps();
        let (fc, mc, lc) = (T::cst(fr), T::cst(mr), T::cst(lr));
        let slope = disc_h(r, rho, k_ret, chi_t.with_eps(1.0), (fc, mc, lc)).eps();
        if slope != 0.0 {
            chi_t = chi_t.with_eps(-along / slope);
        }
    }
    let (f, m, _, _) = disc_on_surface(r, rho, chi_t, limit);
    (f, m)
}

/// The point of the ellipsoid of size `limit` in the disc's direction at slip angle χ, with
/// sin χ and cos χ: (f, m, sin χ, cos χ).
#[inline]
fn disc_on_surface<T: Scalar>(r: Real, rho: Real, chi: T, limit: T) -> (T, T, T, T) {
    let (s, c) = chi.sin_cos();
    let (f_hat, m_hat) = disc_law(c.max(T::zero()), s.max(T::zero()));
    let (x, y) = (f_hat, m_hat * r / rho);
    let n = norm2(x, y);
    (limit * x / n, limit * rho * y / n, s, c)
}

/// h(χ) of `disc_flow_return` for the trial (F, M) and the limit L.
#[inline]
fn disc_h<T: Scalar>(
    r: Real,
    rho: Real,
    [k_s, k_r]: [Real; 2],
    chi: T,
    (f_tr, m_tr, limit): (T, T, T),
) -> T {
    let (f, m, s, c) = disc_on_surface(r, rho, chi, limit);
    (f_tr - f) * k_r * s - (m_tr - m) * r * k_s * c
}

/// How much the motion since the committed state loaded each stick spring along its trial
/// force (sliding, spin): the elastic slip's change dotted with the force (> 0: loading).
#[inline]
fn loading<T: Scalar>(st: &FrictionState<T>, pos: [T; 3], f: [T; 3]) -> [T; 2] {
    let e = elastic(st, pos);
    let d = [
        e[0] - st.elastic[0],
        e[1] - st.elastic[1],
        e[2] - st.elastic[2],
    ];
    [d[0] * f[0] + d[1] * f[1], d[2] * f[2]]
}

/// Whether an effect whose trial force lies on its limit within round-off slips: in a substep,
/// when the substep's motion loaded its spring further along the force (a breakaway or a slip
/// going on; at rest or moving back the spring holds: stick); elsewhere (a read where a step
/// ended, restored or not) the status that step committed, so a read reports what the step did.
#[inline]
fn on_limit_slips(stepping: bool, load: Real, committed: Status) -> bool {
    if stepping {
        load > 0.0
    } else {
        committed == Status::Slip
    }
}

/// Relative band around the friction limit that counts as "on the limit".
pub const ON_LIMIT: Real = 1e-9;

/// Scale factor onto the limit and the status for a trial magnitude; `branch`: the status
/// whose branch of the return map a tangent evaluation keeps; `flowing`: whether a trial on
/// the limit within round-off slips (`on_limit_slips`).
#[inline]
fn return_status<T: Scalar>(
    trial: T,
    limit: T,
    normal: T,
    (branch, flowing): (Option<Status>, bool),
) -> (T, Status) {
    let (one, normal) = (T::one(), normal.re());
    // the tangent's branch: a slipping effect on its limit, a sticking one elastic
    match branch {
        Some(Status::Slip) if normal > 0.0 && trial.re() > 0.0 => {
            return (limit / trial, Status::Slip)
        }
        Some(Status::Stick) if normal > 0.0 => return (one, Status::Stick),
        _ => {}
    }
    // On the limit within round-off there is no further return: re-evaluating the connector
    // where a slip step ended puts the trial force back on the limit (to round-off, either
    // side), and that is the same slip with the same force (`on_limit_slips`). A contact
    // brought to rest on its limit sticks from its first substep at rest.
    if normal > 0.0 && (trial - limit).re().abs() <= ON_LIMIT * limit.re() {
        let status = if flowing { Status::Slip } else { Status::Stick };
        return (one, status);
    }
    if trial.re() <= limit.re() {
        let s = if normal > 0.0 {
            Status::Stick
        } else {
            Status::NoNormal
        };
        (one, s)
    } else {
        let s = if normal > 0.0 {
            Status::Slip
        } else {
            Status::NoNormal
        };
        // trial > limit ≥ 0, so trial > 0
        (limit / trial, s)
    }
}

#[cfg(test)]
mod tests;
