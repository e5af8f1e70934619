"""The native master (master/, ./scripts/master) runs FMUs that others wrote: the Modelica
Reference-FMUs (FMI 2.0 and 3.0 Co-Simulation) give, column for column, what fmusim (the
Modelica Association's reference importer) gives for the same experiment: the default
experiment, a communication step equal to fmusim's output interval (the stepSize, or
(stop − start)/500 where there is none), the same start and stop, on fmusim's time grid
(`--grid diff`: t_k = t_0 + k·H as the master's default grid, but steps h_k = t_(k+1) − t_k where
the default hands h = H exactly). The grid matters for Roberts only (t_0 = 1e-5: h_k differs
from H in the last bit, and its fixed 1e-6 Euler substeps then fit one more or one less into a
step: 4e-8 apart at t = 4.1e-4 on the default grid, measured); every other model is equal on both.

Tolerance 1e-12 relative (to max(1, |fmusim|)): both importers call the same compiled model
code with the same t_k = t_0 + k·H and h = H, so the values should be bitwise equal; fmusim
writes 16 significant digits, so a value read back from its CSV can differ in the 17th.

Skipped where ../shared/tools (fmusim and the Reference-FMUs) is absent: a user's clone has it
not. Not compared: Binary outputs (this master records no Binary column), Clocks (Scheduled
Execution only) and Roberts past t = 0.1 (its default experiment runs to 1e8 at an Euler step
of 1e-6; both run it to 0.1 here).
"""
from __future__ import annotations

import csv
import subprocess
from pathlib import Path

import pytest

from conftest import REPO

TOOLS = REPO.parent / "shared" / "tools"
FMUSIM = TOOLS / "fmusim"
REF = TOOLS / "reference-fmus"
MASTER = REPO / "target" / "release" / "master"

MODELS = [(v, m) for v in (2, 3) for m in ("BouncingBall", "Dahlquist", "Feedthrough", "Resource", "Stair", "VanDerPol")]
MODELS += [(3, "StateSpace"), (3, "Roberts")]
STOP = {"Roberts": 0.10001}   # from its start 1e-5: 0.1 s in 500 steps of 2e-4
STEP = {"Roberts": 2e-4}
# an input file both versions' Feedthrough read: a ramp, a jump (a repeated time), held values
INPUT = """time,Float64_continuous_input,Float64_discrete_input,Int32_input,Boolean_input
0,0,0,0,0
0.5,1.5,2.5,3,1
0.5,-1,-2,-3,0
1.3,4,5,6,1
2,0.25,0.5,7,0
"""


def needs_tools():
    if not FMUSIM.exists() or not REF.exists():
        pytest.skip(f"{TOOLS} (fmusim, Reference-FMUs) is absent: a user's clone has none")
    probe = subprocess.run([str(FMUSIM), "--version"], capture_output=True, text=True)
    if probe.returncode != 0:
        pytest.skip(f"fmusim does not start here ({probe.stderr.strip()}); see {TOOLS}/README.md for its set-up")
    if not MASTER.exists():
        pytest.fail("target/release/master is missing: run ./scripts/run first", pytrace=False)


def experiment(fmu: Path):
    import zipfile
    import xml.etree.ElementTree as ET
    with zipfile.ZipFile(fmu) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    d = root.find("DefaultExperiment")
    start = float(d.get("startTime", "0"))
    stop = float(d.get("stopTime", "1"))
    step = d.get("stepSize")
    return start, stop, float(step) if step else (stop - start) / 500


def read(path: Path) -> dict[str, list[str]]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    cols: dict[str, list[str]] = {}
    for j, name in enumerate(rows[0]):
        values = [r[j] for r in rows[1:]]
        if any(" " in v for v in values) and name != "String_output":   # fmusim writes an array as "a b c"
            parts = [v.split() for v in values]
            for i in range(len(parts[0])):
                cols[f"{name}[{i + 1}]"] = [p[i] for p in parts]
        else:
            cols[name] = values
    return cols


def same(a: str, b: str) -> bool:
    try:
        x, y = float(a), float(b)
    except ValueError:
        return a == b
    return abs(x - y) <= 1e-12 * max(1.0, abs(y))


def run_both(tmp_path, version, model, extra_fmusim=(), extra_master=()):
    fmu = REF / f"fmi{version}" / f"{model}.fmu"
    start, stop, step = experiment(fmu)
    stop = STOP.get(model, stop)
    step = STEP.get(model, step)
    theirs, ours = tmp_path / "fmusim.csv", tmp_path / "master.csv"
    subprocess.run([str(FMUSIM), "--interface-type", "cs", "--stop-time", repr(stop), "--output-interval", repr(step),
                    *extra_fmusim, "--output-file", str(theirs), str(fmu)], check=True, capture_output=True)
    p = subprocess.run([str(MASTER), "run", str(fmu), "--step", repr(step), "--stop", repr(stop), "--grid", "diff", *extra_master,
                        "--out", str(ours)], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    return read(theirs), read(ours), p.stdout


def compare(theirs, ours):
    common = [c for c in theirs if c in ours]
    missing = [c for c in theirs if c not in ours and c != "Binary_output"]
    assert not missing, f"columns fmusim has and the master has not: {missing}"
    assert len(theirs["time"]) == len(ours["time"]), (len(theirs["time"]), len(ours["time"]))
    for c in common:
        bad = [(k, a, b) for k, (a, b) in enumerate(zip(ours[c], theirs[c])) if not same(a, b)]
        assert not bad, f"{c}: first differences (row, master, fmusim): {bad[:3]}"


@pytest.mark.parametrize("version,model", MODELS, ids=[f"fmi{v}-{m}" for v, m in MODELS])
def test_reference_fmu_matches_fmusim(tmp_path, version, model):
    needs_tools()
    theirs, ours, out = run_both(tmp_path, version, model)
    compare(theirs, ours)
    if model == "Stair":
        # terminate requested at counter 10 (t = 9): a normal end, the rows kept
        assert "component 'Stair' asked to terminate at t = 9: a normal end" in out
        assert float(ours["time"][-1]) == 9.0


@pytest.mark.parametrize("version", (2, 3))
def test_feedthrough_with_an_input_file_matches_fmusim(tmp_path, version):
    needs_tools()
    inp = tmp_path / "input.csv"
    inp.write_text(INPUT)
    theirs, ours, _ = run_both(tmp_path, version, "Feedthrough", ("--input-file", str(inp)), ("--input", str(inp)))
    compare(theirs, ours)
    # the ramp is interpolated (continuous), the discrete values held: not start values
    # (row k + 1 holds what was set at t_k: 0.196 at row 50)
    assert float(ours["Float64_continuous_output"][50]) == pytest.approx(0.196 * 1.5 / 0.5, rel=1e-12)
    assert set(ours["Int32_output"]) == {"0", "-3", "6"}     # 3 only at t = 0.5, where the later row holds


def test_feedthrough_reads_fmi3_integer_types_to_their_limits(tmp_path):
    """Reference-FMUs' own input file: Int8 … UInt64 from their minimum to their maximum."""
    needs_tools()
    inp = str(REF / "ref" / "Feedthrough_in.csv")
    theirs, ours, _ = run_both(tmp_path, 3, "Feedthrough", ("--input-file", inp), ("--input", inp))
    compare(theirs, ours)
    assert {"-9223372036854775808", "9223372036854775807"} <= set(ours["Int64_output"])
    assert "18446744073709551615" in ours["UInt64_output"]


@pytest.mark.parametrize("version", (2, 3))
def test_a_nan_output_ends_the_run_with_its_message_and_the_rows_before(tmp_path, version):
    """Dahlquist with k = NaN: its state, and so its output x, is NaN after the first step. The
    master stops there with one message naming the component, the variable, the FMI function and
    the time, keeps the row before it (t = 0, x = 1) and exits non-zero."""
    needs_tools()
    fmu = REF / f"fmi{version}" / "Dahlquist.fmu"
    out = tmp_path / "nan.csv"
    p = subprocess.run([str(MASTER), "run", str(fmu), "--step", "0.1", "--start", "k=nan", "--out", str(out)],
                       capture_output=True, text=True)
    assert p.returncode != 0
    get = "fmi2GetReal" if version == 2 else "fmi3GetFloat64"
    want = f"component 'Dahlquist': variable 'x': {get} at t = 0.1: the output is NaN"
    assert want in p.stderr, p.stderr
    assert p.stderr.count("\n") == 1, p.stderr          # one message
    rows = read(out)
    assert rows["time"] == ["0.0"] and rows["x"] == ["1.0"], rows
