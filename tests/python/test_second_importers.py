"""Second importers, besides fmpy, installed from PyPI through requirements.txt:

1. ``fmutool -check`` (fmu-manipulation-toolbox): the modelDescription.xml of every packaged FMU
   validates against the FMI 2.0 XSD and passes the toolbox's semantic checks (unique names,
   causality/variability/initial combinations, start values, ModelStructure). A deliberately
   broken copy must fail the same check, so a passing check is not vacuous.

2. libcosimpy (the Open Simulation Platform's co-simulation engine libcosim, which loads FMUs
   through the FMI Library): scenes run by libcosim give the same results as the same scenes
   run through fmpy's FMU2Slave.

   * "extrapolated" (every variant): springs and dampers set as parameters, the node inputs
     (positions, orientations, velocities, angular velocities) set once as initial values.
     With ``cosim.extrapolation = 1`` (default) the FMU moves the nodes along the velocities
     over each step and reads the inputs back at t + h, so the outputs evolve over the run.
   * "prescribed" (RadialThrust with a stop and a given reference; Planar with stick/slip
     friction and ``friction.coupling = 1``): node b follows a closed-form path, set before
     every step through libcosim's override manipulator (fmpy: fmi2SetReal before fmi2DoStep).

   libcosim counts time in integer nanoseconds and hands the FMU
   ``t_k = double(k * h_ns) / 1e9`` and the step ``t_{k+1} - t_k`` (cosim::to_double_duration),
   not a constant 1e-3. The fmpy run uses the same time grid, so both importers call the same
   binary with the same arguments: every Real output and input read back must agree to
   TOL_SAME_GRID = 1e-12 of the channel's largest magnitude (observed: bit for bit), every
   Integer output exactly. In the extrapolated scenes a second fmpy run with the nominal
   h = 1e-3 must agree to the same relative tolerance (observed <= 1.5e-14): the time grid is
   the only difference between the importers, and it is at round-off level. (Not asserted for
   the prescribed scenes: there a round-off difference could move a stick/slip or stop
   transition by one step.) libcosim sets the initial values after fmi2Instantiate and again
   in Initialization Mode; fmpy sets them once before fmi2SetupExperiment: the same state.

   libcosim runs in a child process (this file run as a script): an error it meets during
   initialization ends its process with std::terminate, which must fail one test, not kill
   pytest. The child writes the samples and libcosim's own view of the variable table to an
   .npz file.

libcosim reads the values through its last-value observer after every step; it reports the
step's outcome through ``step()`` and the execution status, both checked.
"""

from __future__ import annotations

import importlib.util
import math
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

import _ref
from conftest import VARIANTS, fmu_path, model_description, vr

H_NS = 1_000_000         # communication step: 1 ms in libcosim's nanosecond ticks
N_STEPS = 1000           # 1 s
TOL_SAME_GRID = 1e-12    # relative to the channel's largest magnitude over the run
TOL_NOMINAL_GRID = 1e-12


def t_grid(k: int) -> float:
    """libcosim's communication point k as a double: duration_cast<duration<double>>(k h ns)."""
    return (k * H_NS) / 1e9


# ==========================================================================
# scenes (shared by the fmpy run here and the libcosim run in the child)
# ==========================================================================


def _quat(rotvec):
    return [float(x) for x in _ref.quat_exp(np.asarray(rotvec, dtype=float))]


def _node(prefix, r=None, q=None, v=None, w=None):
    out = {}
    for key, vec in (("r", r), ("v", v), ("w", w)):
        if vec is not None:
            out.update({f"{prefix}.{key}[{j + 1}]": float(vec[j]) for j in range(3)})
    if q is not None:
        out.update(dict(zip((f"{prefix}.q.w", f"{prefix}.q.x", f"{prefix}.q.y", f"{prefix}.q.z"), q)))
    return out


class Scene:
    """Initial values (Real, Integer, Boolean) and, optionally, b's path set before every step."""

    def __init__(self, variant, real, integer=None, boolean=None, path=None, keep_present=False):
        names = set(vr(variant))
        self.variant = variant
        # keep_present: a scene written once for all variants keeps the variables this one has
        self.real = {n: x for n, x in real.items() if n in names or not keep_present}
        self.integer = dict(integer or {})
        self.boolean = dict(boolean or {})
        self.path = path
        for n in [*self.real, *self.integer, *self.boolean, *(path(0.0) if path else {})]:
            assert n in names, f"{variant} has no variable {n}"
        if path:
            self.real.update(path(0.0))  # the initial state is the path at t = 0

    def prescribed(self, k):
        return self.path(t_grid(k)) if self.path else {}


def extrapolated(variant):
    ra = np.array([0.01, -0.02, 0.03])
    real = {
        **{f"elasticity.k{k}": x for k, x in zip(range(1, 7), [1e3, 2e3, 3e3, 10.0, 20.0, 30.0])},
        **{f"damping.c{k}": x for k, x in zip(range(1, 7), [5.0, 6.0, 7.0, 0.1, 0.2, 0.3])},
        **_node("a", r=ra, q=_quat([0.0, 0.0, 0.3]), v=[0.05, 0.0, -0.02], w=[0.0, 0.0, 0.2]),
        **_node("b", r=ra + [0.1, 0.02, -0.03], q=_quat(0.4 * np.array([1.0, 2.0, 3.0]) / math.sqrt(14.0)),
                v=[0.2, -0.1, 0.05], w=[0.3, -0.4, 0.5]),
    }
    return Scene(variant, real, keep_present=True)


def prescribed_radial_thrust():
    """b spirals outwards about a's (tilted, spinning) axis and bobs along it; the radial
    component meets its upper stop at t ~ 0.69 s; the radial reference is given."""

    def path(t):
        rho, th, z = 0.05 + 0.1 * t, 2.0 * t, 0.02 * math.sin(3.0 * t)
        c, s = math.cos(th), math.sin(th)
        return _node("b", r=[rho * c, rho * s, z],
                     v=[0.1 * c - 2.0 * rho * s, 0.1 * s + 2.0 * rho * c, 0.06 * math.cos(3.0 * t)])

    real = {"elasticity.k1": 500.0, "elasticity.k3": 800.0, "damping.c1": 2.0, "damping.c3": 3.0,
            "reference.value1": 0.06, "stop.upper1": 0.12, "stop.stiffness": 1e5, "stop.damping": 10.0,
            **_node("a", q=_quat([0.2, 0.0, 0.0]), w=[0.0, 0.0, 0.3])}
    return Scene("RadialThrust", real, boolean={"reference.given1": True}, path=path)


def prescribed_planar():
    """b slides to and fro in the plane and spins to and fro about e1 under a constant internal
    normal force: friction slips, and sticks around the reversals (t = pi/12, pi/4), in both
    effects (coupled limit surface)."""

    def path(t):
        s, ds = math.sin(6.0 * t), 6.0 * math.cos(6.0 * t)  # both effects reverse together
        return _node("b", r=[0.0, 0.01 * s, 0.005 * s], v=[0.0, 0.01 * ds, 0.005 * ds],
                     q=_quat([0.3 * s, 0.0, 0.0]), w=[0.3 * ds, 0.0, 0.0])

    real = {"elasticity.k2": 200.0, "elasticity.k3": 300.0, "elasticity.k4": 5.0, "damping.c2": 1.0,
            "friction.muStatic": 0.5, "friction.muKinetic": 0.3, "friction.decay": 2.0,
            "friction.R": 0.05, "friction.Fint": 100.0, "friction.Mint": 2.0}
    return Scene("Planar", real, integer={"friction.coupling": 1}, path=path)


SCENES = {
    **{("extrapolated", v): (lambda v=v: extrapolated(v)) for v in VARIANTS},
    ("prescribed", "RadialThrust"): prescribed_radial_thrust,
    ("prescribed", "Planar"): prescribed_planar,
}


# ==========================================================================
# libcosim side (runs in the child process)
# ==========================================================================

# libcosimpy's CosimVariableType / CosimVariableCausality / CosimVariableVariability values
LC_TYPE = {0: "Real", 1: "Integer", 2: "String", 3: "Boolean"}
LC_CAUSALITY = {0: "input", 1: "parameter", 2: "output", 3: "calculatedParameter", 4: "local", 5: "independent"}
LC_VARIABILITY = {0: "constant", 1: "fixed", 2: "tunable", 3: "discrete", 4: "continuous"}


def run_libcosim(scene_key, out_path):
    from libcosimpy.CosimEnums import CosimErrorCode
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.WARNING)  # the parent fails on any warning or error line
    scene = SCENES[scene_key]()
    execution = CosimExecution.from_step_size(H_NS)
    slave = CosimLocalSlave(fmu_path=str(fmu_path(scene.variant)), instance_name=scene.variant)
    index = execution.add_local_slave(slave)
    assert index >= 0, f"libcosim could not add {scene.variant}"
    table = list(execution.slave_variables(index))
    ref = {v.name.decode(): v.reference for v in table}
    for name, value in scene.real.items():
        assert execution.real_initial_value(index, ref[name], value), name
    for name, value in scene.integer.items():
        assert execution.integer_initial_value(index, ref[name], value), name
    for name, value in scene.boolean.items():
        assert execution.boolean_initial_value(index, ref[name], value), name
    observer = CosimObserver.create_last_value()
    assert execution.add_observer(observer)
    override = CosimManipulator.create_override()
    assert execution.add_manipulator(override)

    real_names = [v.name.decode() for v in table if LC_TYPE[v.type] == "Real" and LC_CAUSALITY[v.causality] in ("input", "output")]
    int_names = [v.name.decode() for v in table if LC_TYPE[v.type] == "Integer" and LC_CAUSALITY[v.causality] == "output"]
    real_refs, int_refs = [ref[n] for n in real_names], [ref[n] for n in int_names]
    times, reals, ints = [], [], []
    for k in range(N_STEPS):
        values = scene.prescribed(k)
        if values:
            assert override.slave_real_values(index, [ref[n] for n in values], list(values.values()))
        assert execution.step(1), f"libcosim step {k} failed"
        status = execution.status()
        assert CosimErrorCode(status.error_code) == CosimErrorCode.SUCCESS, status
        times.append(status.current_time)
        reals.append(observer.last_real_values(index, real_refs))
        ints.append(observer.last_integer_values(index, int_refs) if int_refs else [])
    np.savez(
        out_path,
        names=np.array([v.name.decode() for v in table]),
        refs=np.array([v.reference for v in table], dtype=np.int64),
        types=np.array([LC_TYPE[v.type] for v in table]),
        causalities=np.array([LC_CAUSALITY[v.causality] for v in table]),
        variabilities=np.array([LC_VARIABILITY[v.variability] for v in table]),
        times=np.array(times, dtype=np.int64),
        real_names=np.array(real_names), reals=np.array(reals, dtype=float).reshape(N_STEPS, len(real_names)),
        int_names=np.array(int_names), ints=np.array(ints, dtype=np.int64).reshape(N_STEPS, len(int_names)),
    )


# ==========================================================================
# fmpy side
# ==========================================================================


def run_fmpy(make_slave, scene, real_names, int_names, grid=True):
    """The libcosim call sequence through fmpy: set the initial values, setup/enter/exit
    initialization, then per step: set b's path (prescribed scenes), fmi2DoStep, read."""
    v = vr(scene.variant)
    log = []
    s = make_slave(scene.variant, instance_name=scene.variant, log=log)
    s.setReal([v[n] for n in scene.real], list(scene.real.values()))
    if scene.integer:
        s.setInteger([v[n] for n in scene.integer], list(scene.integer.values()))
    if scene.boolean:
        s.setBoolean([v[n] for n in scene.boolean], list(scene.boolean.values()))
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    real_refs, int_refs = [v[n] for n in real_names], [v[n] for n in int_names]
    reals, ints = [], []
    for k in range(N_STEPS):
        values = scene.prescribed(k)
        if values:
            s.setReal([v[n] for n in values], list(values.values()))
        if grid:
            s.doStep(currentCommunicationPoint=t_grid(k), communicationStepSize=t_grid(k + 1) - t_grid(k))
        else:
            s.doStep(currentCommunicationPoint=k * 1e-3, communicationStepSize=1e-3)
        reals.append(s.getReal(real_refs))
        ints.append(s.getInteger(int_refs) if int_refs else [])
    s.terminate()
    problems = [m for m in log if m[0] != 0]  # fmi2OK only
    assert not problems, problems
    return np.array(reals, dtype=float), np.array(ints, dtype=np.int64).reshape(N_STEPS, len(int_names))


def worst_relative(a, b, names):
    """max over channels of max_t |a - b| / max_t |b| (0/0 = 0), and the channel."""
    diff = np.abs(a - b).max(axis=0)
    scale = np.abs(b).max(axis=0)
    rel = np.where(diff == 0.0, 0.0, diff / np.where(scale > 0.0, scale, np.inf))
    rel = np.where((diff > 0.0) & (scale == 0.0), np.inf, rel)
    j = int(np.argmax(rel))
    return float(rel[j]), names[j], float(diff[j]), float(scale[j])


def _require(module, what):
    if importlib.util.find_spec(module) is None:
        pytest.fail(f"{what} is not installed in {sys.prefix}: install requirements.txt "
                    "(./scripts/run or ./scripts/test do)", pytrace=False)


# ==========================================================================
# 1. fmutool -check
# ==========================================================================


def fmutool_exe():
    _require("fmu_manipulation_toolbox", "fmu-manipulation-toolbox (fmutool)")
    beside = Path(sys.executable).with_name("fmutool")
    exe = str(beside) if beside.is_file() else shutil.which("fmutool")
    if exe is None:
        pytest.fail("the fmutool console script of fmu-manipulation-toolbox was not found", pytrace=False)
    return exe


def fmutool_check(fmu, cwd):
    proc = subprocess.run([fmutool_exe(), "-input", str(fmu), "-check"], cwd=cwd,
                          capture_output=True, text=True, timeout=300)
    lines = (proc.stdout + proc.stderr).splitlines()
    # fmutool logs "LEVEL    | message"
    complaints = [ln for ln in lines if re.match(r"\s*(WARNING|ERROR|CRITICAL|FATAL)\b", ln)]
    return proc, lines, complaints


def test_fmutool_check_passes(variant, tmp_path):
    proc, lines, complaints = fmutool_check(fmu_path(variant), tmp_path)
    report = "\n".join(lines)
    assert proc.returncode == 0, report
    assert not complaints, report
    assert "This FMU seems to be compliant with FMI-2.0." in report, report
    assert "No semantic error against the FMI-2 standard." in report, report


@pytest.mark.parametrize("breakage", ["duplicate name", "schema"])
def test_fmutool_check_fails_on_a_broken_copy(breakage, tmp_path):
    """Control: the same check rejects a copy of Bushing.fmu with one defect."""
    broken = tmp_path / "Bushing.fmu"
    with zipfile.ZipFile(fmu_path("Bushing")) as src, zipfile.ZipFile(broken, "w", zipfile.ZIP_DEFLATED) as dst:
        for item in src.infolist():
            data = src.read(item.filename)
            if item.filename == "modelDescription.xml":
                xml = data.decode("utf-8")
                if breakage == "duplicate name":
                    fixed = xml.replace('name="CP2"', 'name="CP1"', 1)
                else:
                    fixed = xml.replace('causality="output"', 'causality="result"', 1)
                assert fixed != xml
                data = fixed.encode("utf-8")
            dst.writestr(item, data)
    proc, lines, complaints = fmutool_check(broken, tmp_path)
    report = "\n".join(lines)
    assert proc.returncode != 0, report
    assert any(ln.lstrip().startswith("ERROR") for ln in complaints), report
    if breakage == "duplicate name":
        assert "'CP1'" in report, report
    else:
        assert "result" in report, report


# ==========================================================================
# 2. libcosimpy scenes against fmpy
# ==========================================================================


@pytest.mark.parametrize("scene_key", list(SCENES), ids=[f"{s}-{v}" for s, v in SCENES])
def test_libcosim_matches_fmpy(scene_key, make_slave, tmp_path):
    _require("libcosimpy", "libcosimpy")
    scene = SCENES[scene_key]()
    out = tmp_path / "libcosim.npz"
    env = dict(os.environ, TMPDIR=str(tmp_path))  # libcosim unpacks the FMU under TMPDIR
    proc = subprocess.run([sys.executable, __file__, "libcosim", *scene_key, str(out)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=600)
    log = proc.stdout + proc.stderr
    assert proc.returncode == 0 and out.is_file(), f"libcosim child exited with {proc.returncode}:\n{log[-4000:]}"
    assert not re.search(r"\[(warning|error|fatal)\]", log), log[-4000:]
    lc = np.load(out)

    # libcosim's view of the variable table (FMI Library) is fmpy's
    md = model_description(scene.variant)
    theirs = sorted(zip(lc["names"], lc["refs"].tolist(), lc["types"], lc["causalities"], lc["variabilities"]))
    ours = sorted((x.name, x.valueReference, x.type, x.causality, x.variability) for x in md.modelVariables)
    assert theirs == ours

    assert lc["times"].tolist() == [(k + 1) * H_NS for k in range(N_STEPS)]
    real_names, int_names = [str(n) for n in lc["real_names"]], [str(n) for n in lc["int_names"]]
    reals, ints = run_fmpy(make_slave, scene, real_names, int_names, grid=True)

    # the scene is not static: outputs move by more than round-off
    moving = [n for j, n in enumerate(real_names)
              if np.ptp(reals[:, j]) > 1e-3 * max(np.abs(reals[:, j]).max(), 1e-300)]
    assert {"energy.stored", "energy.damping"} <= set(moving), moving

    rel, name, diff, scale = worst_relative(lc["reals"], reals, real_names)
    assert rel <= TOL_SAME_GRID, f"{name}: |libcosim - fmpy| = {diff:.3e}, channel scale {scale:.3e}"
    assert np.array_equal(lc["ints"], ints), [n for j, n in enumerate(int_names)
                                              if not np.array_equal(lc["ints"][:, j], ints[:, j])]

    if scene.path is None:
        # the time grid is the only difference: fmpy with the nominal h = 1e-3 agrees to round-off
        nominal, nominal_ints = run_fmpy(make_slave, scene, real_names, int_names, grid=False)
        rel, name, diff, scale = worst_relative(lc["reals"], nominal, real_names)
        assert rel <= TOL_NOMINAL_GRID, f"{name}: |libcosim - fmpy(h=1e-3)| = {diff:.3e}, channel scale {scale:.3e}"
        assert np.array_equal(lc["ints"], nominal_ints)
    elif scene.variant == "RadialThrust":
        status = ints[:, int_names.index("CSLST1")]
        assert set(status.tolist()) == {0, 1}, "the radial stop must engage during the run"
    elif scene.variant == "Planar":
        for n in ("friction.status", "friction.statusR1"):
            seen = set(ints[:, int_names.index(n)].tolist())
            assert {1, 2} <= seen, f"{n} must both stick (1) and slip (2): {seen}"


if __name__ == "__main__":
    # child process of test_libcosim_matches_fmpy: libcosim <scene> <variant> <out.npz>
    if len(sys.argv) != 5 or sys.argv[1] != "libcosim":
        sys.exit(f"usage: {sys.argv[0]} libcosim SCENE VARIANT OUT.npz")
    run_libcosim((sys.argv[2], sys.argv[3]), sys.argv[4])
