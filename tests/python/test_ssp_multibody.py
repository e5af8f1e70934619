"""The multi-body scenes as SSP archives (SCENES.md §8 chain, §9 engine_mount; scripts/sspkit/
chain.py, engine_mount.py, engine_reference.py) in the real tools, libcosim and Ecos, and the
checks that refuse an archive that cannot work before a tool runs it (structure.py,
./scripts/ssp). No mocks: every run is the tool stepping the packaged FMUs.

1. The archives validate against the SSP 1.0 schema (and fmpy's reader) and fit their scene.
2. (The runs of 2 and 3 are of the held-input archives, every connector at cosim.extrapolation
   = 0, packaged by the test.) The chain in both tools at H = 0.1 ms is, step for step, the
   Jacobi coupling of the linear chain written out in numpy (the Body's exact update under the held spring forces, the
   springs at the held positions): to 1e-9 of the amplitude although the run grows by 1e3
   (plain Jacobi without damping is unstable at every H, SCENES §7), which checks the ports'
   wiring and the signs of every load; both tools agree to 1e-9 on their own grids; at small
   H over 20 ms the runs converge to the exact solution expm(A t) z0 at first order.
3. The engine: the linearised frequencies are SCENES §9's; the monolithic reference converges
   (rtol 1e-9 → 1e-11) and conserves energy to 1e-8; it meets the linear response to the
   order of the rotation (5e-3) and, at a hundredth of the amplitude, a hundred times closer;
   both tools at H = 1 ms agree to 1e-9 on their own grids, and at small H over 0.2 s converge
   to the reference at first order.
4. Broken archives, made here by editing a packaged one, are refused by ./scripts/ssp's code
   with one line per problem naming the connection or element and exit status 1, before a tool
   runs: two connections into one input, a connection to a variable the FMU lacks, an output
   connected to an output, a parameter set naming an unknown variable; and an archive of one's
   own (a system not named as a scene) runs by its path.

Tolerances are stated where used.
"""
from __future__ import annotations

import functools
import subprocess
import sys
import zipfile

import numpy as np
import pytest
from fmpy.ssp.ssd import read_ssd

from conftest import REPO
from sspkit import archive, chain, cli, engine_mount, engine_reference as ref, multibody, structure, tools
# edited: a copy of an archive with one entry's text replaced; ssp: dist/ssp/<scene>.ssp;
# held: the scene's held-input archive (cosim.extrapolation = 0) and its System
from test_ssp import edited, held, ssp

NAMES = multibody.NAMES
TOL = 1e-9


@functools.lru_cache(maxsize=None)
def system(name):
    return multibody.system(name)


@functools.lru_cache(maxsize=None)
def run(tool, name, H, t_end=None):
    """The held-input archive's run: plain Jacobi with the nodes held, which the checks of the
    wiring below write out (the archives of dist/ssp: test_ssp_defaults.py)."""
    return tools.run_multi(tool, *held(name), H, t_end)


def difference(a, b, names):
    """Largest |a − b| over the samples `names`, each relative to its largest |b|."""
    return max(np.abs(a[n] - b[n]).max() / max(np.abs(b[n]).max(), 1e-300) for n in names)


# --- 1. valid archives ------------------------------------------------------------------------
@pytest.mark.parametrize("name", NAMES)
def test_archive_validates_and_fits_its_scene(name, tmp_path):
    path = ssp(name)
    with zipfile.ZipFile(path) as zf:
        zf.extractall(tmp_path)
    archive.validate(tmp_path / archive.SSD_NAME, "ssd")
    for ssv in (tmp_path / "resources").glob("*.ssv"):
        archive.validate(ssv, "ssv")
    read_ssd(str(path))
    assert structure.problems(path) == []
    archive.check(path, system(name))


# --- 2. the chain -----------------------------------------------------------------------------
def jacobi_chain(scene, h):
    """The chain as a fixed-step Jacobi master couples its FMUs, in numpy, over the steps h_k.
    After its step to t_k a connector outputs its load at the node inputs it held over that
    step, those of t_(k−1) (at t_0: of t_0, transferred at initialization); each body then
    steps from t_k under that load. So body i moves from (x_k, v_k) under
    Q_k = F_(i+1)(t_(k−1)) − F_i(t_(k−1)), where spring j's force F_j = k_j Δ_j + c_j Δ̇_j acts as
    +F_j on its node a (the body on its left) and −F_j on its node b, as the Body FMU's model 0
    moves under a held load: x += h v + (h²/6)(3Q)/m, v += h Q/m."""
    walls = np.array(chain.WALLS)
    rest = np.diff(np.concatenate([[walls[0]], chain.X0, [walls[1]]]))

    def forces(x, v):
        F = (chain.K * (np.diff(np.concatenate([[walls[0]], x, [walls[1]]])) - rest)
             + scene.c * np.diff(np.concatenate([[0.0], v, [0.0]])))
        return F[1:] - F[:-1]

    x, v = chain.X0.copy(), chain.V0.copy()
    Q = forces(x, v)
    rows = [np.concatenate([x, v])]
    for hk in h:
        Q_next = forces(x, v)                  # what the connectors output after this step
        x, v = x + hk * v + (hk * hk / 6) * (3 * Q) / chain.MASS, v + hk * Q / chain.MASS
        Q = Q_next
        rows.append(np.concatenate([x, v]))
    return np.array(rows)


@pytest.mark.parametrize("tool", tools.TOOLS)
@pytest.mark.parametrize("name", ["chain", "chain_damped"])
def test_the_chain_in_the_tool_is_the_jacobi_coupling_of_the_linear_chain(tool, name):
    H = 1e-3
    r = run(tool, name, H)
    assert r.failed is None and r.steps == 1000
    t, h = tools.grid(tool, H, r.steps)
    mine = jacobi_chain(system(name).scene, h)
    cols = [f"{b}.{x}" for x in ("r[1]", "v[1]") for b in chain.BODIES]
    # 1e-9 of the largest displacement and speed: the two sum the same terms in other orders
    # (and the FMU's connector measures along its triad), a few ulp per step on a run that
    # grows by 1e3 and so amplifies them by as much
    u = np.column_stack([r[c] for c in cols])
    for j in range(6):
        scale = np.abs(mine[:, j] - (chain.X0[j] if j < 3 else 0.0)).max()
        assert np.abs(u[:, j] - mine[:, j]).max() <= TOL * scale, cols[j]
    # unstable, as SCENES §8 says plain explicit coupling is at every H
    assert system(name).scene.measure(r)["error"] > 10


def test_libcosim_and_ecos_give_the_same_chain_on_their_own_grids():
    a, b = run("libcosim", "chain", 1e-3), run("ecos", "chain", 1e-3)
    assert difference(a, b, a.samples) <= TOL


def test_the_chain_converges_to_the_exact_solution_at_first_order():
    """Over 20 ms (before the instability grows: ω² H t / 2 ≤ 0.03 at 5e-5 s), halving H halves
    the error against expm(A t) z0, the first order of the one-step lag."""
    scene = system("chain").scene
    errs = [scene.measure(run("ecos", "chain", H, 0.02))["error"] for H in (1e-4, 5e-5, 2.5e-5)]
    for big, small in zip(errs, errs[1:]):
        assert 1.7 <= big / small <= 2.3, errs
    assert errs[-1] < 0.03


def test_the_chains_reference_has_the_scenes_frequencies_and_keeps_its_energy():
    scene = chain.Chain(0)
    assert np.allclose(scene.frequencies(), [23.789, 168.327, 359.305], rtol=0, atol=1e-3)
    t = np.linspace(0, 1, 101)
    u, v = scene.reference(t)
    E = scene.energy(u, v)
    # expm is exact but for round-off: scaling and squaring of |A t| up to 360 leaves ~1e-12
    assert np.abs(E - E[0]).max() <= 1e-11 * E[0]
    u1, _ = chain.Chain(1).reference(t)
    assert np.abs(u1[-1]).max() < np.abs(u[-1]).max()


# --- 3. the engine ----------------------------------------------------------------------------
GEO = engine_mount.EngineMount


def test_the_linearised_frequencies_are_the_scenes():
    w, _ = ref.modes(GEO)
    assert np.allclose(w, [55.887, 68.259, 83.966, 88.501, 94.868, 95.566], rtol=0, atol=1e-3)


def test_the_monolithic_reference_converges_and_keeps_its_energy():
    t = np.linspace(0.0, GEO.T_END, 401)
    rows = ref.convergence(GEO, 0, t, (1e-8, 1e-9))
    diffs = {rtol: max(p, q) for rtol, p, q, _ in rows}
    # tightening the tolerance tenfold moves the run by less and less (docs/ssp.md: 1e-11 too)
    assert diffs[1e-8] > 3 * diffs[1e-9] and diffs[1e-9] <= 1e-7, diffs
    r, q, v, w = ref.monolithic(GEO, 0).at(t)
    mounts = ref.Mounts(GEO, 0)
    try:
        E = mounts.energy(r[::10], q[::10], v[::10], w[::10])
    finally:
        mounts.close()
    assert np.abs(E - E[0]).max() <= 1e-8 * E[0]


def test_the_reference_meets_the_linear_modes_at_small_amplitude():
    """The relative difference of the full response to the linear one is of the order of the
    rotation (5e-3 rad); at a hundredth of the initial velocities it falls a hundredfold."""
    t = np.linspace(0.0, GEO.T_END, 401)
    out = []
    for scale in (1.0, 0.01):
        r, q, _, _ = ref.Monolithic(GEO, 0, scale=scale).at(t)
        z = ref.linear(GEO, 0, t, scale)
        rot = ref.rotation_vector(q)
        out.append(max(np.abs(r - z[:, :3]).max() / np.abs(z[:, :3]).max(),
                       np.abs(rot - z[:, 3:6]).max() / np.abs(z[:, 3:6]).max()))
        if scale == 1.0:
            assert 4e-3 <= np.abs(rot).max() <= 6e-3 and 1.0e-3 <= np.abs(r).max() <= 1.4e-3
    assert 1e-3 <= out[0] <= 1e-2, out
    assert 50 <= out[0] / out[1] <= 200, out


def test_libcosim_and_ecos_give_the_same_engine_on_their_own_grids():
    """At 1 ms plain Jacobi is unstable here: by t = 1 s the block has left its mounts by 0.4 m
    and tumbles; until then the tools agree to 1e-13 (measured 3.7e-14), after it two
    exponentially growing runs that differ in the last bits of h part (docs/ssp.md)."""
    a, b = run("libcosim", "engine_mount", 1e-3), run("ecos", "engine_mount", 1e-3)
    assert a.failed is None and b.failed is None
    k = 1001                                                  # t ≤ 1 s
    first = multibody.Run(t=a.t[:k], samples={n: x[:k] for n, x in a.samples.items()})
    second = multibody.Run(t=b.t[:k], samples={n: x[:k] for n, x in b.samples.items()})
    assert difference(first, second, a.samples) <= TOL
    assert np.abs(b["block.r[1]"][:k]).max() > 0.1            # it did blow up: not a calm run


def test_the_engine_in_both_tools_converges_to_the_reference_at_first_order():
    """Over 0.2 s, halving H halves the pose error (the first order of Jacobi); one tool (the
    other gives the same runs, above)."""
    scene = system("engine_mount").scene
    for tool in ("ecos",):
        errs = [scene.measure(run(tool, "engine_mount", H, 0.2))["error"] for H in (4e-4, 2e-4, 1e-4)]
        for big, small in zip(errs, errs[1:]):
            assert 1.6 <= big / small <= 2.4, (tool, errs)
        assert errs[-1] < 0.1, errs


# --- 4. broken archives -------------------------------------------------------------------------
SSD = archive.SSD_NAME


def refused(path, capsys):
    """./scripts/ssp's code on `path`: exit status and the problem lines it printed."""
    code = cli.main([str(path), "--tool", "ecos", "--out", str(path.parent)])
    err = capsys.readouterr().err
    return code, [ln.strip() for ln in err.splitlines()[2:]]


def test_two_connections_into_one_input_are_refused(tmp_path, capsys):
    """m1's right spring's load moved onto its left port: two loads into m1.port[1].f[1]."""
    path = edited(ssp("chain"), tmp_path / "double.ssp", SSD,
                  'startElement="k2" startConnector="a.f[1]" endElement="m1" endConnector="port[2].f[1]"',
                  'startElement="k2" startConnector="a.f[1]" endElement="m1" endConnector="port[1].f[1]"')
    code, lines = refused(path, capsys)
    assert code == 1
    assert lines == ["input m1.port[1].f[1] has 2 connections into it (k1.b.f[1], k2.a.f[1]); an input "
                     "takes one: give each load its own input (a Body's ports, docs/body.md)"]
    assert not list(tmp_path.glob("*.csv"))            # no tool ran


def test_a_connection_to_a_missing_variable_is_refused(tmp_path, capsys):
    path = edited(ssp("engine_mount"), tmp_path / "missing.ssp", SSD, 'endElement="block" endConnector="port[4].f[2]"',
                  'endElement="block" endConnector="port[5].f[2]"')
    code, lines = refused(path, capsys)
    assert code == 1 and lines == ["connection mount4.b.f[2] -> block.port[5].f[2]: Body.fmu has no "
                                   "variable 'port[5].f[2]'"]


def test_an_output_connected_to_an_output_is_refused(tmp_path, capsys):
    path = edited(ssp("chain"), tmp_path / "outout.ssp", SSD,
                  'endElement="k1" endConnector="b.r[1]"', 'endElement="m2" endConnector="r[1]"')
    code, lines = refused(path, capsys)
    assert code == 1
    assert lines == ["connection m1.port[1].r[1] -> m2.r[1]: 'r[1]' of Body.fmu is an output, not an input"]


def test_a_parameter_set_naming_an_unknown_variable_is_refused(tmp_path, capsys):
    path = edited(ssp("engine_mount"), tmp_path / "param.ssp", "resources/block.ssv",
                  '"port[3].offset.q.x"', '"port[3].offset.q.u"')
    code, lines = refused(path, capsys)
    assert code == 1
    assert lines == ["block: the parameter set names 'port[3].offset.q.u', which is no parameter of Body.fmu"]


def test_every_problem_is_listed_one_line_each(tmp_path, capsys):
    a = edited(ssp("chain"), tmp_path / "a.ssp", SSD, 'endConnector="port[2].f[1]"',
               'endConnector="port[1].f[1]"')         # all three bodies' port 2 → port 1
    b = edited(a, tmp_path / "b.ssp", "resources/m3.ssv", '"mass"', '"masse"')
    code, lines = refused(b, capsys)
    assert code == 1 and len(lines) == 4, lines        # three doubled inputs, one parameter
    assert sum("has 2 connections" in ln for ln in lines) == 3 and "'masse'" in lines[-1]


def test_an_archive_of_ones_own_runs_by_its_path(tmp_path, capsys):
    """The chain renamed (a system no scene knows): checked, run in each tool to its stop time,
    every Real output written; its motion is the packaged scene's."""
    path = edited(ssp("chain"), tmp_path / "mine.ssp", SSD, 'name="chain"', 'name="my_chain"')
    assert structure.read(path).name == "my_chain"
    for tool in tools.TOOLS:
        assert cli.main([str(path), "--tool", tool, "--step", "1e-3", "--out", str(tmp_path)]) == 0
        out = capsys.readouterr().out
        assert "s per simulated second" in out
        data = np.genfromtxt(tmp_path / f"my_chain_{tool}_0.001.csv", delimiter=",", names=True,
                             deletechars="")
        assert len(data) == 1000 and "m2.port[1].v[1]" in data.dtype.names
        scene = tools.run_multi(tool, ssp("chain"), system("chain"), 1e-3)    # the packaged one
        assert np.array_equal(data["m2.r[1]"], scene["m2.r[1]"][1:])


def test_what_the_tools_do_with_two_connections_into_one_input(tmp_path):
    """Why the check exists (the tools run in a child process, the check off): libcosim refuses
    the archive, Ecos runs it on the last connection alone and gives another motion, silently."""
    path = edited(ssp("chain"), tmp_path / "double.ssp", SSD,
                  'startElement="k2" startConnector="a.f[1]" endElement="m1" endConnector="port[2].f[1]"',
                  'startElement="k2" startConnector="a.f[1]" endElement="m1" endConnector="port[1].f[1]"')
    code = ("import sys; sys.path.insert(0, sys.argv[1]); from sspkit import multibody, tools\n"
            "s = multibody.system('chain')\n"
            "try:\n"
            "    r = tools.run_multi(sys.argv[2], sys.argv[3], s, 1e-4, 0.02, check=False)\n"
            "    print('RAN', r.failed, s.scene.measure(r)['error'])\n"
            "except tools.ToolError as e:\n"
            "    print('ERROR', e)\n")
    verdicts = {}
    for tool in tools.TOOLS:
        out = subprocess.run([sys.executable, "-c", code, str(REPO / "scripts"), tool, str(path)],
                             capture_output=True, text=True, timeout=120)
        assert out.returncode == 0, out.stderr[-2000:]
        verdicts[tool] = out.stdout.strip().splitlines()[-1]
    assert verdicts["libcosim"].startswith("ERROR") and "already connected" in verdicts["libcosim"]
    ran, failed, error = verdicts["ecos"].split()
    intact = system("chain").scene.measure(run("ecos", "chain", 1e-4, 0.02))["error"]
    assert (ran, failed) == ("RAN", "None") and float(error) > 1.5 * intact


def test_a_declared_connector_the_fmu_lacks_and_a_missing_fmu_are_refused(tmp_path):
    path = edited(ssp("engine_mount"), tmp_path / "decl.ssp", SSD,
                  '<ssd:Connector name="port[4].f[2]"', '<ssd:Connector name="port[4].g[2]"')
    assert structure.problems(path) == [f"{c}: declares the connector 'port[4].g[2]', which is no "
                                        "variable of Body.fmu" for c in ("ground", "block")]
    gone = tmp_path / "gone.ssp"
    with zipfile.ZipFile(ssp("chain")) as zin, zipfile.ZipFile(gone, "w") as zout:
        for item in zin.infolist():
            if item.filename != "resources/ProjectionCartesian.fmu":
                zout.writestr(item, zin.read(item.filename))
    assert structure.problems(gone) == [f"k{j}: its FMU resources/ProjectionCartesian.fmu is not in the archive"
                                        for j in (1, 2, 3, 4)]
