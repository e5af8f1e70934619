"""The native master's cost beside libcosim's and Ecos's on the project's SSP archives
(docs/benchmarks.md, "The native master"): CPU seconds per simulated second of fixed-step Jacobi at
H = 1 ms (every archive in dist/ssp; the systems of several bodies over their first 0.3 s), side by
side in one process, the runners taken in turn for 5 rounds, each sample the CPU
of back-to-back runs adding up to at least 0.2 s, the table the medians. Each figure times the
stepping loop only (not loading, instantiation, initialization):

  master     fmi_master (the bindings, in this process): every step, every output of every
             component read and kept in memory
  libcosim   libcosimpy stepping all N steps in one call, no samples (sspkit.tools, native=True)
  ecos       ecospy likewise

and, from a profiled master run (every FMI call timed), the master's own time per step (wall time
of the loop outside the FMUs' functions) against the time inside them.

    .venv/bin/python scripts/bench_master.py [--repeat 5] [--step 1e-3]

Uses fmi_master, numpy and sspkit (tools, systems).
"""
from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "scripts"))

import fmi_master  # noqa: E402
from sspkit import multibody, systems, tools  # noqa: E402

MIN_CPU = 0.2
# the systems of several bodies over their first 0.3 s: plain Jacobi is unstable on them at every
# H (docs/ssp.md), and the damped engine's Body refuses a step once the block tumbles (1.9 s)
MULTI_T_END = 0.3


def master_sample(system, H, t_end):
    cpu = sim = 0.0
    while cpu < MIN_CPU:
        run = system.run(step=H, stop=t_end)
        assert run.error is None, run.error
        cpu += run.cpu
        sim += run.end
    return cpu / sim


def tool_sample(tool, path, system, H, t_end):
    cpu = sim = 0.0
    while cpu < MIN_CPU:
        run = tools.run_multi if system.scene.name in multibody.NAMES else tools.run
        r = run(tool, path, system, H, t_end, native=True, check=False)
        assert r.failed is None, r.failed
        cpu += r.cpu
        sim += t_end
    return cpu / sim


def profile(system, H, t_end):
    """(master's own, in the FMUs) wall seconds per step, median of 5 profiled runs."""
    own, fmus = [], []
    for _ in range(5):
        run = system.run(step=H, stop=t_end, profile=True)
        own.append((run.wall - run.fmu_time) / run.steps)
        fmus.append(run.fmu_time / run.steps)
    return statistics.median(own), statistics.median(fmus)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--step", type=float, default=1e-3)
    a = ap.parse_args(argv)
    H = a.step
    print("| archive | master (s/s) | libcosim native (s/s) | Ecos native (s/s) | master / faster tool "
          "| master's own per step (µs) | in the FMUs per step (µs) |")
    print("|---|---|---|---|---|---|---|")
    for name in multibody.ALL:
        path = REPO / "dist" / "ssp" / f"{name}.ssp"
        system = multibody.system(name)
        t_end = MULTI_T_END if name in multibody.NAMES else system.scene.t_end
        native = fmi_master.open(path)
        samples = {"master": [], "libcosim": [], "ecos": []}
        for _ in range(a.repeat):
            samples["master"].append(master_sample(native, H, t_end))
            for tool in tools.TOOLS:
                samples[tool].append(tool_sample(tool, path, system, H, t_end))
        med = {k: statistics.median(v) for k, v in samples.items()}
        own, fmus = profile(native, H, t_end)
        ratio = med["master"] / min(med["libcosim"], med["ecos"])
        print(f"| {name} | {med['master']:.2e} | {med['libcosim']:.2e} | {med['ecos']:.2e} | {ratio:.2f} "
              f"| {own * 1e6:.2f} | {fmus * 1e6:.2f} |", flush=True)


if __name__ == "__main__":
    main()
