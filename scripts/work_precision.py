#!/usr/bin/env python3
"""Work-precision charts: for each scene of scripts/cosim/scenes.py and each coupling method of
scripts/cosim/master.py, sweep the macro step H, measure the error against the scene's reference
and the CPU time of the stepping loop (time.process_time; FMU set-up and monitoring excluded),
and write out/wp_<scene>.csv (every run) and out/wp_<scene>.png (error against CPU time, one
curve per method, points labelled by H).

    .venv/bin/python scripts/work_precision.py [--out out] [--quick] [scene ...]

Scenes: belt, puck0, puck1, bounce, bushing_freq, bushing_energy (default: all).
--quick drops the smallest steps (for a smoke run).
"""
from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from cosim.master import LABELS, METHODS, simulate  # noqa: E402
from cosim.scenes import SCENES  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
STYLE = {"zoh": ("C3", "o"), "extrapolation": ("C1", "s"), "linear_implicit": ("C0", "D"),
         "rollback": ("C2", "^")}
FIXED = ["scene", "method", "H", "steps", "cpu_s", "us_per_step", "fmi_calls", "rollback_passes",
         "failed", "error", "error2"]


def fmt_h(H):
    m, e = f"{H:.0e}".split("e")
    return f"{m}e{int(e)}"


def sweep(scene, quick=False, log=print):
    Hs = scene.sweep[:-2] if quick else scene.sweep
    rows = []
    for method in METHODS:
        for H in Hs:
            res = simulate(scene, method, H, record=scene.record)
            fig = scene.measure(res)
            row = {"scene": scene.name, "method": method, "H": H, "steps": res.steps,
                   "cpu_s": res.cpu, "us_per_step": 1e6 * res.cpu / max(res.steps, 1),
                   "fmi_calls": res.calls, "rollback_passes": res.iterations,
                   "failed": res.failed or "", "error": fig.get("error", np.nan),
                   "error2": fig.get("error2", np.nan)}
            row.update({k: v for k, v in fig.items() if k not in row})
            rows.append(row)
            err = row["error"]
            log(f"  {scene.name:15s} {method:16s} H={H:<8g} cpu={res.cpu:7.3f}s "
                f"error={err:.3e}" + (f"  FAILED {res.failed}" if res.failed else ""))
    return rows


def write_csv(rows, path):
    keys = FIXED + sorted({k for r in rows for k in r} - set(FIXED))
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.9g}" if isinstance(v, (float, np.floating)) else v)
                        for k, v in ((k, r.get(k, "")) for k in keys)})


def plot(scene, rows, path):
    panels = [("error", scene.error_label)]
    if scene.error2_label and any(np.isfinite(r["error2"]) for r in rows):
        panels.append(("error2", scene.error2_label))
    fig, axes = plt.subplots(1, len(panels), figsize=(7.5 * len(panels), 6.0), squeeze=False)
    notes = []
    for ax, (key, label) in zip(axes[0], panels):
        for method in METHODS:
            rs = [r for r in rows if r["method"] == method]
            ok = [r for r in rs if not r["failed"] and np.isfinite(r[key]) and r[key] > 0]
            color, marker = STYLE[method]
            if ok:
                x = [r["cpu_s"] for r in ok]
                y = [r[key] for r in ok]
                name = LABELS[method] + (f", θ = {scene.theta:g}" if method == "linear_implicit" else "")
                ax.loglog(x, y, color=color, marker=marker, ms=5, lw=1.5, label=name)
                for r, xi, yi in zip(ok, x, y):
                    ax.annotate(fmt_h(r["H"]), (xi, yi), textcoords="offset points", xytext=(4, 3),
                                fontsize=6.5, color=color)
            else:
                ax.plot([], [], color=color, marker=marker, label=LABELS[method] + " (no result)")
            bad = [r for r in rs if r["failed"] or not np.isfinite(r[key])]
            if bad and key == "error":
                notes.append(f"{method}: no result at H = " + ", ".join(fmt_h(r["H"]) for r in bad))
        ax.set_xlabel("CPU time of the run [s]")
        ax.set_ylabel("relative error")
        ax.set_title(label, fontsize=9)
        ax.grid(True, which="both", alpha=0.25)
        ax.legend(fontsize=8, loc="best")
    fig.suptitle(f"Work-precision, {scene.title}\nt_end = {scene.t_end:g} s; "
                 f"points labelled by the macro step H [s]", fontsize=11)
    if notes:
        fig.text(0.01, 0.01, "\n".join(notes), fontsize=7, va="bottom", color="0.3")
    fig.tight_layout(rect=(0, 0.02 + 0.022 * len(notes), 1, 0.93))
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*", default=list(SCENES))
    ap.add_argument("--out", default=str(REPO / "out"))
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for name in args.scenes:
        scene = SCENES[name]
        print(f"==> {name}: {scene.title}")
        fine = scene.prepare()
        if fine:
            print(f"  fine reference {scene.fine}: " + ", ".join(
                f"{k} = {v:.6g}" for k, v in fine.items() if isinstance(v, float) and math.isfinite(v)))
        rows = sweep(scene, args.quick)
        write_csv(rows, out / f"wp_{name}.csv")
        plot(scene, rows, out / f"wp_{name}.png")
        print(f"  wrote {out / f'wp_{name}.csv'} and .png")


if __name__ == "__main__":
    main()
