"""The engine block on four inclined mounts (SCENES.md §9): a rigid block (Body FMU, model 1)
on four Bushing FMUs, the ground a fixed Body FMU with four ports.

- Block: 150 kg, principal moments (8, 12, 10) kg·m² about its centre of mass, body axes along W
  at the start, no gravity; at rest in position, v0 = (0, 0, 0.05) m/s, ω0 = (0.4, −0.3, 0.2)
  rad/s; t_end = 2 s.
- Mount i at the block's point p_i = (±0.25, ±0.2, −0.15) m (port i: 1 (+, +), 2 (+, −),
  3 (−, +), 4 (−, −)), its frame the body frame turned about x by +30° where p_y > 0 and −30°
  where p_y < 0 (a V layout): the block's port i and the ground's port i both sit there, in
  that frame (offset.r = p_i, offset.q the turn).
- Bushing i: node a on the ground's port i, node b on the block's port i; elasticity (1.5e5,
  1.5e5, 4e5) N/m, (300, 300, 300) N·m/rad in the mount frame; case 1 damping (100, 100, 100)
  N·s/m, (0.5, 0.5, 0.5) N·m·s/rad. Node b's load goes into the block's port i, node a's into
  the ground's (which is fixed and ignores it).

The truth a run converges to is the monolithic reference of the FMUs' own model
(engine_reference.py); its linearisation gives the six natural frequencies. Error: the largest
pose difference to the reference over the samples (position / its max, rotation angle / its
max); in case 0 also the energy balance max |E − E0| / E0 (kinetic + the mounts' energy.stored,
evaluated at the sampled states by Bushing FMU instances, as the tools' own connector outputs
lag a step).

Uses numpy, multibody.py and engine_reference.py.
"""
from __future__ import annotations

import math

import numpy as np

from . import engine_reference as ref
from . import systems
from .multibody import MultiScene, body, link
from .systems import BODY, Component

MOUNTS = ("mount1", "mount2", "mount3", "mount4")


class EngineMount(MultiScene):
    MASS = 150.0
    INERTIA = (8.0, 12.0, 10.0)
    V0 = np.array([0.0, 0.0, 0.05])
    W0 = np.array([0.4, -0.3, 0.2])
    T_END = 2.0
    POINTS = ((0.25, 0.2, -0.15), (0.25, -0.2, -0.15), (-0.25, 0.2, -0.15), (-0.25, -0.2, -0.15))
    TILT = math.radians(30.0)
    STIFFNESS = (1.5e5, 1.5e5, 4e5, 300.0, 300.0, 300.0)
    DAMPING = (100.0, 100.0, 100.0, 0.5, 0.5, 0.5)

    def __init__(self, case=0):
        super().__init__(name="engine_mount" if case == 0 else "engine_mount_damped", t_end=self.T_END,
                         error_label="against the monolithic reference of the FMUs' model: "
                                     "max(|Δr| / max|r|, Δangle / max angle)")
        self.case = case
        self.main_body = "block"
        self.probes = [("block", x) for x in ("r[1]", "r[2]", "r[3]", "q.w", "q.x", "q.y", "q.z",
                                              "v[1]", "v[2]", "v[3]", "w[1]", "w[2]", "w[3]")]

    @classmethod
    def mounts(cls):
        """[(p_i, q_i)]: each mount's point in the body frame and its frame (mount → body)."""
        out = []
        for p in cls.POINTS:
            half = 0.5 * cls.TILT * (1.0 if p[1] > 0 else -1.0)
            out.append((np.array(p), np.array([math.cos(half), math.sin(half), 0.0, 0.0])))
        return out

    @classmethod
    def damping(cls, case):
        return cls.DAMPING if case == 1 else (0.0,) * 6

    @classmethod
    def bushing_params(cls, case):
        p = {f"elasticity.k{i}": k for i, k in enumerate(cls.STIFFNESS, 1)}
        if case == 1:
            p.update({f"damping.c{i}": c for i, c in enumerate(cls.DAMPING, 1)})
        p["cosim.extrapolation"] = systems.EXTRAPOLATION
        return p

    # --- the system --------------------------------------------------------------------------
    def components(self):
        ports = {k: (p, q) for k, (p, q) in enumerate(self.mounts(), 1)}
        comps = [Component(m, "Bushing", self.bushing_params(self.case)) for m in MOUNTS]
        comps.append(Component("ground", BODY, body(ports=ports)))
        comps.append(Component("block", BODY, body(model=1, mass=self.MASS, inertia=self.INERTIA,
                                                   v=self.V0, w=self.W0, ports=ports)))
        return comps

    def connections(self):
        out = []
        for k, m in enumerate(MOUNTS, 1):
            out += link(m, "a", "ground", port=k) + link(m, "b", "block", port=k)
        return out

    # --- the reference -----------------------------------------------------------------------
    def reference(self, t):
        return ref.monolithic(EngineMount, self.case).at(t)

    def measure(self, run):
        """{'error': max(position, rotation), 'position', 'rotation', 'energy' (case 0; else None)}."""
        r = np.column_stack([run[f"block.r[{i}]"] for i in (1, 2, 3)])
        q = np.column_stack([run[f"block.q.{c}"] for c in "wxyz"])
        v = np.column_stack([run[f"block.v[{i}]"] for i in (1, 2, 3)])
        w = np.column_stack([run[f"block.w[{i}]"] for i in (1, 2, 3)])
        r_ref, q_ref, _, _ = self.reference(run.t)
        pos, rot = ref.pose_difference(r, q, r_ref, q_ref)
        out = {"error": max(pos, rot), "position": pos, "rotation": rot, "energy": None}
        if self.case == 0 and np.isfinite(r).all() and np.abs(r).max() < 1.0:
            mounts = ref.Mounts(EngineMount, self.case)
            try:
                E = mounts.energy(r, q, v, w)
            finally:
                mounts.close()
            out["energy"] = float(np.abs(E - E[0]).max() / E[0])
        return out
