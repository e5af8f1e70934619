"""Scenes of several bodies and connectors (SCENES.md §8 and §9), built from FMUs alone: Body FMUs
joined by connector FMUs at their load ports (docs/body.md, "Load ports"). Unlike the one-body
scenes of systems.py, these have no counterpart in our own master (scripts/cosim); each scene
carries its own reference and measure (chain.py, engine_mount.py), and its system is built
here from plain descriptions:

  body(...)            Body FMU parameters (model, mass, inertia, start state, free degrees of
                       freedom, ports' offsets), every start value written out
  link(...)            the connections of a connector between two nodes: a node's inputs from
                       a Body's centre outputs or from one of its ports, the node's load back
                       into that port (or nowhere: a wall or ground ignores it)
  MultiScene           what a scene gives: name, t_end, components, connections, the outputs
                       it samples (`probes`) and `measure(res)` of a run
  Run                  a tool's run as samples {"component.variable": array} on its time grid
  NAMES, scene(name)   chain, chain_damped, engine_mount, engine_mount_damped
  ALL, system(name)    every packaged scene (systems.py's and these) and its System

Uses numpy and systems.py (Component, System); tools.py runs them, archive.py packages them.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import systems
from .systems import System

STATE = ["r[1]", "r[2]", "r[3]", "q.w", "q.x", "q.y", "q.z", "v[1]", "v[2]", "v[3]", "w[1]", "w[2]", "w[3]"]
LOADS = ["f[1]", "f[2]", "f[3]", "m[1]", "m[2]", "m[3]"]


def body(model=0, mass=1.0, inertia=(1.0, 1.0, 1.0), r=(0.0, 0.0, 0.0), q=(1.0, 0.0, 0.0, 0.0),
         v=(0.0, 0.0, 0.0), w=(0.0, 0.0, 0.0), free=(), ports=None, **extra):
    """Body FMU parameters. Model 0: `free` names the free degrees of freedom ("r1", "w3", …),
    every other one fixed at its start value (no `free`: a fixed body, a wall or the ground).
    `ports` {k: (offset r, offset q)}."""
    p = {"model": model, "mass": float(mass)}
    p.update({f"inertia[{i + 1}]": float(x) for i, x in enumerate(inertia)})
    if model == 0:
        for kind in "rw":
            for i in (1, 2, 3):
                p[f"dof.{kind}[{i}]"] = 1 if f"{kind}{i}" in free else 0
    for name, x in (("r", r), ("v", v), ("w", w)):
        p.update({f"start.{name}[{i + 1}]": float(y) for i, y in enumerate(x)})
    p.update({f"start.q.{c}": float(y) for c, y in zip("wxyz", q)})
    for k, (off_r, off_q) in (ports or {}).items():
        p.update({f"port[{k}].offset.r[{i + 1}]": float(y) for i, y in enumerate(off_r)})
        p.update({f"port[{k}].offset.q.{c}": float(y) for c, y in zip("wxyz", off_q)})
    p.update(extra)
    return p


def link(conn, node, comp, port=None, loads=True):
    """Connections of connector `conn`'s `node` ('a' or 'b') to Body `comp`: the node's inputs
    r, q, v, w from the Body's centre outputs (port None) or from port[k]'s, and, with
    `loads`, the node's load f, m into the same place."""
    pre = "" if port is None else f"port[{port}]."
    out = [(comp, pre + x, conn, f"{node}.{x}") for x in STATE]
    if loads:
        out += [(conn, f"{node}.{x}", comp, pre + x) for x in LOADS]
    return out


@dataclass
class Run:
    """A tool's run of a multi-body scene: time grid t (N + 1) and samples {"comp.var": array}."""
    t: np.ndarray
    samples: dict
    cpu: float = 0.0
    steps: int = 0
    failed: str | None = None
    H: float = 0.0
    method: str = ""

    def __getitem__(self, name):
        return self.samples[name]


@dataclass
class MultiScene:
    """A scene of several bodies: subclasses give `components()`, `connections()`, `probes`
    (the Real outputs sampled: [(component, variable)]) and `measure(run)` → {'error': …}."""
    name: str = ""
    t_end: float = 1.0
    error_label: str = "error"

    def system(self):
        comps = self.components()
        return System(self, comps, self.connections(), self.main_body)

    def start_row(self, system):
        """The probes' values at t = 0 (libcosim shows none before its first step): the Bodies'
        start state (probes are Body centre outputs)."""
        row = []
        for comp, var in self.probes:
            row.append(float(system.component(comp).params[f"start.{var}"]))
        return row


def scenes():
    from . import chain, engine_mount
    return {s.name: s for s in (chain.Chain(0), chain.Chain(1),
                                engine_mount.EngineMount(0), engine_mount.EngineMount(1))}


NAMES = ("chain", "chain_damped", "engine_mount", "engine_mount_damped")


ALL = systems.NAMES + NAMES        # every scene that ships as dist/ssp/<scene>.ssp


def scene(name):
    """The MultiScene `name` (one of NAMES)."""
    all_ = scenes()
    if name not in all_:
        raise KeyError(f"no multi-body scene {name!r}; there are: {', '.join(NAMES)}")
    return all_[name]


def system(name, extrapolation=None):
    """The System of any scene of ALL: the one-body scenes' from systems.py, these from here;
    with `extrapolation`, every connector's cosim.extrapolation set to it (systems.EXTRAPOLATION
    otherwise)."""
    out = systems.system(name) if name in systems.NAMES else scene(name).system()
    return out if extrapolation is None else systems.with_extrapolation(out, extrapolation)
