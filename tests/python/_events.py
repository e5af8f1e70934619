"""Helpers of tests/python/test_fmpy_events.py: one connector FMU, FMI 2.0 (dist/<v>.fmu through
fmpy's FMU2Slave) or FMI 3.0 (dist/fmi3/<v>.fmu through FMU3Slave), behind one small interface,
and the co-simulation master that drives it along a prescribed path and collects the events the
FMU reports.

The master (`run`) owns the body: it knows the path of node b in closed form (`Path.inputs`) and
its own event functions along that path (`Path.truth`, the master's view: penetration, trial
force minus limit, slip rate). At every communication point, also right after an event, it sets
the exact inputs there; the FMU moves the node along its own extrapolation of them over the step
and locates its events on that extrapolation. Routes:

  "early"     FMI 3.0 with earlyReturnAllowed: a step ends at the FMU's first event
              (earlyReturn, lastSuccessfulTime); the master continues from there.
  "rollback"  FMI 2.0 (or FMI 3.0 without early return): the master saves the FMU state before
              every step; when the step reports event.count > 0 with event.time inside the step,
              it restores the state and re-steps to event.time, and continues from there.

Where the extrapolation is exact (linear approach, ramps, velocities with their derivatives) the
FMU's event is the true one. Where it is not (the bounce's release: the penetration is a damped
sine), the FMU's event is the root of the tangent at the step's start, and repeated events
converge on the true root like Newton's method *from the side not yet crossed*. The tangent of a
concave stretch overshoots the true root (or misses it past the step's end); a master that owns
the body sees that from its own event function and does what event-locating masters do: it
rejects the step (restores the state saved before it) and retries with half the step. The
master's test reads signs of its own functions only; it accepts an FMU event when its own
crossing lies within `ACCEPT` × (step) of it (the spec's location tolerance, 1e-9 of the step),
or when it has not crossed yet (the FMU's event came first: the next step starts nearer).
The master never uses a closed-form event time.
"""
from __future__ import annotations

import ctypes
import functools
import tempfile
from dataclasses import dataclass, field
from pathlib import Path as FsPath

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

REPO = FsPath(__file__).resolve().parents[2]

#: the master accepts an FMU event whose time lies within ACCEPT·h of its own crossing (SPEC §9:
#: events are located to 1e-9 of the step)
ACCEPT = 1e-9
#: the resolution of a time t is about EPS·|t|: the master allows a few of those too
EPS = float(np.finfo(float).eps)


def fmu_file(version: int, variant: str) -> FsPath:
    path = REPO / "dist" / ("fmi3" if version == 3 else "") / f"{variant}.fmu"
    if not path.is_file():
        raise FileNotFoundError(f"{path.relative_to(REPO)} is missing: run ./scripts/run first")
    return path


@functools.lru_cache(maxsize=None)
def _md(version, variant):
    return read_model_description(str(fmu_file(version, variant)))


@functools.lru_cache(maxsize=None)
def _unzipped(version, variant):
    return extract(str(fmu_file(version, variant)), tempfile.mkdtemp(prefix=f"events{version}-{variant}-"))


class Twin:
    """One FMU instance, FMI 2.0 or 3.0, with the calls the master needs, by name."""

    def __init__(self, version: int, variant: str, early_return: bool = False, log=None):
        self.version, self.variant = version, variant
        md = _md(version, variant)
        self.v = {x.name: x for x in md.modelVariables}
        kw = dict(guid=md.guid, unzipDirectory=_unzipped(version, variant), modelIdentifier=variant,
                  instanceName=f"events{version}")
        self.log = log
        if version == 3:
            self.s = FMU3Slave(**kw)
            self.s.instantiate(earlyReturnAllowed=early_return, loggingOn=log is not None,
                               logMessage=(lambda env, st, cat, msg: log.append(msg.decode()))
                               if log is not None else None)
        else:
            if early_return:
                raise ValueError("FMI 2.0 has no early return")
            self.s = FMU2Slave(**kw)
            self.s.instantiate()
        self.real_out = [x.valueReference for x in md.modelVariables
                         if x.causality == "output" and x.type in ("Real", "Float64")]
        self.int_out = [x.valueReference for x in md.modelVariables
                        if x.causality == "output" and x.type in ("Integer", "Int32")]
        self.state = None

    # --- values --------------------------------------------------------------------------
    def _setter(self, typ):
        s = self.s
        if self.version == 3:
            return {"Float64": s.setFloat64, "Int32": s.setInt32, "Boolean": s.setBoolean}[typ]
        return {"Real": s.setReal, "Integer": s.setInteger, "Boolean": s.setBoolean}[typ]

    def set(self, values: dict):
        by_type = {}
        for name, x in values.items():
            var = self.v[name]
            by_type.setdefault(var.type, ([], []))
            by_type[var.type][0].append(var.valueReference)
            by_type[var.type][1].append(x)
        for typ, (vrs, xs) in by_type.items():
            self._setter(typ)(vrs, xs)

    def set_derivatives(self, values: dict):
        """fmi2SetRealInputDerivatives, order 1 (FMI 2.0 only)."""
        if not values:
            return
        vrs = [self.v[n].valueReference for n in values]
        self.s.setRealInputDerivatives(vrs, [1] * len(vrs), [float(x) for x in values.values()])

    def real(self, names):
        vrs = [self.v[n].valueReference for n in names]
        return list(self.s.getFloat64(vrs) if self.version == 3 else self.s.getReal(vrs))

    def int(self, names):
        vrs = [self.v[n].valueReference for n in names]
        return list(self.s.getInt32(vrs) if self.version == 3 else self.s.getInteger(vrs))

    def record(self):
        """Every Real and Integer output (for bit-for-bit comparisons)."""
        if self.version == 3:
            return tuple(self.s.getFloat64(self.real_out)) + tuple(self.s.getInt32(self.int_out))
        return tuple(self.s.getReal(self.real_out)) + tuple(self.s.getInteger(self.int_out))

    # --- lifecycle -----------------------------------------------------------------------
    def start(self, params: dict, inputs: dict):
        if self.version == 3:
            self.s.enterInitializationMode(startTime=0.0)
        else:
            self.s.setupExperiment(startTime=0.0)
            self.s.enterInitializationMode()
        self.set(params)
        self.set(inputs)
        self.s.exitInitializationMode()

    def do_step(self, t, h):
        """(earlyReturn, the FMU's time after the step)."""
        if self.version == 3:
            _, _, early, last = self.s.doStep(t, h, False)
            return bool(early), last
        self.s.doStep(t, h, False)
        return False, t + h

    def save(self):
        if self.state is None:
            self.state = self.s.getFMUState()
        elif self.version == 3:
            self.s.fmi3GetFMUState(self.s.component, ctypes.byref(self.state))
        else:
            self.s.fmi2GetFMUstate(self.s.component, ctypes.byref(self.state))

    def restore(self):
        self.s.setFMUState(self.state)

    def free(self):
        if self.s is not None:
            if self.state is not None:
                self.s.freeFMUState(self.state)
            self.s.terminate()
            self.s.freeInstance()
            self.s = None


class Path:
    """A prescribed motion of the nodes with the master's own event functions.

    Subclasses give `variant`, `params`, `statuses` (Integer outputs whose changes are the
    events), `t_end`, and `inputs(t)`, `truth(t)` (array of the master's event functions; the
    sign of each tells on which side of its event the body is) with `truth_scale` (their
    magnitudes, for the rounding band), optionally `derivatives(t)` (FMI 2.0 input derivatives,
    order 1)."""

    variant: str
    params: dict
    statuses: list
    t_end: float
    truth_scale: list

    def derivatives(self, t) -> dict:
        return {}


@dataclass
class Event:
    """A step the master accepted that ended at an FMU event."""
    t_start: float          # the step's start
    time: float             # the step's end: lastSuccessfulTime (early return) or the re-step's end
    event_time: float       # the FMU's event.time output after the step
    event_count: int        # the FMU's event.count output after the step
    before: tuple           # statuses at the exact inputs at t_start
    after: tuple            # statuses committed at `time` (before the master sets new inputs)


@dataclass
class Run:
    events: list = field(default_factory=list)
    records: list = field(default_factory=list)   # (t, every output) after every accepted step
    steps: int = 0                                # doStep calls
    rejected: int = 0                             # steps the master rejected (and halved)
    rollbacks: int = 0                            # FMI 2.0 re-steps to event.time
    passed: list = field(default_factory=list)    # (t, t1, event.time, count): events at a step's start
    triggers: list = field(default_factory=list)  # (t, h, event.time, count) of steps re-stepped to event.time
    statuses: list = field(default_factory=list)  # (t1, statuses committed at t1) after every accepted step

    def status_before(self, t):
        """Statuses committed at the end of the last accepted step ending before t."""
        return [s for t1, s in self.statuses if t1 < t][-1]

    def status_after(self, t):
        """Statuses committed at the end of the first accepted step ending after t."""
        return next(s for t1, s in self.statuses if t1 > t)

    def cluster(self, T, width):
        """The events the master accepted within `width` of T (a closed-form event time)."""
        return [e for e in self.events if abs(e.time - T) <= width]


def _side(path, t):
    """Sides of the master's event functions at t: +1, -1, or 0 within 8 ulps of their scale
    (rounding: the function is at its event)."""
    g = np.asarray(path.truth(t), dtype=float)
    side = np.sign(g)
    side[np.abs(g) <= 8.0 * EPS * np.asarray(path.truth_scale, dtype=float)] = 0.0
    return side


def run(twin: Twin, path: Path, H: float, route: str, derivatives: bool = True, record: bool = False,
        max_steps: int = 5000) -> Run:
    """Drive `twin` along `path` to path.t_end with macro step H by `route` ("early" or
    "rollback"); see the module docstring. `derivatives`: send path.derivatives(t) (FMI 2.0)."""
    out = Run()
    twin.start(path.params, path.inputs(0.0))
    t = 0.0
    while t < path.t_end:
        if out.steps > max_steps:
            raise RuntimeError(f"more than {max_steps} steps at t = {t!r}")
        twin.set(path.inputs(t))
        if derivatives and twin.version == 2:
            twin.set_derivatives(path.derivatives(t))
        before = tuple(twin.int(path.statuses))
        side0 = _side(path, t)
        twin.save()
        h, restep = H, False
        while True:
            out.steps += 1
            early, t1 = twin.do_step(t, h)
            ev_time, = twin.real(["event.time"])
            ev_count, = twin.int(["event.count"])
            if route == "rollback" and ev_count > 0 and not restep and ev_time - t > ACCEPT * h:
                # re-step to the event (the restored state holds the inputs and derivatives)
                twin.restore()
                out.triggers.append((t, h, ev_time, ev_count))
                h, restep = ev_time - t, True
                out.rollbacks += 1
                continue
            at_event = early or restep
            crossed = (side0 != 0) & (_side(path, t1) == -side0)
            ok = True
            if crossed.any():
                # the master's own crossing must lie within tol of an event the FMU reported
                tol = max(ACCEPT * h, 4.0 * EPS * abs(t1))
                ok = ev_count > 0 and not np.any(_side(path, max(t, ev_time - tol))[crossed] == -side0[crossed]) \
                    and not np.any(_side(path, min(t1, ev_time + tol))[crossed] == side0[crossed])
            if ok:
                break
            twin.restore()
            out.rejected += 1
            h, restep = 0.5 * h, False
            if h < 1e-6 * H:
                raise RuntimeError(f"at t = {t!r} the master cannot find a step it accepts")
        after = tuple(twin.int(path.statuses))
        if at_event:
            out.events.append(Event(t, t1, ev_time, ev_count, before, after))
        elif ev_count > 0:
            out.passed.append((t, t1, ev_time, ev_count))
        out.statuses.append((t1, after))
        if record:
            out.records.append((t1, twin.record()))
        t = t1
    return out


def relerr(a, b):
    return abs(a - b) / abs(b)
