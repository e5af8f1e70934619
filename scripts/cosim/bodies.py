"""The bodies the co-simulation master owns, with the integration of each under a connector load
ramped linearly over a step (held when the two ends are equal): `AxesBody` (translations along
and rotations about fixed world axes, each integrated exactly, with an optional spring to ground
and a node a fixed or moving at a constant velocity) and `RigidBody` (a free rigid body in 3-D:
RK4 on Euler's equations, with gravity). The Body FMU (bodies/, docs/body.md) computes the same
update per communication step.

Conventions. The body has n velocity degrees of freedom u and positions p (for a 3-D body p holds
a quaternion, and a position increment is a rotation vector applied by `retract`). Q is the
connector's generalised load on the body (picked from the FMU outputs: b.f, b.m); the body's
own forces (`ext`: a spring to ground, gravity, gyroscopic terms) are its business:
`advance(t, p, u, Q0, Q1, H)` integrates the body under them and the connector load ramped
linearly from Q0 to Q1 over [t, t + H]. `inputs` writes the connector's inputs for a body state,
`seeds` the directions of the body's coordinates in them (for directional derivatives), and
`time_seed` their change with time at a fixed body state (node a moving).
Uses numpy only.
"""
from __future__ import annotations

import math

import numpy as np


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

    def time_seed(self, t, s):
        """s = ∂inputs/∂t at a fixed body state: node a's motion (None when node a is fixed)."""
        if self.node_a is None:
            return None
        s[:] = 0.0
        s[0] = self.node_a[1]
        return s

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
    the body by at most `max_turn` rad (Euler's equations, gyroscopic term exact); gravity g
    (W) adds m g to the connector's force: v̇ = (F + m g)/m."""

    n = 6
    in_names = ([f"b.r[{i}]" for i in (1, 2, 3)] + ["b.q.w", "b.q.x", "b.q.y", "b.q.z"]
                + [f"b.v[{i}]" for i in (1, 2, 3)] + [f"b.w[{i}]" for i in (1, 2, 3)])
    load_names = [f"b.f[{i}]" for i in (1, 2, 3)] + [f"b.m[{i}]" for i in (1, 2, 3)]
    vel_inputs = list(range(7, 13))     # u = (v, ω): the inputs b.v, b.w

    def __init__(self, mass, inertia, max_turn=0.05, gravity=(0.0, 0.0, 0.0)):
        self.m, self.J = float(mass), np.asarray(inertia, float)
        self.max_turn = max_turn
        self.g = np.asarray(gravity, float)
        self.Z = np.zeros((6, 6))

    def time_seed(self, t, s):
        """Node a is fixed: the inputs do not move with time at a fixed body state."""
        return None

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
        return np.concatenate((self.m * self.g, -np.cross(w, self.inertia_w(p[3:]) @ w)))

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

    def potential(self, p):
        """Gravity's potential energy, −m g·r (J)."""
        return -self.m * float(self.g @ p[:3])

    def advance(self, t, p, u, Q0, Q1, H):
        R0 = quat_matrix(p[3:])
        wb0 = R0.T @ u[3:]
        nsub = max(1, math.ceil(float(np.linalg.norm(wb0)) * H / self.max_turn))
        h, J, m = H / nsub, self.J, self.m
        mg = m * self.g

        def f(tau, r, q, v, wb):
            Q = Q0 + (Q1 - Q0) * (tau / H)
            R = quat_matrix(q)
            dwb = (R.T @ Q[3:] - np.cross(wb, J * wb)) / J
            dq = 0.5 * quat_mul(q, np.array([0.0, wb[0], wb[1], wb[2]]))
            return v, dq, (Q[:3] + mg) / m, dwb

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
