//! The load ports: where port k is and how it moves (its kinematics from the body's state and
//! its offset), and the load on the body summed from its own `f`, `m` and every port's. Pure
//! functions on plain data, no allocation (docs/body.md, "Load ports"). Uses `super::quat` and
//! `super::types`.

use super::quat::{cross, mat_vec, matrix, mul, norm, normalized, Quat, Vec3};
use super::types::{Body, Load, Port, MIN_QUAT_NORM, PORTS};

/// Port k's frame as the FMU outputs it: position and velocity of its point, orientation
/// (port → W) and angular velocity, in W.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PortState {
    /// r_k = r + R(q) p_k (m)
    pub r: Vec3,
    /// q_k = q ⊗ q̂_k (port → W)
    pub q: Quat,
    /// v_k = v + ω × R(q) p_k (m/s)
    pub v: Vec3,
    /// ω_k = ω (rad/s)
    pub w: Vec3,
}

/// Checks every port's offset orientation; the message names the port.
pub fn check(ports: &[Port; PORTS]) -> Result<(), String> {
    for (k, port) in ports.iter().enumerate() {
        let n = norm(&port.offset_q);
        if !n.is_finite() || n < MIN_QUAT_NORM {
            return Err(format!(
                "port[{}].offset.q has norm {n:e}: an orientation needs a finite norm of at least {MIN_QUAT_NORM:e}",
                k + 1
            ));
        }
    }
    Ok(())
}

/// The port's lever arm in W, d_k = R(q) p_k (from the centre of mass to the port point).
#[inline]
pub fn arm(b: &Body, port: &Port) -> Vec3 {
    mat_vec(&matrix(&b.q), &port.offset_r)
}

/// Port `port`'s frame on the body `b` (after `check`).
pub fn kinematics(b: &Body, port: &Port) -> PortState {
    let d = arm(b, port);
    let wxd = cross(&b.w, &d);
    PortState {
        r: std::array::from_fn(|i| b.r[i] + d[i]),
        q: mul(&b.q, &normalized(&port.offset_q)),
        v: std::array::from_fn(|i| b.v[i] + wxd[i]),
        w: b.w,
    }
}

/// The load on the body over the next step, about its centre of mass:
/// Q_f = f + Σ_k f_k, Q_m = m + Σ_k (m_k + d_k × f_k), k = 1 … 4 in order, with d_k = R(q) p_k
/// at the step's start. A port whose six inputs are all zero is skipped, so a body without
/// port loads steps on exactly its own `f`, `m` (bit for bit, and at no cost).
pub fn total(b: &Body, ports: &[Port; PORTS], own: &Load, loads: &[Load; PORTS]) -> Load {
    let mut sum = *own;
    for (port, load) in ports.iter().zip(loads) {
        if load.f.iter().chain(&load.m).all(|&x| x == 0.0) {
            continue;
        }
        let lever = cross(&arm(b, port), &load.f);
        sum.f = std::array::from_fn(|i| sum.f[i] + load.f[i]);
        sum.m = std::array::from_fn(|i| sum.m[i] + (load.m[i] + lever[i]));
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::quat::about_axis;

    fn body() -> Body {
        Body {
            r: [1.0, 2.0, 3.0],
            q: about_axis(2, std::f64::consts::FRAC_PI_2),
            v: [0.5, 0.0, 0.0],
            w: [0.0, 0.0, 2.0],
            angle: [0.0; 3],
        }
    }

    #[test]
    fn a_port_on_a_turned_body_sits_and_moves_where_its_offset_is_carried() {
        let port = Port {
            offset_r: [1.0, 0.0, 0.0],
            offset_q: [2.0, 0.0, 0.0, 0.0],
        };
        let s = kinematics(&body(), &port);
        // a quarter turn about z carries body x to world y; ω × d = 2 e_z × e_y = −2 e_x
        assert!((s.r[0] - 1.0).abs() < 1e-15 && (s.r[1] - 3.0).abs() < 1e-15);
        assert!((s.v[0] + 1.5).abs() < 1e-15 && s.v[1].abs() < 1e-15);
        assert_eq!((s.q, s.w), (body().q, body().w));
    }

    #[test]
    fn loads_sum_with_the_moment_of_the_force_about_the_centre_of_mass() {
        let mut ports = [Port::default(); PORTS];
        ports[1].offset_r = [1.0, 0.0, 0.0];
        let own = Load {
            f: [1.0, 0.0, 0.0],
            m: [0.0, 0.0, 0.25],
        };
        let mut loads = [Load::default(); PORTS];
        loads[1] = Load {
            f: [3.0, 0.0, 0.0],
            m: [0.0, 0.0, 1.0],
        };
        let t = total(&body(), &ports, &own, &loads);
        // d = e_y, d × 3 e_x = −3 e_z
        assert_eq!(t.f, [4.0, 0.0, 0.0]);
        assert!((t.m[2] - (0.25 + 1.0 - 3.0)).abs() < 1e-15);
        // zero port loads leave the own load as it is, bit for bit (−0.0 stays −0.0)
        let own = Load {
            f: [-0.0, 1e-300, 7.0],
            m: [0.1, -0.0, 0.0],
        };
        let t = total(&body(), &ports, &own, &[Load::default(); PORTS]);
        assert_eq!(
            t.f.map(f64::to_bits).to_vec(),
            own.f.map(f64::to_bits).to_vec()
        );
        assert_eq!(t.m.map(f64::to_bits), own.m.map(f64::to_bits));
    }

    #[test]
    fn a_degenerate_offset_orientation_is_named() {
        let mut ports = [Port::default(); PORTS];
        assert_eq!(check(&ports), Ok(()));
        ports[2].offset_q = [0.0; 4];
        assert!(check(&ports).unwrap_err().starts_with("port[3].offset.q"));
    }
}
