//! fmi2SetReal and fmi2GetReal remember the last list of node inputs (node loads) they were
//! called with, and fmi2GetDirectionalDerivative its last list of unknowns, and serve the same
//! list again without looking each VR up (src/instance/memo.rs). A repeated list must behave
//! exactly as a first one: all or nothing with a bad value (one message naming it, nothing
//! changed), every value where its own VR says, and reads that follow the inputs and the steps.

mod common;
use common::{assert_error_logged, Fmu};
use connector_fmu::fmi2::exports::{fmi2GetDirectionalDerivative, fmi2GetReal, fmi2SetReal};
use connector_fmu::fmi2::types::fmi2Status;
use connector_fmu::variables::{table, Causality, Start, Variability, Variant, VARIANTS};

/// The variant's node inputs (every Real input), in table order.
fn node_inputs(v: Variant) -> Vec<(u32, &'static str)> {
    table(v)
        .vars
        .iter()
        .filter(|x| x.causality == Causality::Input && matches!(x.start, Start::Real(_)))
        .map(|x| (x.vr, x.name.as_str()))
        .collect()
}

/// Values for the inputs: unit quaternions (w first) where the name says q, small numbers
/// elsewhere, moved by `shift`.
fn values_for(inputs: &[(u32, &str)], shift: f64) -> Vec<f64> {
    inputs
        .iter()
        .enumerate()
        .map(
            |(i, (_, name))| match name.rsplit_once('.').map(|(_, f)| f) {
                Some("q[1]") => 1.0,
                Some(f) if f.starts_with("q[") => 0.0,
                _ => 0.01 * (i as f64 + 1.0) + shift,
            },
        )
        .collect()
}

fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|x| x.to_bits()).collect()
}

fn set(f: &Fmu, vrs: &[u32], x: &[f64]) -> fmi2Status {
    fmi2SetReal(f.c, vrs.as_ptr(), vrs.len(), x.as_ptr())
}

#[test]
fn a_repeated_input_list_is_all_or_nothing_and_lands_where_each_vr_says() {
    for spec in VARIANTS {
        let v = spec.variant;
        let f = Fmu::new(v);
        f.init();
        let inputs = node_inputs(v);
        let vrs: Vec<u32> = inputs.iter().map(|(vr, _)| *vr).collect();
        // the first call resolves the list, the next ones repeat it
        for shift in [0.0, 0.5, 0.25] {
            let x = values_for(&inputs, shift);
            assert_eq!(set(&f, &vrs, &x), fmi2Status::OK, "{v:?}: {:?}", f.log());
            for ((_, name), want) in inputs.iter().zip(&x) {
                assert_eq!(f.get_real(name).to_bits(), want.to_bits(), "{v:?} {name}");
            }
        }
        let kept = f.get_reals(&vrs);
        // a bad value in the repeated list: refused, named, nothing set (also the values
        // before it in the list)
        for (bad_at, bad) in [(inputs.len() - 1, f64::NAN), (2, f64::INFINITY)] {
            let mut x = values_for(&inputs, 0.75);
            x[bad_at] = bad;
            let before = f.log_len();
            let status = set(&f, &vrs, &x);
            assert_error_logged(&f, before, status, "fmi2SetReal");
            let message = &f.log()[before].message;
            assert!(message.contains(inputs[bad_at].1), "{v:?}: {message}");
            assert_eq!(
                f.get_reals(&vrs),
                kept,
                "{v:?}: a refused list changed inputs"
            );
        }
        // the list in another order is another list: it lands where its own VRs say
        let (rev_vrs, mut rev_x): (Vec<u32>, Vec<f64>) = vrs
            .iter()
            .rev()
            .zip(values_for(&inputs, 0.125).iter().rev())
            .map(|(&vr, &x)| (vr, x))
            .unzip();
        assert_eq!(set(&f, &rev_vrs, &rev_x), fmi2Status::OK);
        assert_eq!(f.get_reals(&rev_vrs), rev_x, "{v:?} reversed");
        rev_x.reverse();
        assert_eq!(
            f.get_reals(&vrs),
            rev_x,
            "{v:?} reversed, read in table order"
        );
    }
}

#[test]
fn a_repeated_load_list_reads_the_current_loads() {
    for spec in VARIANTS {
        let v = spec.variant;
        let f = Fmu::new(v);
        for k in 1..=6 {
            f.set_real_if(&format!("elasticity.k{k}"), 100.0 * k as f64);
            f.set_real_if(&format!("damping.c{k}"), 1.0);
        }
        f.init();
        let loads: Vec<u32> = ["a.f", "a.m", "b.f", "b.m"]
            .iter()
            .flat_map(|n| (1..=3).map(move |i| format!("{n}[{i}]")))
            .filter(|n| f.has(n))
            .map(|n| f.vr(&n))
            .collect();
        assert!(!loads.is_empty(), "{v:?} has node loads");
        let inputs = node_inputs(v);
        let vrs: Vec<u32> = inputs.iter().map(|(vr, _)| *vr).collect();
        let mut t = 0.0;
        let mut changed = 0;
        for shift in [0.0, 0.01, 0.02, 0.03] {
            assert_eq!(set(&f, &vrs, &values_for(&inputs, shift)), fmi2Status::OK);
            assert_eq!(f.step(t, 1e-3), fmi2Status::OK, "{v:?}: {:?}", f.log());
            t += 1e-3;
            // the list twice in a row (the second call repeats the remembered list), then
            // one VR per call (each its own list)
            let mut first = vec![f64::NAN; loads.len()];
            let s = fmi2GetReal(f.c, loads.as_ptr(), loads.len(), first.as_mut_ptr());
            assert_eq!(s, fmi2Status::OK);
            let mut got = vec![f64::NAN; loads.len()];
            let s = fmi2GetReal(f.c, loads.as_ptr(), loads.len(), got.as_mut_ptr());
            assert_eq!(s, fmi2Status::OK);
            assert_eq!(bits(&got), bits(&first), "{v:?} repeated at t = {t}");
            for (&vr, &x) in loads.iter().zip(&got) {
                let mut one = f64::NAN;
                assert_eq!(fmi2GetReal(f.c, &vr, 1, &mut one), fmi2Status::OK);
                assert_eq!(x.to_bits(), one.to_bits(), "{v:?} VR {vr} at t = {t}");
            }
            if got.iter().any(|&x| x != 0.0) {
                changed += 1;
            }
        }
        assert!(changed >= 3, "{v:?}: the loads should follow the inputs");
    }
}

/// An initialised instance with a spring and a damper on every component.
fn springs_and_dampers(v: Variant) -> Fmu {
    let f = Fmu::new(v);
    for k in 1..=6 {
        f.set_real_if(&format!("elasticity.k{k}"), 100.0 * k as f64);
        f.set_real_if(&format!("damping.c{k}"), 1.0 + k as f64);
    }
    f.init();
    f
}

/// The variant's continuous Real outputs (every unknown a directional derivative takes).
fn continuous_outputs(v: Variant) -> Vec<u32> {
    table(v)
        .vars
        .iter()
        .filter(|x| x.causality == Causality::Output)
        .filter(|x| x.variability == Variability::Continuous)
        .filter(|x| matches!(x.start, Start::Real(_)))
        .map(|x| x.vr)
        .collect()
}

/// J·δ for the unknowns `u` along one known `k` (seed 1), with the call's status.
fn derivative(f: &Fmu, u: &[u32], k: u32) -> (fmi2Status, Vec<f64>) {
    let mut out = vec![f64::NAN; u.len()];
    let s = fmi2GetDirectionalDerivative(f.c, u.as_ptr(), u.len(), &k, 1, &1.0, out.as_mut_ptr());
    (s, out)
}

#[test]
fn a_repeated_unknown_list_gives_each_unknown_its_own_derivative() {
    for spec in VARIANTS {
        let v = spec.variant;
        let f = springs_and_dampers(v);
        let inputs = node_inputs(v);
        let vrs: Vec<u32> = inputs.iter().map(|(vr, _)| *vr).collect();
        assert_eq!(set(&f, &vrs, &values_for(&inputs, 0.02)), fmi2Status::OK);
        assert_eq!(f.step(0.0, 1e-3), fmi2Status::OK, "{v:?}: {:?}", f.log());
        let unknowns = continuous_outputs(v);
        // the unknowns one at a time: each its own list (the reference)
        let one_by_one = |k: u32| -> Vec<f64> {
            unknowns
                .iter()
                .map(|&u| {
                    let (s, d) = derivative(&f, &[u], k);
                    assert_eq!(s, fmi2Status::OK, "{v:?} VR {u}: {:?}", f.log());
                    d[0]
                })
                .collect()
        };
        let mut nonzero = 0;
        for &(k, _) in inputs.iter().take(13) {
            let want = one_by_one(k);
            nonzero += want.iter().filter(|&&x| x != 0.0).count();
            // the whole list twice (the second call repeats the remembered list) along the
            // same known, and along this known after the last one's list
            for _ in 0..2 {
                let (s, got) = derivative(&f, &unknowns, k);
                assert_eq!(s, fmi2Status::OK, "{v:?}: {:?}", f.log());
                assert_eq!(bits(&got), bits(&want), "{v:?} along VR {k}");
            }
            // the list in another order is another list: each value where its own VR says
            let rev: Vec<u32> = unknowns.iter().rev().copied().collect();
            let (s, mut got) = derivative(&f, &rev, k);
            assert_eq!(s, fmi2Status::OK);
            got.reverse();
            assert_eq!(bits(&got), bits(&want), "{v:?} reversed, along VR {k}");
        }
        assert!(nonzero > 0, "{v:?}: the derivatives should not all be 0");
        // a list with a node input among the unknowns: refused and named, also right after
        // the good list was remembered, and the good list works again after it
        let (k, _) = inputs[0];
        let mut bad = unknowns.clone();
        bad.push(k);
        let name = &inputs[0].1;
        for _ in 0..2 {
            let before = f.log_len();
            let (s, _) = derivative(&f, &bad, k);
            assert_error_logged(&f, before, s, "fmi2GetDirectionalDerivative");
            let message = &f.log()[before].message;
            assert!(message.contains(name), "{v:?}: {message}");
        }
        let (s, got) = derivative(&f, &unknowns, k);
        assert_eq!(s, fmi2Status::OK);
        assert_eq!(
            bits(&got),
            bits(&one_by_one(k)),
            "{v:?} after the refused list"
        );
    }
}

#[test]
fn what_was_asked_before_does_not_change_a_derivative() {
    // Two instances on the same inputs and steps; one is asked for every derivative at every
    // point on the way (its remembered unknown lists and centred triads then come from other
    // points), the other only at the end: the same bits.
    for spec in VARIANTS {
        let v = spec.variant;
        let (asked, fresh) = (springs_and_dampers(v), springs_and_dampers(v));
        let inputs = node_inputs(v);
        let vrs: Vec<u32> = inputs.iter().map(|(vr, _)| *vr).collect();
        let unknowns = continuous_outputs(v);
        let jacobian = |f: &Fmu| -> Vec<Vec<u64>> {
            vrs.iter()
                .take(13)
                .map(|&k| {
                    let (s, d) = derivative(f, &unknowns, k);
                    assert_eq!(s, fmi2Status::OK, "{v:?}: {:?}", f.log());
                    bits(&d)
                })
                .collect()
        };
        let mut t = 0.0;
        for shift in [0.0, 0.03, 0.06] {
            // the orientations turn from point to point too (inputs are normalised)
            let mut x = values_for(&inputs, shift);
            for ((_, name), x) in inputs.iter().zip(x.iter_mut()) {
                if name.ends_with("q[2]") || name.ends_with("q[4]") {
                    *x = if name.starts_with('a') {
                        shift
                    } else {
                        -2.0 * shift
                    };
                }
            }
            for f in [&asked, &fresh] {
                assert_eq!(set(f, &vrs, &x), fmi2Status::OK);
                assert_eq!(f.step(t, 1e-3), fmi2Status::OK, "{v:?}: {:?}", f.log());
            }
            t += 1e-3;
            jacobian(&asked);
        }
        assert_eq!(jacobian(&asked), jacobian(&fresh), "{v:?}");
    }
}

#[test]
fn the_order_of_the_directions_at_a_point_does_not_change_a_derivative() {
    // At one point every direction shares the frames and the centred triad, or REVOLUTE's
    // rotations (remembered, src/instance/memo.rs): computed by a direction along a position
    // or a velocity, or the triad's libm values recorded by one along an orientation. Asked in table order (positions first)
    // and with the orientations first, on two instances at the same point: the same bits.
    for spec in VARIANTS {
        let v = spec.variant;
        let (table_order, turns_first) = (springs_and_dampers(v), springs_and_dampers(v));
        let inputs = node_inputs(v);
        let vrs: Vec<u32> = inputs.iter().map(|(vr, _)| *vr).collect();
        let mut x = values_for(&inputs, 0.02);
        for ((_, name), x) in inputs.iter().zip(x.iter_mut()) {
            if name.ends_with(".q.y") {
                *x = if name.starts_with('a') { 0.1 } else { -0.2 };
            }
        }
        let unknowns = continuous_outputs(v);
        let mut turns: Vec<(u32, &str)> = inputs.clone();
        turns.sort_by_key(|(_, name)| !name.contains(".q."));
        assert!(turns[0].1.contains(".q."), "{v:?}: an orientation input");
        for f in [&table_order, &turns_first] {
            assert_eq!(set(f, &vrs, &x), fmi2Status::OK);
            assert_eq!(f.step(0.0, 1e-3), fmi2Status::OK, "{v:?}: {:?}", f.log());
        }
        let column = |f: &Fmu, k: u32| {
            let (s, d) = derivative(f, &unknowns, k);
            assert_eq!(s, fmi2Status::OK, "{v:?}: {:?}", f.log());
            bits(&d)
        };
        let want: Vec<(u32, Vec<u64>)> = inputs
            .iter()
            .map(|&(k, _)| (k, column(&table_order, k)))
            .collect();
        let mut got: Vec<(u32, Vec<u64>)> = turns
            .iter()
            .map(|&(k, _)| (k, column(&turns_first, k)))
            .collect();
        got.sort_by_key(|(k, _)| vrs.iter().position(|vr| vr == k));
        assert_eq!(got, want, "{v:?}");
    }
}

#[test]
fn a_read_at_the_point_does_not_change_a_derivative() {
    // After a step the outputs there are cached, and a directional derivative computes the
    // centred triad for the directions at that point itself; after new inputs it reads the
    // outputs first (for the friction statuses), and the read's triad serves the directions
    // (src/instance/memo.rs, `PointMemo::read`). Two instances at the same point, the inputs of
    // one set again to the values they have (which empties its cache): the same bits, along
    // an orientation first and along a position first.
    for spec in VARIANTS {
        let v = spec.variant;
        let inputs = node_inputs(v);
        let vrs: Vec<u32> = inputs.iter().map(|(vr, _)| *vr).collect();
        let unknowns = continuous_outputs(v);
        let mut turns = inputs.clone();
        turns.sort_by_key(|(_, name)| !name.contains(".q."));
        for order in [inputs.clone(), turns] {
            let (read, cached) = (springs_and_dampers(v), springs_and_dampers(v));
            let mut x = values_for(&inputs, 0.01);
            for ((_, name), x) in inputs.iter().zip(x.iter_mut()) {
                if name.ends_with(".q.x") {
                    *x = if name.starts_with('a') { -0.1 } else { 0.3 };
                }
            }
            for f in [&read, &cached] {
                assert_eq!(set(f, &vrs, &x), fmi2Status::OK);
                assert_eq!(f.step(0.0, 1e-3), fmi2Status::OK, "{v:?}: {:?}", f.log());
            }
            let mut now = vec![0.0; vrs.len()];
            let s = fmi2GetReal(read.c, vrs.as_ptr(), vrs.len(), now.as_mut_ptr());
            assert_eq!(s, fmi2Status::OK, "{v:?}: {:?}", read.log());
            assert_eq!(set(&read, &vrs, &now), fmi2Status::OK);
            for &(k, name) in &order {
                let (s1, d1) = derivative(&read, &unknowns, k);
                let (s2, d2) = derivative(&cached, &unknowns, k);
                assert_eq!((s1, s2), (fmi2Status::OK, fmi2Status::OK), "{v:?} {name}");
                assert_eq!(bits(&d1), bits(&d2), "{v:?} {name}");
            }
        }
    }
}

#[test]
fn a_read_at_the_inputs_a_step_wrote_back_gives_the_steps_outputs() {
    // After a step the outputs are the step's; the inputs set again to the values they have
    // empty the cache, and the read evaluates them anew (for the centred types with the triad
    // it keeps for the directional derivatives, src/instance/memo.rs): the same bits, and again
    // on a second read (the kept triad).
    for spec in VARIANTS {
        let v = spec.variant;
        let f = springs_and_dampers(v);
        let inputs = node_inputs(v);
        let vrs: Vec<u32> = inputs.iter().map(|(vr, _)| *vr).collect();
        let outputs: Vec<u32> = table(v)
            .vars
            .iter()
            .filter(|x| x.causality == Causality::Output && matches!(x.start, Start::Real(_)))
            .map(|x| x.vr)
            .collect();
        let read = |f: &Fmu| {
            let mut y = vec![0.0; outputs.len()];
            let s = fmi2GetReal(f.c, outputs.as_ptr(), outputs.len(), y.as_mut_ptr());
            assert_eq!(s, fmi2Status::OK, "{v:?}: {:?}", f.log());
            bits(&y)
        };
        for n in 0..5 {
            let mut x = values_for(&inputs, 0.01 * n as f64);
            for ((_, name), x) in inputs.iter().zip(x.iter_mut()) {
                if name.ends_with(".q.z") || name.ends_with(".w[1]") {
                    *x = if name.starts_with('a') { 0.2 } else { -0.3 };
                }
            }
            assert_eq!(set(&f, &vrs, &x), fmi2Status::OK);
            assert_eq!(
                f.step(n as f64 * 1e-3, 1e-3),
                fmi2Status::OK,
                "{v:?}: {:?}",
                f.log()
            );
            let stepped = read(&f);
            let mut now = vec![0.0; vrs.len()];
            let s = fmi2GetReal(f.c, vrs.as_ptr(), vrs.len(), now.as_mut_ptr());
            assert_eq!(s, fmi2Status::OK);
            for _ in 0..2 {
                assert_eq!(set(&f, &vrs, &now), fmi2Status::OK);
                assert_eq!(read(&f), stepped, "{v:?}, step {n}");
            }
        }
    }
}
