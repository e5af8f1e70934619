//! The plain data the body's motion works on: the parameters, the state at a communication
//! point and the load over a step. Uses `super::quat`'s array types only.

use super::quat::{Quat, Vec3};

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
    /// the load ports' offsets
    pub ports: [Port; PORTS],
}

/// Number of load ports.
pub const PORTS: usize = 4;

/// A load port's place on the body (parameters `port[k].offset.*`); the default is the
/// parameters' start: at the centre of mass, the body frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Port {
    /// the port point p_k in the body frame, from the centre of mass (m)
    pub offset_r: Vec3,
    /// the port frame relative to the body frame, port → body (any norm ≥ 1e-6; normalised)
    pub offset_q: Quat,
}

impl Default for Port {
    fn default() -> Self {
        Port {
            offset_r: [0.0; 3],
            offset_q: [1.0, 0.0, 0.0, 0.0],
        }
    }
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

/// A load held over a step, in W: the body's own inputs (force at the centre of mass, moment
/// about it) or a port's (force at the port point, moment), gravity not included.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Load {
    /// force (N)
    pub f: Vec3,
    /// moment (N.m)
    pub m: Vec3,
}

/// A start orientation whose norm is below this (or not finite) is refused.
pub const MIN_QUAT_NORM: f64 = 1e-6;
