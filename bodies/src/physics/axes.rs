//! Model 0 ("axes"): every degree of freedom is a translation along, or a rotation about, a
//! world axis, integrated exactly and independently under the load held over the step. One
//! coordinate's update is master.py's `AxesBody.advance` with Q0 = Q1 = Q, written operation
//! for operation (its two groupings included). Uses `super::quat` and `super::types`.

use super::quat::{about_axis, normalized};
use super::types::{Body, Dof, Load, Params};

/// The exact motion of one coordinate, m x'' + k x = Q with Q held, over h, from (x, u).
///
/// `grouped` picks master.py's grouping of the spring-free formula: its `AxesBody.advance`
/// evaluates all coordinates at once (numpy, `(h·h/6)·(2Q0 + Q1)/m`) when no coordinate of
/// the body has a spring, and one by one (`h·h·(2Q0 + Q1)/(6m)`) otherwise; the two round
/// differently in the last bit.
#[inline]
pub fn advance(x: f64, u: f64, q: f64, m: f64, k: f64, h: f64, grouped: bool) -> (f64, f64) {
    let (q0, q1) = (q, q); // the master's ramp from Q0 to Q1, held
    if k == 0.0 {
        let x1 = if grouped {
            x + h * u + (h * h / 6.0) * (2.0 * q0 + q1) / m
        } else {
            x + h * u + h * h * (2.0 * q0 + q1) / (6.0 * m)
        };
        return (x1, u + (0.5 * h) * (q0 + q1) / m);
    }
    let w = (k / m).sqrt();
    let s = (q1 - q0) / h;
    let a = x - q0 / k;
    let b = (u - s / k) / w;
    let (c, sn) = ((w * h).cos(), (w * h).sin());
    (q1 / k + a * c + b * sn, s / k - a * w * sn + b * w * c)
}

/// The one rotation of model 0 that is not fixed, if any: (axis, its dof).
pub fn rotating_axis(p: &Params) -> Option<(usize, Dof)> {
    (0..3)
        .find(|&i| p.dof_w[i] != Dof::Fixed)
        .map(|i| (i, p.dof_w[i]))
}

/// The angle of `start.q` about world axis `axis`: 2 atan2(q_axis, q_w).
pub fn start_angle(p: &Params, axis: usize) -> f64 {
    2.0 * p.start_q[1 + axis].atan2(p.start_q[0])
}

/// Checks model 0's parameters: at most one rotation not fixed, and a start orientation about
/// that axis. The message names the parameters.
pub fn check(p: &Params) -> Result<(), String> {
    let turning: Vec<String> = (0..3)
        .filter(|&i| p.dof_w[i] != Dof::Fixed)
        .map(|i| format!("dof.w[{}]", i + 1))
        .collect();
    if turning.len() > 1 {
        return Err(format!(
            "model 0 allows at most one rotation that is not fixed, but {} are free or prescribed",
            turning.join(", ")
        ));
    }
    if let Some((i, _)) = rotating_axis(p) {
        let n = super::quat::norm(&p.start_q);
        const XYZ: [&str; 3] = ["x", "y", "z"];
        for j in (0..3).filter(|&j| j != i) {
            // a rotation about world axis i has no other vector part (to round-off)
            if p.start_q[1 + j].abs() > 1e-12 * n {
                return Err(format!(
                    "dof.w[{}] is free or prescribed, so start.q must be a rotation about world {}, but start.q.{} = {:?}",
                    i + 1,
                    XYZ[i],
                    XYZ[j],
                    p.start_q[1 + j]
                ));
            }
        }
    }
    Ok(())
}

/// The state at the start time.
pub fn initial(p: &Params) -> Body {
    let mut b = Body {
        r: p.start_r,
        ..Body::default()
    };
    for i in 0..3 {
        b.v[i] = if p.dof_r[i] == Dof::Fixed {
            0.0
        } else {
            p.start_v[i]
        };
    }
    match rotating_axis(p) {
        Some((i, _)) => {
            b.angle[i] = start_angle(p, i);
            b.q = about_axis(i, b.angle[i]);
            b.w[i] = p.start_w[i];
        }
        None => b.q = normalized(&p.start_q),
    }
    b
}

/// One step of h ending `elapsed` after the start time, under `load` held.
pub fn step(p: &Params, b: &Body, load: &Load, elapsed: f64, h: f64) -> Body {
    let grouped = !(0..3).any(|i| p.dof_r[i] == Dof::Free && p.spring[i] != 0.0);
    let mut n = *b;
    for i in 0..3 {
        (n.r[i], n.v[i]) = match p.dof_r[i] {
            Dof::Fixed => (p.start_r[i], 0.0),
            Dof::Prescribed => (p.start_r[i] + p.start_v[i] * elapsed, p.start_v[i]),
            Dof::Free => {
                let q = load.f[i] + p.mass * p.gravity[i];
                advance(b.r[i], b.v[i], q, p.mass, p.spring[i], h, grouped)
            }
        };
    }
    if let Some((i, dof)) = rotating_axis(p) {
        (n.angle[i], n.w[i]) = match dof {
            Dof::Prescribed => (start_angle(p, i) + p.start_w[i] * elapsed, p.start_w[i]),
            _ => advance(b.angle[i], b.w[i], load.m[i], p.inertia[i], 0.0, h, grouped),
        };
        n.q = about_axis(i, n.angle[i]);
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_held_force_gives_the_parabola() {
        // x = x0 + u0 h + Q h²/(2m), u = u0 + Q h/m (to round-off: h²/6 is not exact)
        for grouped in [true, false] {
            let (x, u) = advance(1.0, 2.0, 4.0, 2.0, 0.0, 0.5, grouped);
            assert!((x - 2.25).abs() < 1e-15 && u == 3.0);
        }
    }

    #[test]
    fn a_spring_oscillates_about_its_loaded_rest() {
        // k = 4, m = 1: ω = 2; rest at Q/k = 0.25; from rest at 1.25 the amplitude is 1
        let h = 0.1;
        let (x, u) = advance(1.25, 0.0, 1.0, 1.0, 4.0, h, false);
        assert!((x - (0.25 + (2.0 * h).cos())).abs() < 1e-15);
        assert!((u + 2.0 * (2.0 * h).sin()).abs() < 1e-15);
    }
}
