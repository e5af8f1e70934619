"""fmi_master: the native co-simulation master (Rust) from Python.

Run an SSP 1.0 archive or a lone FMI 2.0/3.0 Co-Simulation FMU with fixed-step Jacobi or
Gauss-Seidel and get the outputs as a numpy structured array, as fmpy's ``simulate_fmu`` gives::

    import fmi_master
    result = fmi_master.simulate("dist/ssp/bounce.ssp", step=1e-3,
                                 start_values={"mass.start.v[3]": -2.0})
    result["time"], result["mass.r[3]"]

``open(path)`` keeps an archive imported for many runs (``System.simulate`` takes the same
arguments). Columns are ``time`` and every output of every component as ``component.variable``
(a lone FMU: the variable's name); Booleans are 0/1, Strings are objects. A bad archive, FMU,
value or setting raises ``MasterError`` with the master's message (archive element, component,
variable, FMI function, time); a failure during the run raises ``SimulationError`` carrying the
rows before it as ``.result``. An FMU asking to terminate ends the run normally
(``Run.terminated``).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._native import MasterError, System as _System

__all__ = ["open", "simulate", "System", "Run", "MasterError", "SimulationError"]


class SimulationError(RuntimeError):
    """A run failed after it started (a step returned Discard, Error or Fatal, an output was
    NaN, ...): the message names it, ``.run`` holds the rows before the failure."""

    def __init__(self, message, run):
        super().__init__(message)
        self.run = run
        self.result = run.result


@dataclass
class Run:
    """One run: ``result`` (the structured array), and how it went."""
    result: np.ndarray
    steps: int
    step: float
    calls: int
    cpu: float
    cpu_per_second: float
    wall: float
    fmu_time: float
    end: float
    terminated: tuple | None
    error: str | None


def _text(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    return str(value)


def _array(d) -> np.ndarray:
    columns = d["columns"]
    n = len(d["time"])
    values = np.asarray(d["values"], dtype=float).reshape(n, len(columns)) if columns else np.empty((n, 0))
    strings = iter(d["strings"])
    string_cols = [j for j in range(len(columns)) if n and np.isnan(values[0, j]) and d["strings"]]
    dtype = [("time", "f8")] + [(c, "O" if j in string_cols else "f8") for j, c in enumerate(columns)]
    out = np.empty(n, dtype=dtype)
    out["time"] = d["time"]
    for j, c in enumerate(columns):
        if j not in string_cols:
            out[c] = values[:, j]
    if string_cols:
        for k in range(n):
            for j in string_cols:
                out[columns[j]][k] = next(strings)
    return out


class System:
    """An SSP archive or FMU, imported and checked once; run it as often as wanted."""

    def __init__(self, path):
        self._native = _System(str(path))

    @property
    def name(self) -> str:
        return self._native.name

    @property
    def components(self) -> list[str]:
        return self._native.components()

    def variables(self, component: str | None = None) -> list[tuple]:
        """(name, type, causality, start) of each variable of ``component`` (a lone FMU: its
        only component)."""
        return self._native.variables(component if component is not None else self.components[0])

    @property
    def default_experiment(self):
        """(start, stop, step), each None where the archive or FMU gives none."""
        return self._native.default_experiment()

    def run(self, step=None, stop=None, method="jacobi", start_values=None, output_interval=None,
            grid="exact", input=None, profile=False) -> Run:
        """Runs and returns a ``Run`` (``error`` set, not raised, if the run failed midway)."""
        starts = [(k, _text(v)) for k, v in (start_values or {}).items()]
        d = self._native.run(method=method, step=step, stop=stop, interval=output_interval, grid=grid,
                             start_values=starts, input=None if input is None else str(input),
                             profile=profile)
        return Run(result=_array(d), **{k: d[k] for k in ("steps", "step", "calls", "cpu", "cpu_per_second",
                                                           "wall", "fmu_time", "end", "terminated", "error")})

    def simulate(self, step=None, stop=None, method="jacobi", start_values=None, output_interval=None,
                 grid="exact", input=None) -> np.ndarray:
        """The result array; raises ``SimulationError`` (with the rows before) if the run fails."""
        run = self.run(step, stop, method, start_values, output_interval, grid, input)
        if run.error is not None:
            raise SimulationError(run.error, run)
        return run.result


def open(path) -> System:  # noqa: A001  (like fmpy's and zipfile's open)
    """Imports the archive (.ssp) or FMU (.fmu) at ``path``."""
    return System(path)


def simulate(path, step=None, stop=None, method="jacobi", start_values=None, output_interval=None,
             grid="exact", input=None) -> np.ndarray:
    """Runs the archive or FMU at ``path``: the outputs as a numpy structured array.

    step: the communication step H (default: the archive's base step or the FMU's stepSize);
    stop: the stop time (default: the DefaultExperiment's); method: "jacobi" or "gauss_seidel";
    start_values: {"component.variable": value} (a lone FMU: {"variable": value});
    output_interval: sample every so many seconds (a whole number of steps; default every step);
    grid: "exact" (t_k = k·H, h = H), "diff" (fmusim's), "ns" (libcosim's), "sum" (Ecos's);
    input: a CSV file driving a lone FMU's inputs (time first, then input names).
    """
    return System(path).simulate(step, stop, method, start_values, output_interval, grid, input)
