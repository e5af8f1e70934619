//! PLANAR predefined friction (seed pages 631–632): sliding in the local 2–3 plane and spin
//! about the local 1-direction, each an elastic stick spring with a return map onto the
//! friction limit; optionally coupled through an ellipsoidal limit surface (Contensou).

use super::math::Real;

/// What an evaluation of the connector is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Eval {
    /// A substep along the path: friction takes its μ afresh from the committed status.
    Step,
    /// The outputs at the current inputs: the μ of the last committed return map.
    Read,
    /// The consistent tangent: as `Read`, and the effects marked (sliding, spin) stay on their
    /// limit (the slip branch of the return map): those that slip at the point where the
    /// derivative is taken, so that it does not straddle the stick/slip kink there.
    Tangent([bool; 2]),
}

/// Friction parameters (SPEC §3 names `friction.*`).
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
    /// Cap on the tangential friction force (N); +∞ = none.
    pub max_force: Real,
    /// 0: the two effects separate (Abaqus); 1: coupled through the ellipsoidal limit surface.
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

    /// Parameter values friction cannot use, named as in the model description.
    pub fn check(&self) -> Result<(), &'static str> {
        let nonneg = [
            (self.mu_static, "friction.muStatic"),
            (self.mu_kinetic, "friction.muKinetic"),
            (self.decay, "friction.decay"),
            (self.radius, "friction.R"),
            (self.max_force, "friction.maxForce"),
        ];
        for (v, name) in nonneg {
            if v < 0.0 {
                return Err(name);
            }
        }
        if self.k_stick.is_nan() || self.k_stick <= 0.0 {
            return Err("friction.stickStiffness (must be > 0)");
        }
        if self.k_stick_r1.is_nan() || self.k_stick_r1 <= 0.0 {
            return Err("friction.stickStiffnessR1 (must be > 0)");
        }
        if self.mu_kinetic > self.mu_static {
            return Err("friction.muKinetic > friction.muStatic");
        }
        match self.coupling {
            0 => Ok(()),
            1 if self.radius > 0.0 => Ok(()),
            1 => Err("friction.coupling = 1 needs friction.R > 0"),
            _ => Err("friction.coupling (0 or 1)"),
        }
    }

    /// μ at a slip rate (m/s).
    #[inline]
    pub fn mu(&self, rate: Real) -> Real {
        if self.decay == 0.0 {
            return self.mu_static;
        }
        self.mu_kinetic + (self.mu_static - self.mu_kinetic) * (-self.decay * rate).exp()
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
pub struct FrictionState {
    /// Plastic slip of sliding in the 2–3 plane (m); elastic slip = (y, z) − this.
    pub slip_plastic: [Real; 2],
    /// Plastic spin slip about 1 (rad).
    pub slip_plastic_r1: Real,
    /// Accumulated sliding slip (m).
    pub slip_acc: Real,
    /// Accumulated spin slip (rad).
    pub slip_acc_r1: Real,
    /// Sliding status.
    pub status: Status,
    /// Spin status.
    pub status_r1: Status,
    /// Energy dissipated by friction (J).
    pub dissipated: Real,
    /// Slip speeds (m/s) at which μ was taken in the last return map, sliding (or coupled)
    /// and spin; 0 (μ = μ_s) when the effect entered it sticking.
    pub mu_rate: [Real; 2],
    /// Friction force and moment of the last return map (f2, f3, m1).
    pub force: [Real; 3],
}

/// Friction outputs (SPEC §5).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct FrictionOut {
    /// CNF = F_NC (N).
    pub cnf: Real,
    /// CNM1 = M_NR1 (N.m).
    pub cnm1: Real,
    /// CSFC: magnitude of the sliding friction force (N).
    pub csfc: Real,
    /// CSMC1: magnitude of the spin friction moment (N.m).
    pub csmc1: Real,
    /// Accumulated sliding slip (m).
    pub slip: Real,
    /// Accumulated spin slip (rad).
    pub slip_r1: Real,
    /// Sliding status.
    pub status: Status,
    /// Spin status.
    pub status_r1: Status,
}

/// Result of one friction update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionResult {
    /// Friction forces on components 2, 3 (N) and moment on 4 (N.m): CSF2, CSF3, CSM1.
    pub force: [Real; 3],
    /// Outputs.
    pub out: FrictionOut,
    /// Energy stored in the stick springs (J).
    pub stored: Real,
    /// State after the return map.
    pub state: FrictionState,
}

/// F_NC and M_NR1 from the constraint reactions f1, m2, m3 (seed page 631–632).
#[inline]
pub fn normal_loads(p: &FrictionParams, f1: Real, m2: Real, m3: Real) -> (Real, Real) {
    let m_bend = m2.hypot(m3);
    let f1 = f1.abs();
    // "If R is 0.0, M_bend is ignored" (F_C) and "M_1 is ignored" (M_R1)
    let (f_c, m_1) = if p.radius > 0.0 {
        (f1 + m_bend / p.radius, 2.0 / 3.0 * p.radius * f1)
    } else {
        (f1, 0.0)
    };
    let m_r1 = m_1 + m_bend;
    ((f_c + p.f_int).abs(), (m_r1 + p.m_int).abs())
}

/// Return map of both friction effects from the committed state `st`.
///
/// `reaction` = (f1, m2, m3), `pos` = (y, z, α), `rate` = (ẏ, ż, α̇).
///
/// μ: while an effect's committed status is stick, μ = μ_s (breakaway happens at μ_s N, and
/// the elastic motion of a stuck stick spring does not lower μ and make the contact chatter);
/// while it slips, μ = μ(relative slip speed). `Eval::Step` takes that choice afresh (a
/// substep of the path); otherwise the speed of the last committed return map is reused, so
/// that evaluating the connector again where a step ended reproduces that step's forces.
pub fn update(
    p: &FrictionParams,
    st: &FrictionState,
    reaction: [Real; 3],
    pos: [Real; 3],
    rate: [Real; 3],
    mode: Eval,
) -> FrictionResult {
    let stepping = mode == Eval::Step;
    // the slip branch of the return map, for the consistent tangent of a slipping effect
    let on_limit = |effect: usize| matches!(mode, Eval::Tangent(slip) if slip[effect]);
    let (f_nc, m_nr1) = normal_loads(p, reaction[0], reaction[1], reaction[2]);
    let mut next = *st;
    // trial forces of the stick springs
    let f_tr = [
        p.k_stick * (pos[0] - st.slip_plastic[0]),
        p.k_stick * (pos[1] - st.slip_plastic[1]),
    ];
    let m_tr = p.k_stick_r1 * (pos[2] - st.slip_plastic_r1);
    // effective spin radius ρ = 2R/3 turns the spin rate into a slip speed (1 m when R = 0)
    let rho = if p.radius > 0.0 {
        2.0 / 3.0 * p.radius
    } else {
        1.0
    };
    let slide = rate[0].hypot(rate[1]);
    let spin = rho * rate[2].abs();
    let speed_for = |status: Status, v: Real, committed: Real| match (stepping, status) {
        (true, Status::Slip) => v,
        (true, _) => 0.0,
        (false, _) => committed,
    };

    let (f, m) = if !p.enabled() {
        // friction off: no force, slip follows the motion, no stored energy
        next.slip_plastic = [pos[0], pos[1]];
        next.slip_plastic_r1 = pos[2];
        next.status = Status::NoNormal;
        next.status_r1 = Status::NoNormal;
        next.mu_rate = [0.0; 2];
        next.force = [0.0; 3];
        return FrictionResult {
            force: [0.0; 3],
            out: outputs(&next, f_nc, m_nr1, 0.0, 0.0),
            stored: 0.0,
            state: next,
        };
    } else if p.coupling == 1 {
        // ellipsoidal limit surface |(f2, f3, m1/ρ)| ≤ μ F_NC with associated flow
        let v = speed_for(st.status, slide.hypot(spin), st.mu_rate[0]);
        next.mu_rate = [v, v];
        let limit = (p.mu(v) * f_nc).min(p.max_force);
        let norm = (f_tr[0] * f_tr[0] + f_tr[1] * f_tr[1] + (m_tr / rho) * (m_tr / rho)).sqrt();
        let (scale, status) = return_status(norm, limit, f_nc, on_limit(0));
        next.status = status;
        next.status_r1 = status;
        if scale == 1.0 {
            (f_tr, m_tr)
        } else {
            let (a, b) = ellipsoid_return(p, rho, f_tr[0].hypot(f_tr[1]), m_tr.abs() / rho, limit);
            ([f_tr[0] * a, f_tr[1] * a], m_tr * b)
        }
    } else {
        // sliding: radial return in the 2–3 plane; spin: scalar return
        let v = speed_for(st.status, slide, st.mu_rate[0]);
        let v_r = speed_for(st.status_r1, spin, st.mu_rate[1]);
        next.mu_rate = [v, v_r];
        let limit = (p.mu(v) * f_nc).min(p.max_force);
        let (scale, status) = return_status(f_tr[0].hypot(f_tr[1]), limit, f_nc, on_limit(0));
        let (scale_r, status_r) = return_status(m_tr.abs(), p.mu(v_r) * m_nr1, m_nr1, on_limit(1));
        next.status = status;
        next.status_r1 = status_r;
        ([f_tr[0] * scale, f_tr[1] * scale], m_tr * scale_r)
    };
    slip_update(&mut next, p, f_tr, f, m_tr, m);
    // The force as the stick springs give it from the new plastic slip: the same expression a
    // later evaluation at this point starts from, so both report the same bits.
    let f = [
        p.k_stick * (pos[0] - next.slip_plastic[0]),
        p.k_stick * (pos[1] - next.slip_plastic[1]),
    ];
    let m = p.k_stick_r1 * (pos[2] - next.slip_plastic_r1);
    next.force = [f[0], f[1], m];
    let csfc = f[0].hypot(f[1]);
    FrictionResult {
        force: [f[0], f[1], m],
        out: outputs(&next, f_nc, m_nr1, csfc, m.abs()),
        stored: 0.5 * (csfc * csfc / p.k_stick + m * m / p.k_stick_r1),
        state: next,
    }
}

fn outputs(st: &FrictionState, cnf: Real, cnm1: Real, csfc: Real, csmc1: Real) -> FrictionOut {
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

/// Closest-point return onto the ellipsoid |(f, m/ρ)| = L in the energy norm of the stick
/// springs (associated flow: the plastic slip rate (v, ω) is normal to the ellipsoid, so
/// (f, m/ρ) ∥ (v, ρω), the Contensou coupling). With F = |f_tr|, M = |m_tr|/ρ the returned
/// forces are f_tr/(1 + x k_s) and m_tr/(1 + x k_r/ρ²), with x the root of
/// g(x) = F²/(1 + x k_s)² + M²/(1 + x k_r/ρ²)² − L², convex and decreasing: Newton converges
/// monotonically once on the left of the root. Returns the two scale factors.
fn ellipsoid_return(p: &FrictionParams, rho: Real, f: Real, m: Real, limit: Real) -> (Real, Real) {
    let (ka, kb) = (p.k_stick, p.k_stick_r1 / (rho * rho));
    let mut x: Real = 0.0;
    for _ in 0..60 {
        let (a, b) = (1.0 / (1.0 + x * ka), 1.0 / (1.0 + x * kb));
        let g = a * a * f * f + b * b * m * m - limit * limit;
        if g.abs() <= 1e-15 * limit * limit {
            break;
        }
        let dg = -2.0 * (a * a * a * ka * f * f + b * b * b * kb * m * m);
        let next = x - g / dg;
        // keep 1 + x k > 0 (the tangent branch may start inside the ellipsoid, x < 0)
        let floor = -0.5 / ka.max(kb);
        x = if next > floor {
            next
        } else {
            0.5 * (x + floor)
        };
    }
    (1.0 / (1.0 + x * ka), 1.0 / (1.0 + x * kb))
}

/// Relative band around the friction limit that counts as "on the limit".
pub const ON_LIMIT: Real = 1e-9;

/// Scale factor onto the limit and the status for a trial magnitude.
#[inline]
fn return_status(trial: Real, limit: Real, normal: Real, on_limit: bool) -> (Real, Status) {
    if on_limit && normal > 0.0 && trial > 0.0 {
        return (limit / trial, Status::Slip);
    }
    // On the limit within round-off counts as slip, with no further return: re-evaluating the
    // connector where a slip step ended puts the trial force back on the limit (to round-off,
    // either side), and that is the same slip with the same force.
    if normal > 0.0 && (trial - limit).abs() <= ON_LIMIT * limit {
        return (1.0, Status::Slip);
    }
    if trial <= limit {
        let s = if normal > 0.0 {
            Status::Stick
        } else {
            Status::NoNormal
        };
        (1.0, s)
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

/// Plastic slip increments Δs = (trial − returned)/k_s, their accumulation and dissipation.
#[inline]
fn slip_update(
    next: &mut FrictionState,
    p: &FrictionParams,
    f_tr: [Real; 2],
    f: [Real; 2],
    m_tr: Real,
    m: Real,
) {
    let ds = [(f_tr[0] - f[0]) / p.k_stick, (f_tr[1] - f[1]) / p.k_stick];
    let ds_r = (m_tr - m) / p.k_stick_r1;
    next.slip_plastic[0] += ds[0];
    next.slip_plastic[1] += ds[1];
    next.slip_plastic_r1 += ds_r;
    next.slip_acc += ds[0].hypot(ds[1]);
    next.slip_acc_r1 += ds_r.abs();
    // Work of the friction force on the plastic slip, by the trapezoidal rule between the
    // last committed force and this one: with the stick-spring energy ½f²/k this closes
    // work = Δstored + dissipated exactly for the trapezoidal work of the force, also where μ
    // changes from step to step (static → kinetic). Never negative: a dissipation.
    let f0 = &next.force;
    let w = 0.5 * ((f0[0] + f[0]) * ds[0] + (f0[1] + f[1]) * ds[1] + (f0[2] + m) * ds_r);
    next.dissipated += w.max(0.0);
    next.force = [f[0], f[1], m];
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> FrictionParams {
        FrictionParams {
            mu_static: 0.5,
            mu_kinetic: 0.3,
            decay: 0.0,
            radius: 0.1,
            k_stick: 1e4,
            k_stick_r1: 1e2,
            ..FrictionParams::default()
        }
    }

    #[test]
    fn normal_loads_follow_the_seed() {
        let p = params();
        let (f, m) = normal_loads(&p, -10.0, 0.3, 0.4);
        assert!((f - (10.0 + 0.5 / 0.1)).abs() < 1e-12);
        assert!((m - (2.0 / 3.0 * 0.1 * 10.0 + 0.5)).abs() < 1e-12);
        let p0 = FrictionParams { radius: 0.0, ..p };
        let (f, m) = normal_loads(&p0, -10.0, 0.3, 0.4);
        assert_eq!(f, 10.0);
        assert!((m - 0.5).abs() < 1e-12);
    }

    #[test]
    fn stick_then_slip_saturates_at_mu_fn() {
        let p = params();
        let st = FrictionState::default();
        let r = update(
            &p,
            &st,
            [-10.0, 0.0, 0.0],
            [1e-4, 0.0, 0.0],
            [0.0; 3],
            Eval::Step,
        );
        assert_eq!(r.out.status, Status::Stick);
        assert!((r.force[0] - 1.0).abs() < 1e-12);
        let r = update(
            &p,
            &r.state,
            [-10.0, 0.0, 0.0],
            [1e-2, 0.0, 0.0],
            [0.0; 3],
            Eval::Step,
        );
        assert_eq!(r.out.status, Status::Slip);
        assert!((r.out.csfc - 0.5 * 10.0).abs() < 1e-12);
        // plastic slip: 1e-2 − 5/1e4
        assert!((r.state.slip_plastic[0] - (1e-2 - 5e-4)).abs() < 1e-15);
        assert!(r.state.dissipated > 0.0);
    }

    #[test]
    fn coupled_limit_is_an_ellipsoid() {
        let p = FrictionParams {
            coupling: 1,
            ..params()
        };
        let r = update(
            &p,
            &FrictionState::default(),
            [-10.0, 0.0, 0.0],
            [1.0, 0.0, 1.0],
            [0.0; 3],
            Eval::Step,
        );
        let rho = 2.0 / 3.0 * 0.1;
        let lhs = (r.force[0].powi(2) + r.force[1].powi(2) + (r.force[2] / rho).powi(2)).sqrt();
        assert!((lhs - 5.0).abs() < 1e-12);
        assert_eq!(r.out.status, Status::Slip);
        assert_eq!(r.out.status_r1, Status::Slip);
    }

    /// Associated flow on the ellipsoid with unequal stick stiffnesses: the returned force is on
    /// the surface and the plastic slip increment is normal to it, (Δs, Δs_r) ∥ (f, m/ρ²).
    #[test]
    fn coupled_return_is_normal_to_the_ellipsoid() {
        let p = FrictionParams {
            coupling: 1,
            k_stick: 1e4,
            k_stick_r1: 7.0, // ≠ k_s ρ² = 44.4
            ..params()
        };
        let rho = 2.0 / 3.0 * 0.1;
        let st = FrictionState::default();
        let r = update(
            &p,
            &st,
            [-10.0, 0.0, 0.0],
            [0.3, -0.2, 2.0],
            [0.0; 3],
            Eval::Step,
        );
        let (f, m) = ([r.force[0], r.force[1]], r.force[2]);
        let on = (f[0] * f[0] + f[1] * f[1] + (m / rho).powi(2)).sqrt();
        assert!((on - 5.0).abs() < 1e-10, "on the ellipsoid: {on}");
        let ds = [
            r.state.slip_plastic[0],
            r.state.slip_plastic[1],
            r.state.slip_plastic_r1,
        ];
        let normal = [f[0], f[1], m / (rho * rho)];
        let cross = [
            ds[1] * normal[2] - ds[2] * normal[1],
            ds[2] * normal[0] - ds[0] * normal[2],
            ds[0] * normal[1] - ds[1] * normal[0],
        ];
        let size = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        assert!(
            size(cross) < 1e-9 * size(ds) * size(normal),
            "flow is normal"
        );
    }

    /// The tangent evaluation of a slipping effect stays on the slip branch: just inside the
    /// limit it still returns the limit force (central differences see the slip tangent).
    #[test]
    fn tangent_mode_keeps_a_slipping_effect_on_its_limit() {
        let p = params();
        let slipped = update(
            &p,
            &FrictionState::default(),
            [-10.0, 0.0, 0.0],
            [1e-2, 0.0, 0.0],
            [0.0; 3],
            Eval::Step,
        );
        assert_eq!(slipped.state.status, Status::Slip);
        let inside = [1e-2 - 1e-6, 0.0, 0.0];
        let read = update(
            &p,
            &slipped.state,
            [-10.0, 0.0, 0.0],
            inside,
            [0.0; 3],
            Eval::Read,
        );
        let tangent = update(
            &p,
            &slipped.state,
            [-10.0, 0.0, 0.0],
            inside,
            [0.0; 3],
            Eval::Tangent([true, false]),
        );
        assert!(read.force[0] < 5.0 - 1e-3, "read: elastic unloading");
        assert!(
            (tangent.force[0] - 5.0).abs() < 1e-12,
            "tangent: on the limit"
        );
    }

    #[test]
    fn refusals_name_the_parameter() {
        let bad = FrictionParams {
            mu_kinetic: 0.6,
            ..params()
        };
        assert_eq!(bad.check(), Err("friction.muKinetic > friction.muStatic"));
        let bad = FrictionParams {
            radius: -1.0,
            ..params()
        };
        assert_eq!(bad.check(), Err("friction.R"));
    }
}
