//! The body's motion, pure Rust on plain data (no FMI types, no logging, no allocation per
//! step): the parameters, the state at a communication point, the checks of the parameters
//! that need more than one of them, the state at the start time, one communication step
//! (`axes` for model 0, `rigid` for model 1), the load ports' kinematics and the summed load
//! (`ports`) and the energies. Per step it equals the body
//! update of scripts/cosim/master.py's zero-order-hold method (docs/body.md). Uses its own
//! submodules only (`types` holds the data, `axes` and `rigid` the two models' steps, `ports`
//! the load ports).

pub mod axes;
pub mod ports;
pub mod quat;
pub mod rigid;
pub mod types;

use quat::{mat_t_vec, matrix, norm, norm2};
pub use types::{Body, Dof, Load, Model, Params, Port, MIN_QUAT_NORM, PORTS};

/// Checks what needs more than one parameter; the message names them.
pub fn check(p: &Params) -> Result<(), String> {
    let n = norm(&p.start_q);
    if !n.is_finite() || n < MIN_QUAT_NORM {
        return Err(format!(
            "start.q has norm {n:e}: an orientation needs a finite norm of at least {MIN_QUAT_NORM:e}"
        ));
    }
    ports::check(&p.ports)?;
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
