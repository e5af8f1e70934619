"""The archives of dist/ssp with their default connector setting (systems.EXTRAPOLATION: every
connector at cosim.extrapolation = 2, the nodes moved over a step along their velocities and the
accelerations the FMU takes from its input history) against the held-input archives of the same
scenes (cosim.extrapolation = 0, packaged by the test as ./scripts/ssp --extrapolation 0 does), in
the real tools, libcosim and Ecos, at H = 1 ms: no mocks, every run the tool stepping the
packaged FMUs, and each error the scene's own measure against its reference (the closed forms,
the monolithic reference, expm(A t) z0; docs/ssp.md's table of the settings).

- Where docs/ssp.md's table says the setting helps (every scene but the belt), the default
  archive's error is at most GAIN times below the held one's. GAIN = 1.5 is below every measured
  gain at 1 ms (puck0 2.0, the smallest: the puck's stop times move from the one-step lag to half
  of it; bounce 3.2, the pendulum 5.2, the engine 1.7e3 and the chain 1e23): the runs are
  deterministic, so the margin only covers a change of the FMUs that keeps their physics.
  Where the held run stops (libcosim, engine_mount_damped: the Body refuses a step at 1.88 s),
  the default run must reach the end.
- The belt, which the setting cannot help (its stick spring, k_s = 1e6 N/m on 1 kg with
  ω_s H = 1 at 1 ms, is not resolved by a lagged explicit coupling whatever path the nodes take):
  within BELT = 2 % of the held error (measured 1.0 %), i.e. no worse than that.
- libcosim and Ecos give the same error on the default archives (REL = 1e-6 relative: their
  grids differ in the last bits of t and h, which moves nothing but rounding in these runs),
  but for the belt: its stick/slip is decided by a threshold at every step, and the last bits
  move a transition by a step (0.1407 in libcosim, 0.1419 in Ecos; test_ssp.py checks each
  tool's belt against our master's on the tool's own grid instead).
"""
from __future__ import annotations

import functools
import math

import pytest

from sspkit import cli, multibody, systems, tools
from test_ssp import held, ssp

H = 1e-3
GAIN = 1.5
BELT = 0.02
REL = 1e-6


@functools.lru_cache(maxsize=None)
def error(tool, name, kind):
    """(error, failed) of scene `name` in `tool` at H, from its default or held archive."""
    path, system = held(name) if kind == "held" else (ssp(name), multibody.system(name))
    run = (tools.run_multi if name in multibody.NAMES else tools.run)(tool, path, system, H)
    if run.failed:
        return math.inf, run.failed
    return system.scene.measure(run)["error"], None


def test_the_default_archives_use_the_default_setting():
    for name in multibody.ALL:
        conns = [c for c in multibody.system(name).components if "cosim.extrapolation" in c.params]
        assert conns and all(c.params["cosim.extrapolation"] == systems.EXTRAPOLATION for c in conns)
        assert all(c.params["cosim.extrapolation"] == systems.HELD for c in held(name)[1].components
                   if "cosim.extrapolation" in c.params)
    assert systems.EXTRAPOLATION == 2


@pytest.mark.parametrize("tool", tools.TOOLS)
@pytest.mark.parametrize("name", [n for n in multibody.ALL if n != "belt"])
def test_the_default_archive_is_more_accurate_than_the_held_one(name, tool):
    mine, failed = error(tool, name, "default")
    assert failed is None, failed
    theirs, _ = error(tool, name, "held")
    assert math.isfinite(mine)
    assert mine * GAIN <= theirs, (mine, theirs)


@pytest.mark.parametrize("tool", tools.TOOLS)
def test_the_belt_is_no_worse_with_the_default(tool):
    mine, failed = error(tool, "belt", "default")
    theirs, _ = error(tool, "belt", "held")
    assert failed is None
    assert abs(mine - theirs) <= BELT * theirs, (mine, theirs)


@pytest.mark.parametrize("name", [n for n in multibody.ALL if n != "belt"])
def test_libcosim_and_ecos_give_the_same_error_with_the_default(name):
    a, b = error("libcosim", name, "default")[0], error("ecos", name, "default")[0]
    assert abs(a - b) <= REL * abs(b), (a, b)


def test_the_cli_packages_and_runs_a_scene_at_another_setting(tmp_path, capsys):
    """./scripts/ssp SCENE --extrapolation 0: the held-input archive, packaged and run; its error
    is the held run's of the tests above, and --compare finds our plain jacobi in it."""
    args = ["bounce", "--tool", "ecos", "--extrapolation", "0", "--compare", "--out", str(tmp_path)]
    assert cli.main(args) == 0
    out = capsys.readouterr().out
    assert f"error = {error('ecos', 'bounce', 'held')[0]:.4g} " in out
    assert "cosim.extrapolation = 0): 0 on ecos's time grid" in out
    with pytest.raises(SystemExit):
        cli.main([str(ssp("bounce")), "--tool", "ecos", "--extrapolation", "0"])
    assert "give a scene's name" in capsys.readouterr().err
