//! Events inside a step (docs/physics.md, "Events"): a stop engaging or letting go, a friction
//! effect going stick → slip or slip → stick, the normal force of friction passing through
//! zero. Each is a sign change of its own event function along the path of the step:
//!
//! | functions | event | value |
//! |---|---|---|
//! | `STOP_UPPER + k`, `STOP_LOWER + k` | stop of component k+1 engages (> 0) or lets go (≤ 0) | penetration c − upper, lower − c |
//! | `STICK_SLIP + e` | effect e (sliding, spin) breaks away | trial force minus its limit (≥ 0: slips) |
//! | `SLIP_STICK + e` | effect e stops slipping | with a stick damper, the trial force minus its limit (≤ 0: the plastic slip stops); without, the slip rate along the friction force, v·f (≤ 0: the slip reverses) |
//! | `STOP_FORCE + k` | an engaged damped stop's force lets go (clipped: it never pulls) | k·p + c·ṗ |
//! | `NORMAL_AXIAL`, `NORMAL_SLIDE`, `NORMAL_SPIN` | the normal force of friction vanishes | CRF1; F_C + F_C^int; M_R1 + M_R1^int |
//!
//! A function takes part in a substep when the state the substep starts from makes it
//! meaningful (a stick → slip function only for a sticking effect, a stop only where it is
//! finite, …); otherwise its value is NaN. The root of a function whose side changed is found
//! by bracketing (Illinois false position, safeguarded so that the bracket closes) on the
//! substep that produced the change, to `EVENT_TOL` of the communication step; the event time
//! is the bracket's far end, where the function has crossed, so that a step restarted there
//! does not find the same event again.

use super::connector::{Outputs, Params, State};
use super::friction::{
    normal_loads, slip_stick_function, stick_slip_function, FrictionParams, FrictionState, Status,
};
use super::kinematics::{with_constant_type, ConnectionType, Role, Rotational};
use super::math::Real;

/// First upper-stop function (one per component slot).
pub const STOP_UPPER: usize = 0;
/// First lower-stop function (one per component slot).
pub const STOP_LOWER: usize = 6;
/// First stick → slip function (sliding, spin).
pub const STICK_SLIP: usize = 12;
/// First slip → stick function (sliding, spin).
pub const SLIP_STICK: usize = 14;
/// The axial reaction CRF1 changes sign (F_NC = |CRF1| without preload or bending).
pub const NORMAL_AXIAL: usize = 16;
/// F_C + F_C^int changes sign (a negative preload).
pub const NORMAL_SLIDE: usize = 17;
/// M_R1 + M_R1^int changes sign (a negative preload).
pub const NORMAL_SPIN: usize = 18;
/// First stop-force function (one per component slot): an engaged damped stop's force
/// k·p + c·ṗ, which lets go (the force is clipped, it never pulls) before the penetration p does.
pub const STOP_FORCE: usize = 19;
/// Number of event functions.
pub const N_EVENTS: usize = 25;

/// A function is far from its event when its value exceeds this many times its change over
/// the last step: then the importer's next inputs (continuous with the path, to well within a
/// step's change) cannot have moved it across zero, and its side at the next step's start is
/// taken from the last step's end without evaluating the connector there (`far`).
pub const FAR: Real = 8.0;

/// Whether every function taking part at the end of a step (`end`, not NaN) is far from its
/// event, judged by its change over the step (from `before`, its values at the step's start:
/// exact, or the sides assumed from the step before, which then include the importer's input
/// jump only through the step after): then the next step may start from `end`'s sides (see
/// `FAR`); otherwise it needs the exact values.
pub fn far(end: &Values, before: &Values) -> bool {
    far_on(end, (1 << N_EVENTS) - 1, before)
}

/// `far` among the functions in `on`, which holds every function taking part in `end` (as
/// `values_on` gives it): the others are far by definition.
#[inline]
pub fn far_on(end: &Values, on: u32, before: &Values) -> bool {
    for i in bits(on) {
        let (e, b) = (end[i], before[i]);
        if !(e.is_nan() || (e != 0.0 && e.abs() > FAR * (e - b).abs())) {
            return false;
        }
    }
    true
}

/// Event times are located to this fraction of the communication step (the spec asks for
/// 1e-9; false position needs few more evaluations for the tenfold margin).
pub const EVENT_TOL: Real = 1e-10;

/// The event functions' values at one point of a substep (NaN: not taking part).
pub type Values = [Real; N_EVENTS];

/// Whether any event function can take part for these parameters (else a step tracks none
/// and costs nothing more).
pub fn tracked(ct: ConnectionType, p: &Params) -> bool {
    let roles = ct.roles();
    let stops = (0..6).any(|k| {
        roles[k] == Role::Available && (p.stop_upper[k].is_finite() || p.stop_lower[k].is_finite())
    });
    stops || (ct.rot == Rotational::Revolute && p.friction.enabled())
}

/// Which side of its event a function's value lies on: stops engaged, friction slipping,
/// the slip still forward, the normal force positive.
#[inline]
pub fn side(i: usize, x: Real) -> bool {
    if (STICK_SLIP..SLIP_STICK).contains(&i) {
        x >= 0.0
    } else {
        x > 0.0
    }
}

/// The event functions at a point of a substep that starts from `st`, from the outputs `o`
/// evaluated there.
pub fn values(ct: ConnectionType, p: &Params, st: &State, o: &Outputs) -> Values {
    values_on(ct, p, st, o).v
}

/// Event function values with the set of those taking part (bit i: function i), which the
/// step's comparisons go through instead of every function (`crossed_on`, `far_on`).
#[derive(Clone, Copy, Debug)]
pub struct Taking {
    /// The values (NaN: not taking part).
    pub v: Values,
    /// Bit i set: function i takes part (its value is written; where the function is
    /// undefined that value can still be NaN, which the comparisons treat as not taking part).
    pub on: u32,
}

impl Taking {
    /// No function taking part.
    pub const NONE: Taking = Taking {
        v: [Real::NAN; N_EVENTS],
        on: 0,
    };

    #[inline(always)]
    fn put(&mut self, i: usize, x: Real) {
        self.v[i] = x;
        self.on |= 1 << i;
    }
}

/// `values` with the set of the functions taking part.
pub fn values_on(ct: ConnectionType, p: &Params, st: &State, o: &Outputs) -> Taking {
    let mut v = Taking::NONE;
    values_on_into(ct, p, st, o, &mut v);
    v
}

/// `values_on` written into `v` (the step's path: the values go straight where they are kept).
pub fn values_on_into(ct: ConnectionType, p: &Params, st: &State, o: &Outputs, v: &mut Taking) {
    // one copy per connection type: its roles fold away
    with_constant_type!(ct, |CT| values_on_body(CT, p, st, o, v))
}

#[inline(always)]
fn values_on_body(ct: ConnectionType, p: &Params, st: &State, o: &Outputs, v: &mut Taking) {
    // in place (assigning `Taking::NONE` is a call to memcpy)
    v.v.fill(Real::NAN);
    v.on = 0;
    for (k, role) in ct.roles().into_iter().enumerate() {
        if role != Role::Available {
            continue;
        }
        if p.stop_upper[k].is_finite() {
            v.put(STOP_UPPER + k, o.cp[k] - p.stop_upper[k]);
        }
        if p.stop_lower[k].is_finite() {
            v.put(STOP_LOWER + k, p.stop_lower[k] - o.cp[k]);
        }
        // an engaged damped stop: its unclipped force, on the side it is engaged
        let (ks, cs) = p.stop.for_slot(k);
        if cs > 0.0 {
            match st.stop_status[k] {
                1 => v.put(
                    STOP_FORCE + k,
                    ks * (o.cp[k] - p.stop_upper[k]) + cs * o.cv[k],
                ),
                -1 => v.put(
                    STOP_FORCE + k,
                    ks * (p.stop_lower[k] - o.cp[k]) - cs * o.cv[k],
                ),
                _ => {}
            }
        }
    }
    if ct.rot != Rotational::Revolute || !p.friction.enabled() {
        return;
    }
    let f = &p.friction;
    let fs = &st.friction;
    let (pos, rate) = ([o.cp[1], o.cp[2], o.cp[3]], [o.cv[1], o.cv[2], o.cv[3]]);
    let coupled = f.coupling == 1;
    // an effect without normal force sticks as soon as one appears (at the step's start when
    // the importer's inputs load it): its breakaway is a stick → slip event too; coupled, the
    // sliding functions stand for both
    let statuses = [fs.status, fs.status_r1];
    let sticks =
        |e: usize| (e == 0 || !coupled) && matches!(statuses[e], Status::Stick | Status::NoNormal);
    if sticks(0) || sticks(1) {
        let phi = stick_slip_function(f, fs, pos, rate, (o.friction.cnf, o.friction.cnm1));
        for (e, phi_e) in phi.into_iter().enumerate() {
            if sticks(e) {
                v.put(STICK_SLIP + e, phi_e);
            }
        }
    }
    let normals = (o.friction.cnf, o.friction.cnm1);
    for (e, x) in slip_stick(f, fs, pos, rate, normals)
        .into_iter()
        .enumerate()
    {
        if let Some(x) = x {
            v.put(SLIP_STICK + e, x);
        }
    }
    // the normal loads pass through zero: through CRF1 when nothing else loads them (no
    // preload; bending only adds), through F_C + F_int or M_R1 + M_int with a negative preload
    if f.f_int == 0.0 || f.m_int == 0.0 {
        v.put(NORMAL_AXIAL, o.crf[0]);
    }
    if f.f_int < 0.0 || f.m_int < 0.0 {
        let unloaded = FrictionParams {
            f_int: 0.0,
            m_int: 0.0,
            ..*f
        };
        let (f_c, m_r1) = normal_loads(&unloaded, o.crf[0], o.crf[4], o.crf[5]);
        if f.f_int < 0.0 {
            v.put(NORMAL_SLIDE, f_c + f.f_int);
        }
        if f.m_int < 0.0 {
            v.put(NORMAL_SPIN, m_r1 + f.m_int);
        }
    }
}

/// The functions that cross between `a` and `b`, as a bit mask (bit i: function i): both
/// taking part, on different sides, and strictly off zero at `a` (a function that starts at
/// zero meets its event at the start, not inside the substep).
#[inline]
pub fn crossed(a: &Values, b: &Values) -> u32 {
    crossed_on(a, b, (1 << N_EVENTS) - 1)
}

/// `crossed` among the functions in `on`, which holds every function taking part in `b` (as
/// `values_on` gives it): the others cannot cross, so only these are compared.
#[inline]
pub fn crossed_on(a: &Values, b: &Values, on: u32) -> u32 {
    let mut mask = 0;
    for i in bits(on) {
        let (x, y) = (a[i], b[i]);
        if x != 0.0 && !x.is_nan() && !y.is_nan() && side(i, x) != side(i, y) {
            mask |= 1 << i;
        }
    }
    mask
}

/// The indices of the bits set in `mask`, in increasing order.
#[inline]
pub fn bits(mask: u32) -> impl Iterator<Item = usize> {
    let mut rest = mask & ((1 << N_EVENTS) - 1);
    std::iter::from_fn(move || {
        (rest != 0).then(|| {
            let i = rest.trailing_zeros() as usize;
            rest &= rest - 1;
            i
        })
    })
}

/// The slip → stick functions of the slipping effects, sliding (or coupled) and spin (None:
/// not slipping). With a stick damper, the trial force minus its limit
/// (`friction::slip_stick_function`: the plastic slip stops where the trial falls inside the
/// limit, while the relative slip still goes on); without, the slip power of the committed
/// friction force `fs.force` at the slip rates `rate`, v·f (the plastic slip follows the
/// relative slip and stops where it reverses). Positive while the slip goes on.
#[inline(always)]
fn slip_stick(
    f: &FrictionParams,
    fs: &FrictionState,
    pos: [Real; 3],
    rate: [Real; 3],
    normals: (Real, Real),
) -> [Option<Real>; 2] {
    let coupled = f.coupling == 1;
    let damped = if coupled {
        [f.c_stick > 0.0 && f.c_stick_r1 > 0.0; 2]
    } else {
        [f.c_stick > 0.0, f.c_stick_r1 > 0.0]
    };
    let slipping = [
        fs.status == Status::Slip,
        fs.status_r1 == Status::Slip && !coupled,
    ];
    if !(slipping[0] || slipping[1]) {
        return [None; 2];
    }
    let trial = (damped[0] || damped[1]).then(|| slip_stick_function(f, fs, pos, rate, normals));
    let [f2, f3, m1] = fs.force;
    let (slide, spin) = (rate[0] * f2 + rate[1] * f3, rate[2] * m1);
    let power = [if coupled { slide + spin } else { slide }, spin];
    std::array::from_fn(|e| {
        slipping[e].then(|| match trial {
            Some(t) if damped[e] => t[e],
            _ => power[e],
        })
    })
}

/// Turns `v = values_on(ct, p, a, o)` into `values_on(ct, p, b, o)` for the same outputs and
/// another state `b` (a substep's start and end state: the next substep starts from `b`), in
/// place. The functions taking part follow the stop and friction statuses, and their values
/// depend on the state only through a sticking effect's plastic slip and a slipping effect's
/// force: with the same statuses and the sticking effects' plastic slips unchanged only the
/// slip → stick functions are evaluated again (the same operations as `values_on`, so the same
/// bits); otherwise all of them.
#[inline]
pub fn values_after(
    ct: ConnectionType,
    p: &Params,
    (a, b): (&State, &State),
    o: &Outputs,
    v: &mut Taking,
) {
    if ct.rot != Rotational::Revolute || !p.friction.enabled() {
        // no friction functions: the stop statuses alone decide which functions take part
        if a.stop_status != b.stop_status {
            values_on_into(ct, p, b, o, v);
        }
        return;
    }
    let (fa, fb) = (&a.friction, &b.friction);
    // a sticking effect's function reads its plastic slip (coupled: the sliding one stands
    // for both and reads all of it); a slipping effect's plastic slip moves, but no function
    // of it reads that
    let coupled = p.friction.coupling == 1;
    let sticks = |s: Status| matches!(s, Status::Stick | Status::NoNormal);
    let (sliding, spin) = (
        fa.slip_plastic == fb.slip_plastic,
        fa.slip_plastic_r1 == fb.slip_plastic_r1,
    );
    let plastic = (!sticks(fb.status) || (sliding && (spin || !coupled)))
        && (!sticks(fb.status_r1) || coupled || spin);
    let same = a.stop_status == b.stop_status
        && fa.status == fb.status
        && fa.status_r1 == fb.status_r1
        && plastic;
    if !same {
        values_on_into(ct, p, b, o, v);
        return;
    }
    if fb.status == Status::Slip || fb.status_r1 == Status::Slip {
        let (pos, rate) = ([o.cp[1], o.cp[2], o.cp[3]], [o.cv[1], o.cv[2], o.cv[3]]);
        let normals = (o.friction.cnf, o.friction.cnm1);
        for (e, x) in slip_stick(&p.friction, fb, pos, rate, normals)
            .into_iter()
            .enumerate()
        {
            if let Some(x) = x {
                v.put(SLIP_STICK + e, x);
            }
        }
    }
}

/// Locates the root of event function `i` on [ta, tb], where `fa` lies on one side and `fb`
/// on the other, to `tol`: the returned time is the far end of the final bracket (the
/// function has crossed there). `f` evaluates the function at a time inside the bracket.
pub fn locate<E>(
    i: usize,
    (mut ta, mut fa): (Real, Real),
    (mut tb, mut fb): (Real, Real),
    tol: Real,
    mut f: impl FnMut(Real) -> Result<Real, E>,
) -> Result<Real, E> {
    let far = side(i, fb);
    // the end replaced by the last probe (Illinois halves the other end's value when the same
    // end is replaced twice in a row); bisection when two probes in a row did not halve the
    // bracket, so that it at least halves every three probes whatever the function
    let mut last_far: Option<bool> = None;
    let (mut w_ref, mut since) = (tb - ta, 0);
    for _ in 0..200 {
        let width = tb - ta;
        if width <= tol {
            break;
        }
        if width <= 0.5 * w_ref {
            (w_ref, since) = (width, 0);
        }
        let secant = tb - fb * width / (fb - fa);
        let mut t = if since < 2 && secant > ta && secant < tb {
            secant
        } else {
            0.5 * (ta + tb)
        };
        since += 1;
        // at least half a tolerance inside: once false position converges from one side, the
        // next probe lands across the root and closes the bracket
        let margin = 0.5 * tol.min(0.5 * width);
        t = t.clamp(ta + margin, tb - margin);
        let ft = f(t)?;
        if ft.is_nan() {
            // not expected (the functions taking part are fixed for the substep): keep the
            // bracket found so far
            break;
        }
        let is_far = side(i, ft) == far;
        if is_far {
            (tb, fb) = (t, ft);
            if last_far == Some(true) {
                fa *= 0.5;
            }
        } else {
            (ta, fa) = (t, ft);
            if last_far == Some(false) {
                fb *= 0.5;
            }
        }
        last_far = Some(is_far);
    }
    Ok(tb)
}
