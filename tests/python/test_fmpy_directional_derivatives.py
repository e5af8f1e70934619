"""fmi2GetDirectionalDerivative through fmpy's FMU2Slave against central finite differences
through the ABI: every variant at random poses, and Planar in stick, in slip and at an active
stop (also with the coupled friction limit and with stick dampers), with the tangent stiffness
checked against the physics.

Uses conftest's `conn` fixture and _cosim_helpers (output names, spring_damper_params and the
poses QA0, RA0, RA_POS)."""

from __future__ import annotations

import numpy as np
import pytest

import _ref
from _cosim_helpers import QA0, RA0, RA_POS, loads_of, spring_damper_params, totals_of
from conftest import VARIANTS

EPS = np.finfo(float).eps

# Step: h_j = 1e-6 max(1, |u_j|) per input (the actual difference (u+h)-u is used).
# Truncation error of the central difference ~ h^2 |y'''| / 6: with the outputs varying on
# length scales >= 1e-3 (m or rad) from any kink (stick/slip limit, stop contact, |f1| = 0,
# |m_bend| = 0 are all kept >= 1e-3 away) this is <= 1e-6 relative to the column.
# Round-off of a central difference ~ eps |y| / h per output; the floor below allows 100x the
# largest output magnitude's round-off (1e2 eps Y / h ~ 2e-8 Y).
# Tolerance per column j:  |J_dd - J_fd| <= 1e-5 |J_fd[:, j]| + 1e2 eps Y / h_j.

FD_REL = 1e-5
FD_ROUNDOFF = 1e2


def _unknowns(variant):
    return loads_of(variant) + totals_of(variant)


def _jacobians(c, knowns, unknowns):
    """(J_dd, J_fd, Y, h) over the given known inputs (columns) and unknown outputs (rows)."""
    s = c.s
    uvr = [c.v[n] for n in unknowns]
    kvr = [c.v[n] for n in knowns]
    u0 = s.getReal(kvr)
    y0 = np.array(s.getReal(uvr))
    rec0 = c.record()
    J_dd = np.zeros((len(unknowns), len(knowns)))
    J_fd = np.zeros_like(J_dd)
    Y = float(np.max(np.abs(y0)))
    hs = []
    for j, (r, u) in enumerate(zip(kvr, u0)):
        J_dd[:, j] = s.getDirectionalDerivative(uvr, [r], [1.0])
        h = 1e-6 * max(1.0, abs(u))
        up, um = u + h, u - h
        s.setReal([r], [up])
        yp = np.array(s.getReal(uvr))
        s.setReal([r], [um])
        ym = np.array(s.getReal(uvr))
        s.setReal([r], [u])
        J_fd[:, j] = (yp - ym) / (up - um)
        Y = max(Y, float(np.max(np.abs(yp))), float(np.max(np.abs(ym))))
        hs.append(h)
    # probes without a step leave the committed state and the outputs exactly as they were
    assert c.record() == rec0
    return J_dd, J_fd, Y, np.array(hs)


def _assert_jacobians(c, knowns, unknowns, label):
    J_dd, J_fd, Y, hs = _jacobians(c, knowns, unknowns)
    worst = 0.0
    for j, name in enumerate(knowns):
        col = float(np.linalg.norm(J_fd[:, j]))
        tol = FD_REL * col + FD_ROUNDOFF * EPS * Y / hs[j]
        err = float(np.max(np.abs(J_dd[:, j] - J_fd[:, j])))
        worst = max(worst, err / tol)
        assert err <= tol, (label, name, err, tol, dict(zip(unknowns, J_dd[:, j])), dict(zip(unknowns, J_fd[:, j])))
    # J is not trivially zero (the connector is loaded and has stiffness)
    assert np.linalg.norm(J_fd) > 0.0
    # a combined random seed: J seed (linearity of the directional derivative)
    rng = np.random.default_rng(len(label))
    seed = rng.normal(size=len(knowns))
    dd = np.array(c.s.getDirectionalDerivative([c.v[n] for n in unknowns], [c.v[n] for n in knowns], list(seed)))
    expect = J_fd @ seed
    tol = FD_REL * np.linalg.norm(J_fd, 2) * np.linalg.norm(seed) + FD_ROUNDOFF * EPS * Y / hs.min() * np.abs(seed).sum()
    assert np.max(np.abs(dd - expect)) <= tol, (label, dd, expect)
    return J_fd, worst


@pytest.mark.parametrize("variant", VARIANTS)
def test_directional_derivatives_random_poses(conn, variant):
    """Springs + dampers (+ Planar penalties) at random poses, after some steps (committed
    state), every input as known, node loads + CTF/CTM as unknowns."""
    rng = np.random.default_rng(7 + VARIANTS.index(variant))
    params = spring_damper_params(variant)
    if variant == "Planar":
        params.update({"constraint.damping": 50.0, "constraint.rotDamping": 5.0})
    init = _ref.random_pose(rng, variant)
    c = conn(variant).start(params, _ref.pose_to_inputs(variant, init))
    c.step(0.01)  # linear extrapolation from the random velocities: a committed state at t > 0
    knowns = [r.name for r in c.real_in]
    for trial in range(4):
        pose = _ref.random_pose(rng, variant)
        c.set(_ref.pose_to_inputs(variant, pose))
        _assert_jacobians(c, knowns, _unknowns(variant), f"{variant} pose {trial}")


# --- Planar in stick, in slip, at an active stop ---------------------------------------------

PLANAR_DD = {
    "elasticity.k2": 200.0, "elasticity.k3": 300.0, "elasticity.k4": 5.0,
    "damping.c2": 2.0, "damping.c3": 3.0, "damping.c4": 0.05,
    # penalties softened so that the reactions stay O(100): f1 = 1e6 N/m * 1e-4 m
    "constraint.stiffness": 1.0e6, "constraint.damping": 20.0,
    "constraint.rotStiffness": 1.0e3, "constraint.rotDamping": 1.0,
    "friction.muStatic": 0.4, "friction.muKinetic": 0.3, "friction.decay": 2.0,
    "friction.R": 0.05, "friction.Fint": 100.0, "friction.Mint": 2.0,
    "friction.stickStiffness": 1.0e4, "friction.stickStiffnessR1": 100.0,
    "cosim.extrapolation": 0,  # hold: the committed state is exactly at the set inputs
}

# b relative to a, in a's frame: in-plane position (x0, y, z), rotation psi about e1 and a
# misalignment (3 mrad about e2 and e3) that gives bending moments m2, m3 ~ 3 N.m, far from the
# kink of |(m2, m3)| at 0 (an FD probe changes the misalignment by ~1e-6 rad).
PL_X0, PL_Y0, PL_Z0, PL_PSI0, PL_MIS = 0.1, 0.2, -0.1, 0.3, 3e-3


def _planar_pose(dx=0.0, dy=0.0, dz=0.0, dpsi=0.0, vrel=(0.0, 0.0, 0.0), wrel=0.0):
    Rrel = _ref.rot_x(PL_PSI0 + dpsi) @ _ref.rot_y(PL_MIS) @ _ref.rot_z(PL_MIS)
    return {
        "a.r": RA_POS, "a.q": QA0, "a.v": np.zeros(3), "a.w": np.zeros(3),
        "b.r": RA_POS + RA0 @ np.array([PL_X0 + dx, PL_Y0 + dy, PL_Z0 + dz]),
        "b.q": _ref.matrix_to_quat(RA0 @ Rrel),
        "b.v": RA0 @ np.array(vrel), "b.w": wrel * RA0[:, 0],
    }


PLANAR_DD_VARIANTS = {
    "abaqus": {},
    "coupled": {"friction.coupling": 1},
    "stick-dampers": {"friction.stickDamping": 300.0, "friction.stickDampingR1": 3.0},
}
PLANAR_DD_CASES = [("stick", "abaqus"), ("slip", "abaqus"), ("stop", "abaqus"),
                   ("stick", "coupled"), ("slip", "coupled"),
                   ("stick", "stick-dampers"), ("slip", "stick-dampers")]


@pytest.mark.parametrize("case,friction", PLANAR_DD_CASES, ids=[f"{c}-{f}" for c, f in PLANAR_DD_CASES])
def test_directional_derivatives_planar_friction_and_stop(conn, case, friction):
    """Friction on (limit mu F_NC ~ 0.39 * 270 N ~ 100 N, stick range ~10 mm; spin limit
    ~ 0.39 * 8.3 N.m ~ 3 N.m, range ~ 30 mrad). A first step (hold) slides b by 20 mm and turns
    it by 80 mrad, which commits a slip state on both effects. Then:
      slip: 1 mm further on (trial ~10 N beyond the limit, moving: mu(rate) smooth);
      stick: 3 mm and 10 mrad back (trial ~30 N inside the limit);
      stop: as slip, with u2 pushed 7 mm into an upper stop (1e5 N/m), moving into it.
    Also with the coupled limit (friction.coupling = 1) and with stick dampers."""
    P = "Planar"
    params = {**PLANAR_DD, **PLANAR_DD_VARIANTS[friction]}
    if case == "stop":
        params.update({"stop.upper2": PL_Y0 + 0.014, "stop.stiffness": 1.0e5, "stop.damping": 50.0})
    c = conn(P).start(params, _ref.pose_to_inputs(P, _planar_pose()))
    # x offset 1e-4 m from x0: f1 = 1e6 * 1e-4 = 100 N, away from the kink of |f1|
    v = (0.0, 0.05, 0.0125)
    c.set(_ref.pose_to_inputs(P, _planar_pose(1e-4, 0.020, 0.005, 0.08, v, 0.2)))
    c.step(0.01)
    assert c.value("friction.status") == 2 and c.value("friction.statusR1") == 2
    if case == "slip":
        pose = _planar_pose(1e-4, 0.021, 0.00525, 0.082, v, 0.2)
        want = (2, 2)
    elif case == "stick":
        pose = _planar_pose(1e-4, 0.017, 0.00425, 0.07, (0.0, -0.05, -0.0125), -0.2)
        want = (1, 1)
    else:
        # 1 mm further on, as in "slip": the friction trial is off the stick/slip boundary (at
        # the committed pose it would sit exactly on it, a kink)
        pose = _planar_pose(1e-4, 0.021, 0.00525, 0.082, v, 0.2)
        want = None
    c.set(_ref.pose_to_inputs(P, pose))
    if want is not None:
        assert (c.value("friction.status"), c.value("friction.statusR1")) == want
    else:
        assert c.value("CSLST2") == 1
        assert c.get(["CRF2"])[0] < -100.0 or c.get(["CRF2"])[0] > 100.0
    knowns = [r.name for r in c.real_in]
    J_fd, _ = _assert_jacobians(c, knowns, _unknowns(P), f"Planar {case}")
    # physics sanity of the tangent (independent of the FMU): in stick, dCTF2/d(b.r) along e2a
    # includes the stick stiffness 1e4 (plus spring 200); in slip it does not.
    if friction == "coupled":
        return
    e2a = RA0[:, 1]
    col = np.array([J_fd[_unknowns(P).index("CTF2"), knowns.index(f"b.r[{j}]")] for j in (1, 2, 3)])
    k_tan = float(col @ e2a)
    if case == "stick":
        assert abs(k_tan - (1.0e4 + 200.0)) < 1e-3 * 1.0e4, k_tan
    elif case == "slip":
        assert abs(k_tan) < 0.5e4, k_tan
    else:
        assert k_tan > 1.0e5 * 0.99, k_tan
