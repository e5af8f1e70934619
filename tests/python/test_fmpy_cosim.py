"""FMI 2.0 Co-Simulation capabilities of the connector FMUs, through fmpy's low-level
FMU2Slave API (docs/fmi.md):

  1. rollback with fmi2Get/SetFMUstate (bit for bit), serialized states restored into a fresh
     instance, corrupt / truncated / foreign serialized states refused, serialized size;
  2. fmi2GetDirectionalDerivative against central finite differences through the ABI;
  3. convergence order of the input extrapolation (hold O(H), linear O(H^2), input
     derivatives O(H^2));
  4. variable communication step size;
  5. several instances driven from different threads;
  6. fmi2GetRealStatus / fmi2GetBooleanStatus / fmi2Reset;
  7. the acceleration inputs (cosim.extrapolation = 3): a closed form, the same path as the
     velocities' input derivatives, ignored below 3, no output depends on them, O(H^3) pose.

Expected values never come from the FMU's internals: they are closed forms of the prescribed
motion, repeated runs (bitwise), finite differences through the ABI, or the FMU's own algebraic
outputs at the exact inputs (outputs are a function of the inputs at the current instant and
the committed state, docs/fmi.md "direct feedthrough").
"""

from __future__ import annotations

import math
import threading

import numpy as np
import pytest
from fmpy.fmi1 import FMICallException

import _ref
from conftest import VARIANTS, Connector, model_description, parameter_sets, vr

fmi2LastSuccessfulTime = 2  # fmi2StatusKind
fmi2Terminated = 3
EPS = np.finfo(float).eps


# ==========================================================================
# driver: conftest's Connector (scripts/cosim/driver.py), one per instance from make_slave
# ==========================================================================


@pytest.fixture
def conn(make_slave):
    count = [0]

    def make(variant, log=None):
        count[0] += 1
        return Connector(variant, make_slave(variant, instance_name=f"{variant}-{count[0]}", log=log))

    return make


def loads_of(variant):
    return [f"{n}[{j}]" for n in _ref.VARIANTS[variant]["loads"] for j in (1, 2, 3)]


def totals_of(variant):
    return sorted(n for n in vr(variant) if n.startswith("CTF") or n.startswith("CTM"))


def viscous_of(variant):
    return sorted(n for n in vr(variant) if n[:3] in ("CVF", "CVM"))


def elastic_of(variant):
    return sorted(n for n in vr(variant) if n[:3] in ("CEF", "CEM") or n.startswith("CP"))


# ==========================================================================
# prescribed motions (closed forms)
# ==========================================================================

QA0 = _ref.quat_exp([0.3, -0.2, 0.5])
RA0 = _ref.quat_to_matrix(QA0)
RA_POS = np.array([0.1, 0.2, -0.3])
N1 = np.array([1.0, 0.0, 0.0])
N2 = np.array([0.3, 0.5, 0.8]) / np.linalg.norm([0.3, 0.5, 0.8])


def _pure(v):
    return np.concatenate([[0.0], v])


class Smooth:
    """Node a fixed (RA_POS, QA0); node b moves smoothly:
        r_b(t) = r_a + D0 + (A1 sin w1 t, A2 (1 - cos w2 t), A3 sin w3 t)
        q_b(t) = exp(phi(t) n1) * exp(psi(t) n2) * QB0,  phi = P sin(w4 t), psi = S (1 - cos w5 t)
    with exact velocity, world angular velocity, quaternion derivative and accelerations."""

    D0 = np.array([0.4, 0.3, 0.6])
    A = np.array([0.05, 0.04, 0.03])
    W = np.array([3.0, 4.0, 5.0])
    P, W4 = 0.4, 3.0
    S, W5 = 0.3, 4.0
    QB0 = _ref.quat_mul(QA0, _ref.quat_exp([0.2, 0.1, 0.3]))

    def __init__(self, variant):
        self.variant = variant

    def r(self, t):
        A, W = self.A, self.W
        return RA_POS + self.D0 + np.array([A[0] * math.sin(W[0] * t), A[1] * (1 - math.cos(W[1] * t)), A[2] * math.sin(W[2] * t)])

    def v(self, t):
        A, W = self.A, self.W
        return np.array([A[0] * W[0] * math.cos(W[0] * t), A[1] * W[1] * math.sin(W[1] * t), A[2] * W[2] * math.cos(W[2] * t)])

    def a(self, t):
        A, W = self.A, self.W
        return np.array([-A[0] * W[0] ** 2 * math.sin(W[0] * t), A[1] * W[1] ** 2 * math.cos(W[1] * t), -A[2] * W[2] ** 2 * math.sin(W[2] * t)])

    def angles(self, t):
        phi, dphi, ddphi = self.P * math.sin(self.W4 * t), self.P * self.W4 * math.cos(self.W4 * t), -self.P * self.W4**2 * math.sin(self.W4 * t)
        psi, dpsi, ddpsi = self.S * (1 - math.cos(self.W5 * t)), self.S * self.W5 * math.sin(self.W5 * t), self.S * self.W5**2 * math.cos(self.W5 * t)
        return phi, dphi, ddphi, psi, dpsi, ddpsi

    def q(self, t):
        phi, _, _, psi, _, _ = self.angles(t)
        return _ref.quat_mul(_ref.quat_exp(phi * N1), _ref.quat_mul(_ref.quat_exp(psi * N2), self.QB0))

    def w(self, t):
        phi, dphi, _, psi, dpsi, _ = self.angles(t)
        return dphi * N1 + _ref.rotvec_to_matrix(phi * N1) @ (dpsi * N2)

    def wdot(self, t):
        phi, dphi, ddphi, psi, dpsi, ddpsi = self.angles(t)
        R1 = _ref.rotvec_to_matrix(phi * N1)
        return ddphi * N1 + R1 @ (ddpsi * N2) + np.cross(dphi * N1, R1 @ (dpsi * N2))

    def qdot(self, t):
        """d/dt of q_b by the product rule (independent of w(t); a self-test checks
        qdot = 1/2 w * q)."""
        phi, dphi, _, psi, dpsi, _ = self.angles(t)
        e1, e2 = _ref.quat_exp(phi * N1), _ref.quat_exp(psi * N2)
        d1 = _ref.quat_mul(_pure(0.5 * dphi * N1), e1)
        d2 = _ref.quat_mul(_pure(0.5 * dpsi * N2), e2)
        return _ref.quat_mul(d1, _ref.quat_mul(e2, self.QB0)) + _ref.quat_mul(e1, _ref.quat_mul(d2, self.QB0))

    def pose(self, t, zero_velocity=False):
        z = np.zeros(3)
        return {
            "a.r": RA_POS, "a.q": QA0, "a.v": z, "a.w": z,
            "b.r": self.r(t), "b.q": self.q(t),
            "b.v": z if zero_velocity else self.v(t), "b.w": z if zero_velocity else self.w(t),
        }

    def inputs(self, t, zero_velocity=False):
        return _ref.pose_to_inputs(self.variant, self.pose(t, zero_velocity))

    def derivatives(self, t, which="rq"):
        """{input name: first derivative} for fmi2SetRealInputDerivatives: r and q of node b
        (node a is fixed: zero), and with which='rqvw' also v and w (accelerations)."""
        spec = _ref.VARIANTS[self.variant]
        out = {}
        for node in ("a", "b"):
            for kind in spec[node]:
                if kind not in which:
                    continue
                if kind == "q":
                    val = self.qdot(t) if node == "b" else np.zeros(4)
                    out.update({f"{node}.q.{c}": float(x) for c, x in zip("wxyz", val)})
                else:
                    val = {"r": self.v, "v": self.a, "w": self.wdot}[kind](t) if node == "b" else np.zeros(3)
                    out.update({f"{node}.{kind}[{j + 1}]": float(val[j]) for j in range(3)})
        return out


def spring_damper_params(variant, damping=True):
    """Deterministic springs (trans 800-1500 N/m, rot 40-60 N.m/rad) and dampers (`spring_damper`
    of tests/data/parameter_sets.json, shared with benches/native/)."""
    sd = parameter_sets()["spring_damper"]
    kt, kr = sd["k_translational"], sd["k_rotational"]
    ct, cr = sd["c_translational"], sd["c_rotational"]
    p = {}
    for _name, k in _ref.components_of(variant):
        p[f"elasticity.k{k}"] = kt[k - 1] if k <= 3 else kr[k - 4]
        p[f"damping.c{k}"] = (ct[k - 1] if k <= 3 else cr[k - 4]) if damping else 0.0
    return p


class PlanarSlide:
    """Planar, node a fixed; node b slides in a's 2-3 plane back and forth along a parabolic arc
    (the sliding direction turns along the arc; both velocity components vanish at its ends, so
    the friction sticks there) and spins about e1a:
        b = a + Ra (X0, Y0 + A s, Z0 + B s^2), s = sin wt,   q_b = q_a * exp(psi(t) e1),
        psi = PSI0 + PS sin(1.5 wt).  Exact velocities. The constants are `planar_slide` of
    tests/data/parameter_sets.json (the native benchmark drives the same path)."""

    _p = parameter_sets()["planar_slide"]
    X0, Y0, Z0 = _p["X0"], _p["Y0"], _p["Z0"]
    A, B, OM = _p["A"], _p["B"], 2.0 * math.pi
    PSI0, PS = _p["PSI0"], _p["PS"]

    def pose(self, t):
        om = self.OM
        s, ds = math.sin(om * t), om * math.cos(om * t)
        rel = np.array([self.X0, self.Y0 + self.A * s, self.Z0 + self.B * s * s])
        drel = np.array([0.0, self.A * ds, 2 * self.B * s * ds])
        psi = self.PSI0 + self.PS * math.sin(1.5 * om * t)
        dpsi = 1.5 * om * self.PS * math.cos(1.5 * om * t)
        return {
            "a.r": RA_POS, "a.q": QA0, "a.v": np.zeros(3), "a.w": np.zeros(3),
            "b.r": RA_POS + RA0 @ rel, "b.q": _ref.quat_mul(QA0, _ref.quat_exp([psi, 0.0, 0.0])),
            "b.v": RA0 @ drel, "b.w": dpsi * RA0[:, 0],
        }

    def inputs(self, t):
        return _ref.pose_to_inputs("Planar", self.pose(t))


# `planar_friction` of tests/data/parameter_sets.json (shared with benches/native/): friction
# F_NC = |f1| + Fint = 100 N (f1 ~ 0 on this path), limit mu F_NC = 40 N (30 N kinetic), stick
# range 40 N / 1e4 N/m = 4 mm << amplitude 20 mm: every reversal sticks for ~0.15 s, the rest
# slips. Spin: M_NR1 ~ Mint = 2 N.m, range 0.8 N.m / 100 N.m/rad = 8 mrad << 50 mrad. Here also a
# stop on u2 at 60 % of the amplitude, hit twice per period.
PLANAR_FRICTION = {
    **dict(parameter_sets()["planar_friction"]["values"]),
    "stop.upper2": PlanarSlide.Y0 + 0.6 * PlanarSlide.A, "stop.stiffness": 1.0e5, "stop.damping": 10.0,
}


def scenario(variant):
    """(params, inputs_at(t)) of a run with springs, dampers, a stop (and friction for Planar)."""
    if variant == "Planar":
        m = PlanarSlide()
        return dict(PLANAR_FRICTION), m.inputs
    m = Smooth(variant)
    params = spring_damper_params(variant)
    # an upper stop on the first component, at 70 % of its excursion over [0, 2] s (positions of
    # the prescribed path from the independent reference kinematics)
    name, k = _ref.components_of(variant)[0]
    vals = [_ref.positions(variant, m.pose(t))[name] for t in np.linspace(0.0, 2.0, 401)]
    params[f"stop.upper{k}"] = min(vals) + 0.7 * (max(vals) - min(vals))
    params["stop.stiffness" if k <= 3 else "stop.rotStiffness"] = 1.0e4 if k <= 3 else 500.0
    return params, m.inputs


def test_closed_forms_are_consistent():
    """Self-check of the prescribed motions (no FMU): velocities, angular velocities,
    quaternion derivatives and accelerations against central differences of the positions
    (h = 1e-6, error ~1e-9 of O(1) rates); qdot = 1/2 w * q."""
    m = Smooth("Bushing")
    h = 1e-6
    for t in np.linspace(0.0, 1.0, 7):
        assert np.allclose((m.r(t + h) - m.r(t - h)) / (2 * h), m.v(t), atol=1e-8)
        assert np.allclose((m.v(t + h) - m.v(t - h)) / (2 * h), m.a(t), atol=1e-7)
        assert np.allclose((m.w(t + h) - m.w(t - h)) / (2 * h), m.wdot(t), atol=1e-7)
        assert np.allclose((m.q(t + h) - m.q(t - h)) / (2 * h), m.qdot(t), atol=1e-8)
        assert np.allclose(m.qdot(t), 0.5 * _ref.quat_mul(_pure(m.w(t)), m.q(t)), atol=1e-14)
    p = PlanarSlide()
    for t in np.linspace(0.0, 1.0, 7):
        P0, P1, Pm = p.pose(t), p.pose(t + h), p.pose(t - h)
        assert np.allclose((P1["b.r"] - Pm["b.r"]) / (2 * h), P0["b.v"], atol=1e-8)
        dq = (P1["b.q"] - Pm["b.q"]) / (2 * h)
        assert np.allclose(dq, 0.5 * _ref.quat_mul(_pure(P0["b.w"]), P0["b.q"]), atol=1e-8)


# ==========================================================================
# 1. rollback, serialization, corrupt states
# ==========================================================================

H_ROLL = 0.005
N_ROLL = 100


def _survey_planar(conn):
    """Runs the Planar friction scenario once; returns the statuses after every step."""
    params, inputs_at = scenario("Planar")
    c = conn("Planar").start(params, inputs_at(0.0))
    status, status_r1, stop = [], [], []
    for _ in range(400):
        c.set(inputs_at(c.t))
        c.step(H_ROLL)
        status.append(c.value("friction.status"))
        status_r1.append(c.value("friction.statusR1"))
        stop.append(c.value("CSLST2"))
    return status, status_r1, stop


def _rollback_check(c, inputs_at, n_before):
    """Runs n_before steps, saves the state, records N_ROLL steps, restores, repeats (twice),
    asserts the repeated runs equal the first bit for bit, and returns (record at the save point,
    records right after each restore, first run, state handle, save time)."""
    c.drive(inputs_at, n_before, H_ROLL, record=False)
    t_save = c.t
    before = c.record()
    state = c.s.getFMUstate()
    first = c.drive(inputs_at, N_ROLL, H_ROLL)
    restored = []
    for _ in range(2):  # restoring twice must give the same run twice
        c.s.setFMUstate(state)
        c.t = t_save
        restored.append(c.record())
        again = c.drive(inputs_at, N_ROLL, H_ROLL)
        # bit for bit: == on every float, no tolerance (docs/fmi.md)
        assert again == first
    return before, restored, first, state, t_save


def _record_diff(c, a, b):
    """Names and values where two records differ (for failure messages)."""
    names = [[r.name for r in c.real_out], [r.name for r in c.int_out], [r.name for r in c.real_in], ["time"]]
    out = {}
    for grp, (x, y) in enumerate(zip(a, b)):
        if grp == 3:
            x, y = (x,), (y,)
        for n, u, w in zip(names[grp], x, y):
            if u != w:
                out[n] = (u, w)
    return out


def _fresh_restore(conn, variant, data, t_save):
    """A FRESH instance (instantiate, setupExperiment, enter/exit initialization with default
    values), then fmi2DeSerializeFMUstate + fmi2SetFMUstate."""
    fresh = conn(variant)
    fresh.s.setupExperiment(startTime=0.0)
    fresh.s.enterInitializationMode()
    fresh.s.exitInitializationMode()
    st2 = fresh.s.deSerializeFMUstate(data)
    fresh.s.setFMUstate(st2)
    fresh.s.freeFMUstate(st2)
    fresh.t = t_save
    return fresh


@pytest.mark.parametrize("phase", ["stick", "slip"])
def test_rollback_planar_friction_bitwise(conn, phase):
    status, status_r1, stop = _survey_planar(conn)
    # the scenario really has both friction phases and the stop engaged (else the test is void)
    assert 1 in status and 2 in status, status
    assert 1 in status_r1 and 2 in status_r1, status_r1
    assert 1 in stop, "the stop on u2 is never reached"
    want = 1 if phase == "stick" else 2
    i_save = next(i for i in range(60, len(status) - N_ROLL) if status[i] == want)
    params, inputs_at = scenario("Planar")

    c = conn("Planar").start(params, inputs_at(0.0))
    before, _restored, first, state, t_save = _rollback_check(c, inputs_at, i_save + 1)
    # saved mid-run in the wanted phase (status after step i_save); the recorded window sees
    # stick/slip transitions (and, from the stick save, the stop)
    statuses = [r[1][c.int_out.index(c.v["friction.status"])] for r in first]
    stops = [r[1][c.int_out.index(c.v["CSLST2"])] for r in first]
    assert before[1][c.int_out.index(c.v["friction.status"])] == want
    assert len(set(statuses)) >= 2, statuses
    assert 1 in stops or phase == "slip", stops

    # serialized state into a FRESH instance continues identically
    data = c.s.serializeFMUstate(state)
    assert isinstance(data, bytes) and len(data) <= 1024, len(data)
    c.s.freeFMUstate(state)
    fresh = _fresh_restore(conn, "Planar", data, t_save)
    assert fresh.drive(inputs_at, N_ROLL, H_ROLL) == first


@pytest.mark.parametrize("coupling", [0, 1])
def test_rollback_planar_stick_dampers_bitwise(conn, coupling):
    """The same rollback and serialization checks with stick dampers, whose elastic slip and
    plastic slip rate are part of the FMU state, uncoupled and coupled. Uncoupled: saved in
    stick, the recorded window also slips (found by a survey run). Coupled: on this path the
    spin keeps the coupled limit slipping through the reversals, so the window is all slip."""
    params, inputs_at = scenario("Planar")
    params.update({"friction.coupling": coupling, "friction.stickDamping": 200.0,
                   "friction.stickDampingR1": 0.5})
    survey = conn("Planar").start(params, inputs_at(0.0))
    status = [r[1][survey.int_out.index(survey.v["friction.status"])]
              for r in survey.drive(inputs_at, 400, H_ROLL)]
    want = {1, 2} if coupling == 0 else {2}
    i_save = next(i for i in range(20, len(status) - N_ROLL)
                  if status[i] == min(want) and set(status[i + 1:i + 1 + N_ROLL]) == want)
    c = conn("Planar").start(params, inputs_at(0.0))
    _before, _restored, first, state, t_save = _rollback_check(c, inputs_at, i_save + 1)
    assert {r[1][c.int_out.index(c.v["friction.status"])] for r in first} == want
    data = c.s.serializeFMUstate(state)
    assert len(data) <= 1024, len(data)
    c.s.freeFMUstate(state)
    assert _fresh_restore(conn, "Planar", data, t_save).drive(inputs_at, N_ROLL, H_ROLL) == first


@pytest.mark.parametrize("variant", VARIANTS)
def test_restored_state_reports_the_saved_values(conn, variant):
    """Right after fmi2SetFMUstate (same instance, or a fresh one from the serialized bytes)
    every output, input and the time read exactly what they read when fmi2GetFMUstate was
    called (the FMU state is the whole observable state of the slave; a master that rolls back
    and re-reads the outputs must see the same values). Saved mid-run right after a step (the
    common case: save at a communication point, step, reject, restore)."""
    params, inputs_at = scenario(variant)
    c = conn(variant).start(params, inputs_at(0.0))
    diffs = {}
    for n in range(1, 81):
        c.set(inputs_at(c.t))
        c.step(H_ROLL)
        if n % 4:
            continue
        before = c.record()
        state = c.s.getFMUstate()
        c.s.setFMUstate(state)
        d_same = _record_diff(c, before, c.record())
        data = c.s.serializeFMUstate(state)
        c.s.freeFMUstate(state)
        fresh = _fresh_restore(conn, variant, data, c.t)
        d_fresh = _record_diff(fresh, before, fresh.record())
        if d_same or d_fresh:
            diffs[f"after step {n}"] = {"same instance": d_same, "fresh instance": d_fresh}
    assert not diffs, f"{len(diffs)} of 20 save points differ; first: {next(iter(diffs.items()))}"


def _corruptions(data, foreign):
    """(label, bytes) of corrupt versions of a serialized state."""
    out = []
    for i in range(len(data)):
        for mask in (0x01, 0x80, 0xFF):  # lowest bit, highest bit, whole byte
            b = bytearray(data)
            b[i] ^= mask
            out.append((f"byte {i} ^ {mask:#04x}", bytes(b)))
    for n in sorted({0, 1, 4, 8, len(data) // 2, len(data) - 9, len(data) - 8, len(data) - 1}):
        out.append((f"truncated to {n} bytes", data[:n]))
    out.append(("one byte appended", data + b"\x00"))
    out.append(("8 bytes appended", data + bytes(8)))
    for v, other in foreign.items():
        out.append((f"state of {v}", other))
    return out


def test_corrupt_serialized_state_refused_instance_unchanged(conn):
    params, inputs_at = scenario("Planar")
    # a foreign state of every other variant (after a few steps of its own scenario)
    foreign = {}
    for v in VARIANTS:
        if v == "Planar":
            continue
        p, f = scenario(v)
        o = conn(v).start(p, f(0.0))
        o.drive(f, 5, H_ROLL, record=False)
        st = o.s.getFMUstate()
        foreign[v] = o.s.serializeFMUstate(st)
        o.s.freeFMUstate(st)

    log = []
    c = conn("Planar", log=log)
    c.start(params, inputs_at(0.0))
    c.drive(inputs_at, 150, H_ROLL, record=False)
    st = c.s.getFMUstate()
    data = c.s.serializeFMUstate(st)
    c.s.freeFMUstate(st)
    t0 = c.t
    before = c.record()

    accepted = []
    for label, bad in _corruptions(data, foreign):
        n_log = len(log)
        try:
            st_bad = c.s.deSerializeFMUstate(bad)
        except FMICallException as e:
            assert e.status == 3, (label, e.status)  # fmi2Error
            msgs = [m for (s, _cat, m) in log[n_log:] if s >= 3]
            assert msgs and "fmi2DeSerializeFMUstate" in msgs[-1], (label, log[n_log:])
            continue
        c.s.freeFMUstate(st_bad)
        accepted.append(label)
    assert not accepted, f"corrupt serialized states accepted: {accepted[:20]} ({len(accepted)} in all)"

    # instance unchanged: every output, input and the time are as before, and the run goes on
    # exactly as from the good state restored in a fresh instance
    assert c.record() == before
    cont = c.drive(inputs_at, 50, H_ROLL)
    fresh = _fresh_restore(conn, "Planar", data, t0)
    assert fresh.drive(inputs_at, 50, H_ROLL) == cont


SERIALIZED_SIZES = {}


@pytest.mark.parametrize("variant", VARIANTS)
def test_serialized_state_every_variant(conn, variant, record_property, capsys):
    """Rollback and fresh-instance restore for every variant (springs, dampers, a stop);
    serialized size <= 1024 bytes (reported)."""
    params, inputs_at = scenario(variant)
    c = conn(variant).start(params, inputs_at(0.0))
    before, _restored, first, state, t_save = _rollback_check(c, inputs_at, 37)
    data = c.s.serializeFMUstate(state)
    # serializing the same state twice gives the same bytes
    assert c.s.serializeFMUstate(state) == data
    c.s.freeFMUstate(state)
    SERIALIZED_SIZES[variant] = len(data)
    record_property("serialized_size", len(data))
    with capsys.disabled():
        print(f"\n[serialized FMU state] {variant}: {len(data)} bytes")
    assert len(data) <= 1024, f"{variant}: serialized state is {len(data)} bytes"
    fresh = _fresh_restore(conn, variant, data, t_save)
    assert fresh.drive(inputs_at, N_ROLL, H_ROLL) == first


# ==========================================================================
# 2. directional derivatives against central finite differences through the ABI
# ==========================================================================
#
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


# ==========================================================================
# 3. convergence order of the input extrapolation (Bushing)
# ==========================================================================

T_END = 0.4
H_SWEEP = [0.04, 0.02, 0.01, 0.005]


def _run_to_T(conn, H, extrap, damping, source):
    """Bushing from t = 0 to T_END in steps H; the master sets the closed-form inputs at the
    communication points only. source: 'vel' (velocity inputs drive the extrapolation),
    'der_rq' (input derivatives of r and q, velocity inputs zero, no damping),
    'der_all' (input derivatives of r, q, v, w; true velocity inputs).
    Returns (outputs after the last step, outputs at the exact inputs at T) by name."""
    m = Smooth("Bushing")
    names = loads_of("Bushing") + totals_of("Bushing") + elastic_of("Bushing") + viscous_of("Bushing")
    params = spring_damper_params("Bushing", damping)
    params["cosim.extrapolation"] = extrap
    zero_v = source == "der_rq"
    c = conn("Bushing").start(params, m.inputs(0.0, zero_v))
    n = int(round(T_END / H))
    for i in range(n):
        t = i * H
        c.set(m.inputs(t, zero_v))
        if source != "vel":
            d = m.derivatives(t, "rq" if source == "der_rq" else "rqvw")
            c.s.setRealInputDerivatives([c.v[k] for k in d], [1] * len(d), list(d.values()))
        c.s.doStep(currentCommunicationPoint=t, communicationStepSize=H)
    got = c.get(names)
    c.set(m.inputs(T_END, zero_v))
    exact = c.get(names)
    return dict(zip(names, got)), dict(zip(names, exact))


def _error(got, exact, names):
    scale = max(abs(exact[n]) for n in names)
    return max(abs(got[n] - exact[n]) for n in names) / scale


def _slope(Hs, errs):
    return float(np.polyfit(np.log(Hs), np.log(errs), 1)[0])


def test_convergence_order_of_extrapolation(conn, capsys):
    """Error at T = 0.4 s of the outputs after the last step against the outputs at the exact
    inputs at T (the outputs are algebraic in the inputs at T and the committed state; Bushing
    has no path-dependent force state), for H = 0.04 ... 0.005 (T/H integer).

    Expected: hold -> the outputs at T reflect the pose at T - H: O(H). Linear extrapolation from
    the velocity inputs -> pose error O(H^2); the velocity inputs themselves are held over the
    step (they have no derivative unless input derivatives of v, w are given), so the DAMPER part
    stays O(H): with dampers on only the pose-algebraic outputs (CP/CPR, CEF/CEM) converge at
    O(H^2); with dampers off all outputs do. Input derivatives: of r and q (velocity inputs zero,
    so only the derivatives can make the step second order), and of r, q, v, w with dampers on:
    every output O(H^2).

    (Measured: hold 0.94-0.96; linear elastic / springs-only / input derivatives 1.98-2.01;
    viscous part under linear extrapolation ~1; damped totals ~1.4 = a mixture.)

    Slopes are least-squares fits of log(err) over log(H) (4 points); bounds: first order in
    [0.8, 1.2], second order >= 1.8, and linear >= hold + 0.8 on the same outputs."""
    LOADS = loads_of("Bushing") + totals_of("Bushing")
    ELAST = elastic_of("Bushing")
    VISC = viscous_of("Bushing")
    cases = {
        # label: (extrap, damping, source, outputs)
        "hold, dampers, loads+CTF/CTM": (0, True, "vel", LOADS),
        "hold, dampers, CP/CEF": (0, True, "vel", ELAST),
        "hold, springs only, loads+CTF/CTM": (0, False, "vel", LOADS),
        "linear v, dampers, CP/CEF": (1, True, "vel", ELAST),
        "linear v, dampers, loads+CTF/CTM": (1, True, "vel", LOADS),
        "linear v, dampers, CVF/CVM": (1, True, "vel", VISC),
        "linear v, springs only, loads+CTF/CTM": (1, False, "vel", LOADS),
        "der r,q (v=0), springs only, loads+CTF/CTM": (1, False, "der_rq", LOADS),
        "der r,q,v,w, dampers, loads+CTF/CTM": (1, True, "der_all", LOADS),
    }
    slopes, table = {}, {}
    for label, (ex, damp, src, names) in cases.items():
        errs = []
        for H in H_SWEEP:
            got, exact = _run_to_T(conn, H, ex, damp, src)
            errs.append(_error(got, exact, names))
        table[label] = errs
        slopes[label] = _slope(H_SWEEP, errs)
    with capsys.disabled():
        print("\n[convergence] relative error at T for H =", H_SWEEP)
        for label in cases:
            print(f"  {label:45s} slope {slopes[label]:5.2f}  " + "  ".join(f"{e:.2e}" for e in table[label]))
    for label, errs in table.items():
        assert all(e2 < e1 for e1, e2 in zip(errs, errs[1:])), (label, errs)
    for label in ("hold, dampers, loads+CTF/CTM", "hold, dampers, CP/CEF", "hold, springs only, loads+CTF/CTM"):
        assert 0.8 <= slopes[label] <= 1.2, (label, slopes[label])
    # velocity inputs are held over a step: the damper part is first order (documented above);
    # the damped totals mix an O(H^2) elastic and an O(H) viscous error (slope between 1 and 2
    # over this H range, tending to 1): at least first order
    assert 0.8 <= slopes["linear v, dampers, CVF/CVM"] <= 1.2, slopes
    assert slopes["linear v, dampers, loads+CTF/CTM"] >= 0.8, slopes
    for label in ("linear v, dampers, CP/CEF", "linear v, springs only, loads+CTF/CTM",
                  "der r,q (v=0), springs only, loads+CTF/CTM", "der r,q,v,w, dampers, loads+CTF/CTM"):
        assert slopes[label] >= 1.8, (label, slopes[label])
    assert slopes["linear v, dampers, CP/CEF"] >= slopes["hold, dampers, CP/CEF"] + 0.8
    assert slopes["linear v, springs only, loads+CTF/CTM"] >= slopes["hold, springs only, loads+CTF/CTM"] + 0.8


def test_input_derivatives_apply_to_the_next_step_only(conn):
    """Derivatives set by fmi2SetRealInputDerivatives drive one step; the following step
    (without new derivatives) falls back to the velocity inputs. With velocity inputs zero and
    linear extrapolation, a step after one with derivatives must hold the pose."""
    m = Smooth("Bushing")
    c = conn("Bushing").start(spring_damper_params("Bushing"), m.inputs(0.0, zero_velocity=True))
    d = m.derivatives(0.0, "rq")
    c.s.setRealInputDerivatives([c.v[k] for k in d], [1] * len(d), list(d.values()))
    c.step(0.01)
    r1 = c.get(["b.r[1]", "b.r[2]", "b.r[3]"])
    # moved along r' = v(0) for 0.01 s (exact for the linear part: |error| ~ round-off)
    assert np.allclose(r1, m.r(0.0) + 0.01 * m.v(0.0), rtol=0, atol=1e-14)
    c.step(0.01)
    r2 = c.get(["b.r[1]", "b.r[2]", "b.r[3]"])
    assert np.array_equal(r2, r1)  # velocity inputs are zero: held


# ==========================================================================
# 4. variable communication step size
# ==========================================================================


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


# ==========================================================================
# 5. threads
# ==========================================================================

THREAD_STEPS = 400


def _thread_run(c, params, inputs_at, barrier, out, key):
    try:
        barrier.wait()
        c.start(params, inputs_at(0.0))
        out[key] = c.drive(inputs_at, THREAD_STEPS, H_ROLL)
    except BaseException as e:  # noqa: BLE001 - reported by the main thread
        out[key] = e


def test_instances_in_threads_match_single_runs(conn):
    """Ten instances (two per variant, the stateful scenarios with stops and Planar friction)
    run concurrently from ten threads give, bit for bit, the records of the same runs done
    alone (fmpy's ctypes calls release the GIL, so the FMU calls really overlap)."""
    jobs = [(v, rep) for v in VARIANTS for rep in range(2)]
    alone = {}
    for v in VARIANTS:
        params, inputs_at = scenario(v)
        alone[v] = conn(v).start(params, inputs_at(0.0)).drive(inputs_at, THREAD_STEPS, H_ROLL)
    for attempt in range(2):
        conns = {job: conn(job[0]) for job in jobs}
        barrier = threading.Barrier(len(jobs))
        out = {}
        threads = []
        for job, c in conns.items():
            params, inputs_at = scenario(job[0])
            th = threading.Thread(target=_thread_run, args=(c, params, inputs_at, barrier, out, job))
            threads.append(th)
        for th in threads:
            th.start()
        for th in threads:
            th.join(timeout=300)
            assert not th.is_alive()
        for job in jobs:
            res = out[job]
            if isinstance(res, BaseException):
                raise res
            assert res == alone[job[0]], (attempt, job)


# ==========================================================================
# 6. status, reset
# ==========================================================================


@pytest.mark.parametrize("variant", VARIANTS)
def test_status_and_reset(conn, variant):
    params, inputs_at = scenario(variant)
    c = conn(variant).start(params, inputs_at(0.0), t0=0.25)
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
    # cosim.extrapolation back to its default 1 (after a run that did not change it) and the
    # inputs back to their start values
    assert c.s.getInteger([c.v["cosim.extrapolation"]])[0] == 1
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


# ==========================================================================
# 7. acceleration inputs (cosim.extrapolation = 3)
# ==========================================================================
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
    O(H²) (section 3). Slopes over H = 0.04 ... 0.005: ≥ 2.8, and ≥ 1.8 for the damped loads
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
            errs[k].append(_error(got, exact, ns))
    slopes = {k: _slope(H_SWEEP, e) for k, e in errs.items()}
    with capsys.disabled():
        print("\n[acceleration inputs] slopes", {k: round(s, 2) for k, s in slopes.items()},
              {k: [f"{x:.1e}" for x in e] for k, e in errs.items()})
    assert slopes["elastic"] >= 2.8, (slopes, errs)
    assert slopes["loads"] >= 1.8, (slopes, errs)
