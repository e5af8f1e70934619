"""Shared fixtures and helpers for the fmpy test suite.

Plain helpers (importable with ``from conftest import ...``) and fixtures of the same name:
  REPO, VARIANTS           repository root, the five model identifiers
  fmu_path(variant)        dist/<variant>.fmu (fails with "run ./scripts/run first" if missing)
  model_description(v)     fmpy ModelDescription of dist/<v>.fmu (cached)
  vr(md_or_variant)        dict name -> VarRef, an int (the valueReference) with .type
                           ('Real', 'Integer', 'Boolean', ...), .causality, .variability
Fixtures only:
  repo                     REPO
  variant                  parametrised over VARIANTS
  extracted                session-wide dict variant -> unzip directory (each FMU extracted once)
  make_slave(variant, instance_name='t', log=None, logging_on=None, guid=None)
                           an instantiated FMU2Slave, freed at teardown. With ``log=[]`` the
                           FMU's log messages are appended to that list as
                           (status: int, category: str, message: str); without it they are printed
                           (pytest shows them for failing tests). ``logging_on`` defaults to
                           ``log is not None``. ``guid`` overrides the GUID (to test refusal;
                           instantiate then raises and the log holds the reason).
"""
import ctypes
import functools
import itertools
from pathlib import Path

import numpy as np
import pytest
from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi2 import (FMU2Slave, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                       fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
from fmpy.logging import addLoggerProxy

REPO = Path(__file__).resolve().parents[2]
VARIANTS = ["Planar", "ProjectionCartesian", "ProjectionFlexionTorsion", "Bushing", "RadialThrust"]
STATUS = ["OK", "Warning", "Discard", "Error", "Fatal", "Pending"]


def fmu_path(variant: str) -> Path:
    path = REPO / "dist" / f"{variant}.fmu"
    if not path.is_file():
        pytest.fail(f"{path.relative_to(REPO)} is missing: run ./scripts/run first", pytrace=False)
    return path


@functools.lru_cache(maxsize=None)
def model_description(variant: str):
    return read_model_description(str(fmu_path(variant)))


class VarRef(int):
    """A value reference (usable wherever an int is) that also knows its variable's type."""

    def __new__(cls, v):
        self = super().__new__(cls, v.valueReference)
        self.name, self.type, self.causality, self.variability = v.name, v.type, v.causality, v.variability
        return self


def vr(md) -> dict:
    """Map variable name -> VarRef for a ModelDescription (or a variant name)."""
    if isinstance(md, str):
        md = model_description(md)
    return {v.name: VarRef(v) for v in md.modelVariables}


# --- logging -----------------------------------------------------------------------------------
# fmpy's native proxy (fmpy/logging) formats the FMU's printf-style message, then calls ONE global
# Python logger. So we register a single dispatcher and route each message by the
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


_LOGGER = fmi2CallbackLoggerTYPE(_dispatch)    # kept alive for the whole session
_ALLOC = fmi2CallbackAllocateMemoryTYPE(calloc)
_FREE = fmi2CallbackFreeMemoryTYPE(free)


def _callbacks(log):
    env = next(_env_ids)
    _sinks[env] = log
    cb = fmi2CallbackFunctions(logger=_LOGGER, allocateMemory=_ALLOC, freeMemory=_FREE,
                               componentEnvironment=env)
    # Sets the proxy's global logger to _dispatch (again: a test may have called
    # simulate_fmu(logger=...) in between) and swaps cb.logger for the native proxy.
    addLoggerProxy(ctypes.byref(cb))
    return cb


class FMU2TestSlave(FMU2Slave):  # fmpy loads fmi2* functions only for class names starting "FMU2"
    """FMU2Slave whose freeInstance may be called more than once (tests and teardown both free)."""

    def freeInstance(self):
        if self.component is not None:
            self.fmi2FreeInstance(self.component)
            self.component = None
        if getattr(self, "dll", None) is not None:
            self.freeLibrary()
            self.dll = None


# --- fixtures ----------------------------------------------------------------------------------
@pytest.fixture(scope="session")
def repo():
    return REPO


@pytest.fixture(params=VARIANTS)
def variant(request):
    return request.param


@pytest.fixture(name="fmu_path", scope="session")
def _fmu_path_fixture():
    return fmu_path


@pytest.fixture(name="model_description", scope="session")
def _model_description_fixture():
    return model_description


@pytest.fixture(name="vr", scope="session")
def _vr_fixture():
    return vr


@pytest.fixture(scope="session")
def extracted(tmp_path_factory):
    root = tmp_path_factory.mktemp("fmus")
    return {v: str(extract(str(fmu_path(v)), str(root / v))) for v in VARIANTS}


@pytest.fixture
def make_slave(extracted):
    slaves = []
    envs = []

    def make(variant, instance_name="t", log=None, logging_on=None, guid=None):
        md = model_description(variant)
        slave = FMU2TestSlave(guid=md.guid if guid is None else guid, unzipDirectory=extracted[variant],
                              modelIdentifier=md.coSimulation.modelIdentifier, instanceName=instance_name)
        slaves.append(slave)
        cb = _callbacks(log)
        envs.append(cb.componentEnvironment)
        slave.instantiate(callbacks=cb, loggingOn=(log is not None) if logging_on is None else logging_on)
        return slave

    yield make
    for s in reversed(slaves):
        s.freeInstance()
    for e in envs:
        _sinks.pop(e, None)


# --------------------------------------------------------------------------
# a small name-based driver over an instantiated FMU2Slave (stops and friction tests)
# --------------------------------------------------------------------------


class Conn:
    """Set/get by name, step with a running time; `start` initializes with parameters and inputs."""

    def __init__(self, slave, variant="Planar"):
        self.s, self.vr, self.t = slave, vr(variant), 0.0

    def start(self, params, inputs):
        self.s.setupExperiment(startTime=0.0)
        self.s.enterInitializationMode()
        self.set(params)
        self.set(inputs)
        self.s.exitInitializationMode()
        return self

    def set(self, values):
        reals = [(self.vr[n], float(v)) for n, v in values.items() if self.vr[n].type == "Real"]
        ints = [(self.vr[n], int(v)) for n, v in values.items() if self.vr[n].type == "Integer"]
        if reals:
            self.s.setReal([r for r, _ in reals], [v for _, v in reals])
        if ints:
            self.s.setInteger([r for r, _ in ints], [v for _, v in ints])

    def get(self, names):
        return np.array(self.s.getReal([self.vr[n] for n in names]))

    def geti(self, names):
        return np.array(self.s.getInteger([self.vr[n] for n in names]))

    def one(self, name):
        v = self.vr[name]
        return (self.s.getInteger([v]) if v.type == "Integer" else self.s.getReal([v]))[0]

    def step(self, h):
        self.s.doStep(currentCommunicationPoint=self.t, communicationStepSize=h)
        self.t += h
