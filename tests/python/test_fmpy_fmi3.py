"""The FMI 3.0 Co-Simulation FMUs (dist/fmi3/*.fmu) through fmpy's FMU3Slave, against their FMI 2.0
twins (dist/*.fmu through FMU2Slave): same library, same model, so every output must be the same
double, bit for bit.

- fmpy validates every FMI 3.0 FMU clean and simulate_fmu runs each, with the same result as the
  FMI 2.0 FMU under the same start values and input signal;
- the co-simulation scenes of SCENES (scripts/cosim: belt stick-slip, puck, bounce on a stop,
  bushing oscillator) run through the master with an FMI 3.0 connector give the same trajectories
  as with the FMI 2.0 one, for zero-order hold, rollback (get/set FMU state every step) and
  linear-implicit (directional derivatives every step). FMI 3.0 has no input derivatives
  (fmi3SetInputDerivatives does not exist), so for this comparison the FMI 2.0 connector does not
  send them either: both FMUs extrapolate the nodes from their own velocities;
- directional derivatives equal the FMI 2.0 ones bit for bit; adjoint derivatives equal Jᵀ·v of
  that Jacobian within 1e-12 relative (the adjoint is the sum Σᵢ vᵢ Jᵢⱼ, computed in another
  order than numpy's, so only rounding may differ);
- FMU state get/set and serialize/de-serialize round trip bit for bit;
- what the FMUs do not have (Event Mode, clocks, Model Exchange) answers fmi3Error with a log line.
"""
from __future__ import annotations

import functools
import sys
import xml.etree.ElementTree as ET
import zipfile

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave
from fmpy.validation import validate_fmu

from conftest import REPO, VARIANTS

sys.path.insert(0, str(REPO / "scripts"))
from cosim import master  # noqa: E402
from cosim.scenes import Belt, Bounce, BushingFreq, Puck  # noqa: E402

DIST3 = REPO / "dist" / "fmi3"


def fmu3_path(variant):
    path = DIST3 / f"{variant}.fmu"
    if not path.is_file():
        pytest.fail(f"{path.relative_to(REPO)} is missing: run ./scripts/run first", pytrace=False)
    return path


@functools.lru_cache(maxsize=None)
def md3(variant):
    return read_model_description(str(fmu3_path(variant)))


@functools.lru_cache(maxsize=None)
def unzipped3(variant):
    import tempfile
    return extract(str(fmu3_path(variant)), tempfile.mkdtemp(prefix=f"fmi3-{variant}-"))


def bits(a):
    """The IEEE bit patterns of a float array (equality of these is bit-for-bit equality)."""
    return np.ascontiguousarray(np.asarray(a, dtype=np.float64)).view(np.uint64)


# ------------------------------------------------------------------ validation, simulate_fmu

@pytest.mark.parametrize("variant", VARIANTS)
def test_validate_fmu3(variant):
    assert validate_fmu(str(fmu3_path(variant))) == []
    md = md3(variant)
    assert md.fmiVersion == "3.0"
    assert md.coSimulation.modelIdentifier == variant
    # the capability flags as written (fmpy 0.3.32 reads providesDirectionalDerivatives under
    # its FMI 2.0 spelling and reports False, so the XML is read here)
    with zipfile.ZipFile(fmu3_path(variant)) as z:
        cs = ET.fromstring(z.read("modelDescription.xml")).find("CoSimulation").attrib
    for key in ("canHandleVariableCommunicationStepSize", "canGetAndSetFMUState",
                "canSerializeFMUState", "providesDirectionalDerivatives", "providesAdjointDerivatives",
                "mightReturnEarlyFromDoStep"):
        assert cs[key] == "true", key
    for key in ("hasEventMode", "canReturnEarlyAfterIntermediateUpdate", "providesIntermediateUpdate"):
        assert cs[key] == "false", key
    # instantiationToken = the FMI 2.0 GUID; same variables apart from the independent time
    md2 = read_model_description(str(REPO / "dist" / f"{variant}.fmu"))
    assert md.guid == md2.guid
    v2 = {v.name: v for v in md2.modelVariables}
    v3 = {v.name: v for v in md.modelVariables if v.causality != "independent"}
    assert v3.keys() == v2.keys()
    types = {"Real": "Float64", "Integer": "Int32", "Boolean": "Boolean"}
    for name, a in v2.items():
        b = v3[name]
        assert (b.valueReference, b.causality, b.variability, b.start, b.unit) == \
               (a.valueReference, a.causality, a.variability, a.start, a.unit), name
        assert b.type == types[a.type], name


def _driven_inputs(variant, t_end=0.3, dt=1e-3):
    """A sinusoidal drive of node b as an fmpy input signal (structured array)."""
    names = {v.name for v in md3(variant).modelVariables}
    t = np.arange(0.0, t_end + dt / 2, dt)
    w, a = 2 * np.pi * 5.0, 0.02
    cols = {"b.r[1]": a * np.sin(w * t), "b.r[2]": 0.5 * a * np.sin(2 * w * t),
            "b.v[1]": a * w * np.cos(w * t), "b.v[2]": a * w * np.cos(2 * w * t),
            "b.r[3]": 0.005 * np.sin(w * t),
            # a rotation about x by θ = 0.05 sin(w t)
            "b.q.w": np.cos(0.025 * np.sin(w * t)), "b.q.x": np.sin(0.025 * np.sin(w * t)),
            "b.w[1]": 0.05 * w * np.cos(w * t),
            # the accelerations of that drive (they move the nodes with cosim.extrapolation = 3)
            "b.dv[1]": -a * w * w * np.sin(w * t), "b.dv[2]": -2 * a * w * w * np.sin(2 * w * t),
            "b.dv[3]": -0.005 * w * w * np.sin(w * t), "b.dw[1]": -0.05 * w * w * np.sin(w * t)}
    cols = {k: v for k, v in cols.items() if k in names}
    dtype = [("time", np.float64)] + [(k, np.float64) for k in cols]
    signal = np.zeros(len(t), dtype=dtype)
    signal["time"] = t
    for k, v in cols.items():
        signal[k] = v
    return signal


def _start_values(variant):
    names = {v.name for v in md3(variant).modelVariables}
    start = {}
    for k in range(1, 7):
        start.update({f"elasticity.k{k}": 2e3, f"damping.c{k}": 5.0,
                      f"stop.lower{k}": -0.01, f"stop.upper{k}": 0.01})
    start.update({"friction.muStatic": 0.3, "friction.muKinetic": 0.2, "friction.Fint": 20.0})
    return {k: v for k, v in start.items() if k in names}


@pytest.mark.parametrize("variant", VARIANTS)
def test_simulate_fmu_equals_the_fmi2_twin(variant):
    kw = dict(stop_time=0.3, output_interval=1e-3, start_values=_start_values(variant),
              input=_driven_inputs(variant))
    r3 = simulate_fmu(str(fmu3_path(variant)), fmi_type="CoSimulation", **kw)
    r2 = simulate_fmu(str(REPO / "dist" / f"{variant}.fmu"), fmi_type="CoSimulation", **kw)
    assert len(r3) == len(r2) == 301
    assert set(r3.dtype.names) == set(r2.dtype.names)
    moving = 0
    for name in r2.dtype.names:
        assert np.array_equal(bits(r3[name]), bits(r2[name])), name
        assert np.all(np.isfinite(r3[name])), name
        moving += name != "time" and np.ptp(r3[name]) > 0
    assert moving > 0, "the drive moves the outputs"


# ------------------------------------------------------------------ the master's scenes

class Connector3(master.Connector3):
    """The master's FMI 3.0 connector (scripts/cosim/master.py) without early return: every step
    runs to its end, as through FMI 2.0."""

    def __init__(self, *args, **kw):
        super().__init__(*args, early_return=False, **kw)


class Connector2(master.Connector):
    """The FMI 2.0 connector without input derivatives (as the FMI 3.0 one)."""

    def set_rates(self):
        pass


SCENE_RUNS = [(Belt(t_end=1.5), "zoh", 1e-3), (Puck(coupling=0), "zoh", 1e-3),
              (Puck(coupling=1), "rollback", 1e-3), (Bounce(), "zoh", 1e-4),
              (Bounce(), "rollback", 2e-4), (Bounce(), "linear_implicit", 2e-4),
              (BushingFreq(t_end=0.5), "linear_implicit", 1e-3)]


@pytest.mark.parametrize("scene,method,H", SCENE_RUNS,
                         ids=[f"{s.name}-{m}-{h:g}" for s, m, h in SCENE_RUNS])
def test_scene_trajectories_equal_the_fmi2_twin(monkeypatch, scene, method, H):
    runs = {}
    for version, cls in (("2", Connector2), ("3", Connector3)):
        monkeypatch.setattr(master, "Connector", cls)
        runs[version] = master.simulate(scene, method, H, fail_ok=False)
    r2, r3 = runs["2"], runs["3"]
    assert r2.failed is None and r3.failed is None
    assert r3.steps == r2.steps == int(round(scene.t_end / H))
    assert np.array_equal(bits(r3.p), bits(r2.p)), "positions"
    assert np.array_equal(bits(r3.u), bits(r2.u)), "velocities"
    assert r3.calls == r2.calls and r3.iterations == r2.iterations
    assert np.ptp(r3.u) > 0, "the body moved"


# ------------------------------------------------------------------ derivatives, state

def _pair(variant, extrapolation=1):
    """FMU2Slave and FMU3Slave of one variant, initialised with the same friction and stops."""
    md2 = read_model_description(str(REPO / "dist" / f"{variant}.fmu"))
    s2 = FMU2Slave(guid=md2.guid, unzipDirectory=extract(str(REPO / "dist" / f"{variant}.fmu")),
                   modelIdentifier=variant, instanceName="twin2")
    s3 = FMU3Slave(guid=md3(variant).guid, unzipDirectory=unzipped3(variant),
                   modelIdentifier=variant, instanceName="twin3")
    s2.instantiate()
    s3.instantiate()
    s2.setupExperiment(startTime=0.0)
    s2.enterInitializationMode()
    s3.enterInitializationMode(startTime=0.0)
    vr = {v.name: v for v in md3(variant).modelVariables}
    for name, x in _start_values(variant).items():
        s2.setReal([vr[name].valueReference], [x])
        s3.setFloat64([vr[name].valueReference], [x])
    s2.setInteger([vr["cosim.extrapolation"].valueReference], [extrapolation])
    s3.setInt32([vr["cosim.extrapolation"].valueReference], [extrapolation])
    s2.exitInitializationMode()
    s3.exitInitializationMode()
    return s2, s3, vr


def _drive(s2, s3, vr, steps=120, h=1e-3, k0=0):
    """Steps both twins through steps k0 .. k0 + steps - 1 of the drive."""
    sig = _driven_inputs(s3.modelIdentifier, t_end=(k0 + steps) * h, dt=h)
    names = [n for n in sig.dtype.names if n != "time"]
    refs = [vr[n].valueReference for n in names]
    for k in range(k0, k0 + steps):
        u = [float(sig[n][k]) for n in names]
        s2.setReal(refs, u)
        s3.setFloat64(refs, u)
        s2.doStep(k * h, h)
        assert s3.doStep(k * h, h) == (False, False, False, k * h + h)


@pytest.mark.parametrize("variant", VARIANTS)
def test_directional_and_adjoint_derivatives(variant):
    s2, s3, vr = _pair(variant)
    try:
        _drive(s2, s3, vr)
        unknowns = [v.valueReference for v in vr.values()
                    if v.causality == "output" and v.variability == "continuous" and v.type == "Float64"]
        knowns = [v.valueReference for v in vr.values() if v.causality == "input"]
        J = np.empty((len(unknowns), len(knowns)))
        for j, k in enumerate(knowns):
            d2 = s2.getDirectionalDerivative(unknowns, [k], [1.0])
            d3 = s3.getDirectionalDerivative(unknowns, [k], [1.0])
            assert np.array_equal(bits(d3), bits(d2)), f"column {k}"
            J[:, j] = d3
        assert np.any(J != 0)
        rng = np.random.default_rng(11)
        for _ in range(3):
            v = rng.standard_normal(len(unknowns))
            adj = np.array(s3.getAdjointDerivative(unknowns, knowns, list(v), nSensitivity=len(knowns)))
            want = J.T @ v
            scale = np.abs(J.T) @ np.abs(v)
            assert np.all(np.abs(adj - want) <= 1e-12 * scale), (adj, want)
    finally:
        for s in (s2, s3):
            s.terminate()
            s.freeInstance()


@pytest.mark.parametrize("variant", VARIANTS)
def test_acceleration_inputs_equal_the_fmi2_twin(variant):
    """cosim.extrapolation = 3 (the nodes move along the acceleration inputs, FMI 3.0's way to
    give the path FMI 2.0 gives through input derivatives): every output of the twins is the
    same double after every step of the drive, and the drive's accelerations did move the
    nodes (the poses read back differ from a run with extrapolation 1)."""
    s2, s3, vr = _pair(variant, extrapolation=3)
    l2, l3, vr1 = _pair(variant, extrapolation=1)
    outs = [v.valueReference for v in vr.values() if v.causality == "output" and v.type == "Float64"]
    pose = [v.valueReference for v in vr.values() if v.causality == "input"
            and v.name[1:4] not in (".dv", ".dw")]
    try:
        for k in range(0, 120, 10):
            _drive(s2, s3, vr, steps=10, k0=k)
            _drive(l2, l3, vr1, steps=10, k0=k)
            assert np.array_equal(bits(s3.getFloat64(outs)), bits(s2.getReal(outs))), k
            assert np.array_equal(bits(s3.getFloat64(pose)), bits(s2.getReal(pose))), k
        assert not np.array_equal(bits(s3.getFloat64(pose)), bits(l3.getFloat64(pose)))
    finally:
        for s in (s2, s3, l2, l3):
            s.freeInstance()


@pytest.mark.parametrize("variant", VARIANTS)
def test_fmu_state_round_trips(variant):
    s2, s3, vr = _pair(variant)
    outs = [v.valueReference for v in vr.values() if v.causality == "output" and v.type == "Float64"]
    ints = [v.valueReference for v in vr.values() if v.causality == "output" and v.type == "Int32"]
    try:
        _drive(s2, s3, vr, steps=60)
        state = s3.getFMUState()
        y0, i0 = s3.getFloat64(outs), s3.getInt32(ints)
        blob = s3.serializeFMUState(state)
        _drive(s2, s3, vr, steps=40, k0=60)
        assert s3.getFloat64([0]) == [99 * 1e-3 + 1e-3]   # time = the last t + h
        assert not np.array_equal(bits(s3.getFloat64(outs)), bits(y0)), "moved on"
        s3.setFMUState(state)
        assert s3.getFloat64([0]) == [59 * 1e-3 + 1e-3]
        assert np.array_equal(bits(s3.getFloat64(outs)), bits(y0))
        assert s3.getInt32(ints) == i0
        restored = s3.deserializeFMUState(blob)
        s3.setFMUState(restored)
        assert np.array_equal(bits(s3.getFloat64(outs)), bits(y0))
        assert s3.serializeFMUState(restored) == blob
        # the same state format as FMI 2.0: the twin takes the bytes
        s2.setFMUstate(s2.deSerializeFMUstate(blob))
        assert np.array_equal(bits(s2.getReal(outs)), bits(y0))
        s3.freeFMUState(restored)
        s3.freeFMUState(state)
    finally:
        for s in (s2, s3):
            s.freeInstance()


# ------------------------------------------------------------------ refusals

def test_unsupported_calls_are_errors_with_a_log_line():
    log = []

    def on_message(env, status, category, message):
        log.append((status, category.decode(), message.decode()))

    s3 = FMU3Slave(guid=md3("Bushing").guid, unzipDirectory=unzipped3("Bushing"),
                   modelIdentifier="Bushing", instanceName="refusals")
    s3.instantiate(logMessage=on_message)
    try:
        s3.enterInitializationMode(startTime=0.0)
        s3.exitInitializationMode()
        for name, call in [("fmi3EnterEventMode", s3.enterEventMode),
                           ("fmi3EnterStepMode", s3.enterStepMode),
                           ("fmi3EnterConfigurationMode", s3.enterConfigurationMode)]:
            n = len(log)
            with pytest.raises(FMICallException):
                call()
            assert len(log) == n + 1 and log[-1][0] == 3 and log[-1][2].startswith(f"{name}: "), log[n:]
        # still in Step Mode
        assert s3.doStep(0.0, 1e-3)[3] == 1e-3
    finally:
        s3.freeInstance()
    with pytest.raises(Exception, match="Failed to instantiate"):
        bad = FMU3Slave(guid="{wrong}", unzipDirectory=unzipped3("Bushing"),
                        modelIdentifier="Bushing", instanceName="bad")
        bad.instantiate(logMessage=on_message)
    assert "instantiationToken" in log[-1][2]
    with pytest.raises(Exception, match="Failed to instantiate"):
        ev = FMU3Slave(guid=md3("Bushing").guid, unzipDirectory=unzipped3("Bushing"),
                       modelIdentifier="Bushing", instanceName="ev")
        ev.instantiate(eventModeUsed=True, logMessage=on_message)
    assert "eventModeUsed" in log[-1][2]
