//! The event functions of friction through the kernel's public API, against their documented
//! values and contract (mutants of src/physics/events.rs the other tests let pass):
//! - without a stick damper a slipping effect's slip → stick function is the slip rate along
//!   its friction force, v·f (sliding ẏ f2 + ż f3, spin α̇ m1); with one, the trial force minus
//!   its limit;
//! - `values_after` turns the values at one state into those at another, for the same outputs:
//!   equal, bit for bit, to `values_on` at the other state, for random pairs of states that
//!   differ in statuses, plastic slips, forces and stop statuses.

use connector_fmu::physics::connector::{Outputs, Params, State};
use connector_fmu::physics::events::{values_after, values_on, SLIP_STICK};
use connector_fmu::physics::friction::{
    slip_stick_function, FrictionParams, FrictionState, Status,
};
use connector_fmu::variables::Variant;

#[path = "common/lcg.rs"]
mod lcg;
use lcg::Lcg;

impl Lcg {
    fn status(&mut self) -> Status {
        [Status::NoNormal, Status::Stick, Status::Slip][((self.next() + 1.0) * 1.5) as usize % 3]
    }
}

fn params(coupling: i32, damped: bool) -> Params {
    let mut stop_upper = [f64::INFINITY; 6];
    stop_upper[1] = 0.3;
    let mut p = Params {
        friction: FrictionParams {
            mu_static: 0.5,
            mu_kinetic: 0.3,
            decay: 1.0,
            radius: 0.05,
            f_int: 20.0,
            m_int: 1.0,
            k_stick: 1e4,
            k_stick_r1: 1e2,
            c_stick: if damped { 5.0 } else { 0.0 },
            c_stick_r1: if damped { 0.5 } else { 0.0 },
            coupling,
            ..FrictionParams::default()
        },
        stop_upper,
        ..Params::default()
    };
    p.stop.c = 10.0;
    p
}

fn outputs(rng: &mut Lcg) -> Outputs {
    let mut o = Outputs::default();
    for k in 0..6 {
        o.cp[k] = 0.2 * rng.next();
        o.cv[k] = rng.next();
        o.crf[k] = 30.0 * rng.next();
    }
    o.friction.cnf = 25.0 + 5.0 * rng.next();
    o.friction.cnm1 = 1.5 + rng.next();
    o
}

fn state(rng: &mut Lcg) -> State {
    let mut st = State {
        friction: FrictionState {
            status: rng.status(),
            status_r1: rng.status(),
            slip_plastic: [0.01 * rng.next(), 0.01 * rng.next()],
            slip_plastic_r1: 0.05 * rng.next(),
            force: [10.0 * rng.next(), 10.0 * rng.next(), rng.next()],
            ..FrictionState::default()
        },
        ..State::default()
    };
    st.stop_status[1] = if rng.next() > 0.0 { 1 } else { 0 };
    st
}

/// b: a copy of a with each of its parts changed or kept at random.
fn varied(rng: &mut Lcg, a: &State) -> State {
    let other = state(rng);
    let mut b = *a;
    let mut pick = |x: &mut dyn FnMut()| {
        if rng.next() > 0.0 {
            x()
        }
    };
    pick(&mut || b.friction.status = other.friction.status);
    pick(&mut || b.friction.status_r1 = other.friction.status_r1);
    pick(&mut || b.friction.slip_plastic = other.friction.slip_plastic);
    pick(&mut || b.friction.slip_plastic_r1 = other.friction.slip_plastic_r1);
    pick(&mut || b.friction.force = other.friction.force);
    pick(&mut || b.stop_status = other.stop_status);
    b
}

#[test]
fn values_after_equals_values_on_at_the_other_state() {
    let ct = Variant::Planar.spec().connection;
    let mut rng = Lcg(3);
    let mut taking = 0;
    for (coupling, damped) in [(0, false), (0, true), (1, false), (1, true)] {
        let p = params(coupling, damped);
        for _ in 0..500 {
            let o = outputs(&mut rng);
            let a = state(&mut rng);
            let b = varied(&mut rng, &a);
            let mut v = values_on(ct, &p, &a, &o);
            values_after(ct, &p, (&a, &b), &o, &mut v);
            let want = values_on(ct, &p, &b, &o);
            assert_eq!(v.on, want.on, "{a:?} → {b:?}");
            for i in 0..v.v.len() {
                assert_eq!(
                    v.v[i].to_bits(),
                    want.v[i].to_bits(),
                    "function {i}: {a:?} → {b:?}"
                );
            }
            taking += want.on.count_ones();
        }
    }
    assert!(taking > 4000, "{taking} function values compared");
}

#[test]
fn a_slipping_effects_slip_stick_function_is_its_power_or_its_trial_minus_limit() {
    let ct = Variant::Planar.spec().connection;
    let mut rng = Lcg(4);
    for damped in [false, true] {
        let p = params(0, damped);
        for _ in 0..200 {
            let o = outputs(&mut rng);
            let mut st = state(&mut rng);
            st.friction.status = Status::Slip;
            st.friction.status_r1 = Status::Slip;
            let v = values_on(ct, &p, &st, &o).v;
            let [f2, f3, m1] = st.friction.force;
            let (pos, rate) = ([o.cp[1], o.cp[2], o.cp[3]], [o.cv[1], o.cv[2], o.cv[3]]);
            let want = if damped {
                let normals = (o.friction.cnf, o.friction.cnm1);
                slip_stick_function(&p.friction, &st.friction, pos, rate, normals)
            } else {
                [rate[0] * f2 + rate[1] * f3, rate[2] * m1]
            };
            assert_eq!(v[SLIP_STICK], want[0], "sliding, damped {damped}");
            assert_eq!(v[SLIP_STICK + 1], want[1], "spin, damped {damped}");
        }
    }
}

/// A stop crossed 1e-13 s into a step of 4 ms (within min_tau = 1e-10 of the step of its
/// start): met at the start, so the step neither stops there (every early return moves the
/// time on) nor reports it; one crossed 2 ms in is located and stopped at.
#[test]
fn an_event_within_min_tau_of_the_start_is_met_there() {
    use connector_fmu::physics::connector::evaluate;
    use connector_fmu::physics::events::{values, Taking, EVENT_TOL};
    use connector_fmu::physics::friction::Eval;
    use connector_fmu::physics::init::initial_state;
    use connector_fmu::physics::kinematics::Node;
    use connector_fmu::physics::math::Vec3;
    use connector_fmu::physics::step::{advance_into, Ends, Rates, Tracking};
    let ct = Variant::ProjectionCartesian.spec().connection;
    let mut p = Params::default();
    p.stop_upper[0] = 0.01;
    p.stop.k = 1e4;
    let a = Node::default();
    let at = |x: f64| Node {
        r: Vec3::new(x, 0.0, 0.0),
        v: Vec3::new(1.0, 0.0, 0.0),
        ..Node::default()
    };
    let st = initial_state(ct, &p, &a, &at(0.0)).expect("regular");
    let h = 0.004;
    for (x0, stopped) in [(0.01 - 1e-13, false), (0.008, true)] {
        let b = at(x0);
        let (o0, _) = evaluate(ct, &p, &st, &a, &b, Eval::Read).expect("regular");
        let start = values(ct, &p, &st, &o0);
        let (mut o, mut next, mut nodes, mut end) = (
            Outputs::default(),
            State::default(),
            [Node::default(); 2],
            Taking::NONE,
        );
        let met = advance_into(
            ct,
            &p,
            &st,
            (&a, &Rates::HOLD),
            (&b, &Rates::from_velocities(&b)),
            h,
            Some(Tracking {
                start: &start,
                exact: true,
                stop_at_first: true,
                min_tau: EVENT_TOL * h,
                t0: 0.0,
            }),
            Ends {
                outputs: &mut o,
                state: &mut next,
                nodes: &mut nodes,
                events: &mut end,
            },
        )
        .expect("regular path");
        assert_eq!(met.stopped, stopped, "x0 = {x0}");
        if stopped {
            assert!(
                (met.tau - 0.002).abs() < EVENT_TOL * h + 1e-15,
                "{}",
                met.tau
            );
            assert_eq!(met.count, 1);
        } else {
            assert_eq!((met.tau, met.count), (h, 0), "x0 = {x0}");
        }
    }
}
