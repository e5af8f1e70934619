"""The SSP archives dist/ssp/<scene>.ssp (scripts/package_ssp.py, scripts/sspkit/) in real
third-party masters, libcosim (libcosimpy) and Ecos (ecospy), no mocks:

1. Every archive is valid: its SystemStructure.ssd and parameter sets validate against the SSP
   1.0 XSDs that pyssp-standard ships (and fmpy's own copy of the SSD schema reads it); the schema
   check is not vacuous (a broken SSD fails it); the archive fits its FMUs and its scene.
2. Every scene through both tools at H = 1 ms gives our master's `jacobi` (the fixed-step Jacobi
   of scripts/cosim/coupling.py) to 1e-9 relative, each run on the tool's own time grid
   (libcosim: t_k = (k·h_ns)/1e9, Ecos: the float sum t_k + H; compare.py says why the grid
   matters): the held-input archive (cosim.extrapolation = 0, packaged here) our `jacobi` as it
   is, the archive of dist/ssp our `jacobi` with the connector at the archive's setting
   (systems.EXTRAPOLATION); not our `zoh` (Gauss-Seidel, the connector first): the tools are
   Jacobi (the held-input runs). Where the motion does not hinge on the last bits of t (bounce, the pendulum), the
   held-input archive also gives master.simulate's own run (t = k H) to 1e-9.
3. A broken connection (an endpoint naming no variable) is refused by our check and by each
   tool with its own message; a parameter naming no FMU variable and a scene's parameter left
   out are refused by our check before the run (the tools only warn, or say nothing, and run on
   the FMU's default: shown here), and ./scripts/ssp's code stops with the message.
"""
from __future__ import annotations

import atexit
import functools
import re
import shutil
import subprocess
import sys
import tempfile
import zipfile

import pytest
import xmlschema

from conftest import REPO

from cosim import master  # noqa: E402  (conftest puts scripts/ on sys.path)
from sspkit import archive, cli, compare, systems, tools  # noqa: E402

H = 1e-3
TOL = 1e-9
SCENES = systems.NAMES


def ssp(name):
    path = REPO / "dist" / "ssp" / f"{name}.ssp"
    if not path.is_file():
        pytest.fail(f"{path.relative_to(REPO)} is missing: run ./scripts/run first", pytrace=False)
    return path


@functools.lru_cache(maxsize=None)
def system(name):
    return systems.system(name)


_HELD = tempfile.mkdtemp(prefix="ssp-held-")
atexit.register(shutil.rmtree, _HELD, True)


@functools.lru_cache(maxsize=None)
def held(name):
    """(path, System) of scene `name`'s held-input archive (every connector at
    cosim.extrapolation = 0), packaged once per session as ./scripts/ssp --extrapolation 0 does."""
    return cli.packaged(name, systems.HELD, _HELD)


def edited(src, dst, entry, old, new):
    """A copy of archive `src` at `dst` with `old` replaced by `new` in `entry` (once at least)."""
    with zipfile.ZipFile(src) as zin, zipfile.ZipFile(dst, "w") as zout:
        for item in zin.infolist():
            data = zin.read(item.filename)
            if item.filename == entry:
                assert old.encode() in data, f"{old!r} not in {entry}"
                data = data.replace(old.encode(), new.encode())
            zout.writestr(item, data)
    return dst


# --- 1. valid archives ------------------------------------------------------------------------
@pytest.mark.parametrize("name", SCENES)
def test_archive_validates_against_the_ssp_schema(name, tmp_path):
    path = ssp(name)
    with zipfile.ZipFile(path) as zf:
        zf.extractall(tmp_path)
        entries = zf.namelist()
    archive.validate(tmp_path / archive.SSD_NAME, "ssd")
    ssvs = [e for e in entries if e.endswith(".ssv")]
    assert len(ssvs) == len(system(name).components)
    for e in ssvs:
        archive.validate(tmp_path / e, "ssv")
    from fmpy.ssp.ssd import read_ssd           # a second schema copy (fmpy's), and a reader
    ssd = read_ssd(str(path), validate=True)
    assert {c.name for c in ssd.system.elements} == {c.name for c in system(name).components}
    archive.check(path, system(name))


def test_schema_check_is_not_vacuous(tmp_path):
    bad = edited(ssp("bounce"), tmp_path / "bad.ssp", archive.SSD_NAME, "<ssd:Connection ", "<ssd:Connexion ")
    with zipfile.ZipFile(bad) as zf:
        zf.extractall(tmp_path / "x")
    with pytest.raises(xmlschema.XMLSchemaValidationError, match="Connexion"):
        archive.validate(tmp_path / "x" / archive.SSD_NAME, "ssd")


# --- 2. the same trajectory as our master -----------------------------------------------------
@pytest.mark.parametrize("archive_kind", ["held", "default"])
@pytest.mark.parametrize("tool", tools.TOOLS)
@pytest.mark.parametrize("name", SCENES)
def test_tool_gives_the_masters_jacobi(name, tool, archive_kind):
    path, s = held(name) if archive_kind == "held" else (ssp(name), system(name))
    e = s.connector.params["cosim.extrapolation"]
    assert e == (systems.HELD if archive_kind == "held" else systems.EXTRAPOLATION)
    run = tools.run(tool, path, s, H)
    assert run.failed is None
    t, h = tools.grid(tool, H, run.steps)
    assert run.t[:-1].tolist() == t.tolist()             # the grid the tool stepped on
    mine = compare.master_as_tool(s.scene, "jacobi", tool, H, extrapolation=e)
    assert compare.difference(run, mine) <= TOL
    if archive_kind == "held":
        zoh = compare.master_as_tool(s.scene, "zoh", tool, H)
        assert compare.difference(run, zoh) > 1e-3       # not Gauss-Seidel
    if archive_kind == "held" and name in ("bounce", "bushing_pendulum"):
        assert compare.difference(run, master.simulate(s.scene, "jacobi", H)) <= TOL
    if archive_kind == "default" and systems.EXTRAPOLATION != systems.HELD:
        # the setting moves the trajectory: the archive is not the held one under another name
        assert compare.difference(run, compare.master_as_tool(s.scene, "jacobi", tool, H)) > 1e-6


# --- 3. broken archives -----------------------------------------------------------------------
def _tool_error(tool, path, name):
    """The tool's own verdict on archive `path`, the archive check off, in a child process (an
    error a tool meets in initialization may end its process)."""
    code = ("import sys; sys.path.insert(0, sys.argv[1]); from sspkit import systems, tools\n"
            "try:\n"
            "    r = tools.run(sys.argv[2], sys.argv[3], systems.system(sys.argv[4]), 1e-3, 0.01, check=False)\n"
            "    print('RAN', r.failed)\n"
            "except tools.ToolError as e:\n"
            "    print('ERROR', e)\n")
    out = subprocess.run([sys.executable, "-c", code, str(REPO / "scripts"), tool, str(path), name],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout.strip().splitlines()[-1]


@pytest.fixture(scope="module")
def broken_connection(tmp_path_factory):
    """bounce with the load connected to f[9], which the Body does not have."""
    path = tmp_path_factory.mktemp("ssp") / "bounce.ssp"
    edited(ssp("bounce"), path, archive.SSD_NAME, '"f[3]"', '"f[9]"')
    return path


def test_broken_connection_is_refused_by_our_check(broken_connection):
    with pytest.raises(archive.ArchiveError, match=r"mass\.f\[9\]: Body\.fmu has no variable 'f\[9\]'"):
        archive.check(broken_connection, system("bounce"))


@pytest.mark.parametrize("tool, message", [("libcosim", "No such variable: mass:f[9]"),
                                           ("ecos", "No such real property: mass::f[9]")])
def test_broken_connection_is_refused_by_the_tool(broken_connection, tool, message):
    verdict = _tool_error(tool, broken_connection, "bounce")
    assert verdict.startswith("ERROR") and message in verdict


@pytest.fixture(scope="module")
def unknown_parameter(tmp_path_factory):
    """bounce with its stop position under a name the RadialThrust does not have."""
    path = tmp_path_factory.mktemp("ssp") / "bounce.ssp"
    edited(ssp("bounce"), path, "resources/radialthrust.ssv", '"stop.lower3"', '"stop.lowr3"')
    return path


def test_unknown_parameter_is_refused_before_the_run(unknown_parameter, capsys):
    with pytest.raises(archive.ArchiveError) as e:
        tools.run("ecos", unknown_parameter, system("bounce"), H)
    assert "names 'stop.lowr3', which is no parameter of RadialThrust.fmu" in str(e.value)
    assert "parameter stop.lower3 (scene bounce: 0.05) is missing" in str(e.value)
    assert cli.main(["bounce", "--tool", "libcosim", "--ssp", str(unknown_parameter)]) == 1
    assert "stop.lowr3" in capsys.readouterr().err


@pytest.mark.parametrize("tool", tools.TOOLS)
def test_the_tools_run_on_an_unknown_parameter(unknown_parameter, tool):
    """Why our check exists: libcosim and Ecos only log a warning and run with the FMU's
    default for the parameter the set meant."""
    assert _tool_error(tool, unknown_parameter, "bounce") == "RAN None"


def test_missing_parameter_is_refused_before_the_run(tmp_path, capsys):
    """puck0 without its normal load friction.Fint: the tools would run it frictionless."""
    path = edited(ssp("puck0"), tmp_path / "puck0.ssp", "resources/planar.ssv",
                  '<ssv:Parameter name="friction.Fint">', '<ssv:Parameter name="friction.Mint">')
    with pytest.raises(archive.ArchiveError, match=r"planar: parameter friction\.Fint \(scene puck0: 9\.81\) is missing"):
        tools.run("libcosim", path, system("puck0"), H)
    assert cli.main(["puck0", "--tool", "ecos", "--ssp", str(path)]) == 1
    assert "friction.Fint" in capsys.readouterr().err


def test_cli_writes_the_csv_and_prints_error_and_cpu(tmp_path, capsys):
    assert cli.main(["bounce", "--tool", "ecos", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "error = " in out and "s per simulated second" in out
    lines = (tmp_path / "bounce_ecos_0.001.csv").read_text().splitlines()
    assert lines[0] == "time,mass.r[3],mass.v[3]"
    assert len(lines) == 1 + 101


# --- docs/ssp.md's snippets, as written ---------------------------------------------------------
def test_docs_snippets_run_as_written(tmp_path):
    """The ```python blocks between the ssp-snippets markers of docs/ssp.md, joined into one
    script and run in a fresh directory holding `dist` as a link to the repository's (a child
    process: libcosim may end its process on an error): libcosim and Ecos print the same bounce."""
    text = (REPO / "docs" / "ssp.md").read_text()
    begin, end = text.index("<!-- ssp-snippets:begin -->"), text.index("<!-- ssp-snippets:end -->")
    blocks = re.findall(r"^```python\n(.*?)^```$", text[begin:end], re.S | re.M)
    assert len(blocks) == 2
    (tmp_path / "snippets.py").write_text("\n".join(blocks))
    (tmp_path / "dist").symlink_to(REPO / "dist")
    out = subprocess.run([sys.executable, "snippets.py"], cwd=tmp_path, capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 0, out.stderr[-2000:]
    lines = [ln for ln in out.stdout.splitlines() if ln.startswith(("libcosim:", "Ecos:", "largest"))]
    assert lines[0].split(":", 1)[1].strip() == lines[1].split(":", 1)[1].strip()
    assert float(lines[2].split(":")[1]) <= 1e-12
