"""The README's quick start, run as written, so that it cannot rot.

The fenced ```python blocks between ``<!-- quickstart:begin -->`` and ``<!-- quickstart:end -->``
in README.md are joined, in order, into one script (a user pasting them into one session) and run
by this venv's Python in a fresh directory that holds ``dist`` as a link to the repository's
``dist/`` (the README's paths are relative to the repository root; the scripts write their CSV
files into the current directory, which must not be the checkout). It runs in a child process:
libcosim ends its process on some errors, which must fail a test, not pytest.

What the blocks compute is then checked against answers the README does not print itself:

* Bushing, spring and damper on u1 (k, c), b sliding along x with its velocity:
  CTF1 = k CU1 + c CV1 and b.f[1] = -CTF1 (equilibrium of a force pair along a fixed triad),
  to 1e-12 of max |CTF1| (a sum of two products: a few roundings);
  CU1 against the driven b.r[1](t): fmpy records at t + h what the FMU reached by moving b along
  b.v[1] from t, so |CU1 - b.r[1]| <= h^2 max|b.r[1]''|/2 (Taylor remainder of the linear
  extrapolation) plus 1e-15 m of round-off.
* libcosim runs the same binary with the same inputs on its integer-nanosecond time grid: CTF1
  equal to fmpy's to 1e-12 of max |CTF1| (the grids differ by round-off only).
* Planar, b offset along the plane normal, sliding in the plane: without preload F_NC = 0 and no
  friction at any time (the plane passes through b's initial position); with friction.Fint = F:
  F_NC = F, after the first step the contact slips with |CSF2| = mu F (relative 1e-9: the return
  map's last rounding, the elastic slip of the stick spring is already spent), b.f[1] = 0 (the
  preload loads no node) and b.f[2] = -CSF2.
* fmusim, when on the PATH (it is not in requirements.txt; the test says so and skips otherwise):
  the shell block run as written gives fmpy's CTF1 to 1e-12 of max |CTF1|.
"""

from __future__ import annotations

import os
import pickle
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
README = REPO / "README.md"
BEGIN, END = "<!-- quickstart:begin -->", "<!-- quickstart:end -->"
FENCE = re.compile(r"^```(\w+)\n(.*?)^```$", re.S | re.M)
TOL_REL = 1e-12

# the variables of the quick start this test reads (a rename in the README must fail here)
EXPORTED = ("u", "res", "k", "c", "ctf1", "runs")

DRIVER = r"""
import pickle, runpy, sys
g = runpy.run_path("quickstart.py", run_name="__main__")
missing = [n for n in NAMES if n not in g]
if missing:
    sys.exit(f"the quick start no longer defines {missing}")
with open("exported.pkl", "wb") as f:
    pickle.dump({n: g[n] for n in NAMES}, f)
"""


def quickstart_blocks():
    """(language, code) of every fenced block between the markers, in order."""
    text = README.read_text(encoding="utf-8")
    assert text.count(BEGIN) == 1 and text.count(END) == 1, "README.md needs one pair of quick-start markers"
    section = text[text.index(BEGIN) + len(BEGIN):text.index(END)]
    return [(m.group(1), m.group(2)) for m in FENCE.finditer(section)]


@pytest.fixture(scope="module")
def quickstart(tmp_path_factory):
    blocks = quickstart_blocks()
    python = [code for lang, code in blocks if lang == "python"]
    assert len(python) >= 3, blocks
    for variant in ("Bushing", "Planar"):
        if not (REPO / "dist" / f"{variant}.fmu").is_file():
            pytest.fail(f"dist/{variant}.fmu is missing: run ./scripts/run first", pytrace=False)
    work = tmp_path_factory.mktemp("quickstart")
    (work / "dist").symlink_to(REPO / "dist", target_is_directory=True)
    (work / "quickstart.py").write_text("\n\n".join(python), encoding="utf-8")
    proc = subprocess.run([sys.executable, "-c", f"NAMES = {EXPORTED!r}\n{DRIVER}"], cwd=work,
                          capture_output=True, text=True, timeout=600)
    report = f"stdout:\n{proc.stdout}\nstderr:\n{proc.stderr}"
    assert proc.returncode == 0, report
    with open(work / "exported.pkl", "rb") as f:
        exported = pickle.load(f)
    return {"dir": work, "stdout": proc.stdout, "stderr": proc.stderr, "report": report,
            "shell": [code for lang, code in blocks if lang == "sh"], **exported}


def test_quickstart_runs_quietly(quickstart):
    """No warning from fmpy (every input is in the table) or libcosim, and the lines it prints."""
    out = quickstart["stdout"] + quickstart["stderr"]
    assert not re.search(r"warning|error", out, re.I), quickstart["report"]
    for line in ("max |CTF1 - (k CU1 + c CV1)|", "max |CTF1 libcosim - CTF1 fmpy|", "friction.Fint = 20.0 N"):
        assert line in quickstart["stdout"], quickstart["report"]
    assert (quickstart["dir"] / "bushing_input.csv").is_file()


def test_bushing_spring_and_damper(quickstart):
    res, u, k, c = quickstart["res"], quickstart["u"], quickstart["k"], quickstart["c"]
    t = res["time"]
    assert len(t) == 1001 and t[-1] == pytest.approx(1.0)
    scale = np.abs(res["CTF1"]).max()
    assert scale > 50.0  # k times the 0.01 m amplitude: the scene did move
    assert np.abs(res["CTF1"] - (k * res["CU1"] + c * res["CV1"])).max() <= TOL_REL * scale
    assert np.abs(res["b.f[1]"] + res["CTF1"]).max() <= TOL_REL * scale
    # the driven slide, against the time fmpy recorded (the table rows are on the same grid)
    slide = 0.01 * np.sin(2 * np.pi * t)
    assert np.array_equal(u["time"], t)
    h = 1e-3
    bound = h * h * 0.01 * (2 * np.pi) ** 2 / 2
    err = np.abs(res["CU1"] - slide).max()
    assert err <= bound + 1e-15, (err, bound)
    assert err >= 0.5 * bound  # the extrapolation is really linear (a hold would be ~ h max|v|)


def test_libcosim_matches_fmpy(quickstart):
    res, ctf1 = quickstart["res"], np.asarray(quickstart["ctf1"])
    assert ctf1.shape == (1000,)
    scale = np.abs(res["CTF1"]).max()
    assert np.abs(ctf1 - res["CTF1"][1:]).max() <= TOL_REL * scale


def test_planar_plane_through_initial_position_and_preload(quickstart):
    runs = quickstart["runs"]
    assert sorted(runs) == [0.0, 20.0]
    free = runs[0.0]
    # b starts 0.02 m off a along the normal: that is where the plane is, nothing presses
    assert np.all(free["CNF"] == 0.0) and np.all(free["CSF2"] == 0.0)
    assert np.all(free["friction.status"] == 0)
    assert np.all(free["b.f[1]"] == 0.0) and np.all(free["b.f[2]"] == 0.0)
    pre = runs[20.0]
    mu, fint = 0.3, 20.0
    assert np.abs(pre["CNF"] - fint).max() <= 1e-12 * fint
    after = pre[1:]  # the first step spends the stick spring's elastic slip (6 N / 1e6 N/m = 6 um)
    assert np.all(after["friction.status"] == 2)
    assert np.abs(after["CSF2"] - mu * fint).max() <= 1e-9 * mu * fint  # slides along +y: resisted
    assert np.all(pre["b.f[1]"] == 0.0)  # the preload is internal
    assert np.abs(pre["b.f[2]"] + pre["CSF2"]).max() <= 1e-12 * mu * fint


def test_fmusim_block_matches_fmpy(quickstart):
    shell = quickstart["shell"]
    assert shell and all("fmusim" in code for code in shell)
    if shutil.which("fmusim") is None:
        pytest.skip("fmusim is not on the PATH (it is not installed by requirements.txt; see the "
                    "README's quick start for where to get it): its block was not run")
    for code in shell:
        proc = subprocess.run(["bash", "-euo", "pipefail", "-c", code], cwd=quickstart["dir"],
                              capture_output=True, text=True, timeout=300, env=dict(os.environ))
        assert proc.returncode == 0, proc.stdout + proc.stderr
    data = np.genfromtxt(quickstart["dir"] / "bushing_fmusim.csv", delimiter=",", names=True)
    res = quickstart["res"]
    assert len(data) == len(res)
    assert np.abs(data["time"] - res["time"]).max() <= 1e-12
    scale = np.abs(res["CTF1"]).max()
    assert np.abs(data["CTF1"] - res["CTF1"]).max() <= TOL_REL * scale
