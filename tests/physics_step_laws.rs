//! The step's guard against the folded flexion configuration (α → π), through `advance`:
//! a substep whose two ends are regular but whose path turns node b through α = π is refused
//! (mutants of src/physics/step.rs the other tests let pass).

use connector_fmu::physics::connector::Params;
use connector_fmu::physics::init::initial_state;
use connector_fmu::physics::kinematics::{Node, Singular};
use connector_fmu::physics::math::{Quat, Vec3};
use connector_fmu::physics::step::{advance, Rates, StepError};
use connector_fmu::variables::Variant;

/// PROJECTION FLEXION-TORSION, node b turning about e1 within one step of 10 ms:
/// - from α = 0 a full 2π: α = π half-way, though both ends are regular (cos α = 1);
/// - from α = 1.5 by 2.5 rad: through π at 1.64 rad, ending at α = 2π − 4 = 2.28 (cos α < 0);
///
/// both pass the folded configuration and are refused as singular near π; a turn of 0.5 rad
/// from α = 0 (α ≤ π/2 all along) steps.
#[test]
fn a_step_through_the_folded_configuration_is_refused() {
    let ct = Variant::ProjectionFlexionTorsion.spec().connection;
    let p = Params {
        k: [0.0, 0.0, 0.0, 10.0, 10.0, 10.0],
        ..Params::default()
    };
    let a = Node::default();
    let h = 0.01;
    let cases = [
        (0.0, 2.0 * std::f64::consts::PI, true),
        (1.5, 2.5, true),
        (0.0, 0.5, false),
    ];
    for (alpha0, turn, refused) in cases {
        let b = Node {
            q: Quat::from_scaled_axis(Vec3::new(alpha0, 0.0, 0.0)),
            w: Vec3::new(turn / h, 0.0, 0.0),
            ..Node::default()
        };
        let st = initial_state(ct, &p, &a, &b).expect("regular at the start");
        let r = advance(
            ct,
            &p,
            &st,
            (&a, &Rates::from_velocities(&a)),
            (&b, &Rates::from_velocities(&b)),
            h,
        );
        match r {
            Err(StepError::Singular(Singular::FlexionNearPi(_), _)) => {
                assert!(refused, "turn {turn}")
            }
            Err(e) => panic!("turn {turn}: {e:?}"),
            Ok(_) => assert!(!refused, "turn {turn}: a step through α = π was taken"),
        }
    }
}
