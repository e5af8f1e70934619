#!/usr/bin/env python3
"""The measurements of docs/ssp.md: the SSP scenes' held-input archives (every connector at
cosim.extrapolation = 0, sspkit.cli.packaged; dist/ssp's own setting: ssp_extrapolation.py) in
libcosim and Ecos beside this project's own master (scripts/cosim/master.py), in one run on one
machine.

(a) errors: per scene and communication step H, the scene's error against its reference (the
    scene's own `measure`) of libcosim, Ecos, and our master's jacobi, zoh and event-located
    linear_path_ev, implicit_path_ev, linear_exact_ev (FMI 2.0 with rollback to event.time);
(b) equality: per scene, tool and H, the largest relative difference of the tool's trajectory
    to our jacobi on the tool's time grid and on its own (t = k H) (compare.py);
(c) CPU: per scene at one H, the CPU seconds per simulated second of each tool (sampling the
    body from Python after every step, and stepping natively with no samples) and of our
    master's methods, measured round-robin, --repeat times, in this one process (each sample
    the CPU of back-to-back runs adding up to MIN_CPU); the table gives medians as ratios to our
    jacobi (and its own figure, for scale).

Writes out/ssp_errors.csv, out/ssp_cpu.csv and prints the three tables as markdown.
Usage (from the repository root, after ./scripts/run):
  .venv/bin/python scripts/ssp_tables.py [--steps 1e-2,1e-3,1e-4] [--cpu-step 1e-3]
                                         [--repeat 5] [--scenes belt,bounce,...]
"""
from __future__ import annotations

import argparse
import csv
import math
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from cosim import master  # noqa: E402
from cosim.connectors import REPO  # noqa: E402
from sspkit import cli, compare, systems, tools  # noqa: E402

METHODS = ("jacobi", "zoh", "linear_path_ev", "implicit_path_ev", "linear_exact_ev")
CPU_METHODS = ("jacobi", "zoh", "linear_path_ev")
MIN_CPU = 0.2              # s of stepping CPU per CPU sample
TOOL_RUNS = {"libcosim": ("libcosim", False), "libcosim native": ("libcosim", True),
             "ecos": ("ecos", False), "ecos native": ("ecos", True)}


def error_of(scene, res):
    if res.failed is not None:
        return math.nan
    return float(scene.measure(res)["error"])


def fmt(x, digits=2):
    return "–" if x is None or not math.isfinite(x) else f"{x:.{digits}g}" if x >= 1e-3 else f"{x:.{digits}e}"


def errors(names, steps):
    """Rows (scene, H, method, error, diff_grid, diff_own) for tables (a) and (b)."""
    rows = []
    for name in names:
        path, s = cli.packaged(name, systems.HELD)        # the held-input archive: our jacobi
        scene = s.scene
        for H in steps:
            own = {}
            for method in METHODS:
                t0 = time.time()
                try:
                    res = master.simulate(scene, method, H, record=scene.record)
                except Exception as e:  # noqa: BLE001  (a method that cannot run is a row)
                    res = master.Result(failed=str(e))
                own[method] = res
                rows.append((name, H, method, error_of(scene, res), None, None))
                print(f"  {name} H={H:g} {method}: {fmt(rows[-1][3])} ({time.time() - t0:.1f} s)",
                      file=sys.stderr)
            for tool in tools.TOOLS:
                res = tools.run(tool, path, s, H)
                grid = compare.master_as_tool(scene, "jacobi", tool, H)
                ok = res.failed is None and own["jacobi"].failed is None
                rows.append((name, H, tool, error_of(scene, res),
                             compare.difference(res, grid) if res.failed is None else math.nan,
                             compare.difference(res, own["jacobi"]) if ok else math.nan))
                print(f"  {name} H={H:g} {tool}: {fmt(rows[-1][3])}", file=sys.stderr)
    return rows


def per_simulated_second(run, t_end):
    """CPU seconds of the stepping loop per simulated second, over as many back-to-back runs as
    make MIN_CPU of it (a short scene's 100 steps take a few ms: one run alone is noise)."""
    cpu = simulated = 0.0
    while cpu < MIN_CPU:
        cpu += run().cpu
        simulated += t_end
    return cpu / simulated


def cpu(names, H, repeat):
    """{(scene, runner): [CPU s per simulated s, ...]}, the runners taken in turn each round."""
    out = {}
    for r in range(repeat):
        for name in names:
            path, s = cli.packaged(name, systems.HELD)    # the held-input archive: our jacobi
            scene = s.scene
            runs = {m: (lambda m=m: master.simulate(scene, m, H)) for m in CPU_METHODS}
            runs.update({label: (lambda t=tool, nat=native: tools.run(t, path, s, H, native=nat))
                         for label, (tool, native) in TOOL_RUNS.items()})
            for label, run in runs.items():
                out.setdefault((name, label), []).append(per_simulated_second(run, scene.t_end))
        print(f"  CPU round {r + 1}/{repeat} done", file=sys.stderr)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--steps", default="1e-2,1e-3,1e-4")
    ap.add_argument("--cpu-step", type=float, default=1e-3)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--scenes", default=",".join(systems.NAMES))
    ap.add_argument("--out", type=Path, default=REPO / "out")
    args = ap.parse_args(argv)
    names = args.scenes.split(",")
    steps = [float(x) for x in args.steps.split(",")]
    args.out.mkdir(parents=True, exist_ok=True)

    rows = errors(names, steps)
    with open(args.out / "ssp_errors.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["scene", "H", "method", "error", "diff_tool_grid", "diff_own_grid"])
        w.writerows(rows)
    err = {(n, H, m): e for n, H, m, e, *_ in rows}
    cols = list(tools.TOOLS) + list(METHODS)
    print("\n(a) error against the scene's reference\n")
    print("| scene | H | " + " | ".join(cols) + " |")
    print("|---|---|" + "---|" * len(cols))
    for n in names:
        for H in steps:
            print(f"| {n} | {H * 1e3:g} ms | " + " | ".join(fmt(err[(n, H, c)]) for c in cols) + " |")
    print("\n(b) max relative difference to our jacobi: on the tool's time grid / on its own\n")
    print("| scene | H | libcosim | Ecos |\n|---|---|---|---|")
    diff = {(n, H, m): (g, o) for n, H, m, _, g, o in rows if m in tools.TOOLS}
    for n in names:
        for H in steps:
            cells = [" / ".join(fmt(x, 2) for x in diff[(n, H, t)]) for t in tools.TOOLS]
            print(f"| {n} | {H * 1e3:g} ms | " + " | ".join(cells) + " |")

    times = cpu(names, args.cpu_step, args.repeat)
    with open(args.out / "ssp_cpu.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["scene", "H", "runner", "repeat", "cpu_per_simulated_s"])
        for (n, label), xs in times.items():
            w.writerows((n, args.cpu_step, label, i, x) for i, x in enumerate(xs))
    labels = list(CPU_METHODS) + list(TOOL_RUNS)
    print(f"\n(c) CPU per simulated second at H = {args.cpu_step * 1e3:g} ms, median of "
          f"{args.repeat}, as a ratio to our jacobi\n")
    print("| scene | jacobi (s/s) | " + " | ".join(labels[1:]) + " |")
    print("|---|---|" + "---|" * (len(labels) - 1))
    for n in names:
        base = statistics.median(times[(n, "jacobi")])
        cells = [f"{statistics.median(times[(n, lab)]) / base:.2f}" for lab in labels[1:]]
        print(f"| {n} | {base:.3g} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
