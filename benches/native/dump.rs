//! BENCH_DUMP: `dump_bits` writes the bits of every output along every case's path, and
//! directional derivatives along it, as hex lines (nothing timed), so that two builds can be
//! compared bit for bit with `cmp`. Uses `scenes`, `cases` (`params_on`), `instances`, `fmus`
//! and `timing::rounds`.

use crate::cases::params_on;
use crate::fmus::REAL;
use crate::instances::{ok, real_instance_with};
use crate::scenes::{continuous_outputs, name_of, PERIOD, VARIANTS};
use crate::timing::rounds;
use connector_fmu::fmi2::exports as fmi;
use connector_fmu::variables::{table, Causality};
use std::fmt::Write as _;

/// BENCH_DUMP=<file>: the bits of every output after every round of every case (both
/// behaviour sets, linear and second-order extrapolation, two periods), and every 97th round
/// the directional derivatives of all Real outputs along each node input, written as hex lines
/// to <file> (nothing timed). Two builds that write the same file compute the same numbers bit
/// for bit on these paths (docs/benchmarks.md: how the per-step restructuring was checked).
pub fn dump_bits(path: &str) {
    let mut text = String::new();
    for v in VARIANTS {
        let t = table(v);
        let real_out: Vec<u32> = t
            .vars
            .iter()
            .filter(|x| x.causality == Causality::Output)
            .filter(|x| !matches!(x.start, connector_fmu::variables::Start::Integer(_)))
            .map(|x| x.vr)
            .collect();
        let cont_out = continuous_outputs(v);
        let int_out: Vec<u32> = t
            .vars
            .iter()
            .filter(|x| x.causality == Causality::Output)
            .filter(|x| matches!(x.start, connector_fmu::variables::Start::Integer(_)))
            .map(|x| x.vr)
            .collect();
        for on in [false, true] {
            for extrapolation in [1.0, 2.0] {
                let mut params = if on { params_on(v) } else { vec![] };
                if extrapolation != 1.0 {
                    // an Integer parameter: set below through fmi2SetInteger
                    params.push(("cosim.extrapolation".into(), extrapolation));
                }
                let (ints, reals): (Vec<_>, Vec<_>) = params
                    .into_iter()
                    .partition(|(n, _)| n == "cosim.extrapolation");
                let mut f = real_instance_with(v, &reals, &ints);
                let _ = writeln!(text, "{} on={on} extrapolation={extrapolation}", name_of(v));
                let mut r = vec![0.0; real_out.len()];
                let mut i = vec![0; int_out.len()];
                let mut dd = vec![0.0; cont_out.len()];
                for step in 0..2 * PERIOD {
                    rounds(&REAL, &mut f, 1);
                    ok(
                        f.env,
                        fmi::fmi2GetReal(f.c, real_out.as_ptr(), r.len(), r.as_mut_ptr()),
                        "outputs",
                    );
                    ok(
                        f.env,
                        fmi::fmi2GetInteger(f.c, int_out.as_ptr(), i.len(), i.as_mut_ptr()),
                        "integer outputs",
                    );
                    let _ = write!(text, "{step}:");
                    for x in &r {
                        let _ = write!(text, " {:016x}", x.to_bits());
                    }
                    for x in &i {
                        let _ = write!(text, " {x}");
                    }
                    text.push('\n');
                    if step % 97 == 0 {
                        for &known in &f.vin {
                            ok(
                                f.env,
                                fmi::fmi2GetDirectionalDerivative(
                                    f.c,
                                    cont_out.as_ptr(),
                                    cont_out.len(),
                                    &known,
                                    1,
                                    &1.0,
                                    dd.as_mut_ptr(),
                                ),
                                "directional derivative",
                            );
                            let _ = write!(text, "  d/d{known}:");
                            for x in &dd {
                                let _ = write!(text, " {:016x}", x.to_bits());
                            }
                            text.push('\n');
                        }
                    }
                }
            }
        }
    }
    std::fs::write(path, text).expect("write BENCH_DUMP file");
    println!("wrote {path}");
}
