"""A tool's run set beside our master's: the master's fixed-step method (`jacobi`, or `zoh`) run
on the tool's own time grid, and the largest relative difference between two runs.

Why the tool's grid: libcosim hands the FMUs t_k = (k·h_ns)/1e9 and steps t_(k+1) − t_k, Ecos the
float sum t_(k+1) = t_k + H, master.simulate t_k = k·H and H. The three differ in the last bits
of t and h; where the scene's motion depends on them discontinuously (the belt's stick/slip is
decided by a threshold at each step, and node a sits at v_b·t), a last-bit difference moves a
transition by a step. On the same grid the runs are the same (docs/ssp.md).

Uses numpy and cosim (master, coupling, connectors); tools.py gives the grids.
"""
from __future__ import annotations

import numpy as np

from cosim import master
from cosim.connectors import Connector
from cosim.coupling import Coupled

from . import tools


def master_on_grid(scene, method, t, h, extrapolation=None):
    """Our master's `method` (a fixed-step one: jacobi, zoh) with the steps (t_k, h_k): the loop
    of master.simulate on a given grid. A master.Result with the samples at t_0 … t_n. With
    `extrapolation`, the connector's cosim.extrapolation is it instead of the method's (an
    archive's connector setting, systems.EXTRAPOLATION)."""
    body = scene.body()
    params = dict(scene.params)
    params["cosim.extrapolation"], acc = master.connector_args(method, body)
    if extrapolation is not None:
        params["cosim.extrapolation"] = extrapolation
    fmu = Connector(scene.variant, params, scene.init_inputs(), body.in_names, body.load_names,
                    acc_names=acc)
    try:
        scene.after_init(fmu)
        c = Coupled(body, fmu, *scene.initial_state(), **scene.method_options(method))
        step = master.ALL_METHODS[method]
        P, U = [c.p.copy()], [c.u.copy()]
        for tk, hk in zip(t, h):
            step(c, tk, hk)
            P.append(c.p.copy())
            U.append(c.u.copy())
    finally:
        fmu.close()
    times = np.append(t, t[-1] + h[-1])
    return master.Result(t=times, p=np.array(P), u=np.array(U), method=f"{method}@{len(t)}")


def master_as_tool(scene, method, tool, H, t_end=None, extrapolation=None):
    """`method` of our master on the time grid of `tool` at step H (the connector at
    `extrapolation`, as master_on_grid)."""
    n = tools.steps(H, scene.t_end if t_end is None else t_end)
    return master_on_grid(scene, method, *tools.grid(tool, H, n), extrapolation)


def difference(a, b):
    """The largest difference between the states of runs a and b (same sample count), each state
    coordinate relative to its largest magnitude over run b: max over coordinates and samples
    of |a − b| / max |b|."""
    if len(a.p) != len(b.p):
        raise ValueError(f"{len(a.p)} samples against {len(b.p)}")
    worst = 0.0
    for x, y in ((a.p, b.p), (a.u, b.u)):
        scale = np.max(np.abs(y), axis=0)
        scale[scale == 0] = 1.0
        worst = max(worst, float(np.max(np.abs(x - y) / scale)))
    return worst
