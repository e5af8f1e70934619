//! Advancing the connector over a communication step [t, t + h] (docs/physics.md, "Stepping"): the nodes move
//! along the input extrapolation, the path-dependent state (friction, stops, angle branches)
//! follows in internal substeps, and the dissipated energies are integrated.

use super::connector::{evaluate_into, Outputs, Params, State};
use super::events::{self, crossed_on, locate, values, values_on_into, Taking, Values, EVENT_TOL};
use super::friction::Eval;
use super::kinematics::{ConnectionType, Node, Shafts, Singular, ALPHA_MAX_GAP};
use super::math::{quat_exp, Real, Vec3};
use std::f64::consts::PI;

/// Rates along which a node is extrapolated over a step (all in W).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rates {
    /// ṙ (m/s): the velocity input, or the position input derivatives when given.
    pub dr: Vec3,
    /// Angular rate of the orientation (rad/s): the angular-velocity input, or the one
    /// implied by the quaternion input derivatives.
    pub dth: Vec3,
    /// v̇ (m/s²), from input derivatives; zero otherwise.
    pub dv: Vec3,
    /// ω̇ (rad/s²), from input derivatives; zero otherwise.
    pub dw: Vec3,
    /// Whether v̇ and ω̇ also move the pose (second order: r + ṙτ + ½v̇τ²).
    pub second_order: bool,
}

impl Rates {
    /// No motion over the step (zero-order hold).
    pub const HOLD: Rates = Rates {
        dr: Vec3::new(0.0, 0.0, 0.0),
        dth: Vec3::new(0.0, 0.0, 0.0),
        dv: Vec3::new(0.0, 0.0, 0.0),
        dw: Vec3::new(0.0, 0.0, 0.0),
        second_order: false,
    };

    /// First-order extrapolation from the node's own velocities.
    pub fn from_velocities(n: &Node) -> Rates {
        Rates {
            dr: n.v,
            dth: n.w,
            ..Rates::HOLD
        }
    }

    /// First-order extrapolation of node `n` from the derivatives of its 13 pose and twist inputs (r, q as
    /// given `q_raw` = w x y z before normalisation, v, ω) where `set`, its own velocities
    /// elsewhere. Quaternion derivatives give the angular rate ω = 2 q̇ ⊗ q* (q̇ scaled like
    /// the normalised q).
    pub fn linear(n: &Node, q_raw: &[Real], der: &[Real; 13], set: &[bool; 13]) -> Rates {
        if *set == [false; 13] {
            // what the general case below gives without derivatives
            return Rates::from_velocities(n);
        }
        let v3 = |i: usize, fb: Vec3| {
            let pick = |j: usize, f: Real| if set[j] { der[j] } else { f };
            Vec3::new(pick(i, fb.x), pick(i + 1, fb.y), pick(i + 2, fb.z))
        };
        let dth = if set[3..7].iter().any(|&s| s) {
            let norm = q_raw.iter().map(|x| x * x).sum::<Real>().sqrt();
            let qd = nalgebra::Quaternion::new(der[3], der[4], der[5], der[6]) / norm;
            (qd * n.q.quaternion().conjugate() * 2.0).imag()
        } else {
            n.w
        };
        Rates {
            dr: v3(0, n.v),
            dth,
            dv: v3(7, Vec3::zeros()),
            dw: v3(10, Vec3::zeros()),
            second_order: false,
        }
    }

    /// Second-order extrapolation: `linear`, with the accelerations also moving the pose, and
    /// taken where no input derivative gives them from the velocities `prev` (v, ω) of the
    /// previous communication point, `dt` before (None: no such point, accelerations zero).
    pub fn quadratic(
        n: &Node,
        q_raw: &[Real],
        der: &[Real; 13],
        set: &[bool; 13],
        prev: Option<(Real, &[Real; 6])>,
    ) -> Rates {
        let mut r = Rates::linear(n, q_raw, der, set);
        r.second_order = true;
        if let Some((dt, prev)) = prev {
            let now = [n.v.x, n.v.y, n.v.z, n.w.x, n.w.y, n.w.z];
            for i in 0..6 {
                if !set[7 + i] {
                    let a = (now[i] - prev[i]) / dt;
                    if i < 3 {
                        r.dv[i] = a;
                    } else {
                        r.dw[i - 3] = a;
                    }
                }
            }
        }
        r
    }

    /// Second-order extrapolation along given accelerations `acc` = (v̇, ω̇): `linear` (the
    /// position and orientation derivatives where set), with v̇ and ω̇ from `acc` and moving
    /// the pose too.
    pub fn along(
        n: &Node,
        q_raw: &[Real],
        der: &[Real; 13],
        set: &[bool; 13],
        acc: &[Real; 6],
    ) -> Rates {
        Rates {
            dv: Vec3::new(acc[0], acc[1], acc[2]),
            dw: Vec3::new(acc[3], acc[4], acc[5]),
            second_order: true,
            ..Rates::linear(n, q_raw, der, set)
        }
    }
}

/// The node after time τ along its extrapolation (rotations through the exponential map).
#[inline]
pub fn extrapolate(n: &Node, rate: &Rates, tau: Real) -> Node {
    if rate.second_order {
        let half = 0.5 * tau;
        return Node {
            r: n.r + (rate.dr + rate.dv * half) * tau,
            q: quat_exp(&((rate.dth + rate.dw * half) * tau)) * n.q,
            v: n.v + rate.dv * tau,
            w: n.w + rate.dw * tau,
        };
    }
    Node {
        r: n.r + rate.dr * tau,
        q: quat_exp(&(rate.dth * tau)) * n.q,
        v: n.v + rate.dv * tau,
        w: n.w + rate.dw * tau,
    }
}

/// Largest relative rotation per substep (rad): keeps angle branches and turning slip paths
/// resolved.
pub const MAX_ROTATION_PER_SUBSTEP: Real = 0.25;
/// Turn of a substep (rad) below which the path guard needs no flexion angles when both ends
/// have α ≤ π/2: the room 2(π − gap) − α_prev − α is then at least π − 2·gap − round-off.
const CLEAR_TURN: Real = 3.0;
/// Most substeps one communication step may take.
pub const MAX_SUBSTEPS: u32 = 100_000;

/// Why a step was not taken.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepError {
    /// The kinematics met a singular configuration at τ (s) into the step.
    Singular(Singular, Real),
    /// A non-finite output at τ (s) into the step.
    NotFinite(Real),
    /// The step would need more than `MAX_SUBSTEPS` substeps.
    TooManySubsteps(Real),
}

/// Number of substeps for a step of length `h`.
pub fn substeps(p: &Params, ra: &Rates, rb: &Rates, h: Real) -> Result<u32, StepError> {
    let mut turn = (ra.dth.norm() + rb.dth.norm()) * h;
    if ra.second_order || rb.second_order {
        turn += 0.5 * (ra.dw.norm() + rb.dw.norm()) * h * h;
    }
    let rot = turn / MAX_ROTATION_PER_SUBSTEP;
    let time = if p.max_substep > 0.0 {
        h / p.max_substep
    } else {
        1.0
    };
    let n = rot.max(time).ceil().max(1.0);
    if n.is_nan() || n > MAX_SUBSTEPS as Real {
        return Err(StepError::TooManySubsteps(n));
    }
    Ok(n as u32)
}

/// Result of an accepted step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Advanced {
    /// Outputs at t + h.
    pub outputs: Outputs,
    /// State at t + h.
    pub state: State,
    /// Node a at t + h (extrapolated).
    pub a: Node,
    /// Node b at t + h (extrapolated).
    pub b: Node,
}

/// Advances over [t, t + h] from the committed state `st` and the nodes at t.
/// On error nothing is committed: the caller keeps `st`.
pub fn advance(
    ct: ConnectionType,
    p: &Params,
    st: &State,
    (a0, ra): (&Node, &Rates),
    (b0, rb): (&Node, &Rates),
    h: Real,
) -> Result<Advanced, StepError> {
    let mut outputs = Outputs::default();
    let mut state = *st;
    let mut nodes = [Node::default(); 2];
    let mut events = Taking::NONE;
    advance_into(
        ct,
        p,
        st,
        (a0, ra),
        (b0, rb),
        h,
        None,
        Ends {
            outputs: &mut outputs,
            state: &mut state,
            nodes: &mut nodes,
            events: &mut events,
        },
    )?;
    let [a, b] = nodes;
    Ok(Advanced {
        outputs,
        state,
        a,
        b,
    })
}

/// τ as the importer's clock has it: (t0 + τ) − t0, never before τ (the next time on the clock
/// when rounding would put it before: the event's far end, where its function has crossed).
#[inline]
fn on_clock(t0: Real, tau: Real) -> Real {
    let te = t0 + tau;
    let te = if te - t0 < tau { te.next_up() } else { te };
    te - t0
}

/// Event tracking over a step (`events`): the event functions' values at its start, and
/// whether the step stops at the first event.
#[derive(Clone, Copy, Debug)]
pub struct Tracking<'a> {
    /// The event functions at τ = 0: exact (from the outputs at the step's inputs and `st`), or
    /// assumed (values whose sides are those at τ = 0; see `exact`).
    pub start: &'a Values,
    /// Whether `start` is exact. Assumed values only decide whether a function changed side
    /// over the first substep; where one did, the exact values at τ = 0 are evaluated (a read
    /// at the step's inputs) before anything is located.
    pub exact: bool,
    /// Stop the step at the first event (early return).
    pub stop_at_first: bool,
    /// Events located within this time of the step's start are met at the start: neither
    /// reported nor stopped at (every early return moves the time on).
    pub min_tau: Real,
    /// The step's start time: a located event's τ is the one the importer's clock gives,
    /// (t0 + τ) − t0, so that a step ended early there and a step of length event.time − t0
    /// (the FMI 2.0 master's rollback) walk the same path to the same bits.
    pub t0: Real,
}

/// Where a step writes what it ends with: the caller's own buffers (the per-step path: the
/// outputs go straight into the instance's cache, nothing is returned by value).
#[derive(Debug)]
pub struct Ends<'a> {
    /// The outputs there.
    pub outputs: &'a mut Outputs,
    /// The state there.
    pub state: &'a mut State,
    /// Nodes a and b there (extrapolated).
    pub nodes: &'a mut [Node; 2],
    /// The event functions there, with those taking part (`events::values_on`); written with
    /// tracking only.
    pub events: &'a mut Taking,
}

/// What a step met.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Met {
    /// Time into the step of the first event (the step's length when none).
    pub tau: Real,
    /// Number of events: sign changes of event functions over the part of the step taken.
    pub count: u32,
    /// Whether the step stopped at the first event (then it ends at `tau`).
    pub stopped: bool,
}

/// `advance` writing the outputs, the state and the nodes at the step's end into `ends` and
/// returning the events met. Without `track`, no event is looked for (`Met` says none) and
/// `ends.events` is left as it was.
///
/// With `track`, the event functions are compared at the ends of every substep; in the first
/// substep where one changes side its root is located (`events::locate`) on that substep's own
/// evaluation from the state it starts from, so the event time is the time of the committed
/// path, and with `stop_at_first` the step ends there: outputs, state and nodes at that time.
///
/// On error the contents of `ends` are unspecified and `st` is untouched.
#[inline]
#[allow(clippy::too_many_arguments)]
pub fn advance_into(
    ct: ConnectionType,
    p: &Params,
    st: &State,
    (a0, ra): (&Node, &Rates),
    (b0, rb): (&Node, &Rates),
    h: Real,
    track: Option<Tracking>,
    ends: Ends,
) -> Result<Met, StepError> {
    let Ends {
        outputs: o,
        state: next,
        nodes: ends_nodes,
        events: end,
    } = ends;
    let n = substeps(p, ra, rb, h)?;
    let dt = h / n as Real;
    // one substep of length dt from `s` to the nodes (a, b) at τ: evaluation, dissipated
    // energies, finite outputs
    let substep = |s: &State,
                   (tau, dt): (Real, Real),
                   (a, b): (&Node, &Node),
                   o: &mut Outputs,
                   next: &mut State| {
        evaluate_into(ct, p, s, a, b, Eval::Step(dt), (&mut *o, &mut *next))
            .map_err(|e| StepError::Singular(e, tau))?;
        // trapezoidal rule on the dissipation powers
        next.dissipated.damping += 0.5 * (s.power[0] + next.power[0]) * dt;
        next.dissipated.stops += 0.5 * (s.power[1] + next.power[1]) * dt;
        o.energy.damping = next.dissipated.damping;
        o.energy.stops = next.dissipated.stops;
        if !outputs_finite(o) {
            return Err(StepError::NotFinite(tau));
        }
        Ok(())
    };
    let nodes = |tau: Real| (extrapolate(a0, ra, tau), extrapolate(b0, rb, tau));
    let mut met = Met {
        tau: h,
        count: 0,
        stopped: false,
    };
    // the event functions at the start of the substep: the caller's (`track.start`) until the
    // exact values at τ = 0 or a substep's end replace them here; whether the first event is
    // located
    let mut own_start: Option<Values> = None;
    let mut located = false;
    // the state the substep starts from: `st`, then a copy of the last substep's end
    let mut prev: Option<State> = None;
    // path guard of centred types (below): the shafts at the start of the substep, and the
    // bound on the relative angular velocity, |ω_b − ω_a| + |ω̇_b − ω̇_a|·τ
    let mut shafts_prev = if ct.centred() {
        Shafts::of(&a0.q, &b0.q)
    } else {
        // never read: the guard is for centred types only
        Shafts {
            e3a: Vec3::zeros(),
            e3b: Vec3::zeros(),
        }
    };
    let (w_rel0, w_rel1) = ((rb.dth - ra.dth).norm(), (rb.dw - ra.dw).norm());
    for j in 1..=n {
        // time as t0 + j·dt, never accumulated
        let tau0 = h * (j - 1) as Real / n as Real;
        let tau = h * j as Real / n as Real;
        let (mut a, mut b) = nodes(tau);
        if ct.centred() {
            // α changes no faster than the relative angular velocity, so a substep whose ends
            // are both regular can still pass through the folded configuration between them:
            // refuse when the two ends are not far enough from π − gap for that to be ruled out.
            let shafts = Shafts::of(&a.q, &b.q);
            let turn = (w_rel0 + w_rel1 * tau) * dt;
            // Both ends at α ≤ π/2 (cos α > 0) leave room ≥ π − 2·gap, more than CLEAR_TURN:
            // the test would pass, so its two atan2 are skipped.
            let clear =
                shafts_prev.cos_flexion() > 0.0 && shafts.cos_flexion() > 0.0 && turn < CLEAR_TURN;
            if !clear {
                let (alpha_prev, alpha) = (shafts_prev.flexion(), shafts.flexion());
                let room = 2.0 * (PI - ALPHA_MAX_GAP) - alpha_prev - alpha;
                if room < turn {
                    return Err(StepError::Singular(
                        Singular::FlexionNearPi(alpha.max(alpha_prev)),
                        tau,
                    ));
                }
            }
            shafts_prev = shafts;
        }
        let s: &State = if j == 1 { st } else { prev.insert(*next) };
        substep(s, (tau, dt), (&a, &b), o, next)?;
        if let Some(track) = track {
            // the functions at the substep's end, written where the step's end keeps them
            values_on_into(ct, p, s, o, end);
            let mut crossed = crossed_on(own_start.as_ref().unwrap_or(track.start), &end.v, end.on);
            if j == 1 && !track.exact && crossed != 0 {
                // the assumed sides at τ = 0 say a function crossed: take the exact values
                let mut at0 = (Outputs::default(), State::default());
                evaluate_into(ct, p, st, a0, b0, Eval::Read, (&mut at0.0, &mut at0.1))
                    .map_err(|e| StepError::Singular(e, 0.0))?;
                let exact = own_start.insert(values(ct, p, st, &at0.0));
                crossed = crossed_on(exact, &end.v, end.on);
            }
            let start = own_start.as_ref().unwrap_or(track.start);
            if crossed != 0 && !located {
                // the first substep with events: locate each, the earliest is the first event;
                // one within `min_tau` of the step's start is met there (no zero-length step
                // stops at it, and neither version reports it)
                let mut scratch = (Outputs::default(), State::default());
                let mut first = Real::INFINITY;
                let mut met_at_start = 0u32;
                for i in events::bits(crossed) {
                    let at = |t: Real| {
                        let (a, b) = nodes(t);
                        let part = (t, t - tau0);
                        substep(s, part, (&a, &b), &mut scratch.0, &mut scratch.1)?;
                        Ok::<_, StepError>(values(ct, p, s, &scratch.0)[i])
                    };
                    let root = locate(i, (tau0, start[i]), (tau, end.v[i]), EVENT_TOL * h, at)?;
                    if root < track.min_tau {
                        met_at_start |= 1 << i;
                    } else {
                        first = first.min(on_clock(track.t0, root));
                    }
                }
                crossed &= !met_at_start;
                located = first.is_finite();
                if located {
                    met.tau = first;
                }
                if located && track.stop_at_first && (first < tau || j < n) {
                    if first < tau {
                        (a, b) = nodes(first);
                        substep(s, (first, first - tau0), (&a, &b), o, next)?;
                    }
                    // the functions crossed at the event (not those met at the start), then
                    // those of the state the step ends with
                    values_on_into(ct, p, s, o, end);
                    met.count = (crossed_on(start, &end.v, end.on) & !met_at_start).count_ones();
                    met.stopped = true;
                    values_on_into(ct, p, next, o, end);
                    *ends_nodes = [a, b];
                    return Ok(met);
                }
            }
            met.count += crossed.count_ones();
            // the next substep's start: these values, made those of the state it starts from
            // (its activity and friction forces: `events::values_after`)
            events::values_after(ct, p, (s, next), o, end);
            if j < n {
                own_start = Some(end.v);
            }
        }
        if j == n {
            *ends_nodes = [a, b];
            return Ok(met);
        }
    }
    // n ≥ 1, so the loop returned
    Err(StepError::NotFinite(0.0))
}

/// Whether every Real output is finite (NaN never reaches an output).
pub fn outputs_finite(o: &Outputs) -> bool {
    // x·0 is ±0 for a finite x and NaN for ±∞ and NaN, so a sum of such terms is 0 exactly when
    // every x is finite; summed lane by lane (no early exit), which the compiler vectorises
    let f = &o.friction;
    let e = &o.energy;
    let arrays = [
        &o.cp,
        &o.cu,
        &o.cv,
        &o.cef,
        &o.cvf,
        &o.csf,
        &o.crf,
        &o.ctf,
        &[o.fa.x, o.fa.y, o.fa.z, o.ma.x, o.ma.y, o.ma.z],
        &[o.fb.x, o.fb.y, o.fb.z, o.mb.x, o.mb.y, o.mb.z],
        &[f.cnf, f.cnm1, f.csfc, f.csmc1, f.slip, f.slip_r1],
        &[e.stored, e.damping, e.friction, e.stops, 0.0, 0.0],
    ];
    let mut lanes = [0.0; 6];
    for a in arrays {
        for (l, x) in lanes.iter_mut().zip(a) {
            *l += x * 0.0;
        }
    }
    lanes.iter().sum::<Real>() == 0.0
}
