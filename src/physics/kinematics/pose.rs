//! The two nodes as the kinematics reads them: a node's pose and twist (`Node`), both nodes'
//! frames, relative position and twists (`Pose`), also from the raw inputs with derivatives
//! (`NodeDual`), and the frame of a raw orientation input. Uses `math` only.

use crate::physics::math::{rotation_of, Mat3, Quat, Real, Scalar, Vec3};

/// Pose and twist of one node, all in W.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// Position x (m).
    pub r: Vec3,
    /// Orientation: maps node-local coordinates to W.
    pub q: Quat,
    /// Velocity (m/s).
    pub v: Vec3,
    /// Angular velocity (rad/s).
    pub w: Vec3,
}

impl Default for Node {
    fn default() -> Self {
        Node {
            r: Vec3::zeros(),
            q: Quat::identity(),
            v: Vec3::zeros(),
            w: Vec3::zeros(),
        }
    }
}

/// The two nodes as the kinematics reads them: frames, relative position and twists (W).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose<T: Scalar = Real> {
    /// Node a's frame (columns e1a, e2a, e3a).
    pub ra: Mat3<T>,
    /// Node b's frame.
    pub rb: Mat3<T>,
    /// d = x_b − x_a.
    pub d: Vec3<T>,
    /// v_b − v_a.
    pub dv: Vec3<T>,
    /// ω_a.
    pub wa: Vec3<T>,
    /// ω_b.
    pub wb: Vec3<T>,
}

impl Pose {
    /// The pose of nodes a and b.
    #[inline(always)]
    pub fn of(a: &Node, b: &Node) -> Pose {
        Pose {
            ra: *a.q.to_rotation_matrix().matrix(),
            rb: *b.q.to_rotation_matrix().matrix(),
            d: b.r - a.r,
            dv: b.v - a.v,
            wa: a.w,
            wb: b.w,
        }
    }
}

/// A node's raw inputs (x, q as w, i, j, k, v, ω) with their derivatives along a direction.
pub type NodeDual = [crate::physics::math::Dual; 13];

impl Pose<crate::physics::math::Dual> {
    /// The pose of two nodes given as raw inputs with derivatives: the quaternions normalised
    /// as `math::quat_from_wxyz` does (its value; the derivative is that of q/|q|, which the
    /// inputs' round-off rule does not change), so the value is `Pose::of` of the same nodes
    /// bit for bit. `frames`: the frames of these orientation inputs in Real
    /// (`frame_of_raw` of each), which a node whose orientation the direction leaves alone
    /// takes as a constant.
    pub fn of_inputs(a: &NodeDual, b: &NodeDual, frames: &[Mat3; 2]) -> Self {
        use crate::physics::math::{quat_from_wxyz, Dual};
        let frame = |u: &NodeDual, known: &Mat3| {
            let q = [u[3], u[4], u[5], u[6]];
            if q.iter().all(|x| x.eps == 0.0) {
                // an orientation the direction leaves alone (every seed but its own): a
                // constant frame
                return known.map(|x| Dual::new(x, 0.0));
            }
            // the value as the Real path reads it; a refused quaternion never gets here (the
            // inputs were checked when set), and would give NaN, which the caller refuses
            let unit = quat_from_wxyz(q[0].re, q[1].re, q[2].re, q[3].re)
                .map_or([Real::NAN; 4], |x| [x.w, x.i, x.j, x.k]);
            let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
            let q: [Dual; 4] = std::array::from_fn(|i| Dual::new(unit[i], (q[i] / n).eps));
            rotation_of(q[0], q[1], q[2], q[3])
        };
        let v = |u: &NodeDual, i: usize| Vec3::new(u[i], u[i + 1], u[i + 2]);
        Pose {
            ra: frame(a, &frames[0]),
            rb: frame(b, &frames[1]),
            d: v(b, 0) - v(a, 0),
            dv: v(b, 7) - v(a, 7),
            wa: v(a, 10),
            wb: v(b, 10),
        }
    }
}

/// The frame of a node's raw orientation input (w, x, y, z), normalised as
/// `math::quat_from_wxyz` reads it (the same bits as `Pose::of`'s frame of that node); NaN
/// where it is no rotation (the setters refuse such an input).
pub fn frame_of_raw(q: &[Real; 4]) -> Mat3 {
    let unit = crate::physics::math::quat_from_wxyz(q[0], q[1], q[2], q[3])
        .map_or([Real::NAN; 4], |x| [x.w, x.i, x.j, x.k]);
    rotation_of(unit[0], unit[1], unit[2], unit[3])
}
