//! The state at the end of initialization.

use super::connector::{evaluate, Params, State};
use super::friction::Eval;
use super::kinematics::{geometry, Branches, ConnectionType, Node, Singular};

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
    let g = geometry(ct, a, b, &Branches::default())?;
    let mut st = State {
        branches: g.branches,
        c0: g.pos,
        ..State::default()
    };
    st.friction.slip_plastic = [g.pos[1], g.pos[2]];
    st.friction.slip_plastic_r1 = g.pos[3];
    let (_, next) = evaluate(ct, p, &st, a, b, Eval::Start)?;
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
