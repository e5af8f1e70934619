"""fmi2GetRealStatus / fmi2GetBooleanStatus and fmi2Reset through fmpy's FMU2Slave: the last
successful time after each step, and a reset instance back at its start values runs as a fresh
one, bit for bit.

Uses conftest's `conn` fixture and model_description, and _cosim_helpers (scenario, H_ROLL)."""

from __future__ import annotations

import pytest

import _ref
from _cosim_helpers import H_ROLL, fmi2LastSuccessfulTime, scenario
from conftest import VARIANTS, model_description

fmi2Terminated = 3  # fmi2StatusKind


@pytest.mark.parametrize("variant", VARIANTS)
def test_status_and_reset(conn, variant):
    params, inputs_at = scenario(variant)
    # the Integer and Boolean parameters away from their start values too, so that the reset
    # has something to restore in every type: hold extrapolation (start 1), the coupled
    # friction surface (Planar; start 0), a given reference on the first component (start false)
    _, k = _ref.components_of(variant)[0]
    discrete = {"cosim.extrapolation": 0, f"reference.given{k}": True}
    if variant == "Planar":
        discrete["friction.coupling"] = 1
    c = conn(variant).start({**params, **discrete}, inputs_at(0.0), t0=0.25)
    for name, val in discrete.items():
        assert c.value(name) == val, name
    # before any step: the start time
    assert c.s.getRealStatus(fmi2LastSuccessfulTime) == 0.25
    assert c.s.getBooleanStatus(fmi2Terminated) is False
    hs = [0.01, 0.003, 0.02, 0.007] * 10
    for h in hs:
        c.set(inputs_at(c.t))
        t_before = c.t
        c.step(h)
        # the FMU's time is the communication point plus the step, the same float operation
        assert c.s.getRealStatus(fmi2LastSuccessfulTime) == t_before + h
        assert c.s.getBooleanStatus(fmi2Terminated) is False

    # reset: back to start values (parameters read back), then a new experiment from t = 0 gives
    # the same records as a fresh instance, bit for bit
    c.s.reset()
    # (fmi2Get* is not allowed in state Instantiated: read back in Initialization Mode)
    c.s.setupExperiment(startTime=0.0)
    c.s.enterInitializationMode()
    starts = {sv.name: sv.start for sv in model_description(variant).modelVariables}
    for name in params:
        r = c.v[name]
        got = c.s.getReal([r])[0] if r.type == "Real" else c.s.getInteger([r])[0]
        assert float(got) == float(starts[name]), (name, got, starts[name])
    # the Integer and Boolean parameters changed before the run back at their start values
    # (start attributes are strings in fmpy: "1", "0", "false"), and the inputs too
    start_of = {"Integer": int, "Boolean": lambda s: s == "true"}
    for name in discrete:
        want = start_of[c.v[name].type](starts[name])
        assert c.value(name) == want, (name, c.value(name), want)
    assert c.value("cosim.extrapolation") == 1 and not c.value(f"reference.given{k}")
    if variant == "Planar":
        assert c.value("friction.coupling") == 0
    for r in c.real_in:
        assert c.s.getReal([r])[0] == float(starts[r.name]), r.name

    c.set(params)
    c.set(inputs_at(0.0))
    c.s.exitInitializationMode()
    c.t = 0.0
    again = c.drive(inputs_at, 60, H_ROLL)
    fresh = conn(variant).start(params, inputs_at(0.0))
    ref_run = fresh.drive(inputs_at, 60, H_ROLL)
    assert again == ref_run
