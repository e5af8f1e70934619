"""Variable communication step size through fmpy's FMU2Slave: linear extrapolation at constant
rates and hold extrapolation give, after any step sequence, the outputs of equal steps (to
round-off).

Uses conftest's `conn` fixture and _cosim_helpers (Smooth, spring_damper_params)."""

from __future__ import annotations

import numpy as np
import pytest

import _ref
from _cosim_helpers import Smooth, fmi2LastSuccessfulTime, spring_damper_params


def _random_steps(rng, total, lo, hi):
    hs, t = [], 0.0
    while total - t > hi:
        hs.append(rng.uniform(lo, hi))
        t += hs[-1]
    hs.append(total - t)
    return hs


# not functions of the inputs and the committed state: energies dissipated over the steps taken,
# and the time of the last step's first event (t + h when none: it differs with the step sizes)
ALGEBRAIC_EXCLUDE = ("energy.damping", "energy.stops", "energy.friction", "event.time")


@pytest.mark.parametrize("variant", ["ProjectionCartesian", "ProjectionFlexionTorsion", "Bushing", "RadialThrust"])
def test_variable_step_linear_constant_rates(conn, variant):
    """Linear extrapolation, constant velocities and angular velocities set once at t = 0 (the
    master sets no further inputs): the nodes follow r + v t, exp(w t) q exactly, so after any
    step sequence summing to T the inputs read back and all algebraic outputs agree with the
    equal-step run to round-off: ~100 steps x a few eps per step, amplified by the stiffness:
    tolerance 1e-11 relative to each quantity's scale. (The dissipated energies are path
    integrals by quadrature over each step and are excluded.)"""
    m = Smooth(variant)
    T = 1.0
    pose = m.pose(0.0)
    pose["b.v"] = np.array([0.05, -0.03, 0.04])
    pose["b.w"] = np.array([0.2, -0.1, 0.15])
    pose["a.v"] = np.array([-0.01, 0.02, 0.0])
    pose["a.w"] = np.array([0.05, 0.0, -0.05])
    inputs = _ref.pose_to_inputs(variant, pose)
    params = spring_damper_params(variant)

    def run(hs):
        c = conn(variant).start(params, inputs)
        for h in hs:
            c.step(h)
        assert abs(c.s.getRealStatus(fmi2LastSuccessfulTime) - T) <= 1e-14
        keep = [r for r in c.real_out if r.name not in ALGEBRAIC_EXCLUDE] + c.real_in
        return [r.name for r in keep], np.array(c.s.getReal(keep))

    names, equal = run([T / 100] * 100)
    hs = _random_steps(np.random.default_rng(3), T, 0.001, 0.02)
    _, varied = run(hs)
    assert len(hs) > 50 and max(hs) / min(hs[:-1]) > 5
    # inputs read back (m, 1, m/s, rad/s; O(1)): 1e-12 absolute; outputs: 1e-11 of the largest
    # output (the loads are ~1e3 x the pose error)
    n_out = len(names) - sum(1 for n in names if n in _ref.input_names(variant))
    out_scale = float(np.max(np.abs(equal[:n_out])))
    tol = [1e-11 * out_scale if i < n_out else 1e-12 for i in range(len(names))]
    bad = {n: (a, b) for n, a, b, tl in zip(names, equal, varied, tol) if abs(a - b) > tl}
    assert not bad, bad


def test_variable_step_hold_same_result(conn):
    """Hold extrapolation, the master sets the closed-form inputs at every communication point:
    a random step sequence over [0, T - H] followed by one step H ends with the same outputs as
    equal steps H (after the last step the outputs reflect the inputs at T - H and the committed
    state; the communication points differ only by round-off of the summed step sizes, ~1e-16 s,
    so tolerance 1e-12 relative). Dissipated energies (quadrature over the steps) excluded."""
    m = Smooth("Bushing")
    T, H = 1.0, 0.01
    params = dict(spring_damper_params("Bushing"), **{"cosim.extrapolation": 0})

    def run(hs):
        c = conn("Bushing").start(params, m.inputs(0.0))
        for h in hs:
            c.set(m.inputs(c.t))
            c.step(h)
        keep = [r for r in c.real_out if r.name not in ALGEBRAIC_EXCLUDE] + c.real_in
        return c, np.array(c.s.getReal(keep)), [r.name for r in keep]

    c1, equal, names = run([H] * 100)
    hs = _random_steps(np.random.default_rng(5), T - H, 0.002, 0.03) + [H]
    c2, varied, _ = run(hs)
    assert abs(c2.s.getRealStatus(fmi2LastSuccessfulTime) - T) <= 1e-13
    scale = float(np.max(np.abs(equal)))
    bad = {n: (a, b) for n, a, b in zip(names, equal, varied) if abs(a - b) > 1e-12 * scale}
    assert not bad, bad
    # and the outputs after the last step are those at the inputs at T - H (hold)
    c3 = conn("Bushing").start(params, m.inputs(0.0))
    c3.set(m.inputs(c1.t - H))
    keep = [r for r in c3.real_out if r.name not in ALGEBRAIC_EXCLUDE]
    at_prev = np.array(c3.s.getReal(keep))
    got = np.array(c1.s.getReal(keep))
    assert np.max(np.abs(at_prev - got)) <= 1e-12 * scale
