//! BENCH_TANGENT: `tangent_cost` times a directional derivative, and a Jacobian's worth of
//! them, against one set + get (one kernel evaluation) on every variant with its behaviours on,
//! and prints the ratios. Uses `scenes`, `cases` (`params_on`), `instances`, `fmus` and `timing`
//! (`rounds`, `median`).

use crate::cases::params_on;
use crate::fmus::REAL;
use crate::instances::{ok, real_instance, Inst};
use crate::scenes::{continuous_outputs, name_of, PERIOD, PER_NODE, VARIANTS};
use crate::timing::{median, rounds};
use connector_fmu::fmi2::exports as fmi;
use connector_fmu::variables::{table, Field};
use std::time::Instant;

/// BENCH_TANGENT=1: what a directional derivative costs against one kernel evaluation, on
/// every variant with its behaviours on, a quarter period into its path. Interleaved batches,
/// each call sequence at a new point (the seed's input and an orientation input set to other
/// values first: everything moves, as from one communication point to the next):
/// (e) fmi2SetReal of one input + fmi2GetReal of one output: one kernel evaluation at the new
///     inputs, plus the two calls;
/// (d) (e) + fmi2GetDirectionalDerivative of every continuous output along one node input
///     (b.r[2], b.r[1] or b.q.x where that is what there is): the first derivative at a point,
///     one evaluation in `Dual`;
/// (j) (e) + the n derivatives of every continuous output along each input of node b in
///     turn (n = 13; 7 or 6 where node b has an orientation or positions only), as a
///     linear-implicit master asks for its Jacobian: each one evaluation in `Dual`.
/// (dl), (jl) as (d), (j) with the node loads as the unknowns, which is what a linear-implicit
///     master asks for (scripts/cosim/master.py): the same kernel evaluation, fewer values to
///     hand back.
/// Printed: ns per (e), (d), (j), the first derivative's cost ((d) − (e)) / (e), and the cost
/// per derivative of the Jacobian ((j) − (e)) / n / (e), then the same two for the loads
/// ((dl), (jl)); medians of 15 batches of 1000.
/// BENCH_ONLY=<variant> measures that variant alone.
pub fn tangent_cost(only: Option<&str>) {
    println!(
        "variant, ns per set+get (e), set+get+derivative (d), set+get+n derivatives (j), n, first derivative / evaluation, Jacobian per derivative / evaluation, the same two for the node loads alone"
    );
    for v in VARIANTS {
        if only.is_some_and(|o| o != name_of(v)) {
            continue;
        }
        let mut f = real_instance(v, &params_on(v));
        rounds(&REAL, &mut f, PERIOD / 4);
        let t = table(v);
        let cont = continuous_outputs(v);
        let loads: Vec<u32> = t
            .vars
            .iter()
            .filter(|x| matches!(x.field, Field::Load { .. }))
            .map(|x| x.vr)
            .collect();
        let vr_of = |n: &str| t.vars.iter().find(|x| x.name == n).map(|x| x.vr);
        let seed = ["b.r[2]", "b.r[1]", "b.q.x"]
            .iter()
            .find_map(|n| vr_of(n))
            .expect("a node input");
        let node_b: Vec<u32> = t
            .vars
            .iter()
            .filter(
                |x| matches!(x.field, Field::Input { node: 1, idx } if (idx as usize) < PER_NODE),
            )
            .map(|x| x.vr)
            .collect();
        // the point moves along the seed's input and an orientation (as in a co-simulation,
        // where everything moves from one point to the next: nothing the kernel computes
        // from the orientations carries over)
        let turn = ["b.q.x", "a.q.x"]
            .iter()
            .find_map(|n| vr_of(n))
            .expect("an orientation input");
        let moved: Vec<u32> = if turn == seed {
            vec![seed]
        } else {
            vec![seed, turn]
        };
        let mut x = vec![0.0; moved.len()];
        ok(
            f.env,
            fmi::fmi2GetReal(f.c, moved.as_ptr(), moved.len(), x.as_mut_ptr()),
            "moved inputs",
        );
        let mut u = x.clone();
        let mut dd = vec![0.0; cont.len()];
        let (mut e, mut d, mut j, mut dl, mut jl) = (vec![], vec![], vec![], vec![], vec![]);
        const N: usize = 1000;
        let mut y = 0.0;
        let mut batch = |derivatives: &[u32], unknowns: &[u32], f: &mut Inst| {
            let t0 = Instant::now();
            for i in 0..N {
                // alternate between two points, so that every call sequence is at a new one
                for (u, x) in u.iter_mut().zip(&x) {
                    *u = x + if i % 2 == 0 { 1e-9 } else { 0.0 };
                }
                ok(
                    f.env,
                    fmi::fmi2SetReal(f.c, moved.as_ptr(), moved.len(), u.as_ptr()),
                    "set",
                );
                ok(f.env, fmi::fmi2GetReal(f.c, &cont[0], 1, &mut y), "get");
                for k in derivatives {
                    let s = fmi::fmi2GetDirectionalDerivative(
                        f.c,
                        unknowns.as_ptr(),
                        unknowns.len(),
                        k,
                        1,
                        &1.0,
                        dd.as_mut_ptr(),
                    );
                    ok(f.env, s, "directional derivative");
                }
            }
            std::hint::black_box((&dd, y));
            t0.elapsed().as_nanos() as f64 / N as f64
        };
        for _ in 0..15 {
            e.push(batch(&[], &cont, &mut f));
            d.push(batch(&[seed], &cont, &mut f));
            j.push(batch(&node_b, &cont, &mut f));
            dl.push(batch(&[seed], &loads, &mut f));
            jl.push(batch(&node_b, &loads, &mut f));
        }
        let (me, md, mj) = (median(&mut e), median(&mut d), median(&mut j));
        let (mdl, mjl) = (median(&mut dl), median(&mut jl));
        let n = node_b.len() as f64;
        println!(
            "{}, {me:.0}, {md:.0}, {mj:.0}, {}, {:.2}, {:.2}, {:.2}, {:.2}",
            name_of(v),
            node_b.len(),
            (md - me) / me,
            (mj - me) / n / me,
            (mdl - me) / me,
            (mjl - me) / n / me
        );
    }
}
