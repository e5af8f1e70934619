//! Quaternion and 3×3 helpers on plain arrays, written operation for operation as
//! scripts/cosim/master.py writes them with numpy (`quat_mul`, `quat_matrix`, `np.cross`, the
//! matrix-vector products summed left to right), so that the body update rounds as the master's
//! does. Uses nothing else of the crate.

/// A vector in 3-D.
pub type Vec3 = [f64; 3];
/// A quaternion, scalar first (w, x, y, z).
pub type Quat = [f64; 4];
/// A 3×3 matrix, row by row.
pub type Mat3 = [[f64; 3]; 3];

/// p ⊗ q.
#[inline]
pub fn mul(p: &Quat, q: &Quat) -> Quat {
    let [pw, px, py, pz] = *p;
    let [qw, qx, qy, qz] = *q;
    [
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    ]
}

/// The rotation matrix R(q) of a unit quaternion (body → world).
#[inline]
pub fn matrix(q: &Quat) -> Mat3 {
    let [w, x, y, z] = *q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// R a.
#[inline]
pub fn mat_vec(r: &Mat3, a: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| r[i][0] * a[0] + r[i][1] * a[1] + r[i][2] * a[2])
}

/// Rᵀ a.
#[inline]
pub fn mat_t_vec(r: &Mat3, a: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| r[0][i] * a[0] + r[1][i] * a[1] + r[2][i] * a[2])
}

/// a × b.
#[inline]
pub fn cross(a: &Vec3, b: &Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// a · a.
#[inline]
pub fn norm2<const N: usize>(a: &[f64; N]) -> f64 {
    a.iter().fold(0.0, |s, x| s + x * x)
}

/// |q|.
#[inline]
pub fn norm<const N: usize>(a: &[f64; N]) -> f64 {
    norm2(a).sqrt()
}

/// q / |q| (the caller has checked |q| > 0).
#[inline]
pub fn normalized(q: &Quat) -> Quat {
    let n = norm(q);
    q.map(|x| x / n)
}

/// The rotation by `angle` about world axis `axis` (0, 1, 2): (cos θ/2, sin θ/2 e_axis), as
/// master.py's `AxesBody.inputs` writes the node quaternion.
#[inline]
pub fn about_axis(axis: usize, angle: f64) -> Quat {
    let mut q = [(0.5 * angle).cos(), 0.0, 0.0, 0.0];
    q[1 + axis] = (0.5 * angle).sin();
    q
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrix_of_a_quarter_turn_about_z_maps_x_to_y() {
        let q = about_axis(2, std::f64::consts::FRAC_PI_2);
        let r = matrix(&q);
        let y = mat_vec(&r, &[1.0, 0.0, 0.0]);
        assert!((y[0]).abs() < 1e-15 && (y[1] - 1.0).abs() < 1e-15);
        let back = mat_t_vec(&r, &y);
        assert!((back[0] - 1.0).abs() < 1e-15 && back[1].abs() < 1e-15);
    }

    #[test]
    fn product_and_cross_follow_the_right_hand_rule() {
        let i = [0.0, 1.0, 0.0, 0.0];
        let j = [0.0, 0.0, 1.0, 0.0];
        assert_eq!(mul(&i, &j), [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(cross(&[1.0, 0.0, 0.0], &[0.0, 1.0, 0.0]), [0.0, 0.0, 1.0]);
        assert_eq!(normalized(&[2.0, 0.0, 0.0, 0.0]), [1.0, 0.0, 0.0, 0.0]);
    }
}
