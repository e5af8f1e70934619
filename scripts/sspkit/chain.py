"""The chain (SCENES.md §8): three bodies on a line along world x between two walls, four
linear springs, one ProjectionCartesian connector FMU each (node a on the left, node b on the
right):

  wall_left | k1 | m1 | k2 | m2 | k3 | m3 | k4 | wall_right

m = (1, 2, 0.5) kg, k = (1e3, 2e4, 5e4, 1e3) N/m, case 0 undamped, case 1 c = 0.5 N·s/m on every
spring; bodies at x = 0.1, 0.2, 0.3 m, walls at 0 and 0.4 m, springs unstretched there; initial
velocities (1, 0, −1) m/s; t_end = 1 s. Each body is a Body FMU (model 0, only x free) with its
left spring's node b on port 1 and its right spring's node a on port 2; the walls are fixed
Body FMUs whose centres drive the outer nodes.

The reference is the linear system M ẍ + C ẋ + K x = 0 solved exactly: with z = (x − x0, ẋ) and
A = [[0, I], [−M⁻¹K, −M⁻¹C]], z(t) = expm(A t) z0, evaluated by scipy's expm at every sample
time on the run's own grid (no stepping: each sample from t alone). Error: max over the samples
of |x − x_ref| / max |x_ref| (displacements of the three bodies), and in case 0 the energy
error max |E − E0| / E0 with E = ½ Σ m v² + ½ Σ k Δ² (the springs' extensions from the bodies'
displacements).

Uses numpy, scipy (expm) and multibody.py.
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import expm

from . import systems
from .multibody import MultiScene, body, link
from .systems import BODY, Component

MASS = np.array([1.0, 2.0, 0.5])
K = np.array([1e3, 2e4, 5e4, 1e3])
DAMPING = 0.5
X0 = np.array([0.1, 0.2, 0.3])
WALLS = (0.0, 0.4)
V0 = np.array([1.0, 0.0, -1.0])
BODIES = ("m1", "m2", "m3")
SPRINGS = ("k1", "k2", "k3", "k4")


class Chain(MultiScene):
    def __init__(self, case=0):
        super().__init__(name="chain" if case == 0 else "chain_damped", t_end=1.0,
                         error_label="against the exact linear solution expm(A t) z0: "
                                     "max |x − x_ref| / max |x_ref|")
        self.case = case
        self.c = np.full(4, DAMPING if case == 1 else 0.0)
        self.main_body = "m2"
        self.probes = [(b, x) for b in BODIES for x in ("r[1]", "v[1]")]

    # --- the system --------------------------------------------------------------------------
    def components(self):
        comps = []
        for j, name in enumerate(SPRINGS):
            p = {"elasticity.k1": float(K[j]), "cosim.extrapolation": systems.EXTRAPOLATION}
            if self.case == 1:
                p["damping.c1"] = float(self.c[j])
            comps.append(Component(name, "ProjectionCartesian", p))
        comps.append(Component("wall_left", BODY, body(r=(WALLS[0], 0, 0))))
        comps.append(Component("wall_right", BODY, body(r=(WALLS[1], 0, 0))))
        for i, name in enumerate(BODIES):
            comps.append(Component(name, BODY, body(mass=MASS[i], r=(X0[i], 0, 0), v=(V0[i], 0, 0),
                                                    free=("r1",))))
        return comps

    def connections(self):
        out = link("k1", "a", "wall_left", loads=False)
        for j, name in enumerate(BODIES):
            out += link(SPRINGS[j], "b", name, port=1)
            out += link(SPRINGS[j + 1], "a", name, port=2)
        return out + link("k4", "b", "wall_right", loads=False)

    # --- the reference -----------------------------------------------------------------------
    def matrices(self):
        """M, K, C of the linear system in the displacements x − x0."""
        def tridiag(k):
            return np.array([[k[0] + k[1], -k[1], 0.0], [-k[1], k[1] + k[2], -k[2]], [0.0, -k[2], k[2] + k[3]]])
        return np.diag(MASS), tridiag(K), tridiag(self.c)

    def frequencies(self):
        """The undamped natural frequencies (rad/s), ascending."""
        M, Kmat, _ = self.matrices()
        return np.sqrt(np.sort(np.linalg.eigvals(np.linalg.solve(M, Kmat)).real))

    def reference(self, t):
        """(x − x0, ẋ) at times t, arrays of (len(t), 3): expm(A t) z0 at each t."""
        M, Kmat, C = self.matrices()
        Minv = np.linalg.inv(M)
        A = np.block([[np.zeros((3, 3)), np.eye(3)], [-Minv @ Kmat, -Minv @ C]])
        z0 = np.concatenate([np.zeros(3), V0])
        z = np.array([expm(A * tk) @ z0 for tk in t])
        return z[:, :3], z[:, 3:]

    def energy(self, u, v):
        """½ Σ m v² + ½ Σ k Δ², rows of displacements u and velocities v."""
        ext = np.column_stack([u[:, 0], u[:, 1] - u[:, 0], u[:, 2] - u[:, 1], -u[:, 2]])
        return 0.5 * (v * v) @ MASS + 0.5 * (ext * ext) @ K

    def measure(self, run):
        """{'error': position error, 'energy': max |E − E0| / E0 (case 0; None in case 1),
        'amplitude': max |x_ref|}."""
        u = np.column_stack([run[f"{b}.r[1]"] for b in BODIES]) - X0
        v = np.column_stack([run[f"{b}.v[1]"] for b in BODIES])
        u_ref, _ = self.reference(run.t)
        amp = np.abs(u_ref).max()
        out = {"error": float(np.abs(u - u_ref).max() / amp), "amplitude": float(amp), "energy": None}
        if self.case == 0:
            E = self.energy(u, v)
            E0 = 0.5 * V0 @ (MASS * V0)
            out["energy"] = float(np.abs(E - E0).max() / E0)
        return out
