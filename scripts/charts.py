#!/usr/bin/env python3
"""All the co-simulation charts in one pass of the sweep engine: the work-precision charts of
every scene (scripts/work_precision.py) and the §7 stability map (scripts/stability_map.py), their
tasks run together so that the workers stay busy until the last one. Then, from the CSVs
(scripts/figures): the figures into out/ and docs/img/ (with docs/img/commit.txt; not with
--quick), and the interactive out/report.html.

    .venv/bin/python scripts/charts.py [--out out] [--quick] [--serial | --scheduler ADDR] [--workers N]

Default: a local Dask cluster, one worker process per core; --serial runs every task in this
process, one after another; --scheduler tcp://HOST:PORT uses a running cluster (docs/sweeps.md).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import stability_map  # noqa: E402
import work_precision  # noqa: E402
from cosim import sweep as engine  # noqa: E402
from figures import publish  # noqa: E402
from figures.from_cosim import descriptions  # noqa: E402
from cosim.scenes import SCENES  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(work_precision.REPO / "out"))
    ap.add_argument("--quick", action="store_true", help="drop the two smallest steps of each scene")
    work_precision.add_engine_args(ap)
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    wp = {name: work_precision.tasks(SCENES[name], args.quick) for name in SCENES}
    sm = stability_map.tasks()
    every = [t for ts in wp.values() for t in ts] + sm
    where = "serially in this process" if args.serial else (
        "on a local Dask cluster" if args.scheduler == "local" else f"on {args.scheduler}")
    print(f"==> {len(every)} tasks (work-precision: {', '.join(wp)}; stability map) {where}",
          flush=True)

    def log(task, row):
        if task["spec"]["kind"] == "stability":
            return stability_map.log_line(task, row)
        return work_precision.log_line(task, row)

    t0 = time.monotonic()
    results = engine.execute(every, work_precision.where(args), log=log, workers=args.workers)
    print(f"==> tasks done in {time.monotonic() - t0:.1f} s (wall)", flush=True)
    i = 0
    for name, ts in wp.items():
        work_precision.finish(name, ts, results[i:i + len(ts)], out)
        i += len(ts)
    stability_map.finish(sm, results[i:], out, draw=False)
    work_precision.convergence_orders(out)
    print(f"  wrote {out / 'wp_orders.csv'} (convergence orders, H = 0.1-2 ms)")
    docs = None if args.quick else work_precision.REPO / "docs" / "img"    # a smoke run is no figure
    for path, size in publish(out, docs=docs, repo=work_precision.REPO, **descriptions()).items():
        print(f"  wrote {path} ({size / 1000:.0f} kB)")
    if docs is None:
        print("  (--quick: docs/img/ left as it is)")


if __name__ == "__main__":
    main()
