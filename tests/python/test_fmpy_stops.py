"""Connector stops (docs/physics.md, Behaviours) through fmpy: Bushing, RadialThrust and Planar.

A stop is a one-sided penalty on a component POSITION c (x, r, y, beta, alpha, ...):
  upper stop, penetration p = c - upper > 0:  F =  max(0, k p + c_s dp/dt),  CSLST = +1
  lower stop, penetration p = lower - c > 0:  F = -max(0, k p + c_s dp/dt),  CSLST = -1
  free:                                       F = 0,                         CSLST =  0
F is the force IN the connector (reported in CRF_i / CRM_i), positive at the upper stop like a
stretched spring, and it never pulls (clipped at zero while the damper would make it adhesive).
The dissipated stop energy is the work of F - k p on the penetration; a stop without damper
dissipates nothing.

Protocol: one component at a time follows a prescribed sine c(t) = c0 + A sin(2 pi t / T) that
crosses both stops.  The path is piecewise linear in time: before the step [t_k, t_k+1] the
inputs hold c_k and the rate v_k = (c_k+1 - c_k)/h, so the FMU's linear extrapolation moves the
node exactly to c_k+1 (rotations about a fixed axis through the exponential map are exact too),
and the outputs after the step belong to (c_k+1, v_k).  That makes the expected stop force at
each step end the closed form above, evaluated with numbers the test chose.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import Connector

# --------------------------------------------------------------------------
# poses (Connector, the name-based driver, is scripts/cosim/driver.py)
# --------------------------------------------------------------------------


def quat_about(axis, angle):
    q = np.zeros(4)
    q[0] = math.cos(0.5 * angle)
    q[1 + axis] = math.sin(0.5 * angle)
    return q


# --------------------------------------------------------------------------
# the cases: which node input moves which component
# --------------------------------------------------------------------------
# Each case: variant, Abaqus component k, position / rate / reaction / total output names,
# the node load that must equal -F (the connector's force on node b along the component),
# c0, amplitude A, whether rotational, and how a position c and rate v map to node-b inputs.
# With node a at the origin with identity orientation:
#   Bushing u1:     b.r = (c, 0, 0): centred triad = identity, x = c, b.f[1] = -CRF1
#   Bushing ur3:    b rotated by c about z: pure torsion beta = c, b.m[3] = -CRM3
#   RadialThrust:   b.r = (c, 0, 0.3): r = c (c > 0), e_r = x, b.f[1] = -CRF1
#   Planar u2:      b.r = (0, c, 0): y = c, b.f[2] = -CRF2 (constraint satisfied: x = 0)
#   Planar ur1:     b rotated by c about x: alpha = c, b.m[1] = -CRM1


def _trans(axis, offset=(0.0, 0.0, 0.0)):
    def inputs(c, v):
        r = np.array(offset, float)
        r[axis] += c
        vel = np.zeros(3)
        vel[axis] = v
        return {**{f"b.r[{j + 1}]": r[j] for j in range(3)}, **{f"b.v[{j + 1}]": vel[j] for j in range(3)}}

    return inputs


def _rot(axis):
    def inputs(c, v):
        q = quat_about(axis, c)
        w = np.zeros(3)
        w[axis] = v
        return {**{f"b.q.{n}": q[j] for j, n in enumerate("wxyz")}, **{f"b.w[{j + 1}]": w[j] for j in range(3)}}

    return inputs


CASES = {
    "Bushing-u1": dict(variant="Bushing", k=1, cp="CP1", cv="CV1", cr="CRF1", ct="CTF1", load="b.f[1]",
                       c0=0.0, A=0.02, rot=False, inputs=_trans(0)),
    "Bushing-ur3": dict(variant="Bushing", k=6, cp="CPR3", cv="CVR3", cr="CRM3", ct="CTM3", load="b.m[3]",
                        c0=0.0, A=0.4, rot=True, inputs=_rot(2)),
    "RadialThrust-r": dict(variant="RadialThrust", k=1, cp="CP1", cv="CV1", cr="CRF1", ct="CTF1", load="b.f[1]",
                           c0=0.5, A=0.02, rot=False, inputs=_trans(0, (0.0, 0.0, 0.3))),
    "Planar-u2": dict(variant="Planar", k=2, cp="CP2", cv="CV2", cr="CRF2", ct="CTF2", load="b.f[2]",
                      c0=0.0, A=0.02, rot=False, inputs=_trans(1)),
    "Planar-ur1": dict(variant="Planar", k=4, cp="CPR1", cv="CVR1", cr="CRM1", ct="CTM1", load="b.m[1]",
                       c0=0.0, A=0.4, rot=True, inputs=_rot(0)),
}

# Stop penalties: translational k = 1e4 N/m, c = 20 N.s/m; rotational k = 200 N.m/rad,
# c = 2 N.m.s/rad.  With A = 0.02 m (0.4 rad) and T = 1 s the peak penetration is A/2 and the
# peak damper force c*2*pi*A/T = 2.5 N (5 N.m) against k*A/2 = 100 N (40 N.m): the stop force is
# dominated by the spring, the damper is visible, and clipping happens only just before release.
K_T, C_T, K_R, C_R = 1e4, 20.0, 200.0, 2.0
T_PERIOD, H = 1.0, 1e-3


def _stop_params(case, k, c):
    n = case["k"]
    p = {f"stop.upper{n}": case["c0"] + 0.5 * case["A"], f"stop.lower{n}": case["c0"] - 0.5 * case["A"]}
    if case["rot"]:
        p.update({"stop.rotStiffness": k, "stop.rotDamping": c})
    else:
        p.update({"stop.stiffness": k, "stop.damping": c})
    return p


def _expected_stop(c, v, upper, lower, k, d):
    """(force in the connector, status) of a one-sided never-pulling stop penalty."""
    if c > upper:
        return max(0.0, k * (c - upper) + d * v), 1
    if c < lower:
        # penetration rate is -v at the lower stop
        return -max(0.0, k * (lower - c) - d * v), -1
    return 0.0, 0


def _run(make_slave, case, k, d, periods=1.25, h=H, extra_names=()):
    """Drive the case's component along c0 + A sin(2 pi t/T); return per-step arrays.

    Rows belong to the step ends t_k+1: position c_k+1 and rate v_k (the rate over the step).
    'pre' loads are read after setting the inputs at t_k and before the step (direct
    feedthrough), so the trapezoid of the work over a step can use both ends."""
    con = Connector(case["variant"], make_slave(case["variant"], instance_name=f"stop-{case['cp']}"))
    params = _stop_params(case, k, d)
    n = int(round(periods * T_PERIOD / h))
    t = h * np.arange(n + 1)
    c = case["c0"] + case["A"] * np.sin(2 * math.pi * t / T_PERIOD)
    v = np.diff(c) / h
    con.start(params, case["inputs"](c[0], v[0]))
    names = [case["cp"], case["cv"], case["cr"], case["ct"], case["load"], "energy.stored", "energy.stops",
             *extra_names]
    out = np.zeros((n, len(names)))
    pre = np.zeros(n)
    status = np.zeros(n, dtype=int)
    e0 = con.get(["energy.stored", "energy.stops"])
    for i in range(n):
        con.set(case["inputs"](c[i], v[i]))
        pre[i] = con.get([case["load"]])[0]
        con.step(h)
        out[i] = con.get(names)
        status[i] = con.geti([f"CSLST{case['k']}"])[0]
    res = {nm: out[:, j] for j, nm in enumerate(names)}
    res.update(c=c[1:], v=v, status=status, pre_load=pre, c_all=c, e0=e0, params=params)
    return res


# --------------------------------------------------------------------------
# tests
# --------------------------------------------------------------------------


@pytest.mark.parametrize("name", list(CASES))
def test_stop_engages_and_releases(make_slave, name):
    """CSLST runs 0 -> +1 -> 0 -> -1 -> 0 along the sine, and the stop reaction is the
    never-pulling penalty max(0, k p + c dp/dt) with the sign of a stretched spring at the upper
    stop; the node load on b is its opposite (the stop pushes b back)."""
    case = CASES[name]
    k, d = (K_R, C_R) if case["rot"] else (K_T, C_T)
    r = _run(make_slave, case, k, d)
    upper, lower = case["c0"] + 0.5 * case["A"], case["c0"] - 0.5 * case["A"]

    # the path really is the one prescribed (positions to round-off, rates from the inputs)
    assert np.allclose(r[case["cp"]], r["c"], rtol=0, atol=1e-12)
    assert np.allclose(r[case["cv"]], r["v"], rtol=0, atol=1e-9)

    # status: position-based, as docs/physics.md, Kinematics says stops act on positions
    exp = np.array([_expected_stop(c, v, upper, lower, k, d) for c, v in zip(r["c"], r["v"])])
    assert np.array_equal(r["status"], exp[:, 1].astype(int))
    runs = [int(s) for j, s in enumerate(r["status"]) if j == 0 or s != r["status"][j - 1]]
    assert runs == [0, 1, 0, -1, 0, 1], runs

    # force: closed form at every step end.  Values are ~1e2 N; the FMU computes the same few
    # flops from positions equal to ours within ~1e-15 (rotation angles from quaternions within
    # ~1e-15 rad), so 1e-9 of the peak force is a generous round-off allowance.
    scale = k * 0.5 * case["A"]
    assert np.allclose(r[case["cr"]], exp[:, 0], rtol=0, atol=1e-9 * scale)
    assert np.all(r[case["cr"]][r["status"] == 1] >= 0.0)
    assert np.all(r[case["cr"]][r["status"] == -1] <= 0.0)
    # no elasticity, damping or friction is on: the total is the stop reaction ...
    assert np.allclose(r[case["ct"]], r[case["cr"]], rtol=0, atol=1e-9 * scale)
    # ... and it pushes node b back towards the free range (b.f = -f)
    assert np.allclose(r[case["load"]], -exp[:, 0], rtol=0, atol=1e-7 * scale)
    assert np.all(r[case["load"]][r["status"] == 1] <= 0.0)
    assert np.all(r[case["load"]][r["status"] == -1] >= 0.0)
    # the damper is visible: entering (v > 0 at the upper stop) the force exceeds k p
    inside = (r["status"] == 1) & (r["v"] > 0)
    assert np.any(inside)
    assert np.all(r[case["cr"]][inside] > k * (r["c"][inside] - upper))


@pytest.mark.parametrize("name", ["Bushing-u1", "Bushing-ur3", "RadialThrust-r", "Planar-u2"])
def test_stop_never_pulls(make_slave, name):
    """A damper much stronger than the spring: while the node moves out of the stop,
    k p + c dp/dt < 0 and the force must be exactly 0 (clipped), never negative (adhesive)."""
    case = CASES[name]
    # damper force c*v_max = 1e4 * 0.126 = 1.26e3 N (25 * 2.5 = 63 N.m) >> k A/2
    k, d = (K_R, 25.0) if case["rot"] else (K_T, 1e4)
    r = _run(make_slave, case, k, d)
    upper, lower = case["c0"] + 0.5 * case["A"], case["c0"] - 0.5 * case["A"]
    f = r[case["cr"]]
    at_upper_out = (r["c"] > upper) & (k * (r["c"] - upper) + d * r["v"] < 0)
    at_lower_out = (r["c"] < lower) & (k * (lower - r["c"]) - d * r["v"] < 0)
    assert at_upper_out.sum() > 10 and at_lower_out.sum() > 10  # the case is really exercised
    assert np.all(f[at_upper_out] == 0.0), f[at_upper_out].min()
    assert np.all(f[at_lower_out] == 0.0), f[at_lower_out].max()
    assert np.all(f[r["c"] > upper] >= 0.0) and np.all(f[r["c"] < lower] <= 0.0)
    # and the node load is zero there too (no other force element is on)
    assert np.all(np.abs(r[case["load"]][at_upper_out | at_lower_out]) <= 1e-12)


@pytest.mark.parametrize("name", list(CASES))
@pytest.mark.parametrize("damped", [False, True])
def test_stop_energy(make_slave, name, damped):
    """energy.stops >= 0, non-decreasing, unchanged on steps that stay free, growing while the
    damper works; zero throughout for an undamped stop; and the work done on the connector
    equals the stored stop energy plus energy.stops.

    Work: W = sum over steps of -(load_b . v_b) h, trapezoid of the loads read just after
    setting the inputs at t_k and just after the step.  On a step wholly inside or wholly
    outside a stop the load is linear in time (spring) plus constant (damper), so the trapezoid
    is exact; a step that crosses the stop boundary is not: the force jumps from 0 to
    k p1 + c v in mid-step (p1 <= v h), and the trapezoid misses at most k (v h)^2 / 8 +
    c v^2 h / 2; the FMU's dissipation on that step (its power integrated over the step) can
    miss c v^2 h / 2 as well.  Clip onsets are kinks of a linear function, O(k v^2 h^2).
    Tolerance per crossing: k (v_max h)^2 / 8 + c v_max^2 h.  With h = 1e-3 that is 2 % of the
    dissipated energy (translational cases; observed residual ~0.15 %) and 1e-4 J against
    0.5 J of peak stored energy without damper."""
    case = CASES[name]
    k, d = (K_R, C_R if damped else 0.0) if case["rot"] else (K_T, C_T if damped else 0.0)
    r = _run(make_slave, case, k, d)
    es = np.concatenate([[r["e0"][1]], r["energy.stops"]])
    inc = np.diff(es)
    upper, lower = case["c0"] + 0.5 * case["A"], case["c0"] - 0.5 * case["A"]
    c = r["c_all"]
    free_both = (c[:-1] >= lower) & (c[:-1] <= upper) & (c[1:] >= lower) & (c[1:] <= upper)
    in_both = ((c[:-1] > upper) & (c[1:] > upper)) | ((c[:-1] < lower) & (c[1:] < lower))

    assert es[0] == 0.0 and np.all(es >= 0.0)
    assert np.all(inc >= -1e-15), inc.min()
    assert np.all(inc[free_both] == 0.0)
    if not damped:
        # a purely elastic stop is conservative: nothing dissipated, to round-off
        assert np.all(np.abs(es) <= 1e-12)
    else:
        # the damper does work on every step spent inside a stop with the node moving
        moving = in_both & (np.abs(r["v"]) > 1e-6)
        assert np.all(inc[moving] > 0.0)
        # Inside the stop and unclipped, the damper dissipates c v^2 per unit time; the rate
        # is constant over each step (v_k), so the exact dissipation of such a step is
        # c v_k^2 h.  Summed over those steps; the FMU may integrate the damper power with
        # the rate of the previous step at the step start (a trapezoid), whose difference
        # telescopes to at most c v_max^2 h / 2 per run of consecutive steps.
        pen0 = np.where(c[:-1] > upper, c[:-1] - upper, lower - c[:-1])
        pen1 = np.where(c[1:] > upper, c[1:] - upper, lower - c[1:])
        sel = in_both & (k * pen0 - d * np.abs(r["v"]) > 0) & (k * pen1 - d * np.abs(r["v"]) > 0)
        runs = int(np.sum(np.diff(sel.astype(int)) == 1)) + int(sel[0])
        vmax = 2 * math.pi * case["A"] / T_PERIOD
        exact = np.sum(d * r["v"][sel] ** 2 * H)
        assert runs >= 2 and exact > 0
        assert abs(np.sum(inc[sel]) - exact) <= runs * 0.5 * d * vmax**2 * H + 1e-12 * exact

    # energy balance
    lb = r[case["load"]]
    W = -np.sum(0.5 * (r["pre_load"] + lb) * r["v"] * H)
    stored = r["energy.stored"][-1] - r["e0"][0]
    vmax = 2 * math.pi * case["A"] / T_PERIOD
    crossings = int(np.sum(np.diff(np.sign(np.where(c > upper, 1, np.where(c < lower, -1, 0)))) != 0))
    tol = crossings * (k * (vmax * H) ** 2 / 8 + d * vmax**2 * H) + 1e-12
    assert abs(W - (stored + es[-1])) <= tol, (W, stored, es[-1], tol)
