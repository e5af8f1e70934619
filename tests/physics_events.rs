//! Event location in the kernel (src/physics/events.rs, `advance_into` with tracking), on
//! paths whose event times are known in closed form: a node moving at constant speed into and
//! out of a stop, a torsion stop met at constant spin, a stick spring loaded at constant rate
//! (breakaway at μN/k_s), a slip whose velocity reverses at v/a, an axial load through zero.
//! Tolerance: the kernel locates to `EVENT_TOL` (1e-10) of the step and reports the bracket's
//! far end, so each located τ lies in [τ_exact − ε, τ_exact + EVENT_TOL·h + ε] with ε a few
//! ulps of the path arithmetic (1e-15·h here).
//!
//! Also the invariants the FMU interface relies on: tracking without early return leaves the
//! step bit for bit as it was (FMI 2.0 results do not change); a step stopped at an event
//! commits exactly what a step of that length would; a function starting on its zero is not
//! an event; a later substep's event is located in that substep.

use connector_fmu::physics::connector::{evaluate, Outputs, Params, State};
use connector_fmu::physics::events::{self, Taking, Values, EVENT_TOL, N_EVENTS};
use connector_fmu::physics::friction::{Eval, Status};
use connector_fmu::physics::init::initial_state;
use connector_fmu::physics::kinematics::{ConnectionType, Node};
use connector_fmu::physics::math::{Quat, Vec3};
use connector_fmu::physics::step::{advance, advance_into, Ends, Rates, Tracking};
use connector_fmu::variables::Variant;

fn ct(v: Variant) -> ConnectionType {
    v.spec().connection
}

fn node(r: Vec3, v: Vec3) -> Node {
    Node {
        r,
        q: Quat::identity(),
        v,
        w: Vec3::zeros(),
    }
}

/// One tracked step from (st, a, b) moving along `ra`, `rb`: (outputs, state, nodes, met),
/// from the given event functions at its start (exact or assumed), or the exact ones (None).
#[allow(clippy::too_many_arguments)]
fn step_from(
    ct: ConnectionType,
    p: &Params,
    st: &State,
    (a, ra): (&Node, &Rates),
    (b, rb): (&Node, &Rates),
    h: f64,
    stop: bool,
    start: Option<(&Values, bool)>,
) -> (Outputs, State, Node, Met) {
    let exact;
    let (start, exact_start) = match start {
        Some(s) => s,
        None => {
            let (o0, _) = evaluate(ct, p, st, a, b, Eval::Read).expect("regular");
            exact = events::values(ct, p, st, &o0);
            (&exact, true)
        }
    };
    let mut o = Outputs::default();
    let mut next = State::default();
    let mut nodes = [Node::default(); 2];
    let mut end = Taking::NONE;
    let met = advance_into(
        ct,
        p,
        st,
        (a, ra),
        (b, rb),
        h,
        Some(Tracking {
            start,
            exact: exact_start,
            stop_at_first: stop,
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
    let met = Met {
        tau: met.tau,
        count: met.count,
        stopped: met.stopped,
        end: end.v,
    };
    (o, next, nodes[1], met)
}

/// What a step met (`step::Met`) with the event functions at its end (NaN: not taking part).
struct Met {
    tau: f64,
    count: u32,
    stopped: bool,
    end: Values,
}

/// τ located for an exact event time `exact` of a step of length h.
fn assert_located(met: &Met, exact: f64, h: f64, what: &str) {
    let eps = 1e-15 * h;
    assert!(
        met.tau >= exact - eps && met.tau <= exact + EVENT_TOL * h + eps,
        "{what}: located {} for {exact} (h = {h}): off by {:e} of the step",
        met.tau,
        (met.tau - exact) / h
    );
    assert!(met.count >= 1, "{what}: count {}", met.count);
}

fn cartesian_stop(upper: f64) -> Params {
    let mut p = Params::default();
    p.stop_upper[0] = upper;
    p.stop.k = 1e4;
    p
}

#[test]
fn a_stop_is_met_and_left_where_the_straight_path_crosses_it() {
    let ct = ct(Variant::ProjectionCartesian);
    let p = cartesian_stop(0.01);
    let a = node(Vec3::zeros(), Vec3::zeros());
    let b0 = node(Vec3::zeros(), Vec3::new(1.0, 0.0, 0.0));
    let st = initial_state(ct, &p, &a, &b0).expect("regular");
    let h = 0.004;
    // from x = 0.008 at 1 m/s: contact 2 ms into the step
    let b = node(Vec3::new(0.008, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
    let (ra, rb) = (Rates::HOLD, Rates::from_velocities(&b));
    let (o, next, b1, met) = step_from(ct, &p, &st, (&a, &ra), (&b, &rb), h, true, None);
    assert!(met.stopped);
    assert_eq!(met.count, 1);
    assert_located(&met, 0.002, h, "contact");
    assert_eq!(next.stop_status[0], 1, "engaged at the event");
    assert_eq!(o.cslst[0], 1);
    assert!((b1.r.x - (0.008 + met.tau)).abs() < 1e-15);
    // out again at −1 m/s from 0.011: leaves 1 ms into the step
    let b = node(Vec3::new(0.011, 0.0, 0.0), Vec3::new(-1.0, 0.0, 0.0));
    let rb = Rates::from_velocities(&b);
    let (o, next, _, met) = step_from(ct, &p, &next, (&a, &ra), (&b, &rb), h, true, None);
    assert_located(&met, 0.001, h, "release");
    assert_eq!(
        (next.stop_status[0], o.cslst[0]),
        (0, 0),
        "free at the event"
    );
}

#[test]
fn a_torsion_stop_is_met_where_the_constant_spin_reaches_it() {
    // Bushing: β grows at exactly ω for a spin about the common axis e3; upper stop on ur3
    let ct = ct(Variant::Bushing);
    let mut p = Params::default();
    p.stop_upper[5] = 0.3;
    let a = node(Vec3::zeros(), Vec3::zeros());
    let b0 = node(Vec3::zeros(), Vec3::zeros());
    let st = initial_state(ct, &p, &a, &b0).expect("regular");
    let (w, h) = (2.0, 0.05);
    let b = Node {
        q: Quat::from_scaled_axis(Vec3::new(0.0, 0.0, 0.25)),
        w: Vec3::new(0.0, 0.0, w),
        ..b0
    };
    // the state at β = 0.25 (branch), then the step: the stop is met at (0.3 − 0.25)/ω
    let (_, st) = evaluate(ct, &p, &st, &a, &b, Eval::Step(1e-3)).expect("regular");
    let (ra, rb) = (Rates::HOLD, Rates::from_velocities(&b));
    let (_, next, _, met) = step_from(ct, &p, &st, (&a, &ra), (&b, &rb), h, true, None);
    assert_located(&met, 0.05 / w, h, "torsion stop");
    assert_eq!(next.stop_status[5], 1);
}

/// Planar with sliding friction preloaded by F_int = N; stick stiffness k_s.
fn puck(mu: f64, n: f64, ks: f64) -> Params {
    let mut p = Params::default();
    p.friction.mu_static = mu;
    p.friction.f_int = n;
    p.friction.k_stick = ks;
    p
}

#[test]
fn breakaway_is_where_the_stick_spring_reaches_mu_n() {
    let ct = ct(Variant::Planar);
    let (mu, n, ks, v) = (0.5, 20.0, 1e4, 0.1);
    let p = puck(mu, n, ks);
    let a = node(Vec3::zeros(), Vec3::zeros());
    let b = node(Vec3::zeros(), Vec3::new(0.0, v, 0.0));
    let st = initial_state(ct, &p, &a, &b).expect("regular");
    assert_eq!(st.friction.status, Status::Stick);
    // the stick spring k_s·v·t reaches μN at t0 = μN/(k_s v) = 0.01 s
    let h = 0.016;
    let (ra, rb) = (Rates::HOLD, Rates::from_velocities(&b));
    let (o, next, _, met) = step_from(ct, &p, &st, (&a, &ra), (&b, &rb), h, true, None);
    assert_located(&met, mu * n / (ks * v), h, "breakaway");
    assert_eq!(next.friction.status, Status::Slip, "slipping at the event");
    assert!((o.friction.csfc - mu * n).abs() <= 1e-9 * mu * n);
}

#[test]
fn slip_ends_where_the_slip_velocity_reverses() {
    let ct = ct(Variant::Planar);
    let (mu, n, ks) = (0.3, 10.0, 1e6);
    let p = puck(mu, n, ks);
    let a = node(Vec3::zeros(), Vec3::zeros());
    let b = node(Vec3::zeros(), Vec3::new(0.0, 1.0, 0.0));
    let st = initial_state(ct, &p, &a, &b).expect("regular");
    // slide 1 ms at 1 m/s (far past breakaway at 3 µm): slipping
    let rb = Rates::from_velocities(&b);
    let adv = advance(ct, &p, &st, (&a, &Rates::HOLD), (&b, &rb), 1e-3).expect("regular");
    assert_eq!(adv.state.friction.status, Status::Slip);
    // decelerating at a = 4 m/s²: the slip velocity reverses 0.25 s into the step
    let (v, acc, h) = (1.0, 4.0, 0.4);
    let b = node(adv.b.r, Vec3::new(0.0, v, 0.0));
    let rb = Rates {
        dv: Vec3::new(0.0, -acc, 0.0),
        ..Rates::from_velocities(&b)
    };
    let (_, _, _, met) = step_from(
        ct,
        &p,
        &adv.state,
        (&a, &Rates::HOLD),
        (&b, &rb),
        h,
        true,
        None,
    );
    assert_located(&met, v / acc, h, "slip -> stick");
    assert!(met.stopped);
}

#[test]
fn the_normal_force_vanishes_where_the_axial_reaction_changes_sign() {
    let ct = ct(Variant::Planar);
    let mut p = puck(0.3, 0.0, 1e5);
    p.constraint.k = 1e5;
    let a = node(Vec3::zeros(), Vec3::zeros());
    let b0 = node(Vec3::zeros(), Vec3::zeros());
    let st = initial_state(ct, &p, &a, &b0).expect("regular");
    // b pressed 1 mm into the plane (x0 = 0), pulled out at 0.1 m/s: f1 = k·x through 0 at 10 ms
    let b = node(Vec3::new(-1e-3, 0.0, 0.0), Vec3::new(0.1, 0.0, 0.0));
    let h = 0.016;
    let rb = Rates::from_velocities(&b);
    let (_, _, _, met) = step_from(ct, &p, &st, (&a, &Rates::HOLD), (&b, &rb), h, true, None);
    assert_located(&met, 0.01, h, "normal force through zero");
}

#[test]
fn tracking_without_early_return_leaves_the_step_bit_for_bit() {
    let ct = ct(Variant::ProjectionCartesian);
    let p = cartesian_stop(0.01);
    let a = node(Vec3::zeros(), Vec3::zeros());
    let b = node(Vec3::new(0.008, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
    let st = initial_state(ct, &p, &a, &b).expect("regular");
    let (ra, rb) = (Rates::HOLD, Rates::from_velocities(&b));
    let plain = advance(ct, &p, &st, (&a, &ra), (&b, &rb), 0.004).expect("regular");
    let (o, next, b1, met) = step_from(ct, &p, &st, (&a, &ra), (&b, &rb), 0.004, false, None);
    assert!(!met.stopped && met.count == 1);
    assert_located(&met, 0.002, 0.004, "stepped through");
    assert_eq!((o, next, b1), (plain.outputs, plain.state, plain.b));
}

#[test]
fn a_step_stopped_at_an_event_commits_what_a_step_of_that_length_would() {
    let ct = ct(Variant::Planar);
    let p = puck(0.5, 20.0, 1e4);
    let a = node(Vec3::zeros(), Vec3::zeros());
    let b = node(Vec3::zeros(), Vec3::new(0.0, 0.1, 0.0));
    let st = initial_state(ct, &p, &a, &b).expect("regular");
    let (ra, rb) = (Rates::HOLD, Rates::from_velocities(&b));
    let (o, next, b1, met) = step_from(ct, &p, &st, (&a, &ra), (&b, &rb), 0.016, true, None);
    let plain = advance(ct, &p, &st, (&a, &ra), (&b, &rb), met.tau).expect("regular");
    assert_eq!((o, next, b1), (plain.outputs, plain.state, plain.b));
}

#[test]
fn an_event_in_a_later_substep_is_located_there() {
    let ct = ct(Variant::ProjectionCartesian);
    let mut p = cartesian_stop(0.01);
    p.max_substep = 1e-3; // four substeps of 1 ms
    let a = node(Vec3::zeros(), Vec3::zeros());
    let b = node(Vec3::new(0.0075, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
    let st = initial_state(ct, &p, &a, &b).expect("regular");
    let (ra, rb) = (Rates::HOLD, Rates::from_velocities(&b));
    let (_, next, _, met) = step_from(ct, &p, &st, (&a, &ra), (&b, &rb), 0.004, true, None);
    assert_located(&met, 0.0025, 0.004, "third substep");
    assert_eq!(next.stop_status[0], 1);
}

#[test]
fn a_function_starting_on_its_zero_is_no_event() {
    let mut start = [f64::NAN; N_EVENTS];
    let mut end = [f64::NAN; N_EVENTS];
    start[0] = 0.0;
    end[0] = 1.0;
    assert_eq!(events::crossed(&start, &end), 0);
    start[0] = -1e-300;
    assert_eq!(events::crossed(&start, &end), 1);
}

#[test]
fn locate_closes_the_bracket_on_the_far_side() {
    // smooth, curved functions with known roots; the far end must lie past the root
    // (function, bracket end, root, most evaluations: a simple root takes few, the triple
    // root of the cubic defeats false position and leans on the bisection safeguard, which
    // halves the bracket at least every three probes: 3·log2(1/tol) ≈ 100)
    type Case<'a> = (&'a dyn Fn(f64) -> f64, f64, f64, usize);
    let cases: [Case; 4] = [
        (&|t: f64| t - 0.3, 1.0, 0.3, 3),
        (
            &|t: f64| (t * 3.0).sin() - 0.5,
            0.5,
            (0.5f64).asin() / 3.0,
            12,
        ),
        (&|t: f64| (t * t).exp() - 2.0, 1.0, (2f64).ln().sqrt(), 12),
        (&|t: f64| (t - 0.7).powi(3), 1.0, 0.7, 100),
    ];
    for (f, end, root, most) in cases {
        let mut calls = 0;
        let tol = 1e-10;
        let t = events::locate::<()>(0, (0.0, f(0.0)), (end, f(end)), tol, |t| {
            calls += 1;
            Ok(f(t))
        })
        .expect("no error");
        assert!(t >= root - 1e-16 && t <= root + tol, "{t} for {root}");
        assert!(f(t) > 0.0, "far side");
        assert!(calls <= most, "{calls} evaluations for the root {root}");
    }
}

/// The sides of `v` as assumed values (±1), as a step starting from the last one's end uses.
fn sides_of(v: &Values) -> Values {
    let mut s = *v;
    for (i, x) in s.iter_mut().enumerate() {
        if !x.is_nan() {
            *x = if events::side(i, *x) { 1.0 } else { -1.0 };
        }
    }
    s
}

#[test]
fn assumed_sides_give_the_result_of_the_exact_start() {
    let ct = ct(Variant::ProjectionCartesian);
    let p = cartesian_stop(0.01);
    let a = node(Vec3::zeros(), Vec3::zeros());
    let b = node(Vec3::new(0.008, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
    let st = initial_state(ct, &p, &a, &b).expect("regular");
    let (ra, rb) = (Rates::HOLD, Rates::from_velocities(&b));
    let (o0, _) = evaluate(ct, &p, &st, &a, &b, Eval::Read).expect("regular");
    let exact = events::values(ct, &p, &st, &o0);
    for stop in [false, true] {
        let want = step_from(
            ct,
            &p,
            &st,
            (&a, &ra),
            (&b, &rb),
            0.004,
            stop,
            Some((&exact, true)),
        );
        let got = step_from(
            ct,
            &p,
            &st,
            (&a, &ra),
            (&b, &rb),
            0.004,
            stop,
            Some((&sides_of(&exact), false)),
        );
        // (Met.end holds NaN for the functions not taking part: compared as bits)
        assert_eq!((got.0, got.1, got.2), (want.0, want.1, want.2));
        let bits = |m: &Met| (m.tau, m.count, m.stopped, m.end.map(f64::to_bits));
        assert_eq!(bits(&got.3), bits(&want.3));
        assert_eq!(got.3.count, 1);
    }
}

#[test]
fn an_assumed_crossing_is_checked_against_the_exact_start() {
    // the last step ended before the stop, the importer's inputs put b past it: the sides of
    // the last end say "free", the exact start says "engaged", the step stays engaged: no event
    let ct = ct(Variant::ProjectionCartesian);
    let p = cartesian_stop(0.01);
    let a = node(Vec3::zeros(), Vec3::zeros());
    let b = node(Vec3::new(0.0102, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0));
    let st = initial_state(ct, &p, &a, &b).expect("regular");
    let (ra, rb) = (Rates::HOLD, Rates::from_velocities(&b));
    let mut assumed = [f64::NAN; N_EVENTS];
    assumed[events::STOP_UPPER] = -1.0;
    let (_, next, _, met) = step_from(
        ct,
        &p,
        &st,
        (&a, &ra),
        (&b, &rb),
        0.004,
        true,
        Some((&assumed, false)),
    );
    assert_eq!((met.count, met.stopped), (0, false));
    assert_eq!(next.stop_status[0], 1);
}

#[test]
fn far_needs_every_function_beyond_eight_steps_of_change() {
    let mut end = [f64::NAN; N_EVENTS];
    let mut before = [f64::NAN; N_EVENTS];
    end[0] = -0.9;
    before[0] = -1.0;
    assert!(events::far(&end, &before), "0.9 away, 0.1 per step");
    end[0] = -0.7;
    assert!(!events::far(&end, &before), "0.7 away, 0.3 per step");
    end[0] = -0.9;
    end[3] = 0.5;
    assert!(
        !events::far(&end, &before),
        "a function without a value before"
    );
}

/// Damped stops at ±0.05 on every slot and friction (μ 0.4, stick stiffness 1e5) with the
/// preloads `f_int`, `m_int`, coupled or not.
fn stops_and_friction(coupling: i32, f_int: f64, m_int: f64) -> Params {
    let mut p = puck(0.4, f_int, 1e5);
    p.friction.m_int = m_int;
    p.friction.coupling = coupling;
    p.stop.c = 10.0;
    p.stop.c_rot = 1.0;
    p.stop_upper = [0.05; 6];
    p.stop_lower = [-0.05; 6];
    p
}

/// The initial state and the outputs read there, node b offset and moving from node a at rest
/// (None where the connection type refuses the pose).
fn read_at_an_offset(ct: ConnectionType, p: &Params) -> Option<(State, Outputs)> {
    let a = node(Vec3::zeros(), Vec3::zeros());
    let b = node(Vec3::new(0.01, 0.02, 0.03), Vec3::new(0.1, 0.2, 0.3));
    let st0 = initial_state(ct, p, &a, &b).ok()?;
    let (o, _) = evaluate(ct, p, &st0, &a, &b, Eval::Read).expect("regular");
    Some((st0, o))
}

/// `values_on` marks every function that takes part (`crossed_on` and `far_on` compare only
/// those; a marked one may still be NaN, e.g. a stick → slip function of an artificial state
/// here, which both treat as not taking part): over stops on every slot of every variant free
/// and engaged (damped stops add the stop-force functions), and PLANAR friction in every
/// status, coupled and not, with the preloads zero, positive and negative.
#[test]
fn values_on_marks_exactly_the_functions_taking_part() {
    let mut checked = 0;
    let mut seen = 0u32;
    for spec in connector_fmu::variables::VARIANTS {
        let (v, ct) = (spec.variant, spec.connection);
        for (coupling, f_int, m_int) in
            [(0, 0.0, 0.0), (1, 5.0, 0.0), (0, -3.0, -2.0), (1, 0.0, 4.0)]
        {
            let p = stops_and_friction(coupling, f_int, m_int);
            let Some((st0, o)) = read_at_an_offset(ct, &p) else {
                continue;
            };
            for status in [-1, 0, 1] {
                for fs in [Status::Stick, Status::Slip, Status::NoNormal] {
                    let mut st = st0;
                    st.stop_status = [status; 6];
                    st.friction.status = fs;
                    st.friction.status_r1 = fs;
                    let t = events::values_on(ct, &p, &st, &o);
                    let written = (0..N_EVENTS)
                        .filter(|&i| !t.v[i].is_nan())
                        .fold(0u32, |m, i| m | 1 << i);
                    assert_eq!(
                        written & !t.on,
                        0,
                        "{v:?} {status} {fs:?} coupling {coupling}"
                    );
                    assert_eq!(
                        t.v.map(f64::to_bits),
                        events::values(ct, &p, &st, &o).map(f64::to_bits)
                    );
                    seen |= written;
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 100, "{checked} cases");
    // every function took part somewhere
    assert_eq!(seen, (1 << N_EVENTS) - 1, "functions seen {seen:025b}");
}

/// `values_after` turns the values of a substep's start state into those of its end state
/// (the next substep's start) bit for bit, `on` included: over stop and friction statuses that
/// stay or change, plastic slips that move (sliding, spin) or not, and friction forces that
/// move, coupled and not.
#[test]
fn values_after_gives_the_values_of_the_state_the_next_substep_starts_from() {
    let mut checked = 0;
    let mut shortcuts = 0;
    for spec in connector_fmu::variables::VARIANTS {
        let (v, ct) = (spec.variant, spec.connection);
        for (coupling, f_int, m_int) in [(0, 5.0, 1.0), (1, 5.0, 0.0), (0, -3.0, -2.0)] {
            let p = stops_and_friction(coupling, f_int, m_int);
            let Some((st0, o)) = read_at_an_offset(ct, &p) else {
                continue;
            };
            let statuses = [Status::Stick, Status::Slip, Status::NoNormal];
            for (s0, s1) in statuses
                .iter()
                .flat_map(|x| statuses.iter().map(move |y| (*x, *y)))
            {
                for stops in [(0, 0), (1, 1), (0, -1)] {
                    for moved in 0..4 {
                        let mut sa = st0;
                        sa.stop_status = [stops.0; 6];
                        (sa.friction.status, sa.friction.status_r1) = (s0, s1);
                        sa.friction.force = [1.0, -2.0, 0.5];
                        let mut sb = sa;
                        sb.stop_status = [stops.1; 6];
                        match moved {
                            1 => sb.friction.slip_plastic[1] += 1e-3,
                            2 => sb.friction.slip_plastic_r1 += 1e-3,
                            3 => sb.friction.status_r1 = s0,
                            _ => {}
                        }
                        sb.friction.force = [3.0, 1.0, -0.25];
                        let mut t = events::values_on(ct, &p, &sa, &o);
                        let before = t.v;
                        events::values_after(ct, &p, (&sa, &sb), &o, &mut t);
                        let want = events::values_on(ct, &p, &sb, &o);
                        let what = format!("{v:?} {s0:?}/{s1:?} stops {stops:?} moved {moved}");
                        assert_eq!(t.v.map(f64::to_bits), want.v.map(f64::to_bits), "{what}");
                        assert_eq!(t.on, want.on, "{what}");
                        shortcuts += usize::from(stops.0 == stops.1 && t.v != before);
                        checked += 1;
                    }
                }
            }
        }
    }
    assert!(checked > 500, "{checked} cases");
    assert!(
        shortcuts > 0,
        "no slip → stick function was evaluated again"
    );
}
