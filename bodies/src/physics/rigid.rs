//! Model 1 ("rigid"): a free rigid body in 3-D, master.py's `RigidBody.advance` with the load
//! held (Q0 = Q1 = Q), written operation for operation: the body-frame angular velocity
//! ω_b = R(q)ᵀ ω at the step's start, nsub = max(1, ⌈|ω_b| h / rigid.maxTurn⌉) substeps of
//! classical RK4 on ṙ = v, q̇ = ½ q ⊗ (0, ω_b), v̇ = Q_f/m, J ω̇_b = R(q)ᵀ m − ω_b × (J ω_b), q
//! normalised after each substep, then ω = R(q) ω_b. Uses `super::quat` and `super::types`.

use super::quat::{cross, mat_t_vec, mat_vec, matrix, mul, norm, Quat, Vec3};
use super::types::{Body, Load, Params};

/// More substeps than this in one step are refused (a step or spin far too large).
pub const MAX_SUBSTEPS: f64 = 1e6;

/// The integrated state: position, orientation, velocity, body-frame angular velocity.
#[derive(Clone, Copy)]
struct State {
    r: Vec3,
    q: Quat,
    v: Vec3,
    wb: Vec3,
}

/// s + c k, element by element (numpy's `s + c * k`).
#[inline]
fn axpy<const N: usize>(s: &[f64; N], c: f64, k: &[f64; N]) -> [f64; N] {
    std::array::from_fn(|i| s[i] + c * k[i])
}

impl State {
    /// The state advanced along the rate `k` by c (one RK4 stage's argument).
    #[inline]
    fn along(&self, c: f64, k: &State) -> State {
        State {
            r: axpy(&self.r, c, &k.r),
            q: axpy(&self.q, c, &k.q),
            v: axpy(&self.v, c, &k.v),
            wb: axpy(&self.wb, c, &k.wb),
        }
    }
}

/// The rates of the state under the held load: master.py's inner `f` (its ramp
/// Q0 + (Q1 − Q0)·τ/h is Q itself when Q1 = Q0).
#[inline]
fn rates(s: &State, force: &Vec3, moment: &Vec3, mass: f64, j: &Vec3) -> State {
    let rot = matrix(&s.q);
    let jw: Vec3 = std::array::from_fn(|i| j[i] * s.wb[i]);
    let gyro = cross(&s.wb, &jw);
    let m_b = mat_t_vec(&rot, moment);
    let dq = mul(&s.q, &[0.0, s.wb[0], s.wb[1], s.wb[2]]);
    State {
        r: s.v,
        q: dq.map(|x| 0.5 * x),
        v: force.map(|f| f / mass),
        wb: std::array::from_fn(|i| (m_b[i] - gyro[i]) / j[i]),
    }
}

/// One step of h from `b` under `load` held; Err names the cause when the step needs more
/// than `MAX_SUBSTEPS` substeps.
pub fn step(p: &Params, b: &Body, load: &Load, h: f64) -> Result<Body, String> {
    let force: Vec3 = std::array::from_fn(|i| load.f[i] + p.mass * p.gravity[i]);
    let wb0 = mat_t_vec(&matrix(&b.q), &b.w);
    let turns = (norm(&wb0) * h / p.max_turn).ceil();
    if turns.is_nan() || turns > MAX_SUBSTEPS {
        return Err(format!(
            "the step would need {turns:e} RK4 substeps (|w| h / rigid.maxTurn = {:e}; at most {MAX_SUBSTEPS:e}): take a smaller step or a larger rigid.maxTurn",
            norm(&wb0) * h / p.max_turn
        ));
    }
    let nsub = turns.max(1.0) as u32;
    let hs = h / f64::from(nsub);
    let mut s = State {
        r: b.r,
        q: b.q,
        v: b.v,
        wb: wb0,
    };
    let f = |s: &State| rates(s, &force, &load.m, p.mass, &p.inertia);
    for _ in 0..nsub {
        let k1 = f(&s);
        let k2 = f(&s.along(hs / 2.0, &k1));
        let k3 = f(&s.along(hs / 2.0, &k2));
        let k4 = f(&s.along(hs, &k3));
        // s + (h/6)(k1 + 2 k2 + 2 k3 + k4), summed left to right as numpy does
        let sum = |a: &[f64], b: &[f64], c: &[f64], d: &[f64], i: usize| {
            a[i] + 2.0 * b[i] + 2.0 * c[i] + d[i]
        };
        let c6 = hs / 6.0;
        s = State {
            r: std::array::from_fn(|i| s.r[i] + c6 * sum(&k1.r, &k2.r, &k3.r, &k4.r, i)),
            q: std::array::from_fn(|i| s.q[i] + c6 * sum(&k1.q, &k2.q, &k3.q, &k4.q, i)),
            v: std::array::from_fn(|i| s.v[i] + c6 * sum(&k1.v, &k2.v, &k3.v, &k4.v, i)),
            wb: std::array::from_fn(|i| s.wb[i] + c6 * sum(&k1.wb, &k2.wb, &k3.wb, &k4.wb, i)),
        };
        let n = norm(&s.q);
        s.q = s.q.map(|x| x / n);
    }
    Ok(Body {
        r: s.r,
        q: s.q,
        v: s.v,
        w: mat_vec(&matrix(&s.q), &s.wb),
        angle: b.angle,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::quat::about_axis;

    fn params() -> Params {
        Params {
            inertia: [1.0, 2.0, 3.0],
            max_turn: 0.05,
            ..Params::default()
        }
    }

    #[test]
    fn a_spin_about_a_principal_axis_keeps_its_rate() {
        let b = Body {
            q: about_axis(2, 0.3),
            w: [0.0, 0.0, 5.0],
            ..Body::default()
        };
        let load = Load::default();
        let b1 = step(&params(), &b, &load, 0.1).unwrap();
        assert_eq!(b1.w, [0.0, 0.0, 5.0]);
        let angle = 2.0 * b1.q[3].atan2(b1.q[0]);
        // RK4 on q̇ = ½ q ⊗ (0, ω_b): 10 substeps turning 0.05 rad each; per substep the
        // quaternion's half-angle φ = 0.025 falls short by φ⁵/5! (RK4 is exp(iφ) cut after
        // φ⁴; normalising keeps the phase), so the angle by 10 · 2 · 0.025⁵/120 = 1.63e-9
        let lag = 10.0 * 2.0 * 0.025_f64.powi(5) / 120.0;
        assert!((0.8 - angle - lag).abs() < 1e-11, "{angle}");
        assert!((norm(&b1.q) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn a_spin_too_fast_for_the_substep_limit_is_refused() {
        let b = Body {
            q: [1.0, 0.0, 0.0, 0.0],
            w: [1e9, 0.0, 0.0],
            ..Body::default()
        };
        let e = step(&params(), &b, &Load::default(), 1.0).unwrap_err();
        assert!(e.contains("rigid.maxTurn"), "{e}");
    }
}
