"""Event-located coupling in the co-simulation master (scripts/cosim/event_methods.py): the FMU is
driven along the body's own path (acceleration inputs, cosim.extrapolation = 3) and stops at the
first event (FMI 3.0 early return, or FMI 2.0 rollback to `event.time`); a step that meets an
event is taken again to just past it; after every event a restart schedule resolves the fast
transients. Methods: linear_path_ev, implicit_path_ev, linear_exact_ev.

Checked against answers the project did not invent, the truth being the FMU's own model in
continuous time:
- puck, friction.coupling = 0 (SCENES §4): the elastic closed forms t_v = t_b + v0 cos(ω t_b)/(μg),
  t_ω likewise: every method within 1e-8 relative at H = 10, 2 and 1 ms (measured ≤ 1.2e-10: the
  stick phase is a linear oscillator the methods integrate exactly in eigenvalue or in full, the
  slide a constant load, the stops events located to 1e-10 of the step);
- bounce on a clipped stop (SCENES §5): linear_exact_ev is exact for the linear stop between
  located events (measured ≤ 2e-12 at H = 1 ms, 2e-4 at 10 ms where the release falls in the
  restart), the path methods second order (8.7e-5 at 1 ms, 1.7e-5 at 0.5 ms);
- belt (SCENES §1) against its monolithic reference (scripts/cosim/reference.py): a cycle at every
  H to 10 ms, implicit_path_ev ≤ 5e-6 at 1 ms (measured 1.9e-6) and falling as H² (ratio ≥ 20
  from 1 ms to 0.2 ms, measured 38);
- FMI 3.0 and FMI 2.0 routes: the same run bit for bit (the FMU takes a located event's time on
  the importer's clock), FMI 3.0 with fewer FMI calls (no state saving for the event's rollback);
- §7 oscillator: the one-step maps measured through the FMU: linear_exact_ev the exact
  solution's spectral radius exp(−ζωH), the path methods the prewarped trapezoid's (the same where
  |Im hλ| ≤ 2.5) as `amplification` computes it.
"""
from __future__ import annotations

import math
import sys

import pytest

from conftest import REPO

sys.path.insert(0, str(REPO / "scripts"))
from cosim.event_methods import EV_METHODS  # noqa: E402
from cosim.master import simulate  # noqa: E402
from cosim.scenes import Belt, Bounce, OneStepMap, Puck, amplification, spectral_radius  # noqa: E402

METHODS = list(EV_METHODS)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("H", [1e-2, 2e-3, 1e-3])
def test_puck_stop_times_against_the_elastic_closed_forms(method, H):
    """The puck starts sticking on its stick springs (the preload acts from initialization),
    breaks away after t_b (2.9 µs sliding, 3.9 µs spin: located events) and slides and spins
    down at constant friction to the stops (located): the elastic closed forms to 1e-8. The
    rigid forms lie 4.3e-6 and 1.5e-5 away (the stick springs' ramp)."""
    scene = Puck(coupling=0)
    res = simulate(scene, method, H, fail_ok=False)
    fig, ref = scene.measure(res), scene.reference()
    assert res.events >= 4, "both breakaways and both stops were located inside a step"
    assert fig["error"] < 1e-8, fig
    assert 4e-6 < fig["err_rigid_t_v"] < 5e-6 and 1.4e-5 < fig["err_rigid_t_w"] < 1.6e-5, fig
    # neither stop falls on the grid: the located stops are off the multiples of H
    for t in (ref["t_v_elastic"], ref["t_w_elastic"]):
        assert 1e-3 < (t / H) % 1.0 < 1 - 1e-3


@pytest.mark.parametrize("method,tol_1ms", [("linear_exact_ev", 1e-9), ("linear_path_ev", 1.2e-4),
                                            ("implicit_path_ev", 1.2e-4)])
def test_bounce_against_the_clipped_stop(method, tol_1ms):
    """Contact (penetration through 0) and release (the damped stop's force through 0) are
    located; between them the stop is a linear spring-damper, which linear_exact_ev integrates
    exactly and the path methods at second order (the error falls ≥ 4× from 1 to 0.5 ms)."""
    scene = Bounce()
    errs = {}
    for H in (1e-3, 5e-4):
        res = simulate(scene, method, H, fail_ok=False)
        assert res.events >= 2       # contact and release located
        errs[H] = scene.measure(res)["error"]
    assert errs[1e-3] < tol_1ms, errs
    if method != "linear_exact_ev":
        assert errs[5e-4] < errs[1e-3] / 4, errs


def test_belt_against_the_monolithic_reference():
    """A cycle at every H from 10 ms down; the best method ≤ 5e-6 at 1 ms and ≤ 1e-2 at 10 ms,
    second order (≥ 20× from 1 to 0.2 ms)."""
    scene = Belt()
    errs = {}
    for H in (1e-2, 1e-3, 2e-4):
        res = simulate(scene, "implicit_path_ev", H, fail_ok=False)
        # every event met: breakaways at 0.2453 s + k·0.66936 s (k = 0…4, the reference's first
        # breakaway and period) and a re-stick about 0.475 s after each (the last at 3.397 s < 3.5 s)
        assert res.events == 10, (H, res.events)
        fig = scene.measure(res)
        assert fig["cycles"] >= 3, (H, fig)
        errs[H] = fig["error"]
        # the model's own cycle lies 2.6e-5 (x_max) from the rigid closed form
        assert fig["error_rigid"] > 1e-5, fig
    assert errs[1e-2] <= 1e-2 and errs[1e-3] <= 5e-6, errs
    assert errs[2e-4] <= errs[1e-3] / 20, errs


@pytest.mark.parametrize("scene,method", [(Puck(coupling=0), "implicit_path_ev"),
                                          (Bounce(), "linear_exact_ev"),
                                          (Bounce(), "linear_path_ev"),
                                          (Belt(), "linear_exact_ev"),
                                          (Belt(), "implicit_path_ev")],
                         ids=["puck0-implicit_path_ev", "bounce-linear_exact_ev",
                              "bounce-linear_path_ev", "belt-linear_exact_ev",
                              "belt-implicit_path_ev"])
def test_fmi3_early_return_equals_fmi2_rollback(scene, method):
    """The same run bit for bit: both routes locate each event at the same time on the master's
    clock and walk the same path to it."""
    r2 = simulate(scene, method, 1e-3, fail_ok=False)
    r3 = simulate(scene, method + "@fmi3", 1e-3, fail_ok=False)
    assert r2.events == r3.events > 0
    assert len(r2.t) == len(r3.t)
    assert (r2.t == r3.t).all() and (r2.p == r3.p).all() and (r2.u == r3.u).all()
    assert r3.calls < r2.calls     # no fmi2GetFMUstate per step for the event's rollback


# The one-step maps below agree with their closed forms to round-off. Measured (this machine):
# linear_exact_ev ≤ 1.9e-14 relative where ρ ~ 0.1–1, and 1.8e-10 relative at ωH = 20, ζ = 0.5,
# where ρ = exp(−10) = 4.5e-5 is small beside the map's O(1) entries: the absolute error is the
# entries' round-off there too (≤ 8.2e-15); the path methods ≤ 3.4e-16 relative. Hence
# REL_RHO = 1e-12 (50× the worst relative error where ρ ~ 1) and ABS_RHO = 1e-13 (12× the
# worst absolute error; it admits 2.2e-9 relative at ρ = 4.5e-5, not a 2 % error).
REL_RHO, ABS_RHO = 1e-12, 1e-13


@pytest.mark.parametrize("zeta", [0.1, 0.5])
def test_exact_one_step_map(zeta):
    probe = OneStepMap("linear_exact_ev", zeta)
    try:
        for h in (0.1, 2.0, 20.0):
            assert probe.rho(h) == pytest.approx(math.exp(-zeta * h), rel=REL_RHO, abs=ABS_RHO)
    finally:
        probe.close()


@pytest.mark.parametrize("method", ["linear_path_ev", "implicit_path_ev"])
@pytest.mark.parametrize("zeta", [0.0, 0.5])
def test_path_one_step_map_is_the_prewarped_trapezoid(method, zeta):
    """Measured through the FMU against the closed form; where prewarping applies
    (h √(1 − ζ²) ≤ 2.5) the spectral radius is the exact solution's, exp(−ζh)."""
    probe = OneStepMap(method, zeta)
    try:
        for h in (0.1, 2.0, 20.0):
            closed = spectral_radius(amplification(method, h, zeta))
            assert probe.rho(h) == pytest.approx(closed, rel=REL_RHO, abs=ABS_RHO)
            if h * math.sqrt(1 - zeta * zeta) <= 2.5:
                assert closed == pytest.approx(math.exp(-zeta * h), rel=1e-12)
    finally:
        probe.close()
