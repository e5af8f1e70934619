//! The state at the end of initialization.
//!
//! Uses the connector, the friction law, the kinematics and the math; the instance uses it.

use super::connector::{evaluate_pose, Outputs, Params, State};
use super::friction::Eval;
use super::kinematics::{
    geometry_into, Branches, Computed, ConnectionType, Geometry, Node, Pose, Singular,
};
use super::math::Scalar;

/// The initial state for nodes (a, b): component positions become the initial values
/// (CU = 0, SLIDE-PLANE x0), angle branches start on their principal values, friction starts
/// with zero elastic slip (and the stick dampers' force at the initial rates, on the friction
/// limit where they exceed it), and stop status and dissipation powers follow the configuration.
pub fn initial_state(
    ct: ConnectionType,
    p: &Params,
    a: &Node,
    b: &Node,
) -> Result<State, Singular> {
    initial_state_at(ct, p, &Pose::of(a, b))
}

/// `initial_state` at a pose, in any scalar (with `Dual`, the initial state's derivative along
/// the seeded inputs: the tangent of the outputs in initialization mode, where the initial
/// positions move with the inputs).
pub fn initial_state_at<T: Scalar>(
    ct: ConnectionType,
    p: &Params,
    pose: &Pose<T>,
) -> Result<State<T>, Singular> {
    let mut g = Geometry::blank();
    geometry_into(ct, pose, &Branches::default(), Computed, &mut g)?;
    let mut st = State {
        branches: g.branches,
        c0: g.pos,
        ..State::default()
    };
    st.friction.slip_plastic = [g.pos[1], g.pos[2]];
    st.friction.slip_plastic_r1 = g.pos[3];
    let (mut o, mut next) = (Outputs::default(), State::default());
    evaluate_pose(ct, p, &st, pose, Computed, Eval::Start, (&mut o, &mut next))?;
    st.stop_status = next.stop_status;
    st.friction.status = next.friction.status;
    st.friction.status_r1 = next.friction.status_r1;
    // with stick dampers the initial relative rates already load the stick; what exceeds the
    // limit is a plastic rate, so that reading the outputs here takes no slip (Eval::Start)
    st.friction.force = next.friction.force;
    st.friction.slip_rate = next.friction.slip_rate;
    st.friction.mu_rate = next.friction.mu_rate;
    st.power = next.power;
    Ok(st)
}
