//! Early return at events (earlyReturnAllowed): fmi3DoStep ends at a stop contact, with the
//! event's time as lastSuccessfulTime and the instance's time, and continues from there; without
//! early return the step runs through and reports the event; an early return repeats bit for bit
//! from a restored FMU state.
//!
//! Uses `tests/common/fmi3.rs` (`Fmu3`, `assert_error_logged`, `outputs`).

mod common;

use common::fmi3::*;
use connector_fmu::fmi3::exports::*;
use connector_fmu::variables::Variant;
use std::ffi::c_void;
use std::ptr::null_mut;

// ------------------------------------------------------------------ early return at events

/// Whether a located event time lies where the FMU puts it: at most 1e-10 of the step `h` past
/// the exact time (the far end of the bracket), with an ulp of slack for the time sum.
fn just_past(located: f64, exact: f64, h: f64) -> bool {
    (exact - 1e-17..=exact + 1e-10 * h + 1e-17).contains(&located)
}

/// ProjectionCartesian with an upper stop on u1 at 0.01 m; b set at x = x0 moving at `v`.
fn stop_scene(f: &Fmu3, x0: f64, v: f64) {
    f.enter_init();
    f.set_real_if("stop.upper1", 0.01);
    f.set_real_if("stop.stiffness", 1e4);
    f.set_real_if("b.v[1]", v);
    f.exit_init();
    f.set_real_if("b.r[1]", x0);
}

#[test]
fn do_step_returns_early_at_a_stop_contact_and_continues_from_there() {
    let v = Variant::ProjectionCartesian;
    let f = Fmu3::with_early_return(v, true);
    stop_scene(&f, 0.0, 1.0);
    let ev = [f.vr("event.time")];
    let (count, cslst) = (f.vr("event.count"), f.vr("CSLST1"));
    // 0 → 4 ms → 8 ms: no event; 8 ms + 4 ms: contact at x = 0.01, i.e. t = 10 ms
    let mut t = 0.0;
    for _ in 0..2 {
        let (s, [e, term, early], last) = f.step(t, 0.004);
        assert_eq!((s, e, term, early), (OK, 0, 0, 0), "{:?}", f.log());
        assert_eq!(last, t + 0.004);
        assert_eq!(
            f.get_reals(&ev)[0],
            last,
            "event.time = t + h without events"
        );
        assert_eq!(f.get_ints(&[count, cslst]), vec![0, 0]);
        t = last;
    }
    let (s, [e, term, early], last) = f.step(t, 0.004);
    assert_eq!((s, e, term, early), (OK, 0, 0, 1), "{:?}", f.log());
    // the located time is the bracket's far end, within 1e-10 of the step past the contact
    assert!(just_past(last, 0.01, 0.004), "{last}");
    assert_eq!(f.get_reals(&ev)[0], last, "event.time = lastSuccessfulTime");
    assert_eq!(
        f.get_ints(&[count, cslst]),
        vec![1, 1],
        "engaged at the event"
    );
    // the FMU's time is the event's: a step from the old end is refused, from the event runs
    let before = f.log().len();
    let (s, _, _) = f.step(t + 0.004, 0.004);
    assert_error_logged(&f, before, s, "fmi3DoStep");
    let g = Fmu3::with_early_return(v, true);
    stop_scene(&g, 0.0, 1.0);
    for (i, tk) in [0.0, 0.004, 0.008].iter().enumerate() {
        let (s, [.., early], _) = g.step(*tk, 0.004);
        assert_eq!((s, early), (OK, u8::from(i == 2)));
    }
    let (s, [.., early], next) = g.step(last, 0.004);
    assert_eq!((s, early), (OK, 0), "{:?}", g.log());
    assert_eq!(next, last + 0.004);
}

#[test]
fn without_early_return_the_step_runs_through_and_reports_the_event() {
    let v = Variant::ProjectionCartesian;
    let f = Fmu3::new(v);
    stop_scene(&f, 0.008, 1.0);
    let (s, [.., early], last) = f.step(0.0, 0.004);
    assert_eq!((s, early), (OK, 0));
    assert_eq!(last, 0.004);
    let t_event = f.get_reals(&[f.vr("event.time")])[0];
    assert!(just_past(t_event, 0.002, 0.004), "{t_event}");
    assert_eq!(f.get_ints(&[f.vr("event.count")]), vec![1]);
}

#[test]
fn an_early_return_repeats_bit_for_bit_from_a_restored_state() {
    let v = Variant::Planar;
    let f = Fmu3::with_early_return(v, true);
    f.enter_init();
    f.set_real_if("friction.muStatic", 0.5);
    f.set_real_if("friction.Fint", 20.0);
    f.set_real_if("friction.stickStiffness", 1e4);
    f.set_real_if("b.v[2]", 0.1);
    f.exit_init();
    let reals = outputs(v, false);
    let mut s0 = null_mut::<c_void>();
    assert_eq!(fmi3GetFMUState(f.c, &mut s0), OK);
    // breakaway where the stick spring reaches μN: t0 = 0.5·20/(1e4·0.1) = 10 ms
    let (s, [.., early], last) = f.step(0.0, 0.016);
    assert_eq!((s, early), (OK, 1), "{:?}", f.log());
    assert!(just_past(last, 0.01, 0.016), "{last}");
    let y1 = f.get_reals(&reals);
    assert_eq!(fmi3SetFMUState(f.c, s0), OK);
    let (s, [.., early], again) = f.step(0.0, 0.016);
    assert_eq!((s, early, again.to_bits()), (OK, 1, last.to_bits()));
    let y2 = f.get_reals(&reals);
    assert!(y1.iter().zip(&y2).all(|(p, q)| p.to_bits() == q.to_bits()));
    assert_eq!(fmi3FreeFMUState(f.c, &mut s0), OK);
}
