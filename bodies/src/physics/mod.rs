//! The body's motion, pure Rust on plain data (no FMI types, no logging, no allocation per
//! step): the parameters, the state at a communication point, the checks of the parameters
//! that need more than one of them, the state at the start time, one communication step
//! (`axes` for model 0, `rigid` for model 1) and the energies. Per step it equals the body
//! update of scripts/cosim/master.py's zero-order-hold method (docs/body.md). Uses its own
//! submodules only.

pub mod axes;
pub mod quat;
pub mod rigid;

use quat::{mat_t_vec, matrix, norm, norm2, Quat, Vec3};

/// Which model the body follows (parameter `model`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Model {
    /// 0: degrees of freedom along and about world axes, each exact.
    #[default]
    Axes,
    /// 1: a free rigid body in 3-D, RK4.
    Rigid,
}

/// What a degree of freedom of model 0 does (parameters `dof.r[i]`, `dof.w[i]`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Dof {
    /// 0: held at its start value, velocity 0.
    #[default]
    Fixed,
    /// 1: moves under the load.
    Free,
    /// 2: moves at its start velocity forever.
    Prescribed,
}

/// The parameters (units as in the variable table; all finite, and in their ranges: mass,
/// inertia and rigid.maxTurn > 0, spring.k ≥ 0).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Params {
    /// mass (kg)
    pub mass: f64,
    /// principal moments of inertia in the body frame (kg.m2); model 0: about the world axes
    pub inertia: Vec3,
    /// gravitational acceleration in W (m/s2)
    pub gravity: Vec3,
    /// model 0 or 1
    pub model: Model,
    /// model 0: the translations along world x, y, z
    pub dof_r: [Dof; 3],
    /// model 0: the rotations about world x, y, z
    pub dof_w: [Dof; 3],
    /// model 0: springs from the world origin along world x, y, z (N/m)
    pub spring: Vec3,
    /// position at the start time, W (m)
    pub start_r: Vec3,
    /// orientation at the start time (any norm ≥ 1e-6; normalised), body → W
    pub start_q: Quat,
    /// velocity at the start time, W (m/s)
    pub start_v: Vec3,
    /// angular velocity at the start time, W (rad/s)
    pub start_w: Vec3,
    /// model 1: largest turn per RK4 substep (rad)
    pub max_turn: f64,
}

/// The body at a communication point: what the FMU outputs, and model 0's angle about each
/// world axis (the turning axis's; 0 for the others).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Body {
    /// position of the centre of mass, W (m)
    pub r: Vec3,
    /// orientation, unit quaternion body → W
    pub q: Quat,
    /// velocity, W (m/s)
    pub v: Vec3,
    /// angular velocity, W (rad/s)
    pub w: Vec3,
    /// model 0: the angle about each world axis (rad)
    pub angle: Vec3,
}

/// The load on the body over a step (held), in W.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Load {
    /// force at the centre of mass (N), gravity not included
    pub f: Vec3,
    /// moment about the centre of mass (N.m)
    pub m: Vec3,
}

/// A start orientation whose norm is below this (or not finite) is refused.
pub const MIN_QUAT_NORM: f64 = 1e-6;

/// Checks what needs more than one parameter; the message names them.
pub fn check(p: &Params) -> Result<(), String> {
    let n = norm(&p.start_q);
    if !n.is_finite() || n < MIN_QUAT_NORM {
        return Err(format!(
            "start.q has norm {n:e}: an orientation needs a finite norm of at least {MIN_QUAT_NORM:e}"
        ));
    }
    match p.model {
        Model::Axes => axes::check(p),
        Model::Rigid => match (0..3).find(|&i| p.spring[i] != 0.0) {
            Some(i) => Err(format!(
                "spring.k[{}] = {:?}, but springs act in model 0 only: set it to 0 for model 1",
                i + 1,
                p.spring[i]
            )),
            None => Ok(()),
        },
    }
}

/// The state at the start time (after `check`).
pub fn initial(p: &Params) -> Result<Body, String> {
    check(p)?;
    Ok(match p.model {
        Model::Axes => axes::initial(p),
        Model::Rigid => Body {
            r: p.start_r,
            q: quat::normalized(&p.start_q),
            v: p.start_v,
            w: p.start_w,
            angle: [0.0; 3],
        },
    })
}

/// One communication step of h (> 0) from `b` under `load` held, ending `elapsed` after the
/// start time. Err (naming the cause) when the step cannot be taken or gives a value that is
/// not finite; `b` is then still the state.
pub fn step(p: &Params, b: &Body, load: &Load, elapsed: f64, h: f64) -> Result<Body, String> {
    let n = match p.model {
        Model::Axes => axes::step(p, b, load, elapsed, h),
        Model::Rigid => rigid::step(p, b, load, h)?,
    };
    let parts: [(&str, &[f64]); 5] = [
        ("r", &n.r),
        ("q", &n.q),
        ("v", &n.v),
        ("w", &n.w),
        ("angle", &n.angle),
    ];
    match parts.iter().find(|(_, x)| x.iter().any(|x| !x.is_finite())) {
        Some((name, _)) => Err(format!(
            "the step gives values of {name} that are not finite (load or step too large?); the state stays at the step's start"
        )),
        None => Ok(n),
    }
}

/// (kinetic, potential) energy of the body: ½ m |v|² + ½ ω_bᵀ J ω_b (model 0: ½ Σ J_i ω_i²
/// about the world axes) and −m g·r + Σ ½ k_i r_i².
pub fn energies(p: &Params, b: &Body) -> (f64, f64) {
    let wb = match p.model {
        Model::Axes => b.w,
        Model::Rigid => mat_t_vec(&matrix(&b.q), &b.w),
    };
    let spin = (0..3).fold(0.0, |s, i| s + p.inertia[i] * wb[i] * wb[i]);
    let kinetic = 0.5 * p.mass * norm2(&b.v) + 0.5 * spin;
    let g_r = (0..3).fold(0.0, |s, i| s + p.gravity[i] * b.r[i]);
    let springs = (0..3).fold(0.0, |s, i| s + p.spring[i] * b.r[i] * b.r[i]);
    (kinetic, -p.mass * g_r + 0.5 * springs)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axes() -> Params {
        Params {
            mass: 2.0,
            inertia: [1.0, 1.0, 1.0],
            dof_r: [Dof::Free; 3],
            start_q: [1.0, 0.0, 0.0, 0.0],
            max_turn: 0.05,
            ..Params::default()
        }
    }

    #[test]
    fn parameters_that_do_not_fit_together_are_named() {
        let mut p = axes();
        p.dof_w = [Dof::Free, Dof::Prescribed, Dof::Fixed];
        assert!(check(&p).unwrap_err().contains("dof.w[1], dof.w[2]"));
        p.dof_w = [Dof::Fixed, Dof::Fixed, Dof::Free];
        p.start_q = [1.0, 0.1, 0.0, 0.0];
        assert!(check(&p).unwrap_err().contains("start.q.x"));
        p.start_q = [0.0; 4];
        assert!(check(&p).unwrap_err().contains("start.q has norm"));
        p = Params {
            model: Model::Rigid,
            spring: [0.0, 3.0, 0.0],
            ..axes()
        };
        assert!(check(&p).unwrap_err().contains("spring.k[2]"));
    }

    #[test]
    fn a_turning_axis_starts_at_the_angle_of_start_q() {
        let p = Params {
            dof_w: [Dof::Fixed, Dof::Prescribed, Dof::Fixed],
            start_q: quat::about_axis(1, 0.7),
            start_w: [0.0, 2.0, 0.0],
            ..axes()
        };
        let b = initial(&p).unwrap();
        assert!((b.angle[1] - 0.7).abs() < 1e-15 && b.w == [0.0, 2.0, 0.0]);
        let b1 = step(&p, &b, &Load::default(), 0.5, 0.5).unwrap();
        assert!((b1.angle[1] - 1.7).abs() < 1e-15);
    }

    #[test]
    fn energies_of_a_falling_spinning_body() {
        let p = Params {
            gravity: [0.0, 0.0, -9.81],
            spring: [4.0, 0.0, 0.0],
            ..axes()
        };
        let b = Body {
            r: [0.5, 0.0, 2.0],
            v: [0.0, 3.0, 0.0],
            w: [0.0, 0.0, 2.0],
            q: [1.0, 0.0, 0.0, 0.0],
            ..Body::default()
        };
        let (k, u) = energies(&p, &b);
        assert_eq!(k, 0.5 * 2.0 * 9.0 + 0.5 * 4.0);
        assert_eq!(u, 2.0 * 9.81 * 2.0 + 0.5 * 4.0 * 0.25);
    }

    #[test]
    fn a_non_finite_result_is_refused() {
        let p = axes();
        let b = initial(&p).unwrap();
        let load = Load {
            f: [f64::MAX, 0.0, 0.0],
            m: [0.0; 3],
        };
        let e = step(&p, &b, &load, 1e300, 1e300).unwrap_err();
        assert!(e.contains("not finite"), "{e}");
    }
}
