#!/usr/bin/env python3
"""Work-precision charts: for each scene of scripts/cosim/scenes.py and each coupling method of
scripts/cosim/master.py, sweep the macro step H, measure the error against the scene's reference
and the CPU time of the stepping loop (time.process_time; FMU set-up and monitoring excluded),
and write out/wp_<scene>.csv (every run) and out/wp_<scene>.png (drawn from the CSV by
scripts/figures: work-precision beside convergence).

    .venv/bin/python scripts/work_precision.py [--out out] [--quick] [--serial | --scheduler ADDR]
                                                [--workers N] [scene ...]

Scenes: belt, puck0, puck1, bounce, bushing_freq, bushing_energy (default: all).
--quick drops the smallest steps (for a smoke run).
The runs go through the sweep engine (scripts/cosim/sweep.py, docs/sweeps.md): by default on a
local Dask cluster (one worker process per core), --serial in this process one after another,
--scheduler tcp://HOST:PORT on a running cluster. The figures do not depend on where a run goes.
"""
from __future__ import annotations

import argparse
import csv
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import numpy as np  # noqa: E402

from cosim import sweep as engine  # noqa: E402
from cosim.master import EV_METHODS, FMI3_SUFFIX, METHODS, split_method  # noqa: E402
from cosim.scenes import SCENES  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
# scenes with events (stops, stick/slip): the event-located methods run there, at EV_SWEEP's steps
# (the scene's sweep from 10 ms to 0.1 ms), and through FMI 3.0 (early return) at FMI3_SWEEP
EVENT_SCENES = ("belt", "puck0", "bounce")
EV_SWEEP = {"belt": (1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4),
            "puck0": (1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4),
            "bounce": (1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4, 5e-5, 2e-5, 1e-5)}
FMI3_SWEEP = (1e-2, 1e-3, 1e-4)


def methods_of(scene, quick=False):
    """[(method, [H, ...])] of one scene's chart."""
    Hs = scene.sweep[:-2] if quick else scene.sweep
    out = [(m, Hs) for m in METHODS]
    if scene.name in EVENT_SCENES:
        ev = EV_SWEEP[scene.name][:-2] if quick else EV_SWEEP[scene.name]
        out += [(m, ev) for m in EV_METHODS]
        out += [(m + FMI3_SUFFIX, [H for H in FMI3_SWEEP if H in ev]) for m in EV_METHODS]
    return out
FIXED = ["scene", "method", "H", "steps", "cpu_s", "us_per_step", "fmi_calls", "calls_per_step",
         "rollback_passes", "events", "failed", "error", "error_rigid", "error2"]


def tasks(scene, quick=False):
    """The runs of one scene's chart (method outer, H inner), preceded by the scene's fine
    reference run when it has one (belt: error2); the runs wait for it."""
    sha = engine.fmu_ref(scene.variant)["sha256"]
    out, needs = [], None
    if getattr(scene, "fine", None):
        method, H = scene.fine
        out.append(engine.make_task("reference", scene.name, method, H, variant=scene.variant,
                                    fmu_sha=sha, cost=engine.run_cost(scene, method, H)))
        needs = out[0]["spec"]["key"]
    for method, Hs in methods_of(scene, quick):
        variant = scene.variant if split_method(method)[1] == 2 else f"fmi3/{scene.variant}"
        msha = sha if variant == scene.variant else engine.fmu_ref(variant)["sha256"]
        for H in Hs:
            out.append(engine.make_task("run", scene.name, method, H, variant=variant,
                                        fmu_sha=msha, needs=needs,
                                        cost=engine.run_cost(scene, method, H)))
    return out


def log_line(task, r):
    """The progress line of one finished task."""
    s, fig = task["spec"], r.get("figures") or {}
    if s["kind"] == "reference":
        return (f"  {s['scene']:15s} fine reference ({s['method']}, H = {s['H']:g}): " + ", ".join(
            f"{k} = {v:.6g}" for k, v in fig.items() if isinstance(v, float) and math.isfinite(v)))
    err = fig.get("error", np.nan)
    return (f"  {s['scene']:15s} {s['method']:16s} H={s['H']:<8g} cpu={r.get('cpu_s') or 0:7.3f}s "
            f"error={err:.3e}" + (f"  FAILED {r['message']}" if r["status"] != "ok" else ""))


def chart_rows(scene, tasks, results):
    """The chart's rows (the columns of wp_<scene>.csv) from the engine's rows."""
    rows = []
    for t, r in zip(tasks, results):
        s = t["spec"]
        if s["kind"] != "run":
            continue
        fig = r.get("figures") or {}
        steps = r.get("steps") or 0
        row = {"scene": scene.name, "method": s["method"], "H": s["H"], "steps": steps,
               "cpu_s": r.get("cpu_s", np.nan), "us_per_step": 1e6 * (r.get("cpu_s") or 0) / max(steps, 1),
               "fmi_calls": r.get("fmi_calls"),
               "calls_per_step": (r.get("fmi_calls") or 0) / max(steps, 1),
               "rollback_passes": r.get("rollback_passes"),
               "failed": r["message"] if r["status"] != "ok" else "",
               "error": fig.get("error", np.nan), "error_rigid": fig.get("error_rigid", np.nan),
               "error2": fig.get("error2", np.nan)}
        row.update({k: v for k, v in fig.items() if k not in row})
        rows.append(row)
    return rows


def write_csv(rows, path):
    keys = FIXED + sorted({k for r in rows for k in r} - set(FIXED))
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.9g}" if isinstance(v, (float, np.floating)) else v)
                        for k, v in ((k, r.get(k, "")) for k in keys)})


ORDER_RANGE = (1e-4, 2e-3)       # the H range of the convergence orders (s)


def convergence_orders(out, scenes=None):
    """Convergence order per scene and method from out/wp_<scene>.csv: the least-squares slope of
    log(error) against log(H) over the runs with a result and H in ORDER_RANGE (at least 3 of
    them, else blank). Written to out/wp_orders.csv and returned as rows."""
    rows = []
    for path in sorted(Path(out).glob("wp_*.csv")):
        name = path.stem[3:]
        if name == "orders" or (scenes and name not in scenes):
            continue
        with open(path) as f:
            data = list(csv.DictReader(f))
        for method in dict.fromkeys(r["method"] for r in data):
            pts = [(float(r["H"]), float(r["error"])) for r in data if r["method"] == method
                   and not r["failed"] and r["error"] not in ("", "nan")
                   and ORDER_RANGE[0] * 0.999 <= float(r["H"]) <= ORDER_RANGE[1] * 1.001
                   and math.isfinite(float(r["error"])) and float(r["error"]) > 0]
            order = ""
            if len(pts) >= 3:
                x = np.log([h for h, _ in pts])
                y = np.log([e for _, e in pts])
                order = f"{np.polyfit(x, y, 1)[0]:.2f}"
            rows.append({"scene": name, "method": method, "points": len(pts), "order": order,
                         "H_range": f"{ORDER_RANGE[0]:g}-{ORDER_RANGE[1]:g}"})
    with open(Path(out) / "wp_orders.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["scene", "method", "points", "order", "H_range"])
        w.writeheader()
        w.writerows(rows)
    return rows


def add_engine_args(ap):
    ap.add_argument("--serial", action="store_true",
                    help="run in this process, one after another (default: a local Dask cluster)")
    ap.add_argument("--scheduler", default="local", help="tcp://HOST:PORT of a running Dask scheduler")
    ap.add_argument("--workers", type=int, default=None,
                    help="worker processes of the local cluster (default: one per core)")


def where(args):
    return None if args.serial else args.scheduler


def finish(name, tasks_, results, out):
    scene = SCENES[name]
    rows = chart_rows(scene, tasks_, results)
    write_csv(rows, out / f"wp_{name}.csv")
    print(f"  wrote {out / f'wp_{name}.csv'}")


def draw(names, out):
    """out/wp_<scene>.png of the scenes `names`, from their CSVs and the orders (scripts/figures)."""
    from figures import publish
    from figures.from_cosim import descriptions
    for path in publish(out, scenes=list(names), report_page=False, **descriptions()):
        print(f"  wrote {path}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scenes", nargs="*", default=list(SCENES))
    ap.add_argument("--out", default=str(REPO / "out"))
    ap.add_argument("--quick", action="store_true")
    add_engine_args(ap)
    ap.add_argument("--orders-only", action="store_true",
                    help="only compute out/wp_orders.csv from the CSVs already in --out")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.orders_only:
        for r in convergence_orders(out):
            print(f"  {r['scene']:15s} {r['method']:26s} order {r['order'] or '-':>5s} ({r['points']} points)")
        return
    per_scene = {name: tasks(SCENES[name], args.quick) for name in args.scenes}
    for name in args.scenes:
        print(f"==> {name}: {SCENES[name].title}")
    every = [t for ts in per_scene.values() for t in ts]
    results = engine.execute(every, where(args), log=log_line, workers=args.workers)
    i = 0
    for name, ts in per_scene.items():
        finish(name, ts, results[i:i + len(ts)], out)
        i += len(ts)
    convergence_orders(out)
    print(f"  wrote {out / 'wp_orders.csv'}")
    draw(args.scenes, out)


if __name__ == "__main__":
    main()
