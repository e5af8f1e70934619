"""./scripts/ssp SCENE --tool libcosim|ecos [--step H] [--out DIR] [--compare]: run the scene's SSP
archive (dist/ssp/<scene>.ssp, from ./scripts/run) in a third-party master, write the result CSV
(time and the body's state outputs, plus the outputs the scene monitors) to
DIR/<scene>_<tool>_<H>.csv, and print the scene's error against its reference (the scene's own
`measure`, scripts/cosim/scenes.py) and the CPU time per simulated second. The archive is checked
against its FMUs and its scene first (tools.run → archive.check): a broken connection or a wrong
or missing parameter stops the run with a message. --compare also runs our master's `jacobi` on the tool's
time grid and on its own and prints the largest relative differences.

Uses argparse, numpy and the package's modules (systems, archive, tools, compare).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from cosim import master
from cosim.connectors import DIST, REPO

from . import archive, compare, systems, tools

SSP_DIR = DIST / "ssp"


def archive_path(scene):
    """dist/ssp/<scene>.ssp (SystemExit with a hint when it is not there)."""
    path = SSP_DIR / f"{scene}.ssp"
    if not path.is_file():
        raise SystemExit(f"error: {path} is missing; ./scripts/run packages it")
    return path


def write_csv(path, system, res):
    """time, <body>.<output> for the body's state outputs, then the monitored outputs."""
    names = [f"{system.body}.{n}" for n in res.samples]
    cols = [res.t] + list(res.samples.values())
    names += [f"{system.connector.name}.{n}" for n in system.scene.record]
    cols += [res.extra[:, j] for j in range(res.extra.shape[1])]
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=",".join(["time"] + names),
               comments="", fmt="%.17g")
    return path


def main(argv=None):
    ap = argparse.ArgumentParser(prog="./scripts/ssp", description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", choices=systems.NAMES)
    ap.add_argument("--tool", choices=tools.TOOLS, required=True)
    ap.add_argument("--step", type=float, default=1e-3, metavar="H", help="communication step, s (default 1e-3)")
    ap.add_argument("--out", type=Path, default=REPO / "out" / "ssp", metavar="DIR",
                    help="where the CSV goes (default out/ssp)")
    ap.add_argument("--ssp", type=Path, help="another archive of the scene (default dist/ssp/<scene>.ssp)")
    ap.add_argument("--compare", action="store_true",
                    help="also print the relative difference to our master's jacobi")
    args = ap.parse_args(argv)

    system = systems.system(args.scene)
    scene = system.scene
    path = args.ssp or archive_path(args.scene)
    try:
        res = tools.run(args.tool, path, system, args.step)
    except (archive.ArchiveError, tools.ToolError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    csv = write_csv(args.out / f"{args.scene}_{args.tool}_{args.step:g}.csv", system, res)
    print(f"{args.scene} in {args.tool}, H = {args.step:g} s, {res.steps} steps: wrote {csv}")
    if res.failed:
        print(f"error: the run failed: {res.failed}", file=sys.stderr)
        return 1
    figures = scene.measure(res)
    print(f"error = {figures['error']:.4g}   ({scene.error_label.replace(chr(10), ' ')})")
    print(f"CPU   = {res.cpu / (res.t[-1] - res.t[0]):.4g} s per simulated second "
          f"(stepping and sampling, {res.cpu:.3g} s)")
    if args.compare:
        on_grid = compare.master_as_tool(scene, "jacobi", args.tool, args.step)
        own = master.simulate(scene, "jacobi", args.step)
        print(f"max relative difference to our master's jacobi: {compare.difference(res, on_grid):.3g} "
              f"on {args.tool}'s time grid, {compare.difference(res, own):.3g} on its own (t = k H)")
    return 0
