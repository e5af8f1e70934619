"""The engine block on four mounts (SCENES.md §9, engine_mount.py): its references.

- Linearised: K φ = ω² M φ with K = Σ_i T_iᵀ K_i T_i, T_i the map of the block's small twist
  (δr, δθ) to mount i's deflection in the mount frame, u = C_iᵀ (δr + δθ × p_i) and
  θ_i = C_iᵀ δθ (C_i the mount frame → W), K_i = diag(k1 … k6), M = diag(m, m, m, J); C alike
  from c1 … c6. `modes` gives the six frequencies and shapes, `linear(t)` the linear response
  z(t) = expm(A t) z0 from the initial velocities (scipy's expm at each t).
- Monolithic (`Monolithic`): the FMUs' own model in continuous time: the block's rigid-body
  equations, the Body FMU's model 1 without its RK4 (ṙ = v, q̇ = ½ q ⊗ (0, ω_b), m v̇ = F,
  J ω̇_b = Rᵀ M − ω_b × J ω_b), and the four Bushings' loads evaluated by four Bushing FMU
  instances (fmpy: node b's inputs set to the port's kinematics, b.f and b.m read, no step)
  and summed about the centre of mass as the Body's ports sum them (F = Σ f_i,
  M = Σ (m_i + d_i × f_i)). Integrated together by scipy's DOP853 at rtol 1e-10 (the belt's
  reference, scripts/cosim/reference.py, is built the same way; nothing here switches, so no
  events are located), dense output sampled at any time. `convergence` reruns it at 1e-8,
  1e-9 and 1e-11 and gives the largest pose difference to the 1e-10 run.

Uses numpy, scipy, cosim (connectors.Connector, bodies.quat_matrix / quat_mul) and
engine_mount.py's constants.
"""
from __future__ import annotations

import functools

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import eigh, expm

from cosim.bodies import quat_matrix, quat_mul
from cosim.connectors import Connector

RTOL = 1e-10


def skew(p):
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


def twist_map(p, C):
    """T: (δr, δθ) in W → (u, θ) in the mount frame."""
    T = np.zeros((6, 6))
    T[:3, :3] = C.T
    T[:3, 3:] = -C.T @ skew(p)
    T[3:, 3:] = C.T
    return T


def matrices(geo, case):
    """M, K, C (6 × 6) of the linearised block."""
    M = np.diag([geo.MASS] * 3 + list(geo.INERTIA))
    K, C = np.zeros((6, 6)), np.zeros((6, 6))
    for p, q in geo.mounts():
        T = twist_map(p, quat_matrix(q))
        K += T.T @ np.diag(geo.STIFFNESS) @ T
        C += T.T @ np.diag(geo.damping(case)) @ T
    return M, K, C


def modes(geo):
    """(ω, Φ): the six undamped natural frequencies (rad/s, ascending) and mass-normalised shapes."""
    M, K, _ = matrices(geo, 0)
    w2, phi = eigh(K, M)
    return np.sqrt(w2), phi


def linear(geo, case, t, scale=1.0):
    """The linear response at times t: rows of (δr, δθ, δv, δω) from z0 = (0, 0, v0, ω0)·scale."""
    M, K, C = matrices(geo, case)
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((6, 6)), np.eye(6)], [-Minv @ K, -Minv @ C]])
    z0 = np.concatenate([np.zeros(6), geo.V0 * scale, geo.W0 * scale])
    return np.array([expm(A * tk) @ z0 for tk in t])


def rotation_vector(q):
    """Rows of the rotation vectors of unit quaternions q (rows w, x, y, z), angle ≤ π."""
    q = np.where(q[:, :1] < 0, -q, q)
    s = np.linalg.norm(q[:, 1:], axis=1)
    angle = 2.0 * np.arctan2(s, q[:, 0])
    with np.errstate(invalid="ignore", divide="ignore"):
        k = np.where(s > 0, angle / np.where(s > 0, s, 1.0), 2.0)
    return q[:, 1:] * k[:, None]


class Mounts:
    """The four Bushing FMUs as a force law: `loads(r, q, v, w)` → (F, M about the centre of
    mass, Σ energy.stored) of the block at that state. Node a of each sits on the ground's port
    (the mount point and frame at rest), node b on the block's; both start there."""

    IN = [f"b.{x}" for x in ("r[1]", "r[2]", "r[3]", "q.w", "q.x", "q.y", "q.z", "v[1]", "v[2]", "v[3]",
                             "w[1]", "w[2]", "w[3]")]
    OUT = ["b.f[1]", "b.f[2]", "b.f[3]", "b.m[1]", "b.m[2]", "b.m[3]", "energy.stored"]

    def __init__(self, geo, case, scale=1.0):
        self.geo, self.mounts = geo, geo.mounts()
        self.fmus = []
        v0, w0 = geo.V0 * scale, geo.W0 * scale
        for p, q in self.mounts:
            init = {}
            for node, v, w in (("a", np.zeros(3), np.zeros(3)), ("b", v0 + np.cross(w0, p), w0)):
                init.update({f"{node}.r[{i + 1}]": float(p[i]) for i in range(3)})
                init.update({f"{node}.q.{c}": float(q[i]) for i, c in enumerate("wxyz")})
                init.update({f"{node}.v[{i + 1}]": float(v[i]) for i in range(3)})
                init.update({f"{node}.w[{i + 1}]": float(w[i]) for i in range(3)})
            self.fmus.append(Connector("Bushing", geo.bushing_params(case), init, self.IN, self.OUT))

    def loads(self, r, q, v, w):
        R = quat_matrix(q)
        F, M, E = np.zeros(3), np.zeros(3), 0.0
        for (p, qo), fmu in zip(self.mounts, self.fmus):
            d = R @ p
            fmu.x[0:3] = r + d
            fmu.x[3:7] = quat_mul(q, qo)
            fmu.x[7:10] = v + np.cross(w, d)
            fmu.x[10:13] = w
            fmu.set_inputs()
            y = fmu.get_outputs()
            F += y[0:3]
            M += y[3:6] + np.cross(d, y[0:3])
            E += y[6]
        return F, M, E

    def energy(self, r, q, v, w):
        """Kinetic energy of the block plus the mounts' energy.stored at each row."""
        J = np.asarray(self.geo.INERTIA)
        out = np.empty(len(r))
        for k in range(len(r)):
            R = quat_matrix(q[k])
            wb = R.T @ w[k]
            out[k] = 0.5 * self.geo.MASS * v[k] @ v[k] + 0.5 * wb @ (J * wb) + self.loads(r[k], q[k], v[k], w[k])[2]
        return out

    def close(self):
        for f in self.fmus:
            f.close()


class Monolithic:
    """The block and its four mounts integrated together (DOP853 at `rtol`); `at(t)` gives
    (r, q, v, w) rows at times t from the dense output."""

    def __init__(self, geo, case, rtol=RTOL, scale=1.0):
        self.geo = geo
        mounts = Mounts(geo, case, scale)
        J, m = np.asarray(geo.INERTIA), geo.MASS

        def rhs(_t, y):
            q = y[3:7] / np.linalg.norm(y[3:7])
            R = quat_matrix(q)
            wb = y[10:13]
            F, M, _ = mounts.loads(y[0:3], q, y[7:10], R @ wb)
            dq = 0.5 * quat_mul(q, np.array([0.0, *wb]))
            return np.concatenate([y[7:10], dq, F / m, (R.T @ M - np.cross(wb, J * wb)) / J])

        y0 = np.concatenate([np.zeros(3), [1.0, 0.0, 0.0, 0.0], geo.V0 * scale, geo.W0 * scale])
        atol = rtol * np.array([1e-3] * 3 + [1e-3] * 4 + [0.05 * scale] * 3 + [0.4 * scale] * 3)
        try:
            self.sol = solve_ivp(rhs, (0.0, geo.T_END), y0, method="DOP853", rtol=rtol, atol=atol,
                                 dense_output=True)
        finally:
            mounts.close()
        self.evaluations = self.sol.nfev

    def at(self, t):
        y = self.sol.sol(np.asarray(t, dtype=float)).T
        q = y[:, 3:7] / np.linalg.norm(y[:, 3:7], axis=1)[:, None]
        w = np.array([quat_matrix(qk) @ wb for qk, wb in zip(q, y[:, 10:13])])
        return y[:, 0:3], q, y[:, 7:10], w


@functools.lru_cache(maxsize=None)
def monolithic(geo, case, rtol=RTOL, scale=1.0):
    return Monolithic(geo, case, rtol, scale)


def pose_difference(r, q, r_ref, q_ref):
    """(max |r − r_ref| / max |r_ref|, max angle(q_ref⁻¹ q) / max angle(q_ref))."""
    conj = q_ref * np.array([1.0, -1.0, -1.0, -1.0])
    rel = np.array([quat_mul(a, b) for a, b in zip(conj, q)])
    angle = np.linalg.norm(rotation_vector(rel), axis=1)
    ref_angle = np.linalg.norm(rotation_vector(q_ref), axis=1)
    pos = np.linalg.norm(r - r_ref, axis=1).max() / np.linalg.norm(r_ref, axis=1).max()
    return float(pos), float(angle.max() / ref_angle.max())


def convergence(geo, case, t, rtols=(1e-8, 1e-9, 1e-11)):
    """[(rtol, position difference, rotation difference, evaluations)] of the reference at
    looser and tighter settings against the RTOL one, at times t."""
    best = monolithic(geo, case)
    r0, q0, _, _ = best.at(t)
    rows = []
    for rtol in rtols:
        ref = monolithic(geo, case, rtol)
        r, q, _, _ = ref.at(t)
        rows.append((rtol, *pose_difference(r, q, r0, q0), ref.evaluations))
    return rows
