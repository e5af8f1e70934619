//! The kinematics' small parts against independent computations (mutants of
//! src/physics/kinematics the other tests let pass): a shaft axis e3 = R(q)·z is nalgebra's
//! rotation of the z axis, and the total flexion α = ∠(e3a, e3b) is the angle between two such
//! axes, for random orientations.

use connector_fmu::physics::kinematics::{flexion, shaft};
use connector_fmu::physics::math::{Quat, Vec3};

#[path = "common/lcg.rs"]
mod lcg;
use lcg::Lcg;

impl Lcg {
    fn quat(&mut self) -> Quat {
        Quat::from_scaled_axis(Vec3::new(self.next(), self.next(), self.next()) * 3.0)
    }
}

/// e3 = q·z by nalgebra's own rotation (`transform_vector`), to 1.6e-15 (a few ulps of unit
/// components).
#[test]
fn a_shaft_is_the_rotated_third_axis() {
    let mut rng = Lcg(5);
    for _ in 0..1000 {
        let q = rng.quat();
        let want = q.transform_vector(&Vec3::z());
        let got = shaft(&q);
        assert!((got - want).norm() < 1.6e-15, "{q:?}: {got:?} vs {want:?}");
    }
}

/// α = atan2(|a × b|, a·b) of the two rotated axes (nalgebra's), to 1e-14 rad, over the
/// whole range [0, π).
#[test]
fn the_flexion_is_the_angle_between_the_shafts() {
    let mut rng = Lcg(6);
    let (mut small, mut large) = (0, 0);
    for _ in 0..1000 {
        let (qa, qb) = (rng.quat(), rng.quat());
        let (a, b) = (
            qa.transform_vector(&Vec3::z()),
            qb.transform_vector(&Vec3::z()),
        );
        let want = a.cross(&b).norm().atan2(a.dot(&b));
        let got = flexion(&qa, &qb);
        assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        small += (want < 1.0) as usize;
        large += (want > 2.0) as usize;
    }
    assert!(
        small > 100 && large > 100,
        "{small} small, {large} large flexions"
    );
}
