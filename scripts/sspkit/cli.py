"""./scripts/ssp SCENE|ARCHIVE --tool libcosim|ecos [--step H] [--out DIR] [--compare]: run an SSP
archive in a third-party master. SCENE is one of the packaged scenes (its archive
dist/ssp/<scene>.ssp, from ./scripts/run); ARCHIVE is the path of any .ssp file.

Before a tool runs anything the archive's structure is checked against the FMUs inside it
(structure.py): two connections into one input, a connection to a variable the FMU does not
have, an output connected to an output (or an input to an input), a parameter set naming an
unknown variable; each problem is one line naming the connection or the element, and the exit
status is 1. A scene's archive (or an ARCHIVE whose system is named as a scene) is also
checked against the scene (archive.check: its parameter values and connections).

A scene's run writes DIR/<scene>_<tool>_<H>.csv (time and the outputs the scene samples) and
prints its error against its reference (the scene's own `measure`: scripts/cosim/scenes.py,
or chain.py and engine_mount.py) and the CPU time per simulated second. Any other archive runs
to its DefaultExperiment's stop time and writes DIR/<system>_<tool>_<H>.csv with every Real
output of every component, from t = H (libcosim shows nothing at t = 0). --compare (one-body
scenes) also runs our master's `jacobi` on the tool's time grid and on its own and prints the
largest relative differences. --extrapolation E packages the scene with every connector's
cosim.extrapolation = E (0 hold: the held-input archive; dist/ssp's is systems.EXTRAPOLATION)
into out/ssp/extrapolation/x<E>/<scene>.ssp and runs that.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from cosim import master
from cosim.connectors import DIST, REPO

from . import archive, compare, multibody, structure, systems, tools

SSP_DIR = DIST / "ssp"
VARIANTS_DIR = REPO / "out" / "ssp" / "extrapolation"


def packaged(name, extrapolation, out=VARIANTS_DIR):
    """Scene `name` packaged with every connector at cosim.extrapolation = `extrapolation`, as
    out/x<E>/<name>.ssp (from dist/'s FMUs): (path, System)."""
    system = multibody.system(name, extrapolation)
    return archive.write(system, Path(out) / f"x{extrapolation}" / f"{name}.ssp"), system


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


def write_samples(path, run):
    """time, then one column per sampled "component.variable"."""
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savetxt(path, np.column_stack([run.t] + list(run.samples.values())), delimiter=",",
               header=",".join(["time"] + list(run.samples)), comments="", fmt="%.17g")
    return path


def stop_time(path):
    """The DefaultExperiment's stopTime of an archive (SystemExit when it has none)."""
    import zipfile
    from lxml import etree as ET
    with zipfile.ZipFile(path) as zf:
        exp = ET.fromstring(zf.read(structure.SSD_NAME)).find("ssd:DefaultExperiment", structure.NS)
    if exp is None or exp.get("stopTime") is None:
        raise SystemExit(f"error: {path}: no DefaultExperiment stopTime; the run needs an end")
    return float(exp.get("stopTime"))


def run_archive(args, path, info):
    """Any archive: every Real output of every component, to its stop time."""
    probes = [(name, v.name) for name, el in info.components.items()
              for v in info.variables[el.source].values()
              if v.causality == "output" and v.type in ("Real", "Float64")]
    t_end = stop_time(path)
    n = tools.steps(args.step, t_end)
    sets = info.parameter_sets or [systems.PARAMETER_SET]
    t, rows, cpu, failed = tools.run_probes(args.tool, path, probes, args.step, n, parameter_set=sets[0])
    run = multibody.Run(t=t, samples={f"{c}.{v}": rows[:, j] for j, (c, v) in enumerate(probes)}, cpu=cpu)
    csv = write_samples(args.out / f"{info.name}_{args.tool}_{args.step:g}.csv", run)
    print(f"{info.name} in {args.tool}, H = {args.step:g} s, {len(t)} steps: wrote {csv}")
    if failed:
        print(f"error: the run failed: {failed}", file=sys.stderr)
        return 1
    print(f"CPU   = {cpu / t_end:.4g} s per simulated second (stepping and sampling, {cpu:.3g} s)")
    return 0


def main(argv=None):
    ap = argparse.ArgumentParser(prog="./scripts/ssp", description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", metavar="SCENE|ARCHIVE",
                    help=f"a scene ({', '.join(multibody.ALL)}) or the path of an .ssp archive")
    ap.add_argument("--tool", choices=tools.TOOLS, required=True)
    ap.add_argument("--step", type=float, default=1e-3, metavar="H", help="communication step, s (default 1e-3)")
    ap.add_argument("--out", type=Path, default=REPO / "out" / "ssp", metavar="DIR",
                    help="where the CSV goes (default out/ssp)")
    ap.add_argument("--ssp", type=Path, help="another archive of the scene (default dist/ssp/<scene>.ssp)")
    ap.add_argument("--extrapolation", type=int, choices=(0, 1, 2, 3), metavar="E",
                    help="a scene packaged with every connector at cosim.extrapolation = E (0 hold, "
                         "1 linear, 2 quadratic, 3 along the acceleration inputs) instead of dist/ssp's")
    ap.add_argument("--compare", action="store_true",
                    help="also print the relative difference to our master's jacobi (one-body scenes)")
    args = ap.parse_args(argv)

    system = None
    if args.extrapolation is not None and (args.ssp or args.scene not in multibody.ALL):
        ap.error("--extrapolation packages a scene: give a scene's name and no --ssp")
    if args.extrapolation is not None:
        name = args.scene
        path, system = packaged(name, args.extrapolation)
    elif args.scene in multibody.ALL:
        name, path = args.scene, args.ssp or archive_path(args.scene)
    elif Path(args.scene).is_file():
        path = Path(args.scene)
        name = None
    else:
        ap.error(f"{args.scene!r} is neither a scene ({', '.join(multibody.ALL)}) nor an archive's path")
    try:
        info = structure.check(path)
    except structure.StructureError as e:
        print(f"error: the archive cannot work:\n{e}", file=sys.stderr)
        return 1
    except (OSError, KeyError, ValueError) as e:
        print(f"error: {path}: not an SSP archive: {e}", file=sys.stderr)
        return 1
    name = name or (info.name if info.name in multibody.ALL else None)
    if name is None:
        try:
            return run_archive(args, path, info)
        except (tools.ToolError, ValueError) as e:
            print(f"error: {e}", file=sys.stderr)
            return 1
    system = system or multibody.system(name)
    scene = system.scene
    multi = name in multibody.NAMES
    try:
        res = (tools.run_multi if multi else tools.run)(args.tool, path, system, args.step)
    except (archive.ArchiveError, tools.ToolError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    csv = args.out / f"{name}_{args.tool}_{args.step:g}.csv"
    csv = write_samples(csv, res) if multi else write_csv(csv, system, res)
    print(f"{name} in {args.tool}, H = {args.step:g} s, {res.steps} steps: wrote {csv}")
    if res.failed:
        print(f"error: the run failed: {res.failed}", file=sys.stderr)
        return 1
    figures = scene.measure(res)
    print(f"error = {figures['error']:.4g}   ({scene.error_label.replace(chr(10), ' ')})")
    if figures.get("energy") is not None:
        print(f"energy error = {figures['energy']:.4g}   (max |E - E0| / E0)")
    print(f"CPU   = {res.cpu / (res.t[-1] - res.t[0]):.4g} s per simulated second "
          f"(stepping and sampling, {res.cpu:.3g} s)")
    if args.compare and not multi:
        e = system.connector.params["cosim.extrapolation"]
        on_grid = compare.master_as_tool(scene, "jacobi", args.tool, args.step, extrapolation=e)
        line = (f"max relative difference to our master's jacobi (connector at cosim.extrapolation = {e}): "
                f"{compare.difference(res, on_grid):.3g} on {args.tool}'s time grid")
        if e == master.EXTRAPOLATION["jacobi"]:
            own = master.simulate(scene, "jacobi", args.step)
            line += f", {compare.difference(res, own):.3g} on its own (t = k H)"
        print(line)
    return 0
