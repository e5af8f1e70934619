"""A small co-simulation master: the master owns a body, the connector FMU (fmpy FMU2Slave)
returns the load the connector exerts on node b, and one of four coupling methods advances both
over a macro step H.

  zoh               explicit, zero-order hold
  extrapolation     explicit, the FMU driven along the predicted body path (input derivatives)
  linear_implicit   linear-implicit with the FMU's directional derivatives (θ-method)
  rollback          iterative with rollback (fmi2Get/SetFMUstate) to a stated tolerance

Loading, instantiating, initialising and name-based access are the shared driver's
(scripts/cosim/driver.py, also the fmpy tests' driver); `Connector` adds the per-step path. Its
FMI calls go through fmpy's FMU2Slave function wrappers (status checked) with ctypes buffers
prepared once per instance: a step builds no value-reference lists or ctypes arrays (fmpy's
convenience getReal/setReal would). The body arithmetic uses small numpy temporaries.

Conventions. The body has n velocity degrees of freedom u and positions p (for a 3-D body p holds
a quaternion, and a position increment is a rotation vector applied by `retract`). Q is the
connector's generalised load on the body (picked from the FMU outputs: b.f, b.m); the body's
own forces (`Body.ext`: a spring to ground, gyroscopic terms) are its business:
`Body.advance(t, p, u, Q0, Q1, H)` integrates the body under them and the connector load ramped
linearly from Q0 to Q1 (Q1 = Q0: held) over [t, t + H], exactly where the body allows it (RK4
for the 3-D rigid body). The linear-implicit method integrates the body itself (θ-method on
M u' = Q + ext, M the mass matrix) since it must treat body and connector together.
"""
from __future__ import annotations

import ctypes
import math
import os
import time
from pathlib import Path

import numpy as np
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2FMUstate, fmi2Integer, fmi2Real, fmi2ValueReference
from fmpy.fmi3 import FMU3Slave, fmi3Boolean, fmi3Float64, fmi3ValueReference

from . import driver

REPO = Path(__file__).resolve().parents[2]
DIST = Path(os.environ.get("COSIM_DIST", REPO / "dist"))     # the FMUs (default: dist/)
FMI3 = "fmi3"                     # the FMI 3.0 FMUs are DIST/fmi3/<variant>.fmu


class CosimFailure(RuntimeError):
    """A run that cannot go on: the FMU refused a step, the state blew up, rollback diverged."""


def model_description(variant):
    try:
        return driver.model_description(variant, DIST)
    except driver.MissingFMU as e:
        raise SystemExit(f"error: {e.path} is missing; run ./scripts/run first") from None


def unzipped(variant, unzipdir=None):
    if unzipdir is not None:
        return str(unzipdir)
    model_description(variant)
    return driver.unzipped(variant, DIST)


class Connector(driver.Connector):
    """One connector FMU instance (scripts/cosim/driver.py), initialised, with every per-step
    call prepared once.

    `in_names`: the inputs the master writes each step (buffer `x`, derivatives `d`);
    `out_names`: the outputs it reads each step (buffer `y`)."""

    _count = 0
    version = 2

    def __init__(self, variant, params, init_inputs, in_names, out_names, unzipdir=None,
                 acc_names=()):
        model_description(variant)
        Connector._count += 1
        s = driver.instantiate(variant, unzipped(variant, unzipdir),
                               instance_name=f"{variant}-{Connector._count}", dist=DIST)
        super().__init__(variant, s, dist=DIST)
        self.start(params, init_inputs)
        self.c = s.component
        nin, nout = len(in_names), len(out_names)
        self.nin, self.nout = nin, nout
        self.vin = (fmi2ValueReference * nin)(*[self.vr[n] for n in in_names])
        self.vout = (fmi2ValueReference * nout)(*[self.vr[n] for n in out_names])
        self.xin, self.yout = (fmi2Real * nin)(), (fmi2Real * nout)()
        self.din, self.order = (fmi2Real * nin)(), (fmi2Integer * nin)(*([1] * nin))
        self.seed_c, self.dd_c = (fmi2Real * nin)(), (fmi2Real * nout)()
        # numpy views on the ctypes buffers: writing x[...] fills the FMI argument in place
        self.x, self.y, self.d = (np.ctypeslib.as_array(b) for b in (self.xin, self.yout, self.din))
        self.seed, self.dd = np.ctypeslib.as_array(self.seed_c), np.ctypeslib.as_array(self.dd_c)
        self.state = fmi2FMUstate()
        self.state_ref = ctypes.byref(self.state)
        # fmpy's wrappers of the C functions (argument types set, status checked)
        self._setReal, self._getReal = s.fmi2SetReal, s.fmi2GetReal
        self._setDer, self._doStep = s.fmi2SetRealInputDerivatives, s.fmi2DoStep
        self._dd, self._get, self._set = (s.fmi2GetDirectionalDerivative, s.fmi2GetFMUstate,
                                          s.fmi2SetFMUstate)
        self.ev_vr = (fmi2ValueReference * 1)(self.vr["event.time"])
        self.ev_buf = (fmi2Real * 1)()
        self._acc_buffers([self.vr[n] for n in acc_names])
        self.calls = 0          # FMI calls made through the per-step paths

    def _acc_buffers(self, refs):
        """The acceleration inputs the master writes (`acc`, `set_accelerations`), by VR."""
        self.nacc = len(refs)
        self.vacc = (ctypes.c_uint32 * self.nacc)(*refs)
        self.xacc = (ctypes.c_double * self.nacc)()
        self.acc = np.ctypeslib.as_array(self.xacc) if self.nacc else np.zeros(0)

    # --- per-step calls (prepared buffers only) ------------------------------------------------
    def set_inputs(self):
        self._setReal(self.c, self.vin, self.nin, self.xin)
        self.calls += 1

    def get_outputs(self):
        self._getReal(self.c, self.vout, self.nout, self.yout)
        self.calls += 1
        return self.y

    def set_rates(self):
        self._setDer(self.c, self.vin, self.nin, self.order, self.din)
        self.calls += 1

    def set_accelerations(self):
        """The acceleration inputs (buffer `acc`): the path with cosim.extrapolation = 3."""
        self._setReal(self.c, self.vacc, self.nacc, self.xacc)
        self.calls += 1

    def do_step(self, t, H, no_rollback=True):
        self._doStep(self.c, t, H, no_rollback)
        self.calls += 1

    def event_time(self):
        """`event.time`: the first event in the last step (t + h when none)."""
        self._getReal(self.c, self.ev_vr, 1, self.ev_buf)
        self.calls += 1
        return self.ev_buf[0]

    def directional(self, seed):
        """J·seed: derivatives of the outputs along `seed` (over the written inputs)."""
        self.seed[:] = seed
        self._dd(self.c, self.vout, self.nout, self.vin, self.nin, self.seed_c, self.dd_c)
        self.calls += 1
        return self.dd

    def save(self):
        self._get(self.c, self.state_ref)      # overwrites the same state in place after the first
        self.calls += 1

    def restore(self):
        self._set(self.c, self.state)
        self.calls += 1

    # --- slow paths (set-up, monitoring): driver.Connector's set and value ---------------------
    def read(self, names):
        return [self.value(n) for n in names]

    def close(self):
        if self.s is not None:
            if self.state:
                self.s.freeFMUstate(self.state)
            self.s.terminate()
            self.s.freeInstance()
            self.s = None


_UNZIPPED3: dict = {}


class Connector3(Connector):
    """The same connector over the FMI 3.0 FMU (DIST/fmi3/<variant>.fmu, fmpy FMU3Slave), with the
    same prepared buffers and per-step calls. FMI 3.0 has no input derivatives (`set_rates` does
    nothing: the FMU extrapolates the nodes itself, `cosim.extrapolation`). With
    `early_return` (earlyReturnAllowed) `do_step_early` stops at the first event inside the step."""

    version = 3

    def __init__(self, variant, params, init_inputs, in_names, out_names, unzipdir=None,
                 acc_names=(), early_return=True):
        path = Path(DIST) / FMI3 / f"{variant}.fmu"
        try:
            md = driver._read(str(path))
        except FileNotFoundError:
            raise SystemExit(f"error: {path} is missing; run ./scripts/run first") from None
        if unzipdir is None:
            if str(path) not in _UNZIPPED3:
                import tempfile
                from fmpy import extract
                _UNZIPPED3[str(path)] = extract(str(path), tempfile.mkdtemp(prefix=f"cosim3-{variant}-"))
            unzipdir = _UNZIPPED3[str(path)]
        self.variant, self.t = variant, 0.0
        self.vr = self.v = {v.name: v for v in md.modelVariables}
        Connector._count += 1
        s = FMU3Slave(guid=md.guid, unzipDirectory=str(unzipdir),
                      modelIdentifier=md.coSimulation.modelIdentifier,
                      instanceName=f"{variant}-3-{Connector._count}")
        s.instantiate(earlyReturnAllowed=early_return)
        self.s, self.c = s, s.component
        s.enterInitializationMode(startTime=0.0)
        self.set(params)
        self.set(init_inputs)
        s.exitInitializationMode()
        nin, nout = len(in_names), len(out_names)
        self.nin, self.nout = nin, nout
        self.vin = (fmi3ValueReference * nin)(*[self.vr[n].valueReference for n in in_names])
        self.vout = (fmi3ValueReference * nout)(*[self.vr[n].valueReference for n in out_names])
        self.xin, self.yout = (fmi3Float64 * nin)(), (fmi3Float64 * nout)()
        self.din = (fmi3Float64 * nin)()
        self.seed_c, self.dd_c = (fmi3Float64 * nin)(), (fmi3Float64 * nout)()
        self.x, self.y, self.d = (np.ctypeslib.as_array(b) for b in (self.xin, self.yout, self.din))
        self.seed, self.dd = np.ctypeslib.as_array(self.seed_c), np.ctypeslib.as_array(self.dd_c)
        self.ev_vr = (fmi3ValueReference * 1)(self.vr["event.time"].valueReference)
        self.ev_buf = (fmi3Float64 * 1)()
        self._acc_buffers([self.vr[n].valueReference for n in acc_names])
        self._flags = [fmi3Boolean() for _ in range(3)]
        self._last = fmi3Float64()
        self._flag_refs = [ctypes.byref(f) for f in self._flags] + [ctypes.byref(self._last)]
        self.state = None
        self.calls = 0

    def set(self, values):
        """Parameters and inputs by name (set-up, not per step), through the FMI 3.0 setters."""
        for name, val in values.items():
            v = self.vr[name]
            {"Float64": lambda r, x: self.s.setFloat64(r, [float(x)]),
             "Int32": lambda r, x: self.s.setInt32(r, [int(x)]),
             "Boolean": lambda r, x: self.s.setBoolean(r, [bool(x)])}[v.type]([v.valueReference], val)

    def value(self, name):
        v = self.vr[name]
        return {"Float64": self.s.getFloat64, "Int32": self.s.getInt32,
                "Boolean": self.s.getBoolean}[v.type]([v.valueReference])[0]

    def set_inputs(self):
        self.s.fmi3SetFloat64(self.c, self.vin, self.nin, self.xin, self.nin)
        self.calls += 1

    def get_outputs(self):
        self.s.fmi3GetFloat64(self.c, self.vout, self.nout, self.yout, self.nout)
        self.calls += 1
        return self.y

    def set_rates(self):
        """No input derivatives in FMI 3.0."""

    def set_accelerations(self):
        self.s.fmi3SetFloat64(self.c, self.vacc, self.nacc, self.xacc, self.nacc)
        self.calls += 1

    def do_step_early(self, t, H):
        """fmi3DoStep; returns (earlyReturn, lastSuccessfulTime)."""
        self.s.fmi3DoStep(self.c, t, H, fmi3Boolean(True), *self._flag_refs)
        self.calls += 1
        return bool(self._flags[2].value), self._last.value

    def do_step(self, t, H, no_rollback=True):
        early, last = self.do_step_early(t, H)
        if early:
            raise CosimFailure(f"fmi3DoStep returned early at t = {last!r} in a method without "
                               "event location")

    def event_time(self):
        self.s.fmi3GetFloat64(self.c, self.ev_vr, 1, self.ev_buf, 1)
        self.calls += 1
        return self.ev_buf[0]

    def directional(self, seed):
        self.seed[:] = seed
        self.s.fmi3GetDirectionalDerivative(self.c, self.vout, self.nout, self.vin, self.nin,
                                            self.seed_c, self.nin, self.dd_c, self.nout)
        self.calls += 1
        return self.dd

    def save(self):
        if self.state is None:
            self.state = self.s.getFMUState()
        else:
            self.s.fmi3GetFMUState(self.c, ctypes.byref(self.state))
        self.calls += 1

    def restore(self):
        self.s.fmi3SetFMUState(self.c, self.state)
        self.calls += 1

    def close(self):
        if self.s is not None:
            if self.state is not None:
                self.s.freeFMUState(self.state)
            self.s.terminate()
            self.s.freeInstance()
            self.s = None


# =================================================================================================
# bodies owned by the master
# =================================================================================================
def quat_mul(p, q):
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return np.array([pw * qw - px * qx - py * qy - pz * qz, pw * qx + px * qw + py * qz - pz * qy,
                     pw * qy - px * qz + py * qw + pz * qx, pw * qz + px * qy - py * qx + pz * qw])


def quat_exp(th):
    a = math.sqrt(th[0] * th[0] + th[1] * th[1] + th[2] * th[2])
    s = 0.5 if a < 1e-8 else math.sin(0.5 * a) / a
    return np.array([math.cos(0.5 * a), s * th[0], s * th[1], s * th[2]])


def quat_log(q):
    """Rotation vector of a unit quaternion (shortest)."""
    w, v = q[0], q[1:]
    if w < 0:
        w, v = -w, -v
    s = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return (2.0 * math.atan2(s, w) / s) * v if s > 1e-12 else 2.0 * v


def quat_matrix(q):
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


class AxesBody:
    """A body whose degrees of freedom are translations along, and rotations about, fixed world
    axes (no gyroscopic coupling), each with a mass (or moment of inertia) and an optional
    linear spring to ground. Node b = the body; node a = `node_a(t)` (fixed or moving at a
    constant velocity). With a ramped load the motion is integrated exactly per coordinate.

    coords: list of ('r', i) (translation along world axis i, 1..3) or ('w', i) (rotation
    about world axis i; the node-b quaternion is the rotation about that axis)."""

    def __init__(self, coords, mass, k_ground=None, node_a=None, load_names=None):
        self.coords = coords
        self.n = len(coords)
        self.m = np.asarray(mass, float)
        self.kg = np.zeros(self.n) if k_ground is None else np.asarray(k_ground, float)
        self.M = np.diag(self.m)
        self.node_a = node_a            # None, or (axis i, velocity): a.r[i] = v t, a.v[i] = v
        names = []
        if node_a is not None:
            names.append(f"a.r[{node_a[0]}]")
        for kind, i in coords:
            names += [f"b.r[{i}]"] if kind == "r" else ["b.q.w", f"b.q.{'xyz'[i - 1]}"]
        for kind, i in coords:
            names.append(f"b.v[{i}]" if kind == "r" else f"b.w[{i}]")
        self.in_names = names
        self.load_names = load_names or [f"b.f[{i}]" if k == "r" else f"b.m[{i}]" for k, i in coords]
        # where each coordinate's position entries start in the input vector
        self._pos, j = [], (1 if node_a is not None else 0)
        for kind, _ in coords:
            self._pos.append(j)
            j += 1 if kind == "r" else 2
        self._vel = list(range(j, j + self.n))
        self.vel_inputs = self._vel     # where each coordinate's velocity sits in the inputs
        self.rot = np.array([k == "w" for k, _ in coords])
        self.Kext, self.Dext = -np.diag(self.kg), np.zeros((self.n, self.n))

    def inputs(self, t, p, u, x):
        if self.node_a is not None:
            x[0] = self.node_a[1] * t
        for j, (kind, _) in enumerate(self.coords):
            k = self._pos[j]
            if kind == "r":
                x[k] = p[j]
            else:
                x[k], x[k + 1] = math.cos(0.5 * p[j]), math.sin(0.5 * p[j])
            x[self._vel[j]] = u[j]

    def rates(self, t, H, p0, u0, p1, u1, d):
        if self.node_a is not None:
            d[0] = self.node_a[1]
        for j, (kind, _) in enumerate(self.coords):
            k, rate = self._pos[j], (p1[j] - p0[j]) / H
            if kind == "r":
                d[k] = rate
            else:   # q̇ of the rotation about a fixed axis at p0, angular rate = chord rate
                d[k], d[k + 1] = -0.5 * math.sin(0.5 * p0[j]) * rate, 0.5 * math.cos(0.5 * p0[j]) * rate
            d[self._vel[j]] = (u1[j] - u0[j]) / H

    def seeds(self, p, S):
        """S[:, j] = ∂inputs/∂p_j, S[:, n + j] = ∂inputs/∂u_j."""
        S[:] = 0.0
        for j, (kind, _) in enumerate(self.coords):
            k = self._pos[j]
            if kind == "r":
                S[k, j] = 1.0
            else:
                S[k, j], S[k + 1, j] = -0.5 * math.sin(0.5 * p[j]), 0.5 * math.cos(0.5 * p[j])
            S[self._vel[j], self.n + j] = 1.0

    def mass(self, p):
        return self.M

    def ext(self, t, p, u):
        return -self.kg * p

    def ext_jac(self, t, p, u):
        return self.Kext, self.Dext

    def retract(self, p, dp):
        return p + dp

    def dist(self, p1, p2):
        return float(np.max(np.abs(p1 - p2)))

    def kinetic(self, p, u):
        return 0.5 * float(np.dot(self.m, u * u))

    def advance(self, t, p, u, Q0, Q1, H):
        """Exact motion of m x'' + k_g x = Q0 + (Q1 − Q0) τ/H per coordinate."""
        m, k = self.m, self.kg
        if not k.any():
            return (p + H * u + (H * H / 6.0) * (2.0 * Q0 + Q1) / m, u + (0.5 * H) * (Q0 + Q1) / m)
        p1, u1 = np.empty(self.n), np.empty(self.n)
        for j in range(self.n):
            if k[j] == 0.0:
                p1[j] = p[j] + H * u[j] + H * H * (2.0 * Q0[j] + Q1[j]) / (6.0 * m[j])
                u1[j] = u[j] + 0.5 * H * (Q0[j] + Q1[j]) / m[j]
            else:
                w, s = math.sqrt(k[j] / m[j]), (Q1[j] - Q0[j]) / H
                A, B = p[j] - Q0[j] / k[j], (u[j] - s / k[j]) / w
                c, sn = math.cos(w * H), math.sin(w * H)
                p1[j] = Q1[j] / k[j] + A * c + B * sn
                u1[j] = s / k[j] - A * w * sn + B * w * c
        return p1, u1


class RigidBody:
    """A rigid body in 3-D: p = (r, q) (position, scalar-first quaternion body → W), u = (v, ω)
    with ω in W. Node b = the body's centre of mass and principal frame; node a is fixed (set at
    initialisation). Integrated with classical RK4 on (r, q, v, ω_body) in substeps that turn
    the body by at most `max_turn` rad (Euler's equations, gyroscopic term exact)."""

    n = 6
    in_names = ([f"b.r[{i}]" for i in (1, 2, 3)] + ["b.q.w", "b.q.x", "b.q.y", "b.q.z"]
                + [f"b.v[{i}]" for i in (1, 2, 3)] + [f"b.w[{i}]" for i in (1, 2, 3)])
    load_names = [f"b.f[{i}]" for i in (1, 2, 3)] + [f"b.m[{i}]" for i in (1, 2, 3)]
    vel_inputs = list(range(7, 13))     # u = (v, ω): the inputs b.v, b.w

    def __init__(self, mass, inertia, max_turn=0.05):
        self.m, self.J = float(mass), np.asarray(inertia, float)
        self.max_turn = max_turn
        self.Z = np.zeros((6, 6))

    def inputs(self, t, p, u, x):
        x[0:7] = p
        x[7:13] = u

    def rates(self, t, H, p0, u0, p1, u1, d):
        d[0:3] = (p1[:3] - p0[:3]) / H
        th = quat_log(quat_mul(p1[3:], p0[3:] * np.array([1.0, -1.0, -1.0, -1.0])))
        d[3:7] = 0.5 * quat_mul(np.concatenate(([0.0], th / H)), p0[3:])
        d[7:13] = (u1 - u0) / H

    def seeds(self, p, S):
        S[:] = 0.0
        q = p[3:]
        for j in range(3):
            S[j, j] = 1.0
            e = np.zeros(4)
            e[1 + j] = 0.5
            S[3:7, 3 + j] = quat_mul(e, q)       # δq = ½ (0, δθ) ⊗ q, δθ in W
            S[7 + j, 6 + j] = 1.0
            S[10 + j, 9 + j] = 1.0

    def inertia_w(self, q):
        R = quat_matrix(q)
        return R @ np.diag(self.J) @ R.T

    def mass(self, p):
        M = np.zeros((6, 6))
        M[0, 0] = M[1, 1] = M[2, 2] = self.m
        M[3:, 3:] = self.inertia_w(p[3:])
        return M

    def ext(self, t, p, u):
        w = u[3:]
        return np.concatenate((np.zeros(3), -np.cross(w, self.inertia_w(p[3:]) @ w)))

    def ext_jac(self, t, p, u):
        return self.Z, self.Z        # gyroscopic term treated explicitly

    def retract(self, p, dp):
        q = quat_mul(quat_exp(dp[3:]), p[3:])
        return np.concatenate((p[:3] + dp[:3], q / np.linalg.norm(q)))

    def dist(self, p1, p2):
        dq = quat_mul(p2[3:], p1[3:] * np.array([1.0, -1.0, -1.0, -1.0]))
        return max(float(np.max(np.abs(p1[:3] - p2[:3]))), 2.0 * float(np.max(np.abs(dq[1:]))))

    def kinetic(self, p, u):
        w = u[3:]
        return 0.5 * self.m * float(u[:3] @ u[:3]) + 0.5 * float(w @ self.inertia_w(p[3:]) @ w)

    def advance(self, t, p, u, Q0, Q1, H):
        R0 = quat_matrix(p[3:])
        wb0 = R0.T @ u[3:]
        nsub = max(1, math.ceil(float(np.linalg.norm(wb0)) * H / self.max_turn))
        h, J, m = H / nsub, self.J, self.m
        def f(tau, r, q, v, wb):
            Q = Q0 + (Q1 - Q0) * (tau / H)
            R = quat_matrix(q)
            dwb = (R.T @ Q[3:] - np.cross(wb, J * wb)) / J
            dq = 0.5 * quat_mul(q, np.array([0.0, wb[0], wb[1], wb[2]]))
            return v, dq, Q[:3] / m, dwb

        r, q, v, wb = p[:3].copy(), p[3:].copy(), u[:3].copy(), wb0
        for i in range(nsub):
            tau = i * h
            k1 = f(tau, r, q, v, wb)
            k2 = f(tau + h / 2, *(s + (h / 2) * k for s, k in zip((r, q, v, wb), k1)))
            k3 = f(tau + h / 2, *(s + (h / 2) * k for s, k in zip((r, q, v, wb), k2)))
            k4 = f(tau + h, *(s + h * k for s, k in zip((r, q, v, wb), k3)))
            r, q, v, wb = (s + (h / 6) * (a + 2 * b + 2 * c + d)
                           for s, a, b, c, d in zip((r, q, v, wb), k1, k2, k3, k4))
            q = q / np.linalg.norm(q)
        return np.concatenate((r, q)), np.concatenate((v, quat_matrix(q) @ wb))


# =================================================================================================
# the coupled system and the four methods
# =================================================================================================
class Coupled:
    """A body, its state (p, u) and one connector FMU, wired for the methods below."""

    def __init__(self, body, fmu, p0, u0, theta=1.0, tol=1e-10, max_iter=50):
        self.body, self.fmu = body, fmu
        self.p, self.u = np.array(p0, float), np.array(u0, float)
        n = body.n
        self.S = np.zeros((fmu.nin, 2 * n))
        self.K, self.D = np.zeros((n, n)), np.zeros((n, n))
        self.theta, self.tol, self.max_iter = theta, tol, max_iter
        self.iterations = 0          # rollback iterations in total
        self.events = 0              # steps cut at an event (event-located methods)
        self.fresh = True            # the step starts at t = 0 or at an event

    def put_state(self, t, p, u):
        """Inputs = node a at t, node b = the body at (p, u)."""
        self.body.inputs(t, p, u, self.fmu.x)
        self.fmu.set_inputs()

    def put_path(self, t, H, p0, u0, p1, u1):
        """Inputs at (p0, u0) and input derivatives along the chord to (p1, u1) over H."""
        self.put_state(t, p0, u0)
        self.body.rates(t, H, p0, u0, p1, u1, self.fmu.d)
        self.fmu.set_rates()

    def load(self):
        """The connector's generalised load on the body at the inputs just set (a copy)."""
        return self.fmu.get_outputs()[:self.body.n].copy()

    def jacobian(self, t, p, u):
        """K = ∂Q/∂p, D = ∂Q/∂u from the FMU's directional derivatives at the current inputs
        and committed state, plus the body's own (ground spring)."""
        n = self.body.n
        self.body.seeds(p, self.S)
        for j in range(2 * n):
            col = self.fmu.directional(self.S[:, j])[:n]
            (self.K[:, j] if j < n else self.D[:, j - n])[:] = col
        Ke, De = self.body.ext_jac(t, p, u)
        return self.K + Ke, self.D + De


def zoh(c, t, H):
    """1. Explicit, zero-order hold (cosim.extrapolation = 0): the FMU holds node b at x(t);
    the body feels the load F(x(t), v(t)) constant over [t, t + H]."""
    c.put_state(t, c.p, c.u)
    c.fmu.do_step(t, H)
    Q = c.load()
    c.p, c.u = c.body.advance(t, c.p, c.u, Q, Q, H)


def extrapolation(c, t, H):
    """2. Explicit with input extrapolation: predict the body's end state with F(t) held, drive
    the FMU along that path (input derivatives), then integrate the body with the load ramped
    from F(t) to the FMU's F at the predicted end state."""
    c.put_state(t, c.p, c.u)
    Q0 = c.load()                                              # evaluated, not committed
    p1, u1 = c.body.advance(t, c.p, c.u, Q0, Q0, H)            # predictor
    c.put_path(t, H, c.p, c.u, p1, u1)
    c.fmu.do_step(t, H)
    Q1 = c.load()
    c.p, c.u = c.body.advance(t, c.p, c.u, Q0, Q1, H)          # corrector


def linear_implicit(c, t, H):
    """3. Linear-implicit: linearise the load about the explicit predictor (x + H v, v) with the
    FMU's directional derivatives K = ∂Q/∂x, D = ∂Q/∂v and take a θ-method step,
        (M − θ H D − θ² H² K) Δv = H ((1 − θ) Q(t) + θ Q_pred),
        v ← v + Δv,  x ← x + H (v + θ Δv);
    then commit the FMU along that chord. θ = 1: linearised implicit Euler; ½: trapezoidal."""
    # (Linearised about the predictor, not at x(t): at the committed state of a slipping friction
    # contact the trial force sits exactly on the friction limit, and the FMU's central-difference
    # tangent there is half the stick stiffness; at the predictor it is the slip or stick tangent.
    # For a linear connector both are the same.)
    th, b = c.theta, c.body
    c.put_state(t, c.p, c.u)
    Q0 = c.load() + b.ext(t, c.p, c.u)
    pp = b.retract(c.p, H * c.u)                                # predictor, a trial evaluation
    c.put_state(t + H, pp, c.u)                                 # (node a at t + H)
    Qp = c.load() + b.ext(t + H, pp, c.u)
    K, D = c.jacobian(t + H, pp, c.u)
    A = b.mass(c.p) - th * H * D - th * th * H * H * K
    du = np.linalg.solve(A, H * ((1.0 - th) * Q0 + th * Qp))
    p1, u1 = b.retract(c.p, H * (c.u + th * du)), c.u + du
    c.put_path(t, H, c.p, c.u, p1, u1)
    c.fmu.do_step(t, H)                                         # commit along the chord
    c.p, c.u = p1, u1


def rollback(c, t, H):
    """4. Iterative with rollback: fixed point on the end state (p1, u1). Each pass restores the
    FMU state saved at t, drives the FMU along the chord to (p1, u1), and integrates the body
    with the load ramped from F(t) to that F(t + H); stop when the end position moves by
    <= c.tol (and H·velocity likewise), at most c.max_iter passes, else CosimFailure."""
    b = c.body
    c.put_state(t, c.p, c.u)
    Q0 = c.load()
    c.fmu.save()
    p1, u1 = b.advance(t, c.p, c.u, Q0, Q0, H)                  # first guess: held load
    for k in range(c.max_iter):
        if k:
            c.fmu.restore()
        c.put_path(t, H, c.p, c.u, p1, u1)
        c.fmu.do_step(t, H, no_rollback=False)
        Q1 = c.load()
        p2, u2 = b.advance(t, c.p, c.u, Q0, Q1, H)
        change = max(b.dist(p1, p2), H * float(np.max(np.abs(u2 - u1))))
        p1, u1 = p2, u2
        if change <= c.tol:
            break
        first = change if k == 0 else first
        if change > 1e8 * first:
            raise CosimFailure(f"rollback: diverging at t = {t:g} (pass {k + 1})")
    else:
        raise CosimFailure(f"rollback: no convergence to {c.tol:g} in {c.max_iter} passes at t = {t:g}")
    c.iterations += k + 1
    c.p, c.u = p1, u1


# =================================================================================================
# event-located methods: the FMU steps first, along its own extrapolation, and stops at the first
# event; the master then advances its body to exactly where the FMU got
# =================================================================================================
EXTRAPOLATION_EV = 2     # cosim.extrapolation of the event-located methods (second order)


def step_fmu(c, t, H):
    """Advance the FMU from t (inputs already set at t) by at most H along its own extrapolation
    and stop at the first event inside the step; return the time reached.

    FMI 3.0: fmi3DoStep with earlyReturnAllowed; at an event it returns early and the FMU's
    time, state and outputs are at lastSuccessfulTime.
    FMI 2.0: fmi2GetFMUstate before the step; if `event.time` < t + H, fmi2SetFMUstate and
    step again with h = event.time − t (the same extrapolated path from the same inputs and
    history, so the event now lies at the end of the step and the FMU commits it there).
    Both routes walk the same path and stop at the same located event (FMU: to 1e-10 of the
    step), so they give the same run."""
    f = c.fmu
    if f.version == 3:
        early, last = f.do_step_early(t, H)
        if early:
            c.events += 1
            return last
        return t + H
    f.save()
    f.do_step(t, H, no_rollback=False)
    te = f.event_time()
    if te < t + H:
        f.restore()
        f.do_step(t, te - t)
        c.events += 1
        return te
    return t + H


def expm(A):
    """exp(A) of a small matrix: scaling and squaring of the Taylor series (degree 18 after
    scaling to norm <= 1/2: truncation < 1e-22 relative)."""
    nrm = float(np.max(np.sum(np.abs(A), axis=1)))
    k = max(0, math.ceil(math.log2(nrm / 0.5))) if nrm > 0.5 else 0
    B = A / (2.0 ** k)
    E, T = np.eye(len(A)), np.eye(len(A))
    for i in range(1, 19):
        T = T @ B / i
        E = E + T
    for _ in range(k):
        E = E @ E
    return E


def _stable_part(X):
    """X without the unstable part of its symmetric part (eigenvalues > 0 set to 0): a negative
    stiffness or damping of the tangent (the exponential friction decay at breakaway gives
    ∂F/∂v = +μ_s−μ_k times N d_c) is left to the load's secant instead of being integrated
    exponentially over the step."""
    S = 0.5 * (X + X.T)
    w, V = np.linalg.eigh(S)
    if np.all(w <= 0.0):
        return X
    return X - (V * np.maximum(w, 0.0)) @ V.T


def _linearise(c, t, H):
    """Q0 at (t, p, u) and the affine model of the load over [t, t + H]:
    Q(s, p, u) ≈ Q0 + K (p − p0) + D (u − u0) + g s (s = time since t), with K, D the FMU's
    directional derivatives at the predictor (t + H, p0 + H u0, u0) plus the body's own, and g
    such that the model also meets the load evaluated at the predictor (so it carries the
    moving node a and the nonlinearity over the step). Trial evaluations only: the FMU is
    left with its inputs at (t, p0, u0), nothing committed."""
    b, p, u = c.body, c.p, c.u
    c.put_state(t, p, u)
    Q0 = c.load() + b.ext(t, p, u)
    pp = b.retract(p, H * u)
    c.put_state(t + H, pp, u)
    Qp = c.load() + b.ext(t + H, pp, u)
    K, D = c.jacobian(t + H, pp, u)
    c.put_state(t, p, u)
    return Q0, Qp, K.copy(), D.copy()


def extrapolation_ev(c, t, H):
    """Input extrapolation, event-located: read F(t); the FMU steps along its own second-order
    extrapolation (r + vτ + ½v̇τ², v̇ from the previous communication point) to t + H or the
    first event t_e; the body is integrated to the same time with the load ramped from F(t) to
    the FMU's F there (explicit)."""
    c.put_state(t, c.p, c.u)
    Q0 = c.load()
    t1 = step_fmu(c, t, H)
    Q1 = c.load()
    c.p, c.u = c.body.advance(t, c.p, c.u, Q0, Q1, t1 - t)
    return t1


def linear_implicit_ev(c, t, H):
    """Linear-implicit, event-located: linearise first (trial evaluations), then the FMU steps
    along its own extrapolation to t + H or the first event; a θ-step on the velocity over the
    step actually made, h = t1 − t, with the affine load model (F_pred at t + h =
    Q0 + h (K u0 + g)): (M − θhD − ½θh²K) Δv = h((1 − θ)Q0 + θF_pred), x += h(v + ½Δv)."""
    th, b = c.theta, c.body
    Q0, Qp, K, D = _linearise(c, t, H)
    t1 = step_fmu(c, t, H)
    h = t1 - t
    g = (Qp - Q0 - K @ (H * c.u)) / H
    Qh = Q0 + h * (K @ c.u + g)
    # the position follows the velocity by the trapezoidal rule, x += h (v + ½Δv), as the FMU's
    # second-order path does (x + vτ + ½v̇τ²): with θ Δv in it (as `linear_implicit`) the body
    # would end ½v̇h² off the path the FMU committed its friction along, and an elastic slip
    # state (μN/k_s = 3 µm on the puck) would unload by k_s times that at the next step
    A = b.mass(c.p) - th * h * D - 0.5 * th * h * h * K
    du = np.linalg.solve(A, h * ((1.0 - th) * Q0 + th * Qh))
    c.p, c.u = b.retract(c.p, h * (c.u + 0.5 * du)), c.u + du
    return t1


def linear_exact_ev(c, t, H):
    """Linear-implicit, second order between events: the same linearisation and event location
    as `linear_implicit_ev`, but the body is integrated exactly (matrix exponential) under the
    affine load model M u' = Q0 + K (p − p0) + D (u − u0) + g s over h = t1 − t. Exact for a
    linear connector (spring-damper, a stop in contact, a stick spring), stable at any H for a
    stable tangent (unstable parts of K, D are left to the secant g, `_stable_part`); with a
    nonlinear load its local error is O(h³) (the model meets the load at both ends)."""
    b, p, u = c.body, c.p, c.u
    Q0, Qp, K, D = _linearise(c, t, H)
    Ks, Ds = _stable_part(K), _stable_part(D)
    g = (Qp - Q0 - Ks @ (H * u)) / H
    t1 = step_fmu(c, t, H)
    h = t1 - t
    n = b.n
    Minv = np.linalg.inv(b.mass(p))
    A = np.zeros((2 * n + 2, 2 * n + 2))      # w = (Δp, u, 1, s)
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, :n] = Minv @ Ks
    A[n:2 * n, n:2 * n] = Minv @ Ds
    A[n:2 * n, 2 * n] = Minv @ (Q0 - Ds @ u)
    A[n:2 * n, 2 * n + 1] = Minv @ g
    A[2 * n + 1, 2 * n] = 1.0
    w0 = np.concatenate((np.zeros(n), u, [1.0, 0.0]))
    w = expm(A * h) @ w0
    c.p, c.u = b.retract(p, w[:n]), w[n:2 * n]
    return t1


# the first step after an event, as a fraction of H, for the methods that take a short one
RESTART = {"linear_path_ev": 0.01}


def linear_path_ev(c, t, H):
    """Linear-implicit on the master's own path, event-located.
    The θ-step over the whole H comes first, from the same linearisation as
    `linear_implicit_ev`: (M − θHD − ½θH²K) Δv = H((1 − θ)Q0 + θF_pred), a = Δv/H. The FMU is
    driven along that path (the acceleration inputs b.dv, b.dw set to a, cosim.extrapolation = 3:
    its path r + vτ + ½aτ² is then the body's path), to t + H or the first event t1; the body moves along
    the same path to t1: x += h(v + ½ah), v += ah, h = t1 − t. So the FMU commits its friction
    and stops along exactly the path the body takes, and the next step's read at the body sees
    no offset from it (a stick spring of 1e6 N/m turns a µm offset into newtons).
    θ = 1 on a step that starts at t = 0 or at an event (it damps what the event leaves behind
    in a stiff stick spring), θ = ½ between events (second order); after an event the first
    step is H/100 long (RESTART), so that the load jump at the event (μ_s → μ_k at a breakaway) does
    not ride on a whole step's linearisation. The acceleration inputs are plain inputs, so both
    FMI versions take the same calls (FMI 3.0 has no input derivatives)."""
    b, p, u = c.body, c.p, c.u
    th = 1.0 if c.fresh else 0.5
    Q0, Qp, K, D = _linearise(c, t, H)
    A = b.mass(p) - th * H * D - 0.5 * th * H * H * K
    du = np.linalg.solve(A, H * ((1.0 - th) * Q0 + th * Qp))
    a = du / H
    # inputs at (t, p, u) are set (_linearise); the path's accelerations: v̇ = a
    c.fmu.acc[:] = a
    c.fmu.set_accelerations()
    t1 = step_fmu(c, t, H)
    h = t1 - t
    c.p, c.u = b.retract(p, h * (u + 0.5 * h * a)), u + h * a
    return t1


METHODS = {"zoh": zoh, "extrapolation": extrapolation, "linear_implicit": linear_implicit,
           "rollback": rollback}
EV_METHODS = {"extrapolation_ev": extrapolation_ev, "linear_implicit_ev": linear_implicit_ev,
              "linear_exact_ev": linear_exact_ev, "linear_path_ev": linear_path_ev}
# cosim.extrapolation per method: 0 hold, 1 linear along the velocities (and, FMI 2.0, the input
# derivatives), 2 second order from the previous communication point, 3 along the acceleration
# inputs the method sets
EXTRAPOLATION = {"zoh": 0, **{m: EXTRAPOLATION_EV for m in EV_METHODS}, "linear_path_ev": 3}
ACC_METHODS = ("linear_path_ev",)   # methods that set the acceleration inputs


def connector_args(base, body):
    """(cosim.extrapolation, acceleration input names) of method `base` on `body`: the
    acceleration inputs of the body's velocity inputs (b.v[i] → b.dv[i], b.w[i] → b.dw[i]), in
    the order of its coordinates, for the methods that set them."""
    acc = [body.in_names[k].replace(".v[", ".dv[").replace(".w[", ".dw[")
           for k in body.vel_inputs] if base in ACC_METHODS else []
    return EXTRAPOLATION.get(base, 1), acc

ALL_METHODS = {**METHODS, **EV_METHODS}
LABELS = {"zoh": "explicit, zero-order hold", "extrapolation": "explicit, input extrapolation",
          "linear_implicit": "linear-implicit (directional derivatives)",
          "rollback": "iterative with rollback",
          "extrapolation_ev": "input extrapolation, event-located",
          "linear_implicit_ev": "linear-implicit, event-located",
          "linear_exact_ev": "linear-exact (exponential), event-located",
          "linear_path_ev": "linear-implicit on the master's path (θ = ½), event-located"}
FMI3_SUFFIX = "@fmi3"       # method@fmi3: the same method through the FMI 3.0 FMU (early return)


def split_method(method):
    """'linear_exact_ev@fmi3' -> ('linear_exact_ev', 3); 'zoh' -> ('zoh', 2)."""
    if method.endswith(FMI3_SUFFIX):
        return method[:-len(FMI3_SUFFIX)], 3
    return method, 2


def label(method):
    base, version = split_method(method)
    return LABELS[base] + (", FMI 3.0 early return" if version == 3 else
                           (", FMI 2.0 rollback to event.time" if base in EV_METHODS else ""))


class Result:
    """Samples of a run: t (N+1), p (N+1, np), u (N+1, n), extra (N+1, k) monitored outputs
    (read at the body state at each sample), cpu (s, stepping only), and the call counts."""

    def __init__(self, **kw):
        self.__dict__.update(kw)


def simulate(scene, method, H, t_end=None, unzipdir=None, record=None, fail_ok=True):
    """Run `scene` with `method` at macro step H up to t_end (default scene.t_end). `record`:
    names of extra Real outputs to sample at every communication point (slow path).
    `method` may end in "@fmi3": the FMI 3.0 FMU (dist/fmi3/) instead of the FMI 2.0 one.
    Event-located methods cut a step at the first event: the samples are then at the
    communication points actually reached (the next step starts at the event, with H again,
    or shorter for a method in RESTART; the last step ends at t_end)."""
    t_end = scene.t_end if t_end is None else t_end
    base, version = split_method(method)
    N = int(round(t_end / H))
    body = scene.body()
    params = dict(scene.params)
    params["cosim.extrapolation"], acc = connector_args(base, body)
    cls = Connector3 if version == 3 else Connector
    fmu = cls(scene.variant, params, scene.init_inputs(), body.in_names,
              body.load_names + list(record or []), unzipdir=unzipdir, acc_names=acc)
    try:
        scene.after_init(fmu)
        c = Coupled(body, fmu, *scene.initial_state(), **scene.method_options(base))
        step = ALL_METHODS[base]
        nr = len(record or [])
        T, P, U, X = [0.0], [c.p.copy()], [c.u.copy()], []
        failed, t, i = None, 0.0, 0
        if nr:
            c.put_state(0.0, c.p, c.u)
            X.append(fmu.get_outputs()[body.n:].copy())
        cpu, clock = 0.0, time.process_time
        while True:
            # fixed steps land on (i + 1) H as before; after an event, steps of H from there
            if c.events == 0:
                if i >= N:
                    break
                h, t_next = H, (i + 1) * H
            else:
                if t >= t_end * (1 - 1e-12):
                    break
                h = min(H * (RESTART.get(base, 1.0) if c.fresh else 1.0), t_end - t)
                t_next = t + h
            c0 = clock()
            ev0 = c.events
            try:
                r = step(c, t, h)
            except (FMICallException, CosimFailure, np.linalg.LinAlgError) as e:
                failed, r = f"t = {t:.6g}: {e}", None
            cpu += clock() - c0
            t = t_next if r is None else r
            c.fresh = c.events > ev0          # the next step starts at an event
            i += 1
            if failed is None and not (np.all(np.isfinite(c.p)) and np.all(np.isfinite(c.u))
                                       and np.max(np.abs(c.u)) < scene.blowup):
                failed = f"t = {t:.6g}: state blew up"
            if failed is not None:
                if not fail_ok:
                    raise CosimFailure(failed)
                break
            T.append(t)
            P.append(c.p.copy())
            U.append(c.u.copy())
            if nr:   # monitored outputs at the body state (direct feedthrough, not committed)
                c.put_state(t, c.p, c.u)
                X.append(fmu.get_outputs()[body.n:].copy())
        X = np.array(X) if nr else np.empty((len(P), 0))
        return Result(t=np.array(T), p=np.array(P), u=np.array(U), extra=X, cpu=cpu,
                      steps=len(P) - 1, calls=fmu.calls, iterations=c.iterations,
                      events=c.events, failed=failed, H=H, method=method)
    finally:
        fmu.close()
