"""The Body FMU (dist/Body.fmu, dist/fmi3/Body.fmu) through fmpy: it validates clean; its motion is
the closed form where one exists (free fall, a mass on a spring, a prescribed degree of freedom,
a spin about a principal axis), torque-free precession conserves energy and angular momentum to
the accuracy of RK4, and, the key check, every step equals the body update of our own master's
zero-order-hold method (scripts/cosim/master.py: AxesBody.advance and RigidBody.advance with the
load held, Q0 = Q1) over random loads and steps. FMI 3.0 gives the FMI 2.0 outputs bit for bit.

Tolerances, stated once: a closed-form comparison allows round-off growing with the steps taken,
N·8·eps of the quantity's scale (each step rounds a handful of operations on values of that
scale, and the per-step update is exact in exact arithmetic); master comparisons allow 1e-12 of
the quantity's scale over the run (the FMU evaluates master.py's expressions in the same order;
numpy's BLAS dot products and norms may round differently in the last bit, nothing more).
"""
from __future__ import annotations

import functools
import math
import sys
import tempfile

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave
from fmpy.validation import validate_fmu

from conftest import REPO

sys.path.insert(0, str(REPO / "scripts"))
from cosim import master  # noqa: E402

EPS = np.finfo(float).eps
OUT = (["r[1]", "r[2]", "r[3]", "q.w", "q.x", "q.y", "q.z", "v[1]", "v[2]", "v[3]", "w[1]", "w[2]",
        "w[3]", "energy.kinetic", "energy.potential"])
PATHS = {2: REPO / "dist" / "Body.fmu", 3: REPO / "dist" / "fmi3" / "Body.fmu"}


def path(version: int):
    p = PATHS[version]
    if not p.is_file():
        pytest.fail(f"{p.relative_to(REPO)} is missing: run ./scripts/run first", pytrace=False)
    return p


@functools.lru_cache(maxsize=None)
def unzipped(version: int):
    return read_model_description(str(path(version))), extract(str(path(version)), tempfile.mkdtemp())


class Body:
    """One Body instance through fmpy's FMU2Slave or FMU3Slave, by variable name: parameters
    (`ints` Integer) set in Initialization Mode, then `step(h, f, m)` sets the load and steps."""

    def __init__(self, version: int, params: dict, ints: dict | None = None):
        md, unzipdir = unzipped(version)
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        cls = FMU2Slave if version == 2 else FMU3Slave
        self.s = cls(guid=md.guid, unzipDirectory=unzipdir, modelIdentifier="Body", instanceName="body")
        self.version, self.t = version, 0.0
        self.s.instantiate()
        if version == 2:
            self.s.setupExperiment(startTime=0.0)
            self.s.enterInitializationMode()
        else:
            self.s.enterInitializationMode(startTime=0.0)
        for name, x in (ints or {}).items():
            (self.s.setInteger if version == 2 else self.s.setInt32)([self.vr[name]], [int(x)])
        self.set(params)
        self.initial = self.out()
        self.s.exitInitializationMode()

    def set(self, values: dict):
        (self.s.setReal if self.version == 2 else self.s.setFloat64)(
            [self.vr[n] for n in values], [float(x) for x in values.values()])

    def get(self, names):
        return np.array((self.s.getReal if self.version == 2 else self.s.getFloat64)(
            [self.vr[n] for n in names]))

    def out(self):
        return dict(zip(OUT, self.get(OUT)))

    def step(self, h, f=(0.0, 0.0, 0.0), m=(0.0, 0.0, 0.0)):
        self.set({**{f"f[{i + 1}]": f[i] for i in range(3)}, **{f"m[{i + 1}]": m[i] for i in range(3)}})
        self.s.doStep(self.t, h)
        self.t += h
        return self.out()

    def close(self):
        self.s.terminate()
        self.s.freeInstance()


def v3(name, x) -> dict:
    """{name[1]: x[0], name[2]: x[1], name[3]: x[2]}."""
    return {f"{name}[{i}]": float(x[i - 1]) for i in (1, 2, 3)}


def start_q(q) -> dict:
    return dict(zip(["start.q.w", "start.q.x", "start.q.y", "start.q.z"], map(float, q)))


def vec(o, name):
    return np.array([o[f"{name}[{i}]"] for i in (1, 2, 3)])


def quat(o):
    return np.array([o["q.w"], o["q.x"], o["q.y"], o["q.z"]])


@pytest.mark.parametrize("version", [2, 3])
def test_validate_fmu_finds_no_problems(version):
    assert validate_fmu(str(path(version))) == []


def test_free_fall_is_the_parabola_to_round_off():
    g, r0, v0 = np.array([0.3, 0.0, -9.81]), np.array([1.0, 2.0, 10.0]), np.array([0.5, -1.0, 2.0])
    b = Body(2, {"mass": 3.0, **v3("gravity", g), **v3("start.r", r0), **v3("start.v", v0)})
    rng, n = np.random.default_rng(1), 0
    while b.t < 2.0:
        o = b.step(rng.uniform(1e-3, 2e-2))   # variable steps: exact for any h
        n += 1
    t = b.t
    r, v = r0 + v0 * t + 0.5 * g * t * t, v0 + g * t
    tol = n * 8 * EPS * np.abs(r).max()
    assert np.abs(vec(o, "r") - r).max() <= tol, (vec(o, "r") - r, tol)
    assert np.abs(vec(o, "v") - v).max() <= n * 8 * EPS * np.abs(v).max()
    e = o["energy.kinetic"] + o["energy.potential"]
    e0 = b.initial["energy.kinetic"] + b.initial["energy.potential"]
    assert abs(e - e0) <= n * 16 * EPS * 3.0 * np.abs(g).max() * np.abs(r).max()
    b.close()


def test_a_mass_on_a_spring_is_the_cosine_to_round_off():
    m, k, x0 = 2.0, 50.0, 0.1                  # ω = 5 rad/s
    w = math.sqrt(k / m)
    b = Body(2, {"mass": m, "spring.k[1]": k, "start.r[1]": x0})
    for n in range(1, 2001):
        o = b.step(1e-3)
    t = b.t
    assert abs(o["r[1]"] - x0 * math.cos(w * t)) <= n * 8 * EPS * x0
    assert abs(o["v[1]"] + x0 * w * math.sin(w * t)) <= n * 8 * EPS * x0 * w
    assert abs(o["energy.kinetic"] + o["energy.potential"] - 0.5 * k * x0 * x0) <= n * 8 * EPS * k * x0 * x0
    b.close()


def test_prescribed_degrees_of_freedom_move_at_their_start_velocity():
    q0 = [math.cos(0.2), 0.0, 0.0, math.sin(0.2)]           # 0.4 rad about z
    b = Body(2, {"start.r[1]": 1.0, "start.v[1]": 0.3, "start.r[2]": -2.0, "start.v[2]": 5.0,
                 "start.w[3]": 1.5, **start_q(q0)},
             ints={"dof.r[1]": 2, "dof.r[2]": 0, "dof.w[3]": 2})
    for _ in range(40):
        o = b.step(0.025, f=(7.0, 7.0, 1.0), m=(0.0, 0.0, 9.0))   # the load moves only r[3]
    assert o["r[1]"] == pytest.approx(1.0 + 0.3 * b.t, abs=1e-15) and o["v[1]"] == 0.3
    assert (o["r[2]"], o["v[2]"]) == (-2.0, 0.0)                   # fixed: start.v ignored
    assert o["r[3]"] == pytest.approx(0.5 * b.t * b.t, rel=1e-13)
    th = 0.4 + 1.5 * b.t
    assert np.allclose(quat(o), [math.cos(th / 2), 0, 0, math.sin(th / 2)], rtol=0, atol=1e-15)
    assert o["w[3]"] == 1.5
    b.close()


def test_a_spin_about_a_principal_axis_keeps_its_rate_and_a_unit_quaternion():
    q0 = np.array([0.8, 0.2, -0.4, 0.4])                       # |q0| = 1
    # body axis 3, of the largest moment: a stable spin (about axis 2, the intermediate one,
    # round-off would grow: the tennis-racket instability)
    axis = master.quat_matrix(q0) @ np.array([0.0, 0.0, 1.0])
    w0 = 6.0 * axis
    b = Body(2, {"inertia[1]": 1.0, "inertia[2]": 2.0, "inertia[3]": 3.0,
                 **start_q(q0),
                 **v3("start.w", w0)}, ints={"model": 1})
    for _ in range(300):
        o = b.step(0.01)
    # ω_b = (0, 0, 6) stays (ω_b × Jω_b = 0) up to the rounding of ω_b = R(q)ᵀω each step
    assert np.abs(vec(o, "w") - w0).max() <= 300 * 8 * EPS * 6.0
    assert abs(np.linalg.norm(quat(o)) - 1.0) <= 4 * EPS
    assert o["energy.kinetic"] == pytest.approx(0.5 * 3.0 * 36.0, rel=1e-13)
    b.close()


def precession_drift(max_turn: float):
    """Largest relative drift of the kinetic energy and of the angular momentum (in W) of a
    tumbling, torque-free body over 5 s in steps of 10 ms, and the number of RK4 substeps."""
    J = np.array([1.0, 2.0, 3.0])
    q0 = np.array([0.9, 0.1, 0.3, -0.3]) / np.linalg.norm([0.9, 0.1, 0.3, -0.3])
    w0 = np.array([1.0, 4.0, 0.5])                             # no principal axis: it tumbles
    b = Body(2, {**v3("inertia", J), "rigid.maxTurn": max_turn,
                 **start_q(q0),
                 **v3("start.w", w0)}, ints={"model": 1})

    def momentum(o):
        R = master.quat_matrix(quat(o))
        return R @ (J * (R.T @ vec(o, "w")))

    L0, E0 = momentum(b.initial), b.initial["energy.kinetic"]
    drift_e = drift_l = 0.0
    for _ in range(500):
        o = b.step(0.01)
        drift_e = max(drift_e, abs(o["energy.kinetic"] - E0) / E0)
        drift_l = max(drift_l, np.linalg.norm(momentum(o) - L0) / np.linalg.norm(L0))
    b.close()
    return drift_e, drift_l, 500 * math.ceil(np.linalg.norm(w0) * 0.01 / max_turn)


def test_torque_free_precession_conserves_energy_and_momentum_to_rk4_accuracy():
    e1, l1, n1 = precession_drift(0.05)     # |ω| h = 0.042: one substep per step
    e2, l2, n2 = precession_drift(0.025)    # two
    # RK4's local error is O((|ω| h_sub)⁵): at most about (|ω| h_sub)⁵/5! per substep, so the
    # drift stays below n_sub·(|ω| h_sub)⁵/5! (5e-7 here; measured 1.4e-9 energy, 3.4e-8
    # momentum), and halving the substep divides it by about 2⁴ = 16 (measured 19 and 16.0)
    w = 4.1533
    for (e, l, n) in ((e1, l1, n1), (e2, l2, n2)):
        bound = n * (w * 5.0 / n) ** 5 / 120     # 5 s in n substeps
        assert e < bound and l < bound, (e, l, bound)
    assert 12 < l1 / l2 < 20 and e1 / e2 > 12, (l1 / l2, e1 / e2)


def axes_case(springs: bool):
    """A model-0 body with three free translations and a free rotation about z, and master.py's
    AxesBody over the same coordinates (its masses: m, m, m, J_z)."""
    k = [40.0, 0.0, 7.0] if springs else [0.0, 0.0, 0.0]
    params = {"mass": 1.7, "inertia[3]": 0.3, "gravity[1]": 0.5, "gravity[3]": -9.81,
              "start.r[1]": 0.2, "start.v[2]": -0.4, "start.q.w": math.cos(0.3), "start.q.z": math.sin(0.3),
              "start.w[3]": 2.0, **v3("spring.k", k)}
    body = master.AxesBody([("r", 1), ("r", 2), ("r", 3), ("w", 3)], [1.7, 1.7, 1.7, 0.3], k_ground=k + [0.0])
    p, u = np.array([0.2, 0.0, 0.0, 0.6]), np.array([0.0, -0.4, 0.0, 2.0])
    return Body(2, params, ints={"dof.w[3]": 1}), body, p, u


def close_to(a, b, scale, rel=1e-12):
    return np.abs(np.asarray(a) - np.asarray(b)).max() <= rel * scale


@pytest.mark.parametrize("springs", [False, True])
def test_model_0_equals_master_axes_body_step_by_step(springs):
    b, body, p, u = axes_case(springs)
    g = np.array([0.5, 0.0, -9.81])
    rng, worst = np.random.default_rng(5 + springs), 0.0
    for _ in range(300):
        f, m3, H = rng.uniform(-3, 3, 3), rng.uniform(-1, 1), rng.uniform(1e-4, 3e-2)
        Q = np.concatenate((f + 1.7 * g, [m3]))                 # the load the body feels, held
        p, u = body.advance(b.t, p, u, Q, Q, H)
        o = b.step(H, f=f, m=(0.0, 0.0, m3))
        q = np.array([math.cos(0.5 * p[3]), 0.0, 0.0, math.sin(0.5 * p[3])])   # AxesBody.inputs
        got = np.concatenate((vec(o, "r"), quat(o), vec(o, "v"), [o["w[3]"]]))
        want = np.concatenate((p[:3], q, u[:3], [u[3]]))
        scale = max(1.0, np.abs(want).max())
        worst = max(worst, np.abs(got - want).max() / scale)
        assert close_to(got, want, scale), (got - want)
    b.close()
    print(f"model 0 vs AxesBody (springs {springs}): worst difference {worst:.3g} of the scale")


def test_model_1_equals_master_rigid_body_step_by_step():
    J, mass, g = np.array([0.4, 1.1, 2.3]), 2.5, np.array([0.0, -1.0, -9.81])
    q0 = np.array([0.7, -0.1, 0.5, 0.5]) / np.linalg.norm([0.7, -0.1, 0.5, 0.5])
    w0 = np.array([3.0, -2.0, 5.0])
    params = {"mass": mass, **v3("inertia", J),
              **v3("gravity", g),
              **start_q(q0),
              **v3("start.w", w0), "rigid.maxTurn": 0.05}
    b = Body(2, params, ints={"model": 1})
    body = master.RigidBody(mass, J, max_turn=0.05)
    rng, worst_step, worst_run = np.random.default_rng(11), 0.0, 0.0
    o = b.initial
    P, U = np.concatenate((np.zeros(3), q0)), np.concatenate((np.zeros(3), w0))  # master's own run
    for _ in range(300):
        f, m, H = rng.uniform(-3, 3, 3), rng.uniform(-2, 2, 3), rng.uniform(1e-4, 4e-2)
        Q = np.concatenate((f + mass * g, m))
        # one step from the FMU's own state (the per-step update), and the master's own run
        p, u = body.advance(b.t, np.concatenate((vec(o, "r"), quat(o))),
                            np.concatenate((vec(o, "v"), vec(o, "w"))), Q, Q, H)
        P, U = body.advance(b.t, P, U, Q, Q, H)
        o = b.step(H, f=f, m=m)
        got = np.concatenate((vec(o, "r"), quat(o), vec(o, "v"), vec(o, "w")))
        for want, name in ((np.concatenate((p, u)), "step"), (np.concatenate((P, U)), "run")):
            scale = max(1.0, np.abs(want).max())
            d = np.abs(got - want).max() / scale
            assert d <= 1e-12, (name, got - want)
            if name == "step":
                worst_step = max(worst_step, d)
            else:
                worst_run = max(worst_run, d)
    b.close()
    print(f"model 1 vs RigidBody: worst per step {worst_step:.3g}, over the run {worst_run:.3g}")


@pytest.mark.parametrize("model", [0, 1])
def test_fmi3_gives_the_fmi2_outputs_bit_for_bit(model):
    params = {"mass": 1.3, "inertia[1]": 0.5, "inertia[2]": 0.7, "inertia[3]": 0.9, "gravity[3]": -9.81,
              "start.w[3]": 3.0, "start.w[1]": 1.0 if model else 0.0, "spring.k[2]": 0.0 if model else 20.0}
    ints = {"model": model, "dof.w[3]": 1}
    b2, b3 = Body(2, params, ints), Body(3, params, ints)
    assert b2.initial == b3.initial
    rng = np.random.default_rng(3)
    for _ in range(200):
        f, m, H = rng.uniform(-3, 3, 3), rng.uniform(-1, 1, 3), rng.uniform(1e-4, 2e-2)
        o2, o3 = b2.step(H, f, m), b3.step(H, f, m)
        assert [np.float64(x).tobytes() for x in o2.values()] == [np.float64(x).tobytes() for x in o3.values()]
    b2.close()
    b3.close()
