"""An SSP archive run by a third-party master, sampled into our master's Result (master.py), so
that a scene's own `measure` applies to it and its trajectory can be set beside ours.

  libcosim  libcosimpy: CosimExecution.from_ssp_file(archive, step in ns) applies each
            component's first parameter set itself; its clock counts integer nanoseconds, so it
            hands the FMUs t_k = (k·h_ns)/1e9 and steps of t_(k+1) − t_k
  ecos      ecospy: EcosSimulation(ssp_path=archive, step_size=H), init(parameter_set=NAME) (Ecos
            applies a parameter set only when init names it); its clock is the float sum
            t_(k+1) = t_k + H, and step_until(T) can stop a step short of T, so we step by count

Both are fixed-step Jacobi masters: every FMU steps from the inputs of the last communication
point, then the connections carry the new outputs (as our master's `jacobi`). A run samples the
outputs of the scene's body (systems.state_outputs) after every step, one Python call per step
and sample; `native=True` instead times the tool stepping all N steps in one call, no samples.
Outputs the scene monitors (scene.record, e.g. energy.stored) are evaluated afterwards at the
sampled body states by an fmpy connector instance, as our master evaluates them (the tools'
own connector output lags one step behind: it is computed at the held inputs).

Uses libcosimpy, ecospy, numpy, cosim (master, connectors), systems.py and archive.py (the check).
"""
from __future__ import annotations

import time

import numpy as np

from cosim import master
from cosim.connectors import Connector

from . import archive, multibody, systems

TOOLS = ("libcosim", "ecos")


class ToolError(RuntimeError):
    """The tool refused the archive or a step; the message is the tool's own."""


def steps(H, t_end):
    """The number of steps of H over t_end (it must divide it to 1e-9)."""
    n = int(round(t_end / H))
    if n < 1 or abs(n * H - t_end) > 1e-9 * t_end:
        raise ValueError(f"H = {H:g} does not divide t_end = {t_end:g}")
    return n


def grid(tool, H, n):
    """(t_k, h_k), k = 0 … n − 1: the communication points and steps the tool hands the FMUs."""
    if tool == "libcosim":
        ns = nanoseconds(H)
        t = np.array([(k * ns) / 1e9 for k in range(n + 1)])
        return t[:-1], np.diff(t)
    t = np.empty(n + 1)
    t[0] = 0.0
    for k in range(n):
        t[k + 1] = t[k] + H
    return t[:-1], np.full(n, H)


def nanoseconds(H):
    ns = int(round(H * 1e9))
    if ns <= 0 or abs(ns - H * 1e9) > 1e-6 * H * 1e9:
        raise ValueError(f"libcosim steps in whole nanoseconds: H = {H!r} s is not")
    return ns


def _libcosim(path, probes, H, n, start_row, native, parameter_set=None):
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy._internal import get_last_error_message

    log_output_level(CosimLogLevel.ERROR)
    try:
        ex = CosimExecution.from_ssp_file(str(path), nanoseconds(H))
    except AssertionError:
        raise ToolError(f"libcosim: {get_last_error_message()}") from None
    index = {s.name.decode(): s.index for s in ex.slave_infos()}
    groups = {}                      # component → (slave index, [value references], [columns])
    for j, (comp, var) in enumerate(probes):
        if comp not in groups:
            groups[comp] = (index[comp], {v.name.decode(): v.reference for v in ex.slave_variables(index[comp])},
                            [], [])
        groups[comp][2].append(groups[comp][1][var])
        groups[comp][3].append(j)
    observer = CosimObserver.create_last_value()
    ex.add_observer(observer)
    # libcosim initialises at its first step: the sample at t = 0 is the start parameters
    rows = [] if start_row is None else [list(start_row)]
    clock, failed = time.process_time(), None
    if native:
        if not ex.step(n):
            failed = f"libcosim: {get_last_error_message()}"
    else:
        row = [0.0] * len(probes)
        for k in range(n):
            if not ex.step(1):
                failed = f"t = {k * H:g}: libcosim: {get_last_error_message()}"
                break
            for i, _, vrs, cols in groups.values():
                for c, x in zip(cols, observer.last_real_values(i, vrs)):
                    row[c] = x
            rows.append(list(row))
    cpu = time.process_time() - clock
    first = 0 if start_row is not None else 1
    t = np.array([(k * nanoseconds(H)) / 1e9 for k in range(first, first + len(rows))])
    return t, np.array(rows).reshape(len(rows), len(probes)), cpu, failed


def _ecos(path, probes, H, n, start_row, native, parameter_set=systems.PARAMETER_SET):
    from ecospy.EcosSimulation import EcosSimulation
    from ecospy.lib import EcosLib

    EcosLib.set_log_level("err")
    try:
        sim = EcosSimulation(ssp_path=str(path), step_size=H)
    except Exception as e:                  # ecospy raises a bare Exception with Ecos's message
        raise ToolError(f"Ecos: {e}") from None
    try:
        if not sim.init(parameter_set=parameter_set):
            raise ToolError(f"Ecos: init: {EcosLib.get_last_error()}")
        ids = [f"{comp}::{var}" for comp, var in probes]
        rows, t = [], []
        if start_row is not None:
            rows, t = [[sim.get_real(i) for i in ids]], [sim.get_time()]
        clock, failed = time.process_time(), None
        if native:
            sim.step(n)
        else:
            for _ in range(n):
                sim.step(1)
                t.append(sim.get_time())
                rows.append([sim.get_real(i) for i in ids])
        cpu = time.process_time() - clock
        if sim.get_time() < (n - 0.5) * H:
            failed = f"Ecos stopped at t = {sim.get_time():g}: {EcosLib.get_last_error()}"
        sim.terminate()
    finally:
        sim.free()
    return np.array(t), np.array(rows).reshape(len(rows), len(probes)), cpu, failed


def run_probes(tool, path, probes, H, n, start_row=None, native=False,
               parameter_set=systems.PARAMETER_SET):
    """Run archive `path` in `tool`, n steps of H, sampling the Real outputs `probes`
    [(component, variable)] after every step: (t, rows, cpu, failed). With `start_row` (the
    values at t = 0, which libcosim cannot show before its first step) the first row is t = 0;
    without it the rows start at t = H in both tools. `parameter_set`: the name Ecos's init is
    given (libcosim applies each component's first set itself)."""
    if tool not in RUNNERS:
        raise ValueError(f"unknown tool {tool!r}; there are: {', '.join(TOOLS)}")
    return RUNNERS[tool](path, probes, H, n, start_row, native, parameter_set)


def run_multi(tool, path, system, H, t_end=None, native=False, check=True):
    """A multi-body scene's archive (multibody.py) in `tool`: a multibody.Run of the scene's
    probes from t = 0, the archive checked first as `run` does."""
    if check:
        archive.check(path, system)
    scene = system.scene
    n = steps(H, scene.t_end if t_end is None else t_end)
    t, rows, cpu, failed = run_probes(tool, path, scene.probes, H, n, scene.start_row(system), native)
    samples = {f"{c}.{v}": rows[:, j] for j, (c, v) in enumerate(scene.probes)}
    return multibody.Run(t=t, samples=samples, cpu=cpu, steps=len(t) - 1, failed=failed, H=H, method=tool)


RUNNERS = {"libcosim": _libcosim, "ecos": _ecos}


def run(tool, path, system, H, t_end=None, native=False, check=True):
    """Run archive `path` of `system` in `tool` with steps of H up to t_end (default the
    scene's): a master.Result (t, p, u, extra = the monitored outputs, cpu = CPU seconds of the
    stepping loop) and, as `samples`, the raw Body outputs {name: array}. With `native` the
    tool steps all at once and only `cpu` (and `failed`) mean anything. The archive is checked
    against its FMUs and the scene first (archive.check, ArchiveError) unless `check` is off:
    both tools only warn about a parameter they cannot apply and run on."""
    if tool not in RUNNERS:
        raise ValueError(f"unknown tool {tool!r}; there are: {', '.join(TOOLS)}")
    if check:
        archive.check(path, system)
    scene = system.scene
    t_end = scene.t_end if t_end is None else t_end
    n = steps(H, t_end)
    body = scene.body()
    names = systems.state_outputs(body)
    start = system.component(system.body).params
    t, rows, cpu, failed = run_probes(tool, path, [(system.body, x) for x in names], H, n,
                                      [start.get("start." + x, 0.0) for x in names], native)
    samples = {name: rows[:, j] for j, name in enumerate(names)}
    p, u = systems.to_state(body, samples)
    extra = monitored(scene, t, p, u) if scene.record and not native else np.empty((len(t), 0))
    return master.Result(t=t, p=p, u=u, extra=extra, cpu=cpu, steps=len(t) - 1, calls=None,
                         iterations=0, events=0, failed=failed, H=H, method=tool, samples=samples)


def monitored(scene, t, p, u):
    """The outputs scene.record at the states (t, p, u), read from a connector instance (fmpy) as
    our master reads them: inputs set, outputs read, no step."""
    body = scene.body()
    params = {**scene.params, "cosim.extrapolation": 0}
    fmu = Connector(scene.variant, params, scene.init_inputs(), body.in_names, list(scene.record))
    try:
        out = np.empty((len(t), len(scene.record)))
        for k in range(len(t)):
            body.inputs(t[k], p[k], u[k], fmu.x)
            fmu.set_inputs()
            out[k] = fmu.get_outputs()
        return out
    finally:
        fmu.close()
