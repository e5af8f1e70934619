"""The acceleration inputs (cosim.extrapolation = 3) through fmpy's FMU2Slave: a closed form of
one step, the same path as the velocities' input derivatives, ignored below 3, no output depends
on them, and a pose of third order.

Uses conftest's `conn` fixture and model_description, and _cosim_helpers (scenario, Smooth,
spring_damper_params, output names, the sweep T_END, H_SWEEP, rel_error, fit_slope)."""

from __future__ import annotations

import numpy as np
import pytest

import _ref
from _cosim_helpers import (H_SWEEP, T_END, Smooth, elastic_of, fit_slope, loads_of, rel_error,
                            scenario, spring_damper_params, totals_of)
from conftest import VARIANTS, model_description


# With cosim.extrapolation = 3 a node moves over a step along the acceleration inputs a.dv, a.dw,
# b.dv, b.dw (the path an importer's own bodies follow, in FMI 3.0 too, which has no input
# derivatives). Checked against a closed form, against the second mechanism (extrapolation 2 with
# the FMI 2.0 input derivatives of the velocities: the same path, so the same bits), and for
# what they must not touch (extrapolation below 3, the outputs' dependencies).


def _acc_inputs(c):
    return [r for r in c.real_in if r.name[1:4] in (".dv", ".dw")]


def _velocity_of(acc_name):
    """b.dv[1] -> b.v[1], a.dw[3] -> a.w[3]."""
    return acc_name.replace(".dv[", ".v[").replace(".dw[", ".w[")


def _accelerations_at(c, inputs_at, t, dt=1e-6):
    """{acceleration input: value}: the central difference of the velocity inputs of the path
    (any values serve where two runs are compared; the closed-form test sets its own)."""
    lo, hi = inputs_at(t - dt), inputs_at(t + dt)
    return {r.name: (hi[_velocity_of(r.name)] - lo[_velocity_of(r.name)]) / (2 * dt)
            for r in _acc_inputs(c)}


def test_acceleration_inputs_move_the_node_along_the_second_order_path(conn):
    """One step h of a Bushing with both nodes accelerating (extrapolation 3): the inputs read
    back after the step are the moved nodes, r + v h + ½ v̇ h², v + v̇ h, ω + ω̇ h and
    q ← exp(ω h + ½ ω̇ h²) ⊗ q (the FMU's documented path, docs/physics.md), to 1e-14 (a few
    roundings of O(1) values); the acceleration inputs keep their values."""
    m = Smooth("Bushing")
    params = dict(spring_damper_params("Bushing"), **{"cosim.extrapolation": 3})
    x0 = m.inputs(0.0)
    c = conn("Bushing").start(params, x0)
    acc = {"a.dv": np.array([0.5, -0.2, 0.1]), "a.dw": np.array([-0.3, 0.4, 0.2]),
           "b.dv": np.array([-1.5, 2.0, 0.7]), "b.dw": np.array([3.0, -1.0, 2.5])}
    c.set({f"{k}[{j + 1}]": float(v[j]) for k, v in acc.items() for j in range(3)})
    h = 0.02
    c.step(h)
    for n in ("a", "b"):
        r0 = np.array([x0[f"{n}.r[{j}]"] for j in (1, 2, 3)])
        v0 = np.array([x0[f"{n}.v[{j}]"] for j in (1, 2, 3)])
        w0 = np.array([x0[f"{n}.w[{j}]"] for j in (1, 2, 3)])
        q0 = np.array([x0[f"{n}.q.{k}"] for k in "wxyz"])
        dv, dw = acc[f"{n}.dv"], acc[f"{n}.dw"]
        q1 = _ref.quat_mul(_ref.quat_exp(w0 * h + 0.5 * dw * h * h), q0 / np.linalg.norm(q0))
        assert np.allclose(c.vec(f"{n}.r"), r0 + v0 * h + 0.5 * dv * h * h, rtol=0, atol=1e-14)
        assert np.allclose(c.vec(f"{n}.v"), v0 + dv * h, rtol=0, atol=1e-14)
        assert np.allclose(c.vec(f"{n}.w"), w0 + dw * h, rtol=0, atol=1e-14)
        assert np.allclose(c.get([f"{n}.q.{k}" for k in "wxyz"]), q1, rtol=0, atol=1e-14)
        assert np.array_equal(c.vec(f"{n}.dv"), dv) and np.array_equal(c.vec(f"{n}.dw"), dw)


@pytest.mark.parametrize("variant", ["Bushing", "Planar"])
def test_acceleration_inputs_equal_velocity_input_derivatives(conn, variant):
    """Extrapolation 3 with the acceleration inputs, and extrapolation 2 with the FMI 2.0 input
    derivatives of the velocities set to the same values, walk the same path: over a driven run
    with a stop (and, on Planar, friction sticking and slipping, so events inside steps) every
    output and every pose and twist read back is the same double at every step."""
    params, inputs_at = scenario(variant)
    by_input = conn(variant).start(dict(params, **{"cosim.extrapolation": 3}), inputs_at(0.0))
    by_der = conn(variant).start(dict(params, **{"cosim.extrapolation": 2}), inputs_at(0.0))
    pose = [r for r in by_input.real_in if r not in _acc_inputs(by_input)]
    events = 0
    for k in range(300):
        t = k * 5e-3
        acc = _accelerations_at(by_input, inputs_at, t)
        for c in (by_input, by_der):
            c.set(inputs_at(t))
        by_input.set(acc)
        by_der.s.setRealInputDerivatives([by_der.v[_velocity_of(n)] for n in acc], [1] * len(acc),
                                         list(acc.values()))
        for c in (by_input, by_der):
            c.step(5e-3)
        one, two = by_input.record(), by_der.record()
        assert one[:2] == two[:2], (variant, k)
        assert by_input.s.getReal(pose) == by_der.s.getReal(pose), (variant, k)
        events += by_input.geti(["event.count"])[0]
    assert events > 0, "the run crosses events inside steps"


@pytest.mark.parametrize("extrapolation", [0, 1, 2])
def test_acceleration_inputs_ignored_below_extrapolation_3(conn, extrapolation):
    """Below 3 the acceleration inputs move nothing: a Planar run (friction, stop) with them set
    to the path's accelerations at every step equals one without, bit for bit."""
    params, inputs_at = scenario("Planar")
    params["cosim.extrapolation"] = extrapolation
    with_acc, plain = (conn("Planar").start(params, inputs_at(0.0)) for _ in range(2))
    for k in range(200):
        t = k * 5e-3
        for c in (with_acc, plain):
            c.set(inputs_at(t))
        with_acc.set(_accelerations_at(with_acc, inputs_at, t))
        for c in (with_acc, plain):
            c.step(5e-3)
        assert with_acc.record()[:2] == plain.record()[:2], (extrapolation, k)


@pytest.mark.parametrize("variant", VARIANTS)
def test_no_output_depends_on_the_acceleration_inputs(conn, variant):
    """The model structure lists no acceleration input among any output's dependencies (initial
    unknowns included), and the directional derivative of every continuous output along each
    is exactly 0.0 while the pose inputs' are not."""
    md = model_description(variant)
    acc_names = {v.name for v in md.modelVariables if v.name[1:4] in (".dv", ".dw")}
    assert acc_names
    for unknown in list(md.outputs) + list(md.initialUnknowns):
        deps = {d.name for d in (unknown.dependencies or [])}
        assert not deps & acc_names, unknown.variable.name
    params, inputs_at = scenario(variant)
    c = conn(variant).start(params, inputs_at(0.0))
    c.drive(inputs_at, 20, 5e-3, record=False)
    c.set(inputs_at(c.t))
    variability = {v.name: v.variability for v in md.modelVariables}
    unknowns = [r for r in c.real_out if variability[r.name] == "continuous"]
    for r in _acc_inputs(c):
        assert c.s.getDirectionalDerivative(unknowns, [r], [1.0]) == [0.0] * len(unknowns), r.name
    pose = [r for r in c.real_in if r not in _acc_inputs(c)]
    assert any(any(c.s.getDirectionalDerivative(unknowns, [r], [1.0])) for r in pose)


def test_acceleration_inputs_make_the_pose_third_order(conn, capsys):
    """Bushing on the Smooth path with its exact accelerations (extrapolation 3), the master
    setting the exact inputs at every communication point: the error of the pose-algebraic
    outputs (CP/CPR, CEF/CEM) after the last step is the local error of one step, O(H³) (the
    path r + vH + ½v̇H² and exp(ωH + ½ω̇H²) q both err by O(H³)); linear extrapolation's is
    O(H²) (test_fmpy_extrapolation.py). Slopes over H = 0.04 ... 0.005: ≥ 2.8, and ≥ 1.8 for the damped loads
    (the velocities v + v̇H err by O(H²))."""
    m = Smooth("Bushing")
    names = {"elastic": elastic_of("Bushing"), "loads": loads_of("Bushing") + totals_of("Bushing")}
    errs = {k: [] for k in names}
    for H in H_SWEEP:
        params = dict(spring_damper_params("Bushing"), **{"cosim.extrapolation": 3})
        c = conn("Bushing").start(params, m.inputs(0.0))
        for i in range(int(round(T_END / H))):
            t = i * H
            c.set(m.inputs(t))
            c.set({f"b.dv[{j + 1}]": float(m.a(t)[j]) for j in range(3)})
            c.set({f"b.dw[{j + 1}]": float(m.wdot(t)[j]) for j in range(3)})
            c.step(H)
        every = names["elastic"] + names["loads"]
        got = dict(zip(every, c.get(every)))
        c.set(m.inputs(T_END))
        exact = dict(zip(every, c.get(every)))
        for k, ns in names.items():
            errs[k].append(rel_error(got, exact, ns))
    slopes = {k: fit_slope(H_SWEEP, e) for k, e in errs.items()}
    with capsys.disabled():
        print("\n[acceleration inputs] slopes", {k: round(s, 2) for k, s in slopes.items()},
              {k: [f"{x:.1e}" for x in e] for k, e in errs.items()})
    assert slopes["elastic"] >= 2.8, (slopes, errs)
    assert slopes["loads"] >= 1.8, (slopes, errs)
