#!/usr/bin/env python3
"""Benchmark through fmpy (docs/benchmarks.md): cost per round set + doStep + get of the Bushing (every
behaviour on) and Planar (friction on) FMUs against the same calls on the empty FMU
(dist/bench/Empty.fmu: set/get store values, doStep does nothing), measured side by side.

The scenes (parameters and the periodic input path, h = 1 ms, 2000 steps per period) are the
"on" scenes of the native benchmark, read from out/bench_scenes.json (written by
`cargo bench --bench native`), so both benchmarks drive the FMUs identically.

Two ways of calling, the same for the connector FMU and for the empty FMU:
  ctypes  fmpy's FMI functions (FMU2Slave.fmi2SetReal / fmi2DoStep / fmi2GetReal) with
          ctypes arrays prepared once: the least Python per round, so the FMU's own cost is
          most visible (the target, ratio <= 1.10 since issue 15 (<= 1.15 before), is
          judged on this one);
  lists   fmpy's convenience API (setReal(list, list), doStep, getReal(list)), which builds
          the ctypes arrays on every call: what most fmpy scripts do.
Rounds per repeat N (default 5000), repeats R (default 25), repeats interleaved between the
connector FMU and its empty twin (short repeats, many of them: the median resists a busy
machine); the figure is the median ns per round.
Writes out/bench_fmpy.csv and prints a table.  Usage: bench_fmpy.py [N [R]]
"""
import ctypes
import gc
import json
import statistics
import sys
import time
from pathlib import Path

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave, fmi2True

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "out"
EMPTY_FMU = REPO / "dist" / "bench" / "Empty.fmu"
TARGET = 1.10  # issue 15 (1.15 before it)


class Driven:
    """One instantiated, initialized FMU with its inputs, outputs and the input path."""

    def __init__(self, fmu_path, inputs, outputs, params, path, h):
        md = read_model_description(str(fmu_path))
        self.name = md.coSimulation.modelIdentifier
        self.unzipdir = extract(str(fmu_path))
        vr = {v.name: v.valueReference for v in md.modelVariables}
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=self.unzipdir,
                             modelIdentifier=self.name, instanceName="bench")
        self.fmu.instantiate()
        if params:
            names = list(params)
            self.fmu.setReal([vr[n] for n in names], [float(params[n]) for n in names])
        self.vin_list = [vr[n] for n in inputs]
        self.vout_list = [vr[n] for n in outputs]
        self.n_in, self.n_out = len(self.vin_list), len(self.vout_list)
        self.vin = (ctypes.c_uint * self.n_in)(*self.vin_list)
        self.vout = (ctypes.c_uint * self.n_out)(*self.vout_list)
        self.out = (ctypes.c_double * self.n_out)()
        self.rows = [(ctypes.c_double * self.n_in)(*row) for row in path]
        self.lists = [list(map(float, row)) for row in path]
        self.h = h
        self.k = 0  # steps taken
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        self.fmu.setReal(self.vin_list, self.lists[0])
        self.fmu.exitInitializationMode()

    def run_ctypes(self, n):
        fmu, comp = self.fmu, self.fmu.component
        set_real, do_step, get_real = fmu.fmi2SetReal, fmu.fmi2DoStep, fmu.fmi2GetReal
        vin, vout, out, n_in, n_out = self.vin, self.vout, self.out, self.n_in, self.n_out
        rows, period, h, k0 = self.rows, len(self.rows), self.h, self.k
        t0 = time.perf_counter_ns()
        for k in range(k0, k0 + n):
            set_real(comp, vin, n_in, rows[k % period])
            do_step(comp, k * h, h, fmi2True)
            get_real(comp, vout, n_out, out)
        t1 = time.perf_counter_ns()
        self.k = k0 + n
        return (t1 - t0) / n

    def run_lists(self, n):
        fmu = self.fmu
        vin, vout = self.vin_list, self.vout_list
        rows, period, h, k0 = self.lists, len(self.lists), self.h, self.k
        t0 = time.perf_counter_ns()
        for k in range(k0, k0 + n):
            fmu.setReal(vin, rows[k % period])
            fmu.doStep(k * h, h)
            fmu.getReal(vout)
        t1 = time.perf_counter_ns()
        self.k = k0 + n
        return (t1 - t0) / n

    def close(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 5000
    repeats = int(sys.argv[2]) if len(sys.argv) > 2 else 25
    scenes_file = OUT / "bench_scenes.json"
    if not scenes_file.is_file():
        sys.exit(f"error: {scenes_file.relative_to(REPO)} is missing; run ./scripts/bench "
                 "(or cargo bench --bench native) first")
    if not EMPTY_FMU.is_file():
        sys.exit(f"error: {EMPTY_FMU.relative_to(REPO)} is missing; run ./scripts/bench")
    data = json.loads(scenes_file.read_text())
    h = data["h"]
    rows = []
    for scene in data["scenes"]:
        variant = scene["variant"]
        real = Driven(REPO / "dist" / f"{variant}.fmu", scene["inputs"], scene["outputs"],
                      scene["params"], scene["path"], h)
        n_in, n_out = len(scene["inputs"]), len(scene["outputs"])
        empty = Driven(EMPTY_FMU, [f"u[{i}]" for i in range(1, n_in + 1)],
                       [f"y[{i}]" for i in range(1, n_out + 1)], {}, scene["path"], h)
        for mode in ("ctypes", "lists"):
            run = {"ctypes": Driven.run_ctypes, "lists": Driven.run_lists}[mode]
            run(real, 2000), run(empty, 2000)  # warm-up
            t_real, t_empty = [], []
            gc.disable()
            try:
                for _ in range(repeats):
                    t_empty.append(run(empty, n))
                    t_real.append(run(real, n))
            finally:
                gc.enable()
            r, e = statistics.median(t_real), statistics.median(t_empty)
            rows.append(dict(variant=variant, behaviours="on", mode=mode, n_inputs=n_in,
                             n_outputs=n_out, ns_round_median=r, empty_ns_round_median=e,
                             ratio=r / e, fmu_own_ns=r - e, target_ratio=TARGET,
                             rounds=n, repeats=repeats))
        real.close()
        empty.close()

    cols = ["variant", "behaviours", "mode", "n_inputs", "n_outputs", "ns_round_median",
            "empty_ns_round_median", "ratio", "fmu_own_ns", "target_ratio", "rounds", "repeats"]
    OUT.mkdir(exist_ok=True)
    with open(OUT / "bench_fmpy.csv", "w") as f:
        f.write(",".join(cols) + "\n")
        for r in rows:
            f.write(",".join(f"{r[c]:.3f}" if isinstance(r[c], float) else str(r[c]) for c in cols) + "\n")
    print(f"fmpy benchmark (fmpy {__import__('fmpy').__version__}, Python "
          f"{sys.version.split()[0]}): round = set(inputs) + doStep + get(node loads), h = {h} s; "
          f"median of {repeats} x {n} rounds, repeats interleaved with the empty FMU")
    print(f"{'variant':<10} {'beh':>3} {'mode':>7} {'in/out':>6} {'ns_round':>10} {'empty_ns':>10} "
          f"{'ratio':>7} {'own_ns':>8}  target")
    for r in rows:
        verdict = "met" if r["ratio"] <= TARGET else "MISSED"
        target = f"<= {TARGET}x: {verdict}" if r["mode"] == "ctypes" else f"({verdict} at {TARGET}x)"
        print(f"{r['variant']:<10} {r['behaviours']:>3} {r['mode']:>7} {r['n_inputs']:>3}/{r['n_outputs']:<2} "
              f"{r['ns_round_median']:>10.0f} {r['empty_ns_round_median']:>10.0f} {r['ratio']:>7.3f} "
              f"{r['fmu_own_ns']:>8.0f}  {target}")
    print(f"wrote {(OUT / 'bench_fmpy.csv').relative_to(REPO)}")


if __name__ == "__main__":
    main()
