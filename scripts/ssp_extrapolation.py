#!/usr/bin/env python3
"""What each `cosim.extrapolation` setting of the connector FMUs gives in a plain fixed-step SSP
master (libcosim, Ecos): every scene of dist/ssp packaged once per setting (0 hold, 1 linear
along the velocity inputs, 2 quadratic from the input history, 3 along the acceleration inputs,
which no Body drives: zero), run in both tools at each H, its error against the scene's
reference (the same runs as `./scripts/ssp SCENE --tool T --step H --extrapolation E`). Writes
out/ssp_extrapolation.csv and prints the table of docs/ssp.md (--table: only the table, from it).
Usage: ssp_extrapolation.py [--step H ...] [--scene NAME ...] [--setting E ...] [--table]
Run after ./scripts/run (it needs dist/*.fmu).
"""
import argparse
import csv
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from cosim.connectors import REPO  # noqa: E402
from sspkit import multibody, tools  # noqa: E402
from sspkit.cli import packaged  # noqa: E402

SETTINGS = (0, 1, 2, 3)
NAMES = {0: "held", 1: "linear", 2: "quadratic", 3: "accelerations"}


def measure(name, setting, tool, H):
    """{'error', 'energy', 'failed'} of scene `name` with every connector at `setting`."""
    path, system = packaged(name, setting)        # out/ssp/extrapolation/x<E>/
    run = (tools.run_multi if name in multibody.NAMES else tools.run)(tool, path, system, H)
    out = {"error": math.nan, "energy": math.nan, "failed": run.failed or ""}
    if not run.failed:
        try:
            fig = system.scene.measure(run)
        except (ValueError, FloatingPointError, OverflowError) as e:
            out["failed"] = f"measure: {e}"
        else:
            out["error"] = fig["error"]
            out["energy"] = math.nan if fig.get("energy") is None else fig["energy"]
    return out


def cell(row):
    """A table cell: the error (and, where the scene has one apart, the energy error), or why
    there is none."""
    if row["failed"]:
        return "stopped" if row["tool"] == "libcosim" else "failed"
    if math.isnan(row["error"]):
        return "–"
    text = f"{row['error']:.3g}"
    return text if math.isnan(row["energy"]) else f"{text} (E {row['energy']:.2g})"


def table(rows):
    """docs/ssp.md's table: one line per scene, H and tool, one column per setting."""
    lines = ["| scene | H | tool | " + " | ".join(NAMES[e] for e in SETTINGS) + " |",
             "|---" * (3 + len(SETTINGS)) + "|"]
    key = {(r["scene"], r["H"], r["tool"], r["setting"]): r for r in rows}
    for name, H, tool in dict.fromkeys((r["scene"], r["H"], r["tool"]) for r in rows):
        cells = [cell(key[name, H, tool, e]) if (name, H, tool, e) in key else "" for e in SETTINGS]
        lines.append(f"| {name} | {H * 1e3:g} ms | {tool} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--step", type=float, nargs="+", default=[1e-3, 1e-2])
    ap.add_argument("--scene", nargs="+", default=list(multibody.ALL))
    ap.add_argument("--setting", type=int, nargs="+", default=list(SETTINGS))
    ap.add_argument("--csv", type=Path, default=REPO / "out" / "ssp_extrapolation.csv")
    ap.add_argument("--table", action="store_true", help="only print the table of an earlier --csv")
    args = ap.parse_args(argv)
    if args.table:
        with open(args.csv) as f:
            rows = [{**r, "H": float(r["H"]), "setting": int(r["setting"]), "error": float(r["error"]),
                     "energy": float(r["energy"])} for r in csv.DictReader(f)]
        print(table(rows))
        return
    rows = []
    for name in args.scene:
        for H in args.step:
            for tool in tools.TOOLS:
                for e in args.setting:
                    m = measure(name, e, tool, H)
                    rows.append({"scene": name, "H": H, "tool": tool, "setting": e, **m})
                    print(f"{name:<20} H = {H:<6g} {tool:<8} {NAMES[e]:<13} error {m['error']:<10.3g} "
                          f"energy {m['energy']:<10.3g} {m['failed'][:60]}", flush=True)
    args.csv.parent.mkdir(parents=True, exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {args.csv}")
    print(table(rows))


if __name__ == "__main__":
    main(sys.argv[1:])
