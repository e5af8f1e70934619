//! Regression 006 (found by the `fmi_calls` fuzz target on the FMI 3.0 programs, with event
//! location; the cause is older): fmi3DoStep / fmi2DoStep accepted a step whose end
//! t + h overflows (t = 1e308, h = 1e308): the FMU's time became +INF, and with the new output
//! `event.time` (t + h when no event) +INF reached an output read with OK, breaking "NaN never
//! reaches an output". Fixed: such a step is refused with one error message naming the two
//! arguments; the instance keeps its time and state (fmi2Reset / fmi2SetFMUstate recover, as for
//! any refused step).

mod common;

use common::*;
use connector_fmu::fmi2::exports::fmi2GetRealStatus;
use connector_fmu::fmi2::types::*;
use connector_fmu::variables::VARIANTS;

#[test]
fn a_step_whose_end_overflows_is_refused_and_nothing_reads_infinite() {
    for spec in VARIANTS {
        let f = Fmu::new(spec.variant);
        f.init();
        let h = 1e-3;
        assert_eq!(f.step(0.0, h), fmi2Status::OK);
        // a huge step that still ends finite is taken (nothing in the connector moves)
        assert_eq!(f.step(h, 1e308), fmi2Status::OK, "{:?}", f.log());
        let t = h + 1e308;
        let n = f.log_len();
        let status = f.step(t, 1e308);
        assert_error_logged(&f, n, status, "fmi2DoStep");
        assert!(
            f.log()[n].message.contains("is not finite"),
            "{:?}",
            f.log()[n]
        );
        let mut last = f64::NAN;
        // fmi2LastSuccessfulTime = 2
        assert_eq!(fmi2GetRealStatus(f.c, 2, &mut last), fmi2Status::OK);
        assert_eq!(last, t, "the time is kept");
        let reals = f.outputs(false);
        for (vr, x) in reals.iter().zip(f.get_reals(&reals)) {
            assert!(x.is_finite(), "{:?}: vr {vr} reads {x}", spec.variant);
        }
    }
}
