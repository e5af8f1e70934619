"""Shared helpers of the fmpy co-simulation tests (test_fmpy_rollback.py,
test_fmpy_directional_derivatives.py, test_fmpy_extrapolation.py, test_fmpy_variable_step.py,
test_fmpy_threads.py, test_fmpy_status_reset.py, test_fmpy_acceleration_inputs.py; the
self-check of the motions is test_cosim_helpers.py). Plain code, no fixtures: the tests drive
the FMUs through conftest's `conn` fixture (a conftest.Connector per instance).

  - output names of a variant: loads_of, totals_of, elastic_of;
  - the prescribed motions in closed form: Smooth (any variant), PlanarSlide (Planar), and the
    poses they start from (QA0, RA0, RA_POS);
  - parameter sets: spring_damper_params, PLANAR_FRICTION, and scenario(variant) = (params,
    inputs_at(t)) of a run with springs, dampers, a stop (and friction for Planar);
  - H_ROLL, the communication step of the stateful scenario runs;
  - the convergence sweeps: T_END, H_SWEEP, rel_error, fit_slope.

Expected values never come from the FMU's internals: they are closed forms of the prescribed
motion, repeated runs (bitwise), finite differences through the ABI, or the FMU's own algebraic
outputs at the exact inputs (outputs are a function of the inputs at the current instant and
the committed state, docs/fmi.md "direct feedthrough"). This module may use _ref (the
independent numpy reference) and conftest's plain helpers only.
"""

from __future__ import annotations

import math

import numpy as np

import _ref
from conftest import parameter_sets, vr

fmi2LastSuccessfulTime = 2  # fmi2StatusKind


# ==========================================================================
# output names
# ==========================================================================


def loads_of(variant):
    return [f"{n}[{j}]" for n in _ref.VARIANTS[variant]["loads"] for j in (1, 2, 3)]


def totals_of(variant):
    return sorted(n for n in vr(variant) if n.startswith("CTF") or n.startswith("CTM"))


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


def pure_quat(v):
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
        d1 = _ref.quat_mul(pure_quat(0.5 * dphi * N1), e1)
        d2 = _ref.quat_mul(pure_quat(0.5 * dpsi * N2), e2)
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


# ==========================================================================
# runs
# ==========================================================================

# the communication step of the stateful scenario runs (rollback, threads, status and reset)
H_ROLL = 0.005


# ==========================================================================
# convergence sweeps (test_fmpy_extrapolation.py, test_fmpy_acceleration_inputs.py)
# ==========================================================================

T_END = 0.4
H_SWEEP = [0.04, 0.02, 0.01, 0.005]


def rel_error(got, exact, names):
    scale = max(abs(exact[n]) for n in names)
    return max(abs(got[n] - exact[n]) for n in names) / scale


def fit_slope(Hs, errs):
    return float(np.polyfit(np.log(Hs), np.log(errs), 1)[0])
