"""One connector FMU instance driven through fmpy's low-level FMU2Slave API: the single driver
shared by the co-simulation master (scripts/cosim/master.py) and the fmpy test suite
(tests/python, whose conftest puts scripts/ on sys.path).

  fmu_path(variant, dist)        dist/<variant>.fmu (MissingFMU when it is not there)
  model_description(variant)     fmpy ModelDescription, read once per file
  unzipped(variant, dist)        the FMU extracted once per process into a temporary directory
  vr(variant or md)              {name: VarRef}; a VarRef is an int (the valueReference) that
                                 also carries .name, .type, .causality, .variability
  instantiate(variant, unzipdir, instance_name, log, logging_on, guid)
                                 an instantiated FMU2Instance. The FMU's messages go to `log`
                                 (a list, appended as (status, category, message)) or, without
                                 one, are printed. fmi2Instantiate failing raises; the library
                                 is released then.
  Connector(variant, slave)      name-based access (set / get / value / vec / values / record),
                                 the lifecycle (enter / start / step / drive) and a master
                                 clock `t` over an instantiated slave

Every call goes through fmpy's wrappers, which check the status (FMICallException).
"""
from __future__ import annotations

import ctypes
import functools
import itertools
import tempfile
from pathlib import Path

import numpy as np
from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
from fmpy.logging import addLoggerProxy

REPO = Path(__file__).resolve().parents[2]
DIST = REPO / "dist"
VARIANTS = ["Planar", "ProjectionCartesian", "ProjectionFlexionTorsion", "Bushing", "RadialThrust"]
STATUS = ["OK", "Warning", "Discard", "Error", "Fatal", "Pending"]
fmi2LastSuccessfulTime = 2  # fmi2StatusKind


class MissingFMU(FileNotFoundError):
    """dist/<variant>.fmu is not there (./scripts/run builds it); `.path` is the file."""

    def __init__(self, path):
        super().__init__(f"{path} is missing: run ./scripts/run first")
        self.path = Path(path)


def fmu_path(variant: str, dist=None) -> Path:
    path = Path(DIST if dist is None else dist) / f"{variant}.fmu"
    if not path.is_file():
        raise MissingFMU(path)
    return path


@functools.lru_cache(maxsize=None)
def _read(path: str):
    return read_model_description(path)


def model_description(variant: str, dist=None):
    return _read(str(fmu_path(variant, dist)))


_UNZIPPED: dict = {}


def unzipped(variant: str, dist=None) -> str:
    """The FMU extracted once per process (into a temporary directory of its own)."""
    path = str(fmu_path(variant, dist))
    if path not in _UNZIPPED:
        _UNZIPPED[path] = extract(path, tempfile.mkdtemp(prefix=f"cosim-{variant}-"))
    return _UNZIPPED[path]


class VarRef(int):
    """A value reference (usable wherever an int is) that also knows its variable's type."""

    def __new__(cls, v):
        self = super().__new__(cls, v.valueReference)
        self.name, self.type, self.causality, self.variability = v.name, v.type, v.causality, v.variability
        return self

    @property
    def valueReference(self):  # noqa: N802 (fmpy's attribute name)
        return int(self)


def vr(md, dist=None) -> dict:
    """Map variable name -> VarRef for a ModelDescription (or a variant name)."""
    if isinstance(md, str):
        md = model_description(md, dist)
    return {v.name: VarRef(v) for v in md.modelVariables}


# --- logging -----------------------------------------------------------------------------------
# fmpy's native proxy (fmpy/logging) formats the FMU's printf-style message, then calls ONE global
# Python logger. So one dispatcher is registered and each message is routed by the
# componentEnvironment pointer that every instance's callbacks carry (FMI 2.0 requires the FMU to
# pass it back). Messages with an unknown environment are printed like fmpy's default logger.
_sinks: dict = {}              # componentEnvironment id -> list or None (print)
_env_ids = itertools.count(1)


def _dispatch(env, instance_name, status, category, message):
    msg = message.decode("utf-8", "replace") if message else ""
    cat = category.decode("utf-8", "replace") if category else ""
    sink = _sinks.get(env)
    if sink is not None:
        sink.append((status, cat, msg))
    else:
        name = instance_name.decode("utf-8", "replace") if instance_name else ""
        label = STATUS[status] if 0 <= status < len(STATUS) else str(status)
        print(f"[{label}] {name} {cat}: {msg}")


_LOGGER = fmi2CallbackLoggerTYPE(_dispatch)    # kept alive for the whole process
_ALLOC = fmi2CallbackAllocateMemoryTYPE(calloc)
_FREE = fmi2CallbackFreeMemoryTYPE(free)


def callbacks(log=None):
    """A callback struct whose logger appends to `log` (a list) or, with None, prints."""
    env = next(_env_ids)
    _sinks[env] = log
    cb = fmi2CallbackFunctions(logger=_LOGGER, allocateMemory=_ALLOC, freeMemory=_FREE,
                               componentEnvironment=env)
    # Sets the proxy's global logger to _dispatch (again: a caller may have run
    # simulate_fmu(logger=...) in between) and swaps cb.logger for the native proxy.
    addLoggerProxy(ctypes.byref(cb))
    return cb


class FMU2Instance(FMU2Slave):  # fmpy loads fmi2* functions only for class names starting "FMU2"
    """FMU2Slave whose freeInstance may be called more than once (a test and its teardown both
    free) and forgets the instance's log routing."""

    env = None

    def freeInstance(self):
        if self.component is not None:
            self.fmi2FreeInstance(self.component)
            self.component = None
        if getattr(self, "dll", None) is not None:
            self.freeLibrary()
            self.dll = None
        _sinks.pop(self.env, None)


def instantiate(variant, unzipdir, instance_name="t", log=None, logging_on=None, guid=None, dist=None):
    """An instantiated FMU2Instance of `variant` from its extracted directory. `logging_on`
    defaults to `log is not None`; `guid` overrides the model description's (to test refusal)."""
    md = model_description(variant, dist)
    slave = FMU2Instance(guid=md.guid if guid is None else guid, unzipDirectory=str(unzipdir),
                         modelIdentifier=md.coSimulation.modelIdentifier, instanceName=instance_name)
    cb = callbacks(log)
    slave.env = cb.componentEnvironment
    try:
        slave.instantiate(callbacks=cb, loggingOn=(log is not None) if logging_on is None else logging_on)
    except Exception:
        slave.freeInstance()
        raise
    return slave


class Connector:
    """One instantiated slave with name-based access and a master clock `t`.

    `v` (also `vr`): {name: VarRef}; `real_out`, `int_out`, `real_in`, `params`: the VarRefs of
    the Real and Integer outputs, the Real inputs and the parameters, in model-description order."""

    def __init__(self, variant, slave, dist=None):
        self.variant, self.s, self.t = variant, slave, 0.0
        self.v = self.vr = vr(variant, dist)
        byc = lambda c, t: [r for r in self.v.values() if r.causality == c and r.type == t]  # noqa: E731
        self.real_out = byc("output", "Real")
        self.int_out = byc("output", "Integer")
        self.real_in = byc("input", "Real")
        self.params = [r for r in self.v.values() if r.causality == "parameter"]

    # --- values ---------------------------------------------------------------------------
    def set(self, values):
        """One fmi2Set<Type> call per type, in the order the types first appear in `values`."""
        groups = {}
        for name, val in values.items():
            r = self.v[name]  # KeyError: the variant has no such variable
            groups.setdefault(r.type, ([], []))
            groups[r.type][0].append(r)
            groups[r.type][1].append(val)
        for typ, (vrs, vals) in groups.items():
            if typ == "Real":
                self.s.setReal(vrs, [float(x) for x in vals])
            elif typ == "Integer":
                self.s.setInteger(vrs, [int(x) for x in vals])
            elif typ == "Boolean":
                self.s.setBoolean(vrs, [bool(x) for x in vals])
            else:
                raise TypeError(typ)

    def get(self, names):
        """Real values as an array, in the order of `names`."""
        return np.array(self.s.getReal([self.v[n] for n in names]))

    def named(self, names):
        """Real values as {name: value}."""
        return dict(zip(names, self.s.getReal([self.v[n] for n in names])))

    def geti(self, names):
        """Integer values as an array."""
        return np.array(self.s.getInteger([self.v[n] for n in names]))

    def value(self, name):
        """One value of any type (Real, Integer, Boolean)."""
        r = self.v[name]
        return {"Real": self.s.getReal, "Integer": self.s.getInteger, "Boolean": self.s.getBoolean}[r.type]([r])[0]

    def vec(self, prefix):
        """a.f -> np.array([a.f[1], a.f[2], a.f[3]])"""
        return self.get([f"{prefix}[{j}]" for j in (1, 2, 3)])

    def values(self):
        """Every parameter and input as ((name, value), ...) (no outputs: they need evaluable
        inputs)."""
        return tuple((r.name, self.value(r.name)) for r in self.params + self.real_in)

    def record(self):
        """Everything observable: Real and Integer outputs, the inputs read back, the time."""
        return (
            tuple(self.s.getReal(self.real_out)),
            tuple(self.s.getInteger(self.int_out)),
            tuple(self.s.getReal(self.real_in)),
            self.s.getRealStatus(fmi2LastSuccessfulTime),
        )

    # --- lifecycle ------------------------------------------------------------------------
    def enter(self, params, inputs, t0=0.0):
        """fmi2SetupExperiment(t0), fmi2EnterInitializationMode, then parameters and inputs."""
        self.s.setupExperiment(startTime=t0)
        self.s.enterInitializationMode()
        self.set(params)
        self.set(inputs)
        self.t = t0

    def start(self, params, inputs, t0=0.0):
        """`enter`, then fmi2ExitInitializationMode."""
        self.enter(params, inputs, t0)
        self.s.exitInitializationMode()
        return self

    def step(self, h):
        self.s.doStep(currentCommunicationPoint=self.t, communicationStepSize=h)
        self.t = self.t + h

    def drive(self, inputs_at, n, h, record=True):
        """n communication steps of size h; before each step the master sets the inputs at the
        current communication point. Returns the record after each step."""
        out = []
        for _ in range(n):
            self.set(inputs_at(self.t))
            self.step(h)
            if record:
                out.append(self.record())
        return out
