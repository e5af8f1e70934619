"""PLANAR predefined friction (the manual's PLANAR friction; docs/physics.md, PLANAR friction) through fmpy.

Node a sits at the origin with the identity orientation (e1a, e2a, e3a = world x, y, z); node b
follows a prescribed path of (y, z, alpha) = (e2a.d, e3a.d, rotation about e1a).  The path is
piecewise linear in time: before the step [t_k, t_k+1] the inputs hold the pose at t_k and the
rates (p_k+1 - p_k)/h, so the FMU's linear extrapolation lands exactly on p_k+1 (rotation about
the fixed axis e1 through the exponential map is exact), and the outputs after the step belong
to (p_k+1, rate over the step).

Expected values come from the seed:
  F_NC = |F_C + F_C^int|,  F_C = |f1| + sqrt(m2^2 + m3^2)/R   (bending dropped when R = 0)
  M_NR1 = |(2/3) R |f1| + sqrt(m2^2 + m3^2) + M_R1^int|
  Phi_C = sqrt(f2^2 + f3^2) - mu F_NC <= 0,  Phi_R1 = |m1| - mu M_NR1 <= 0
and from the stick model of docs/physics.md (elastic stick spring, radial return in the 2-3 plane, scalar
return for spin), mu = mu_k + (mu_s - mu_k) exp(-d_c rate).

Normal load: either friction.Fint (b stays exactly in the plane, f1 = 0), or b pressed into the
plane, x = -N / constraint.stiffness so that f1 = -N.

Sign convention (README, Conventions): CSF is the force IN the connector; when b slides +y relative
to a the stick spring is stretched, CSF2 > 0, and the load on b is b.f[2] = -CSF2 < 0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

import _ref
from conftest import Connector

# --------------------------------------------------------------------------
# driver inputs (Connector, the name-based driver, is scripts/cosim/driver.py)
# --------------------------------------------------------------------------


A_INPUTS = {"a.r[1]": 0.0, "a.r[2]": 0.0, "a.r[3]": 0.0, "a.q.w": 1.0, "a.q.x": 0.0, "a.q.y": 0.0, "a.q.z": 0.0,
            "a.v[1]": 0.0, "a.v[2]": 0.0, "a.v[3]": 0.0, "a.w[1]": 0.0, "a.w[2]": 0.0, "a.w[3]": 0.0}


def b_quat(alpha, tilt=(0.0, 0.0)):
    """b's orientation: a tilt about (e2a, e3a) (rotation vector), then a spin alpha about e1a."""
    return _ref.quat_mul(_ref.quat_exp([alpha, 0.0, 0.0]), _ref.quat_exp([0.0, tilt[0], tilt[1]]))


def b_inputs(y=0.0, z=0.0, alpha=0.0, vy=0.0, vz=0.0, w1=0.0, x=0.0, tilt=(0.0, 0.0)):
    q = b_quat(alpha, tilt)
    return {"b.r[1]": x, "b.r[2]": y, "b.r[3]": z, "b.v[1]": 0.0, "b.v[2]": vy, "b.v[3]": vz,
            "b.q.w": q[0], "b.q.x": q[1], "b.q.y": q[2], "b.q.z": q[3],
            "b.w[1]": w1, "b.w[2]": 0.0, "b.w[3]": 0.0}


def start(make_slave, params, name="planar", **b0):
    con = Connector("Planar", make_slave("Planar", instance_name=name))
    return con.start(params, {**A_INPUTS, **b_inputs(**b0)})


KC = 1e7  # default constraint.stiffness (N/m), set explicitly in every test that presses


def press(n_force):
    """b.r[1] that makes the SLIDE-PLANE penalty carry f1 = -N (x0 = 0)."""
    return -n_force / KC


REALS = ["CP2", "CP3", "CPR1", "CV2", "CV3", "CVR1", "CSF2", "CSF3", "CSM1", "CTF2", "CTF3", "CTM1",
         "CRF1", "CRM2", "CRM3", "CNF", "CNM1", "CSFC", "CSMC1", "friction.slip", "friction.slipR1",
         "a.f[2]", "a.f[3]", "b.f[1]", "b.f[2]", "b.f[3]", "b.m[1]", "b.m[2]", "b.m[3]",
         "energy.stored", "energy.damping", "energy.friction", "energy.stops"]
INTS = ["friction.status", "friction.statusR1"]


def drive(con, path, h, x=0.0, tilt=(0.0, 0.0)):
    """Move b along path[k] = (y, z, alpha), k = 0..n; return a dict of arrays over the n step
    ends (REALS, INTS), plus 'y', 'z', 'alpha' (positions at the step ends) and 'rate' (rates
    over each step)."""
    path = np.asarray(path, float)
    rate = np.diff(path, axis=0) / h
    n = len(rate)
    out, st = np.zeros((n, len(REALS))), np.zeros((n, len(INTS)), dtype=int)
    for k in range(n):
        y, z, al = path[k]
        vy, vz, w = rate[k]
        con.set(b_inputs(y, z, al, vy, vz, w, x=x, tilt=tilt))
        con.step(h)
        out[k] = con.get(REALS)
        st[k] = con.geti(INTS)
    r = {nm: out[:, j] for j, nm in enumerate(REALS)}
    r.update({nm: st[:, j] for j, nm in enumerate(INTS)})
    r.update(y=path[1:, 0], z=path[1:, 1], alpha=path[1:, 2], rate=rate)
    return r


def line(p0, p1, n):
    """n steps from p0 to p1 (n + 1 points)."""
    return np.linspace(np.asarray(p0, float), np.asarray(p1, float), n + 1)


def runs(seq):
    """Run-length values of a sequence: [1, 1, 2, 2, 1] -> [1, 2, 1]."""
    seq = list(seq)
    return [s for j, s in enumerate(seq) if j == 0 or s != seq[j - 1]]


def mu_of(mus, muk, decay, rate):
    return mus if decay == 0 else muk + (mus - muk) * math.exp(-decay * rate)


# --------------------------------------------------------------------------
# sliding and spin limits
# --------------------------------------------------------------------------

MU, N, KS, KSR = 0.4, 20.0, 1e4, 100.0


@pytest.mark.parametrize("load", ["press", "Fint"])
def test_sliding_friction_saturates_at_mu_fnc(make_slave, load):
    """Slide b along +y at 0.01 m/s: elastic stick (CSF2 = k_s y, status 1) until
    k_s y = mu F_NC, then slip at CSF2 = mu F_NC (status 2), force opposing b's motion.

    Tolerances: forces are ~10 N computed in a handful of flops from y (exact in the inputs to
    ~1e-19 m), so 1e-9 N is round-off with a wide margin; steps within 1e-9 relative of the
    breakaway are not classified (either answer is right there)."""
    h, v, n = 1e-3, 0.01, 250
    x = press(N) if load == "press" else 0.0
    params = {"constraint.stiffness": KC, "friction.muStatic": MU, "friction.muKinetic": MU,
              "friction.stickStiffness": KS, **({"friction.Fint": N} if load == "Fint" else {})}
    con = start(make_slave, params)
    r = drive(con, line([0, 0, 0], [v * h * n, 0, 0], n), h, x=x)

    # normal force: F_NC = |f1| + F_int (R = 0), f1 = k_c x
    f1 = KC * x
    assert np.allclose(r["CRF1"], f1, rtol=0, atol=1e-9)
    assert np.allclose(r["CNF"], N, rtol=0, atol=1e-9)
    assert np.allclose(r["CV2"], v, rtol=0, atol=1e-12)

    limit = MU * N
    trial = KS * r["y"]
    stick, slip = trial < limit * (1 - 1e-9), trial > limit * (1 + 1e-9)
    assert stick.sum() > 50 and slip.sum() > 100
    assert np.all(r["friction.status"][stick] == 1) and np.all(r["friction.status"][slip] == 2)
    assert runs(r["friction.status"]) == [1, 2]
    # stick: the elastic stick spring
    assert np.allclose(r["CSF2"][stick], trial[stick], rtol=0, atol=1e-9)
    assert np.all(r["friction.slip"][stick] == 0.0)
    # slip: on the limit, along +y, nothing along z
    assert np.allclose(r["CSFC"][slip], MU * r["CNF"][slip], rtol=1e-12, atol=0)
    assert np.allclose(r["CSF2"][slip], limit, rtol=0, atol=1e-9)
    assert np.all(r["CSF2"] >= 0) and np.allclose(r["CSF3"], 0.0, atol=1e-12)
    # the accumulated slip is the travel beyond the elastic stick displacement
    assert np.allclose(r["friction.slip"][slip], r["y"][slip] - limit / KS, rtol=0, atol=1e-12)
    # loads: the connector holds b back and drags a along (b.f = -f, a.f = +f)
    assert np.allclose(r["CTF2"], r["CSF2"], rtol=0, atol=1e-12)
    assert np.allclose(r["b.f[2]"], -r["CSF2"], rtol=0, atol=1e-9)
    assert np.allclose(r["a.f[2]"], r["CSF2"], rtol=0, atol=1e-9)
    assert np.all(r["b.f[2]"][slip] < 0)
    # dissipation at a constant friction force: mu F_NC times the plastic slip (1e-9 relative)
    assert r["energy.friction"][-1] == pytest.approx(limit * r["friction.slip"][-1], rel=1e-9)
    # spin is untouched
    assert np.all(r["CSM1"] == 0.0)


@pytest.mark.parametrize("radius,mint", [(0.3, 0.0), (0.3, 0.5), (0.0, 2.0)])
def test_spin_friction_saturates_at_mu_mnr1(make_slave, radius, mint):
    """Spin b about e1a at 0.2 rad/s with f1 = -20 N: M_NR1 = (2/3) R |f1| + M_int
    (R = 0: M_int only); elastic stick CSM1 = k_r alpha, then CSM1 = mu M_NR1 (statusR1 2);
    b.m[1] = -CSM1.  Tolerance 1e-9 N.m: round-off, as for sliding."""
    h, w, n = 1e-3, 0.2, 300
    params = {"constraint.stiffness": KC, "friction.muStatic": MU, "friction.muKinetic": MU,
              "friction.R": radius, "friction.Mint": mint, "friction.stickStiffnessR1": KSR}
    con = start(make_slave, params)
    r = drive(con, line([0, 0, 0], [0, 0, w * h * n], n), h, x=press(N))

    mnr1 = abs(2.0 / 3.0 * radius * N + mint)
    assert np.allclose(r["CNM1"], mnr1, rtol=0, atol=1e-9)
    assert np.allclose(r["CNF"], N, rtol=0, atol=1e-9)  # no bending: F_NC = |f1|
    assert np.allclose(r["CPR1"], r["alpha"], rtol=0, atol=1e-12)
    limit = MU * mnr1
    trial = KSR * r["alpha"]
    stick, slip = trial < limit * (1 - 1e-9), trial > limit * (1 + 1e-9)
    assert stick.sum() > 20 and slip.sum() > 50
    assert runs(r["friction.statusR1"]) == [1, 2]
    assert np.all(r["friction.statusR1"][stick] == 1) and np.all(r["friction.statusR1"][slip] == 2)
    assert np.allclose(r["CSM1"][stick], trial[stick], rtol=0, atol=1e-9)
    assert np.allclose(r["CSM1"][slip], limit, rtol=0, atol=1e-9)
    assert np.allclose(r["CSMC1"], np.abs(r["CSM1"]), rtol=0, atol=1e-12)
    assert np.allclose(r["friction.slipR1"][slip], r["alpha"][slip] - limit / KSR, rtol=0, atol=1e-12)
    assert np.allclose(r["b.m[1]"], -r["CSM1"], rtol=0, atol=1e-9)
    # sliding is untouched: stick with zero force
    assert np.all(r["friction.status"] == 1) and np.allclose(r["CSFC"], 0.0, atol=1e-12)


@pytest.mark.parametrize("v", [0.002, 0.01, 0.05])
def test_mu_decays_with_sliding_rate(make_slave, v):
    """Steady sliding at rate v: CSFC = (mu_k + (mu_s - mu_k) exp(-d_c v)) F_NC.
    d_c = 50 s/m puts d_c v at 0.1, 0.5, 2.5: the three answers differ by up to 30 %.
    Tolerance 1e-9 relative (round-off)."""
    mus, muk, dc, h = 0.5, 0.3, 50.0, 1e-3
    n = int(math.ceil(3 * mus * N / KS / (v * h)))  # three times the largest stick travel
    con = start(make_slave, {"friction.muStatic": mus, "friction.muKinetic": muk, "friction.decay": dc,
                             "friction.Fint": N, "friction.stickStiffness": KS})
    r = drive(con, line([0, 0, 0], [v * h * n, 0, 0], n), h)
    assert r["friction.status"][-1] == 2
    assert r["CSFC"][-1] == pytest.approx(mu_of(mus, muk, dc, v) * N, rel=1e-9)
    assert r["CSF2"][-1] > 0


@pytest.mark.parametrize("radius,w", [(0.3, 0.05), (0.3, 0.5), (0.0, 0.02)])
def test_mu_decays_with_spin_rate(make_slave, radius, w):
    """Steady spin at rate w: the slip rate of spin is (2R/3)|w| (|w| when R = 0), so
    CSMC1 = (mu_k + (mu_s - mu_k) exp(-d_c rate)) M_NR1.  Tolerance 1e-9 relative."""
    mus, muk, dc, h, mint = 0.5, 0.3, 50.0, 1e-3, 1.0
    con = start(make_slave, {"constraint.stiffness": KC, "friction.muStatic": mus, "friction.muKinetic": muk,
                             "friction.decay": dc, "friction.R": radius, "friction.Mint": mint,
                             "friction.stickStiffnessR1": KSR})
    mnr1 = 2.0 / 3.0 * radius * N + mint
    n = int(math.ceil(3 * mus * mnr1 / KSR / (w * h)))
    r = drive(con, line([0, 0, 0], [0, 0, w * h * n], n), h, x=press(N))
    rate = (2.0 / 3.0 * radius if radius > 0 else 1.0) * w
    assert r["friction.statusR1"][-1] == 2
    assert r["CNM1"][-1] == pytest.approx(mnr1, rel=1e-12)
    assert r["CSMC1"][-1] == pytest.approx(mu_of(mus, muk, dc, rate) * mnr1, rel=1e-9)


def test_max_force_caps_sliding(make_slave):
    """friction.maxForce = 5 N below mu F_NC = 8 N: the sliding force saturates at 5 N and the
    stick phase ends at k_s y = 5 N; spin is not capped.  Tolerance: round-off (1e-9)."""
    h, v, n, cap = 1e-3, 0.01, 200, 5.0
    con = start(make_slave, {"friction.muStatic": MU, "friction.muKinetic": MU, "friction.Fint": N,
                             "friction.Mint": 2.0, "friction.stickStiffness": KS,
                             "friction.stickStiffnessR1": KSR, "friction.maxForce": cap})
    r = drive(con, line([0, 0, 0], [v * h * n, 0, 0.01 * n * h * 30], n), h)
    trial = KS * r["y"]
    stick, slip = trial < cap * (1 - 1e-9), trial > cap * (1 + 1e-9)
    assert np.allclose(r["CSF2"][stick], trial[stick], atol=1e-9)
    assert np.all(r["friction.status"][slip] == 2) and np.all(r["friction.status"][stick] == 1)
    assert np.allclose(r["CSFC"][slip], cap, atol=1e-9)
    assert r["friction.statusR1"][-1] == 2
    assert r["CSMC1"][-1] == pytest.approx(MU * 2.0, rel=1e-9)


def test_no_normal_force_status_0(make_slave):
    """mu > 0 but no normal force (b in the plane, F_int = M_int = 0): status 0, no force."""
    con = start(make_slave, {"friction.muStatic": MU, "friction.muKinetic": MU})
    r = drive(con, line([0, 0, 0], [1e-3, 5e-4, 0.02], 20), 1e-3)
    assert np.all(r["friction.status"] == 0) and np.all(r["friction.statusR1"] == 0)
    assert np.all(r["CNF"] == 0) and np.all(r["CNM1"] == 0)
    assert np.all(r["CSFC"] == 0) and np.all(r["CSMC1"] == 0)


# --------------------------------------------------------------------------
# the normal force and moment of the seed, with bending
# --------------------------------------------------------------------------


@pytest.mark.parametrize("radius,fint", [(0.5, 5.0), (0.5, -60.0), (0.0, 5.0)])
def test_tilt_raises_the_limits_through_R(make_slave, radius, fint):
    """Tilt b by (2e-3, -1e-3) rad about (e2a, e3a): the REVOLUTE penalty carries
    m2 = k_r phi2, m3 = k_r phi3 (phi2 = -e3a.e1b, phi3 = e2a.e1b), and the seed's
    F_NC = | |f1| + sqrt(m2^2 + m3^2)/R + F_int |, M_NR1 = |(2/3) R |f1| + sqrt(m2^2 + m3^2) + M_int|
    (bending ignored in F_C and (2/3) R |f1| ignored in M_R1 when R = 0).  Then b slides and spins
    at once until both slip: CSFC = mu F_NC, CSMC1 = mu M_NR1 with those raised values.

    Tolerances: the reactions against k phi from the numpy reference (phi ~1e-3 from
    quaternions good to ~1e-16): 1e-9 N.m; F_NC, M_NR1 from the FMU's own reactions: 1e-12
    relative (a few flops); limits 1e-9 relative."""
    kr, mint, tilt, h = 1e4, 0.3, (2e-3, -1e-3), 1e-3
    params = {"constraint.stiffness": KC, "constraint.rotStiffness": kr, "friction.muStatic": MU,
              "friction.muKinetic": MU, "friction.R": radius, "friction.Fint": fint, "friction.Mint": mint,
              "friction.stickStiffness": KS, "friction.stickStiffnessR1": KSR}
    con = start(make_slave, params)
    # press and tilt after initialization (the SLIDE-PLANE target x0 is the initial x = 0)
    con.set(b_inputs(x=press(10.0), tilt=tilt))
    out = dict(zip(["CRF1", "CRM2", "CRM3", "CNF", "CNM1"], con.get(["CRF1", "CRM2", "CRM3", "CNF", "CNM1"])))
    p = _ref.planar([press(10.0), 0, 0], np.eye(3), _ref.quat_to_matrix(b_quat(0.0, tilt)))
    assert out["CRF1"] == pytest.approx(-10.0, abs=1e-9)
    assert out["CRM2"] == pytest.approx(kr * p["phi2"], abs=1e-9)
    assert out["CRM3"] == pytest.approx(kr * p["phi3"], abs=1e-9)

    def fnc(o):
        bend = math.hypot(o["CRM2"], o["CRM3"])
        return abs(abs(o["CRF1"]) + (bend / radius if radius > 0 else 0.0) + fint)

    def mnr1(o):
        return abs(2.0 / 3.0 * radius * abs(o["CRF1"]) + math.hypot(o["CRM2"], o["CRM3"]) + mint)

    assert out["CNF"] == pytest.approx(fnc(out), rel=1e-12)
    assert out["CNM1"] == pytest.approx(mnr1(out), rel=1e-12)
    if radius > 0 and fint > 0:
        assert out["CNF"] > 10.0 + fint + 40.0  # the bending term (~44.7 N) really counts

    # slide 4e-2 m and spin 1 rad over 400 steps: far beyond both stick ranges
    n = 400
    r = drive(con, line([0, 0, 0], [0.04, 0, 1.0], n), h, x=press(10.0), tilt=tilt)
    last = {k: r[k][-1] for k in ["CRF1", "CRM2", "CRM3"]}
    assert r["friction.status"][-1] == 2 and r["friction.statusR1"][-1] == 2
    assert r["CNF"][-1] == pytest.approx(fnc(last), rel=1e-12)
    assert r["CNM1"][-1] == pytest.approx(mnr1(last), rel=1e-12)
    assert r["CSFC"][-1] == pytest.approx(MU * fnc(last), rel=1e-9)
    assert r["CSMC1"][-1] == pytest.approx(MU * mnr1(last), rel=1e-9)
    # the spin turns the tilt with b but keeps its size: the bending magnitude is unchanged
    assert math.hypot(last["CRM2"], last["CRM3"]) == pytest.approx(math.hypot(out["CRM2"], out["CRM3"]), rel=1e-6)


# --------------------------------------------------------------------------
# path dependence
# --------------------------------------------------------------------------


def test_friction_direction_follows_a_turning_path(make_slave):
    """Slide +y until well into slip, then turn 90 deg and slide +z.  The elastic slip
    e (|e| = e0 = mu F_NC / k_s while slipping) is dragged round: for a rigid-plastic radial
    return dphi/ds = cos(phi)/e0, so the y-part of the force decays as
    CSF2 / CSFC = sech(z / e0) and the force points along +z within a few e0.

    Tolerances: the FMU returns radially once per step of length D = 1e-5 m = e0/80; that
    discrete map, e <- e0 (e + D e3)/|e + D e3|, stays within 0.0022 of sech(z/e0) over this
    path (worked out in numpy with the same D/e0; it is O(D/e0)), so the direction is compared
    with sech within 0.005; the magnitude
    stays on the limit to round-off (1e-9); at z = 5 e0, sech = 0.0135, we require
    |CSF2|/CSFC < 0.03 (and < 1e-3 at z = 10 e0, sech = 9e-5)."""
    h, d = 1e-3, 1e-5
    e0 = MU * N / KS  # 8e-4 m
    con = start(make_slave, {"friction.muStatic": MU, "friction.muKinetic": MU, "friction.Fint": N,
                             "friction.stickStiffness": KS})
    y1 = 5 * e0
    leg1 = line([0, 0, 0], [y1, 0, 0], int(round(y1 / d)))
    leg2 = line([y1, 0, 0], [y1, 10 * e0, 0], int(round(10 * e0 / d)))
    r1 = drive(con, leg1, h)
    assert r1["friction.status"][-1] == 2
    assert r1["CSF2"][-1] == pytest.approx(MU * N, rel=1e-9) and abs(r1["CSF3"][-1]) < 1e-12
    r2 = drive(con, leg2, h)
    # still slipping all along the turn (the trial leaves the limit circle at once)
    assert np.all(r2["friction.status"] == 2)
    assert np.allclose(r2["CSFC"], MU * N, rtol=1e-9, atol=0)
    c2, c3 = r2["CSF2"] / r2["CSFC"], r2["CSF3"] / r2["CSFC"]
    assert np.all(c2 > 0) and np.all(np.diff(c2) < 0) and np.all(np.diff(c3) > 0)
    expect = 1.0 / np.cosh(r2["z"] / e0)
    assert np.max(np.abs(c2 - expect)) < 0.005, np.max(np.abs(c2 - expect))
    at5 = np.searchsorted(r2["z"], 5 * e0)
    assert c2[at5] < 0.03 and c2[-1] < 1e-3 and c3[-1] > 1 - 1e-6
    # the accumulated slip keeps counting the path length beyond the elastic part
    assert r2["friction.slip"][-1] > r1["friction.slip"][-1] + 10 * e0 - 2 * e0


def test_status_stick_slip_stick(make_slave):
    """Rest, slide +y, stop, slide -y, stop: friction.status runs 1, 2, 1, 2, 1.
    mu_s = 0.5, mu_k = 0.3, d_c = 100 s/m (so at v = 0.01 m/s mu = 0.374): after a stop the
    limit is back at mu_s F_NC, above the kinetic force, so the stop is a clean stick (each slip
    run breaks away at mu_s F_NC: the stick force before it stays below that limit, and the slip
    force after it is mu at the slip rate, docs/physics.md "friction"); on
    reversal the stick spring unloads elastically (CSF2 falls by k_s per metre) until the force
    reaches the opposite limit.  Accumulated slip: constant in stick, growing in slip."""
    mus, muk, dc, h, v = 0.5, 0.3, 100.0, 1e-3, 0.01
    con = start(make_slave, {"friction.muStatic": mus, "friction.muKinetic": muk, "friction.decay": dc,
                             "friction.Fint": N, "friction.stickStiffness": KS})
    y1, y2 = 300 * v * h, 300 * v * h - 400 * v * h
    path = np.concatenate([line([0, 0, 0], [0, 0, 0], 10), line([0, 0, 0], [y1, 0, 0], 300)[1:],
                           line([y1, 0, 0], [y1, 0, 0], 50)[1:], line([y1, 0, 0], [y2, 0, 0], 400)[1:],
                           line([y2, 0, 0], [y2, 0, 0], 50)[1:]])
    r = drive(con, path, h)
    st = r["friction.status"]
    assert runs(st) == [1, 2, 1, 2, 1], runs(st)
    slip = r["friction.slip"]
    ds = np.diff(slip)
    assert np.all(ds[st[1:] == 1] == 0.0)
    assert np.all(ds[(st[1:] == 2) & (st[:-1] == 2)] > 0.0)
    # breakaway at mu_s F_NC: the stick force never exceeds it, and the step before each slip run
    # ends stuck below it; in the step that breaks away the force returns onto the limit at the
    # slip rate v, so every slip step (both directions) reports mu(v) F_NC, 1e-9 relative
    mu_v = mu_of(mus, muk, dc, v)
    first = (st == 2) & (np.r_[1, st[:-1]] != 2)
    assert first.sum() == 2
    assert np.all(np.abs(r["CSFC"][st == 1]) <= mus * N * (1 + 1e-12))
    before = np.flatnonzero(first) - 1
    assert np.all(r["CSFC"][before] > mu_v * N) and np.all(r["CSFC"][before] <= mus * N * (1 + 1e-12))
    assert np.allclose(r["CSFC"][st == 2], mu_v * N, rtol=1e-9, atol=0)
    # elastic unloading on reversal: from the held force, k_s per metre travelled back
    k_rev = 310 + 50  # first step of the reversal (index of its step end)
    f_hold = r["CSF2"][k_rev - 1]
    rev_stick = np.arange(k_rev, k_rev + 400)
    rev_stick = rev_stick[st[rev_stick] == 1]
    assert len(rev_stick) > 100
    assert np.allclose(r["CSF2"][rev_stick], f_hold - KS * (y1 - r["y"][rev_stick]), rtol=0, atol=1e-9)
    # the reversed slip holds b against -y: CSF2 < 0
    assert np.all(r["CSF2"][(st == 2) & (r["rate"][:, 0] < 0)] < 0)


def test_feedthrough_does_not_commit_friction(make_slave):
    """Outputs follow inputs at once with the committed state: a trial far beyond the limit
    reports slip at mu F_NC, but setting the inputs back (no doStep) returns the committed
    stick force exactly; only doStep commits.  Also the initial state has zero elastic slip
    even at an off-centre start (CU = 0, CSF = 0)."""
    h = 1e-3
    y0, z0 = 0.1, -0.05
    con = start(make_slave, {"friction.muStatic": MU, "friction.muKinetic": MU, "friction.Fint": N,
                             "friction.stickStiffness": KS, "cosim.extrapolation": 0}, y=y0, z=z0)
    init = con.get(["CU2", "CU3", "CSF2", "CSF3", "CSFC"])
    assert np.all(init == 0.0) and con.value("friction.status") == 1
    # stick: elastic force of a 2e-4 m offset, committed by a step (hold extrapolation)
    con.set(b_inputs(y0 + 2e-4, z0))
    con.step(h)
    committed = con.get(["CSF2", "CSF3", "friction.slip"])
    assert committed[0] == pytest.approx(KS * 2e-4, abs=1e-9) and committed[2] == 0.0
    # a big trial, read without stepping
    con.set(b_inputs(y0 + 5e-3, z0))
    assert con.value("friction.status") == 2
    assert con.value("CSFC") == pytest.approx(MU * N, rel=1e-12)
    # back: the committed state is untouched
    con.set(b_inputs(y0 + 2e-4, z0))
    assert np.array_equal(con.get(["CSF2", "CSF3", "friction.slip"]), committed)
    assert con.value("friction.status") == 1


def test_stick_damper_in_parallel_with_the_stick_spring(make_slave):
    """friction.stickDamping c (beyond Abaqus): in stick CSF2 = k_s y + c v, so breakaway comes
    where k_s y + c v = mu F_NC; in slip CSF2 = mu F_NC and the elastic slip relaxes to
    mu F_NC / k_s with time constant c/k_s (backward Euler: factor 1/(1 + k_s h/c) per step).
    The damper dissipates c v^2 per unit time in stick (trapezoidal rule; the first step starts
    from the damper force 0 at rest).  Tolerances: round-off (1e-9 N, 1e-12 J) and the decayed
    transient ((c v/k_s)·1.1^-170 < 1e-11 m)."""
    h, v, n, c = 1e-3, 0.01, 250, 100.0
    con = start(make_slave, {"friction.muStatic": MU, "friction.muKinetic": MU, "friction.Fint": N,
                             "friction.stickStiffness": KS, "friction.stickDamping": c})
    r = drive(con, line([0, 0, 0], [v * h * n, 0, 0], n), h)
    limit = MU * N
    trial = KS * r["y"] + c * v
    stick, slip = trial < limit * (1 - 1e-9), trial > limit * (1 + 1e-9)
    assert runs(r["friction.status"]) == [1, 2] and stick.sum() > 50 and slip.sum() > 150
    y_break = (limit - c * v) / KS                  # earlier than limit / KS without the damper
    assert np.all(r["y"][stick] < y_break) and np.all(r["y"][slip] > y_break)
    assert np.allclose(r["CSF2"][stick], trial[stick], rtol=0, atol=1e-9)
    assert np.allclose(r["CSF2"][slip], limit, rtol=0, atol=1e-9)
    k_stick = int(stick.sum())
    assert r["energy.friction"][k_stick - 1] == pytest.approx(c * v * v * h * (k_stick - 0.5), abs=1e-12)
    assert r["y"][-1] - r["friction.slip"][-1] == pytest.approx(limit / KS, abs=1e-11)
    # the stick spring stores the elastic part only (the transient left: 2·0.125·1.1^-180 = 9e-9)
    assert r["energy.stored"][-1] == pytest.approx(0.5 * limit**2 / KS, rel=2e-8)


# --------------------------------------------------------------------------
# coupled sliding and spin (beyond Abaqus: ellipsoidal limit, the disc's direction)
# --------------------------------------------------------------------------


def test_coupled_limit_is_the_ellipsoid(make_slave):
    """coupling = 1, R = 0.3 (rho = 2R/3 = 0.2): sliding at 0.01 m/s and spinning at 0.1 rad/s
    together; while both slip, |(CSF2, CSF3, CSM1/rho)| = mu F_NC (1e-9 relative), so the sliding
    force alone stays BELOW mu F_NC (spin takes its share: Contensou), unlike coupling = 0 where
    each effect reaches its own limit."""
    radius, h, n = 0.3, 1e-3, 400
    rho = 2 * radius / 3
    base = {"friction.muStatic": MU, "friction.muKinetic": MU, "friction.Fint": N, "friction.R": radius,
            "friction.Mint": 1.0, "friction.stickStiffness": KS, "friction.stickStiffnessR1": 50.0}
    path = line([0, 0, 0], [0.01 * h * n, 0, 0.1 * h * n], n)
    rc = drive(start(make_slave, {**base, "friction.coupling": 1}, name="coupled"), path, h)
    both = (rc["friction.status"] == 2) & (rc["friction.statusR1"] == 2)
    assert both.sum() > 100
    assert np.all(rc["friction.status"] == rc["friction.statusR1"])  # one limit, one status
    ell = np.sqrt(rc["CSF2"] ** 2 + rc["CSF3"] ** 2 + (rc["CSM1"] / rho) ** 2)
    assert np.allclose(ell[both], MU * rc["CNF"][both], rtol=1e-9, atol=0)
    assert np.all(ell[~both] < MU * rc["CNF"][~both] * (1 + 1e-12))
    assert np.all(rc["CSFC"][both] < MU * N * (1 - 1e-3))
    assert np.all(rc["CSMC1"][both] > 0)
    # uncoupled: each effect on its own limit
    ru = drive(start(make_slave, {**base, "friction.coupling": 0}, name="separate"), path, h)
    assert ru["CSFC"][-1] == pytest.approx(MU * N, rel=1e-9)
    assert ru["CSMC1"][-1] == pytest.approx(MU * ru["CNM1"][-1], rel=1e-9)


def disc_brute_force(eps, n=3000):
    """Friction force and moment of a uniformly loaded unit disc (units mu N, mu N R) sliding at
    eps and spinning at 1: midpoint rule over n radii x 2n angles of (v + w x r)/|v + w x r|
    (an independent computation: the FMU uses closed forms in elliptic integrals; agreement with
    them is ~1e-8 at n = 3000 away from the slip centre's singular point)."""
    r = (np.arange(n) + 0.5) / n
    ph = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    rr, pp = np.meshgrid(r, ph)
    x, y = rr * np.cos(pp), rr * np.sin(pp)
    ux, uy = eps - y, x
    w = rr / n * (np.pi / n) / np.pi / np.hypot(ux, uy)
    return float(np.sum(w * ux)), float(np.sum(w * (x * uy - y * ux)))


@pytest.mark.parametrize("ratio", [1 / 3, 3.0])
def test_coupled_force_direction_is_the_discs(make_slave, ratio):
    """coupling = 1: slide alone until slipping, then add spin so that v/(R w) = ratio.  In steady
    slip the force lies on the ellipsoid in the direction of a uniformly loaded disc sliding and
    spinning at that ratio (Contensou): (CSF2, CSM1/rho) = mu F_NC (F, R M/rho)/|(F, R M/rho)|,
    F, M from `disc_brute_force`.  Tolerance 1e-6 relative: quadrature (~1e-8) plus the
    transient of the stick springs after a travel of 1000 elastic slips."""
    radius, h, v = 0.3, 1e-3, 0.01
    rho = 2 * radius / 3
    con = start(make_slave, {"friction.muStatic": MU, "friction.muKinetic": MU, "friction.Fint": N,
                             "friction.R": radius, "friction.stickStiffness": KS,
                             "friction.stickStiffnessR1": KS * rho**2, "friction.coupling": 1})
    n1, n2 = 200, 1000
    y1 = v * h * n1
    r1 = drive(con, line([0, 0, 0], [y1, 0, 0], n1), h)
    assert r1["friction.status"][-1] == 2 and r1["CSF2"][-1] == pytest.approx(MU * N, rel=1e-9)
    w = v / (radius * ratio)
    r2 = drive(con, line([y1, 0, 0], [y1 + v * h * n2, 0, w * h * n2], n2), h)
    assert np.all(r2["friction.status"] == 2)
    f, m = disc_brute_force(ratio)
    size = math.hypot(f, radius * m / rho)
    assert r2["CSF2"][-1] == pytest.approx(MU * N * f / size, rel=1e-6)
    assert r2["CSM1"][-1] / rho == pytest.approx(MU * N * radius * m / rho / size, rel=1e-6)


# --------------------------------------------------------------------------
# refusals
# --------------------------------------------------------------------------


BAD = [
    ({"friction.muStatic": -0.1}, ["friction.muStatic"]),
    ({"friction.muStatic": 0.5, "friction.muKinetic": -0.1}, ["friction.muKinetic"]),
    ({"friction.muStatic": 0.3, "friction.muKinetic": 0.5}, ["friction.muKinetic", "friction.muStatic"]),
    ({"friction.muStatic": 0.3, "friction.stickStiffness": 0.0}, ["friction.stickStiffness"]),
    ({"friction.muStatic": 0.3, "friction.stickStiffnessR1": 0.0}, ["friction.stickStiffnessR1"]),
    ({"friction.muStatic": 0.3, "friction.stickStiffness": -1e4}, ["friction.stickStiffness"]),
    ({"friction.R": -0.1}, ["friction.R"]),
]


@pytest.mark.parametrize("bad,names", BAD, ids=[", ".join(f"{k}={v}" for k, v in b.items()) for b, _ in BAD])
def test_bad_friction_parameters_are_refused(make_slave, bad, names):
    """Refused when set or, at the latest, at fmi2ExitInitializationMode, with an error logged
    whose message names the parameter(s)."""
    log = []
    s = make_slave("Planar", log=log)
    con = Connector("Planar", s)
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    refused = False
    try:
        con.set(bad)
    except FMICallException:
        refused = True
    if refused:
        # refused at the setter: the bad value was not stored
        assert con.value(names[0]) != bad[names[0]]
    else:
        with pytest.raises(FMICallException):
            s.exitInitializationMode()
    errors = [m for (status, _, m) in log if status >= 3]
    assert errors, log
    assert any(all(nm in m for nm in names) for m in errors), errors


def test_good_friction_parameters_are_accepted(make_slave):
    """The boundary cases of the refusals are legal: mu_k = mu_s, mu = 0, R = 0."""
    log = []
    con = Connector("Planar", make_slave("Planar", log=log))
    con.start({"friction.muStatic": 0.3, "friction.muKinetic": 0.3, "friction.R": 0.0}, A_INPUTS)
    con.step(1e-3)
    assert not [m for (status, _, m) in log if status >= 2]


# --------------------------------------------------------------------------
# energy balance over a long friction cycle
# --------------------------------------------------------------------------


DAMPED_STICK = {"friction.stickDamping": 40.0, "friction.stickDampingR1": 0.1}


@pytest.mark.parametrize("extra", [{}, DAMPED_STICK, {**DAMPED_STICK, "friction.coupling": 1}],
                         ids=["abaqus", "stick-dampers", "coupled-stick-dampers"])
def test_energy_balance_long_friction_cycle(make_slave, extra):
    """Several back-and-forth slides with spin, springs, dampers, a damped stop and a pressed,
    tilted puck: the work done on the connector
        W = sum_k integral of -(b.f . v_b + b.m . w_b) dt     (node a is fixed)
    equals  Delta energy.stored + energy.damping + energy.friction + energy.stops.

    W is the trapezoid over each step of the loads read just after setting the inputs at t_k
    and just after the step; the velocities are the ones prescribed (constant over the step,
    the path is piecewise linear).  Springs and dampers are integrated exactly that way; what is
    not is where the force has a kink inside a step (stick/slip, stop contact) and the friction
    force that changes with the slip rate while slipping: both O(h) per event / O(h) overall.
    Tolerance: 1e-3 of the total dissipated energy, with h = 1e-4 (20000 steps). Also with
    stick dampers (their work on the elastic slip counts as friction dissipation) and with the
    coupled limit."""
    h, tend = 1e-4, 2.0
    params = {
        "constraint.stiffness": KC, "constraint.rotStiffness": 1e4,
        "elasticity.k2": 200.0, "elasticity.k3": 300.0, "elasticity.k4": 2.0,
        "damping.c2": 2.0, "damping.c3": 1.0, "damping.c4": 0.05,
        "stop.upper2": 0.015, "stop.stiffness": 1e4, "stop.damping": 50.0,
        "friction.muStatic": 0.5, "friction.muKinetic": 0.3, "friction.decay": 20.0,
        "friction.R": 0.2, "friction.Fint": 10.0, "friction.Mint": 0.2,
        "friction.stickStiffness": 2e4, "friction.stickStiffnessR1": 50.0, **extra,
    }
    x, tilt = press(15.0), (1e-3, 5e-4)
    con = start(make_slave, params)
    t = h * np.arange(int(round(tend / h)) + 1)
    path = np.stack([0.02 * np.sin(2 * math.pi * 1.5 * t),
                     0.015 * np.sin(2 * math.pi * 1.0 * t + 0.7) - 0.015 * math.sin(0.7),
                     0.3 * np.sin(2 * math.pi * 2.0 * t)], axis=1)
    rate = np.diff(path, axis=0) / h
    names = ["b.f[1]", "b.f[2]", "b.f[3]", "b.m[1]", "b.m[2]", "b.m[3]"]
    # press and tilt at t = 0 (the penalty springs load up through direct feedthrough; this is
    # the starting stored energy, not work along the path)
    con.set(b_inputs(*path[0], *rate[0], x=x, tilt=tilt))
    e_start = con.get(["energy.stored", "energy.damping", "energy.friction", "energy.stops"])
    W = 0.0
    status_seen = set()
    for k in range(len(rate)):
        con.set(b_inputs(*path[k], *rate[k], x=x, tilt=tilt))
        pre = con.get(names)
        con.step(h)
        post = con.get(names)
        status_seen.add(int(con.value("friction.status")))
        # node b's velocity: (0, vy, vz); angular velocity (w1, 0, 0)
        vel = np.array([0.0, rate[k, 0], rate[k, 1], rate[k, 2], 0.0, 0.0])
        W -= 0.5 * float((pre + post) @ vel) * h
    e = con.get(["energy.stored", "energy.damping", "energy.friction", "energy.stops"])
    dissipated = e[1] + e[2] + e[3] - (e_start[1] + e_start[2] + e_start[3])
    balance = (e[0] - e_start[0]) + dissipated
    assert status_seen >= {1, 2}
    assert e[2] > 0.1 * dissipated and e[3] > 0 and e[1] > 0  # every account takes part
    assert abs(W - balance) <= 1e-3 * dissipated, (W, balance, e, e_start)
