"""Shared fixtures and helpers for the fmpy test suite. Loading, instantiating and driving an
FMU is scripts/cosim/driver.py (the one driver, also used by scripts/cosim/master.py); this file
puts scripts/ on sys.path and adds what pytest needs.

Plain helpers (importable with ``from conftest import ...``) and fixtures of the same name:
  REPO, VARIANTS           repository root, the five model identifiers
  fmu_path(variant)        dist/<variant>.fmu (fails with "run ./scripts/run first" if missing)
  model_description(v)     fmpy ModelDescription of dist/<v>.fmu (cached)
  vr(md_or_variant)        dict name -> VarRef, an int (the valueReference) with .type
                           ('Real', 'Integer', 'Boolean', ...), .causality, .variability
  Connector(variant, slave)
                           driver.Connector: name-based set/get, enter/start/step/drive with a
                           master clock, record() of everything observable
  parameter_sets()         tests/data/parameter_sets.json (shared with benches/native/)
Fixtures only:
  repo                     REPO
  variant                  parametrised over VARIANTS
  extracted                session-wide dict variant -> unzip directory (each FMU extracted once)
  make_slave(variant, instance_name='t', log=None, logging_on=None, guid=None)
                           an instantiated FMU2Slave (driver.instantiate), freed at teardown. With ``log=[]`` the
                           FMU's log messages are appended to that list as
                           (status: int, category: str, message: str); without it they are printed
                           (pytest shows them for failing tests). ``logging_on`` defaults to
                           ``log is not None``. ``guid`` overrides the GUID (to test refusal;
                           instantiate then raises and the log holds the reason).
  conn(variant, log=None)  a Connector over a make_slave instance named <variant>-<n> (the fmpy
                           co-simulation tests; test_fmpy_bad_input.py has a `conn` of its own)
"""
import functools
import json
import sys
from pathlib import Path

import pytest
from fmpy import extract

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "scripts"))

from cosim import driver  # noqa: E402  (the one fmpy driver, shared with scripts/cosim/master.py)
from cosim.driver import VARIANTS, Connector, VarRef  # noqa: E402,F401  (re-exported)


def fmu_path(variant: str) -> Path:
    try:
        return driver.fmu_path(variant)
    except driver.MissingFMU as e:
        pytest.fail(f"{e.path.relative_to(REPO)} is missing: run ./scripts/run first", pytrace=False)


def model_description(variant: str):
    fmu_path(variant)
    return driver.model_description(variant)


def vr(md) -> dict:
    """Map variable name -> VarRef for a ModelDescription (or a variant name)."""
    if isinstance(md, str):
        md = model_description(md)
    return driver.vr(md)


@functools.lru_cache(maxsize=None)
def parameter_sets() -> dict:
    """tests/data/parameter_sets.json: the parameter sets and paths shared with the Rust
    benchmark (benches/native/)."""
    return json.loads((REPO / "tests" / "data" / "parameter_sets.json").read_text())


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

    def make(variant, instance_name="t", log=None, logging_on=None, guid=None):
        fmu_path(variant)
        slave = driver.instantiate(variant, extracted[variant], instance_name=instance_name, log=log,
                                   logging_on=logging_on, guid=guid)
        slaves.append(slave)
        return slave

    yield make
    for s in reversed(slaves):
        s.freeInstance()


@pytest.fixture
def conn(make_slave):
    count = [0]

    def make(variant, log=None):
        count[0] += 1
        return Connector(variant, make_slave(variant, instance_name=f"{variant}-{count[0]}", log=log))

    return make
