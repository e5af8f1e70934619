"""The native master's Python bindings (fmi_master, master/python/): what the command line gives,
as numpy arrays; start values, sampling, lone FMUs with an input file; errors with the master's
message and the rows before a failure kept; and the wheel in dist/ installed with pip into a
fresh virtual environment, offline, running an archive there.

Compared with the command line's CSV exactly: both are the same Rust run, and the CSV's `{:?}`
decimals read back to the same doubles.
"""
from __future__ import annotations

import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from conftest import REPO

try:
    import fmi_master
except ImportError:                      # a failure, not a skip: ./scripts/run always builds them
    pytest.fail("fmi_master is not installed in the venv: run ./scripts/run (maturin builds it)", pytrace=False)

MASTER = REPO / "target" / "release" / "master"
BOUNCE = REPO / "dist" / "ssp" / "bounce.ssp"


def cli(tmp_path, *args):
    out = tmp_path / "cli.csv"
    p = subprocess.run([str(MASTER), "run", *map(str, args), "--out", str(out)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return np.genfromtxt(out, delimiter=",", names=True, deletechars="")


def test_simulate_gives_the_command_lines_columns_and_values(tmp_path):
    r = fmi_master.simulate(BOUNCE, step=1e-3, start_values={"mass.start.v[3]": -2.0})
    c = cli(tmp_path, BOUNCE, "--step", "1e-3", "--start", "mass.start.v[3]=-2.0")
    assert r.dtype.names == c.dtype.names
    for name in r.dtype.names:
        assert np.array_equal(r[name], c[name]), name
    assert r["mass.v[3]"][0] == -2.0        # the start value reached the Body


def test_a_system_runs_many_times_with_start_values_for_one_run_each():
    s = fmi_master.open(REPO / "dist" / "ssp" / "bushing_pendulum.ssp")
    assert s.components == ["bushing", "pendulum"]
    assert s.default_experiment == (0.0, 2.0, 0.001)
    assert any(v[:3] == ("elasticity.k1", "Float64", "parameter") for v in s.variables("bushing"))
    a = s.run(stop=0.1, start_values={"pendulum.start.w[1]": 3.0})
    b = s.run(stop=0.1)
    assert a.result["pendulum.w[1]"][0] == 3.0
    assert b.result["pendulum.w[1]"][0] == 2.0          # the archive's own start value again
    assert a.steps == 100 and a.calls > 0 and a.cpu_per_second >= 0
    g = s.simulate(stop=0.1, method="gauss_seidel", output_interval=0.01)
    assert len(g) == 11 and g["time"][10] == 100 * 1e-3


def test_a_lone_fmu_with_an_input_file(tmp_path):
    inp = tmp_path / "in.csv"
    inp.write_text("time,f[3]\n0,0\n1,2\n")
    # the Body's z under a force ramp f = 2t (held over each step): free in z, mass 1
    r = fmi_master.simulate(REPO / "dist" / "fmi3" / "Body.fmu", step=0.1, stop=1.0, input=inp,
                            start_values={"dof.r[3]": 1})
    c = cli(tmp_path, REPO / "dist" / "fmi3" / "Body.fmu", "--step", "0.1", "--stop", "1", "--input", inp,
            "--start", "dof.r[3]=1")
    assert np.array_equal(r["r[3]"], c["r[3]"])
    # zero-order hold of f_k = 2 t_k: v_n = Σ f_k h, exact sums of 0.2 k · 0.1
    v = np.cumsum([2 * (0.1 * k) * 0.1 for k in range(10)])
    assert np.allclose(r["v[3]"][1:], v, rtol=1e-12, atol=1e-15)


def test_errors_carry_the_masters_message_and_the_rows_before():
    with pytest.raises(fmi_master.MasterError, match="nothing.ssp: no such file"):
        fmi_master.open("nothing.ssp")
    with pytest.raises(fmi_master.MasterError, match="variable 'mass.gravity.4': no component has this variable"):
        fmi_master.simulate(BOUNCE, step=1e-3, start_values={"mass.gravity.4": 1})
    with pytest.raises(fmi_master.SimulationError, match="component 'mass': fmi2DoStep at t = 5: returned fmi2Error") as e:
        # the connector holding its inputs, so that its own extrapolated path does not overflow first
        fmi_master.simulate(BOUNCE, step=1, stop=20,
                            start_values={"mass.gravity[3]": 1e307, "radialthrust.cosim.extrapolation": 0})
    assert list(e.value.result["time"]) == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]


def test_the_wheel_installs_offline_into_a_fresh_venv_and_runs_an_archive(tmp_path):
    wheels = sorted((REPO / "dist").glob("fmi_master-*.whl"))
    assert wheels, "dist/fmi_master-*.whl is missing: run ./scripts/run first"
    with zipfile.ZipFile(wheels[-1]) as z:
        assert any(n.startswith("fmi_master/_native") for n in z.namelist())
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    py = venv / "bin" / "python"
    subprocess.run([str(py), "-m", "pip", "install", "--quiet", "--no-index", "--no-deps", str(wheels[-1])], check=True)
    # numpy (the wheel's one dependency) from the project's venv, and nothing else from it:
    # a folder holding only numpy (and its bundled libraries), on the fresh venv's path
    import numpy
    only = tmp_path / "numpy_only"
    only.mkdir()
    site = Path(numpy.__file__).parents[1]
    for name in ("numpy", "numpy.libs"):
        if (site / name).exists():
            (only / name).symlink_to(site / name)
    fresh_site = next((venv / "lib").glob("python3*/site-packages"))
    (fresh_site / "numpy_from_project.pth").write_text(str(only) + "\n")
    code = ("import sys, fmi_master; assert fmi_master.__file__.startswith(sys.prefix), fmi_master.__file__; "
            f"r = fmi_master.simulate({str(BOUNCE)!r}, step=1e-3); print(repr(float(r['mass.r[3]'][-1])))")
    p = subprocess.run([str(py), "-c", code], capture_output=True, text=True, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    ours = fmi_master.simulate(BOUNCE, step=1e-3)
    assert float(p.stdout) == ours["mass.r[3]"][-1]
