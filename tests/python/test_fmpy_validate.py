"""Packaging and interface of the connector FMUs, through fmpy:
validation, a default simulation, the variable set each variant exposes
(README, Variants and Variables) and the units of its Real variables."""

from __future__ import annotations

import re
from types import SimpleNamespace

import numpy as np
import pytest

import _ref
from conftest import REPO, VARIANTS, driver, fmu_path, model_description

ALL = list(_ref.VARIANTS)
DIST = REPO / "dist"


def _fmu(variant):
    return str(fmu_path(variant))


def _md(variant):
    return model_description(variant)


# --------------------------------------------------------------------------
# validation and a default simulation
# --------------------------------------------------------------------------


def test_every_variant_is_packaged():
    assert sorted(VARIANTS) == sorted(ALL)  # conftest and _ref agree
    present = sorted(p.stem for p in DIST.glob("*.fmu")) if DIST.exists() else []
    assert sorted(ALL) == sorted(set(present) & set(ALL)), present


@pytest.mark.parametrize("variant", ALL)
def test_validate_fmu(variant):
    from fmpy.validation import validate_fmu

    assert validate_fmu(_fmu(variant)) == []


@pytest.mark.parametrize("variant", ALL)
def test_model_identifier_and_binary(variant):
    import zipfile

    md = _md(variant)
    assert md.fmiVersion == "2.0"
    assert md.coSimulation is not None and md.modelExchange is None
    assert md.coSimulation.modelIdentifier == variant
    with zipfile.ZipFile(_fmu(variant)) as z:
        names = z.namelist()
    assert "modelDescription.xml" in names
    assert f"binaries/linux64/{variant}.so" in names
    assert "documentation/index.html" in names


@pytest.mark.parametrize("variant", ALL)
def test_simulate_defaults(variant):
    """Default parameters and inputs: the FMU runs, every output is finite
    and -- the default inputs being constant (zero velocities) -- constant, except event.time,
    which is the end of each step (no event located), i.e. the output's time."""
    from fmpy import simulate_fmu

    res = simulate_fmu(_fmu(variant), fmi_type="CoSimulation", stop_time=0.1, output_interval=0.01)
    assert len(res) >= 11
    assert res["time"][-1] == pytest.approx(0.1)
    for name in res.dtype.names:
        col = np.asarray(res[name], dtype=float)
        assert np.all(np.isfinite(col)), name
        if name == "event.time":
            assert np.allclose(col, res["time"], rtol=0, atol=1e-15), name
        elif name != "time":
            assert np.allclose(col, col[0], rtol=1e-12, atol=1e-12), name


# --------------------------------------------------------------------------
# the variable set
# --------------------------------------------------------------------------

TRANS_OUT = ["CP", "CU", "CV", "CTF", "CEF", "CVF", "CRF"]
ROT_OUT = ["CPR", "CUR", "CVR", "CTM", "CEM", "CVM", "CRM"]
CONSTRAINT_PARAMS = ["constraint.stiffness", "constraint.damping", "constraint.rotStiffness", "constraint.rotDamping"]


def _by_name(md):
    return {v.name: v for v in md.modelVariables}


@pytest.mark.parametrize("variant", ALL)
def test_inputs_are_exactly_the_variant_nodes(variant):
    md = _md(variant)
    inputs = {v.name for v in md.modelVariables if v.causality == "input"}
    assert inputs == set(_ref.input_names(variant))
    V = _by_name(md)
    for n in inputs:
        assert V[n].type == "Real" and V[n].variability == "continuous", n
    # sensible defaults: identity orientation, zero velocities and accelerations
    for node in ("a", "b"):
        if f"{node}.q.w" in V:
            assert [float(V[f"{node}.q.{c}"].start) for c in "wxyz"] == [1.0, 0.0, 0.0, 0.0]
        for kind in ("v", "w", "dv", "dw"):
            for j in (1, 2, 3):
                if f"{node}.{kind}[{j}]" in V:
                    assert float(V[f"{node}.{kind}[{j}]"].start) == 0.0


@pytest.mark.parametrize("variant", ALL)
def test_node_load_outputs(variant):
    md = _md(variant)
    loads = {v.name for v in md.modelVariables if re.fullmatch(r"[ab]\.[fm]\[\d\]", v.name)}
    expected = {f"{n}[{j}]" for n in _ref.VARIANTS[variant]["loads"] for j in (1, 2, 3)}
    assert loads == expected
    V = _by_name(md)
    for n in loads:
        assert V[n].causality == "output" and V[n].type == "Real", n


@pytest.mark.parametrize("variant", ALL)
def test_connector_outputs_for_available_components_only(variant):
    md = _md(variant)
    V = _by_name(md)
    trans, rot = _ref.VARIANTS[variant]["trans"], _ref.VARIANTS[variant]["rot"]
    for i in (1, 2, 3):
        for p in TRANS_OUT:
            want = i in trans or (variant == "Planar" and i == 1 and p in ("CRF", "CTF"))
            assert (f"{p}{i}" in V) == want, f"{p}{i}"
            if want:
                assert V[f"{p}{i}"].causality == "output" and V[f"{p}{i}"].type == "Real"
        for p in ROT_OUT:
            want = i in rot or (variant == "Planar" and i in (2, 3) and p in ("CRM", "CTM"))
            assert (f"{p}{i}" in V) == want, f"{p}{i}"
            if want:
                assert V[f"{p}{i}"].causality == "output" and V[f"{p}{i}"].type == "Real"
    for n in ("energy.stored", "energy.damping"):
        assert n in V and V[n].causality == "output" and V[n].type == "Real", n


@pytest.mark.parametrize("variant", ALL)
def test_parameters_for_available_components_only(variant):
    md = _md(variant)
    V = _by_name(md)
    avail = {k for _n, k in _ref.components_of(variant)}
    for k in range(1, 7):
        for p, typ in (("elasticity.k", "Real"), ("damping.c", "Real"), ("reference.given", "Boolean"), ("reference.value", "Real")):
            name = f"{p}{k}"
            assert (name in V) == (k in avail), name
            if k in avail:
                assert V[name].causality == "parameter" and V[name].type == typ, name
                if p in ("elasticity.k", "damping.c"):
                    assert float(V[name].start) == 0.0, name  # behaviours default to off
                if p == "reference.given":
                    assert V[name].start in ("false", "0", False), name
    for name in CONSTRAINT_PARAMS:
        assert (name in V) == (variant == "Planar"), name
        if variant == "Planar":
            assert V[name].causality == "parameter" and V[name].type == "Real"
            assert float(V[name].start) >= 0.0
    if variant == "Planar":
        # the penalty needs a default that enforces the constraint
        assert float(V["constraint.stiffness"].start) > 0.0
        assert float(V["constraint.rotStiffness"].start) > 0.0
    ex = V["cosim.extrapolation"]
    assert ex.type == "Integer" and ex.causality == "parameter" and int(ex.start) == 1


# --------------------------------------------------------------------------
# units
# --------------------------------------------------------------------------

# dimensions as exponents of (kg, m, s, rad)
_BASE = {
    "kg": (1, 0, 0, 0),
    "m": (0, 1, 0, 0),
    "s": (0, 0, 1, 0),
    "rad": (0, 0, 0, 1),
    "N": (1, 1, -2, 0),
    "J": (1, 2, -2, 0),
    "W": (1, 2, -3, 0),
    "1": (0, 0, 0, 0),
}

M, RAD, MPS, RADPS = (0, 1, 0, 0), (0, 0, 0, 1), (0, 1, -1, 0), (0, 0, -1, 1)
N, NM, J = (1, 1, -2, 0), (1, 2, -2, 0), (1, 2, -2, 0)
N_PER_M, NM_PER_RAD = (1, 0, -2, 0), (1, 2, -2, -1)
NS_PER_M, NMS_PER_RAD = (1, 0, -1, 0), (1, 2, -1, -1)
NONE = (0, 0, 0, 0)
S, S_PER_M, KG, KGM2 = (0, 0, 1, 0), (0, -1, 1, 0), (1, 0, 0, 0), (1, 2, 0, 0)
MPS2, RADPS2 = (0, 1, -2, 0), (0, 0, -2, 1)


def _parse_unit(u):
    """'N.m/rad' -> exponents of (kg, m, s, rad); factors joined by '.' or
    '*', one optional '/', integer exponents written 'm2', 's-1' or 'm^2'."""
    if u is None or u.strip() in ("", "1"):
        return NONE
    num, _, den = u.partition("/")
    dims = np.zeros(4, dtype=int)
    for part, sign in ((num, 1), (den, -1)):
        if not part:
            continue
        for f in re.split(r"[.*]", part.strip("()")):
            m = re.fullmatch(r"(kg|rad|[mNsJW1])\^?(-?\d+)?", f)
            if m is None:
                return None
            dims += sign * int(m.group(2) or 1) * np.array(_BASE[m.group(1)])
    return tuple(int(x) for x in dims)


def _unit_dims(md, unit):
    dims = _parse_unit(unit)
    if dims is None:  # fall back to the declared base units
        for u in md.unitDefinitions:
            if u.name == unit and u.baseUnit is not None:
                b = u.baseUnit
                if float(b.factor) == 1.0 and float(b.offset) == 0.0:
                    dims = (int(b.kg), int(b.m), int(b.s), int(b.rad))
    return dims


# One rule per variable family, written from the units SPEC §3 and docs/body.md give (not read
# from the model descriptions): every Real variable of every FMU, FMI 2.0 and 3.0, connectors and
# Body, must match one, and a variable that matches none fails test_units.
_CONNECTOR_RULES = [
    (r"[ab]\.r\[\d\]", M),
    (r"[ab]\.q\.[wxyz]", NONE),
    (r"[ab]\.v\[\d\]", MPS),
    (r"[ab]\.w\[\d\]", RADPS),
    (r"[ab]\.dv\[\d\]", MPS2),                  # acceleration inputs
    (r"[ab]\.dw\[\d\]", RADPS2),
    (r"[ab]\.f\[\d\]", N),
    (r"[ab]\.m\[\d\]", NM),
    (r"C[PU]\d", M),
    (r"C[PU]R\d", RAD),
    (r"CV\d", MPS),
    (r"CVR\d", RADPS),
    (r"C[TEVRS]F\d", N),
    (r"C[TEVRS]M\d", NM),
    (r"CNF|CSFC", N),                           # F_NC, the sliding friction magnitude
    (r"CNM1|CSMC1", NM),                        # M_NR1, the spin friction magnitude
    (r"energy\..*", J),
    (r"event\.time|cosim\.maxSubstep|time", S),
    (r"elasticity\.k[123]", N_PER_M),
    (r"elasticity\.k[456]", NM_PER_RAD),
    (r"damping\.c[123]", NS_PER_M),
    (r"damping\.c[456]", NMS_PER_RAD),
    (r"reference\.value[123]", M),
    (r"reference\.value[456]", RAD),
    (r"stop\.(lower|upper)[123]", M),
    (r"stop\.(lower|upper)[456]", RAD),
    (r"(constraint|stop)\.stiffness", N_PER_M),
    (r"(constraint|stop)\.damping", NS_PER_M),
    (r"(constraint|stop)\.rotStiffness", NM_PER_RAD),
    (r"(constraint|stop)\.rotDamping", NMS_PER_RAD),
    (r"friction\.mu(Static|Kinetic)", NONE),
    (r"friction\.decay", S_PER_M),              # d_c × slip rate (m/s) is an exponent
    (r"friction\.R", M),
    (r"friction\.(Fint|maxForce)", N),
    (r"friction\.Mint", NM),
    (r"friction\.stickStiffness", N_PER_M),
    (r"friction\.stickStiffnessR1", NM_PER_RAD),
    (r"friction\.stickDamping", NS_PER_M),
    (r"friction\.stickDampingR1", NMS_PER_RAD),
    (r"friction\.slip", M),                     # accumulated slip per effect
    (r"friction\.slipR1", RAD),
]
_BODY_RULES = [
    (r"(start\.|port\[\d+\]\.(offset\.)?)?r\[\d\]", M),
    (r"(start\.|port\[\d+\]\.(offset\.)?)?q\.[wxyz]", NONE),
    (r"(start\.|port\[\d+\]\.)?v\[\d\]", MPS),
    (r"(start\.|port\[\d+\]\.)?w\[\d\]", RADPS),
    (r"(port\[\d+\]\.)?f\[\d\]", N),
    (r"(port\[\d+\]\.)?m\[\d\]", NM),
    (r"energy\.(kinetic|potential)", J),
    (r"mass", KG),
    (r"inertia\[\d\]", KGM2),
    (r"gravity\[\d\]", MPS2),
    (r"spring\.k\[\d\]", N_PER_M),
    (r"rigid\.maxTurn", RAD),
    (r"time", S),
]
_REAL = ("Real", "Float64", "Float32")


def _expected_dims(name, rules=None):
    for pat, dims in _CONNECTOR_RULES if rules is None else rules:
        if re.fullmatch(pat, name):
            return dims
    return None


def _unit_problems(md, rules):
    """(problems, checked): each Real variable of `md` without a rule, without a unit where it
    needs one, or with a unit of another dimension."""
    problems, checked = [], 0
    for v in md.modelVariables:
        if v.type not in _REAL:
            continue
        checked += 1
        want = _expected_dims(v.name, rules)
        if want is None:
            problems.append(f"{v.name}: no unit rule (add one from the manual's unit)")
            continue
        unit = v.unit or (v.declaredType.unit if v.declaredType is not None else None)
        if want != NONE and not unit:
            problems.append(f"{v.name} has no unit")
            continue
        got = _unit_dims(md, unit)
        if got != want:
            problems.append(f"{v.name}: unit {unit!r} has dimension {got}, expected {want} (kg, m, s, rad)")
    return problems, checked


_UNIT_FMUS = [(v, d) for v in ALL + ["Body"] for d in ("", "fmi3")]


@pytest.mark.parametrize("variant,fmi", _UNIT_FMUS, ids=[f"{v}-{d or 'fmi2'}" for v, d in _UNIT_FMUS])
def test_units(variant, fmi):
    fmu_path(variant)
    md = driver.model_description(variant, DIST / fmi if fmi else None)
    problems, checked = _unit_problems(md, _BODY_RULES if variant == "Body" else _CONNECTOR_RULES)
    assert problems == []
    assert checked >= 20


def test_control_a_variable_without_a_rule_or_of_a_wrong_unit_fails():
    """The unit check's negative control: a made-up model description with a variable no rule
    names and a friction coefficient declared in newtons, both reported; a correct one not."""
    var = lambda name, unit: SimpleNamespace(name=name, type="Real", unit=unit,  # noqa: E731
                                             declaredType=None)
    md = SimpleNamespace(unitDefinitions=[], modelVariables=[
        var("friction.newThing", "m"), var("friction.muStatic", "N"), var("friction.R", "m"),
        SimpleNamespace(name="cosim.extrapolation", type="Integer")])
    problems, checked = _unit_problems(md, _CONNECTOR_RULES)
    assert checked == 3
    assert len(problems) == 2
    assert problems[0].startswith("friction.newThing: no unit rule")
    assert problems[1].startswith("friction.muStatic: unit 'N'")
    # the Body's port variables (bodies with load ports) have rules, in their units
    for name, dims in (("port[2].offset.r[1]", M), ("port[1].offset.q.w", NONE), ("port[1].f[3]", N),
                       ("port[2].m[1]", NM), ("port[1].r[2]", M), ("port[1].q.z", NONE),
                       ("port[1].v[1]", MPS), ("port[2].w[3]", RADPS)):
        assert _expected_dims(name, _BODY_RULES) == dims, name
