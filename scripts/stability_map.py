#!/usr/bin/env python3
"""Stability map for docs/cosim.md, scene 7: a master-owned mass on the connector's spring k and damper c
(RadialThrust, axial component; ω = sqrt(k/m), ζ = c/(2 m ω)). For each coupling method and
damping ratio ζ, the one-macro-step map is measured through the FMU (scenes.OneStepMap) and the
largest stable ωH (spectral radius <= 1 + 1e-9) is found on a log grid of ωH in [1e-3, 1e3]
refined by bisection to 1e-4 relative. Set beside the closed forms: zero-order hold
ωH < min(4ζ, 1/ζ) (never stable at ζ = 0, ρ = sqrt(1 + (ωH)²/2)); rollback converges for
ωH²/6 + ζ ωH < 1 (ωH < √6 ≈ 2.449 at ζ = 0); linear-implicit unconditionally stable;
extrapolation from its closed-form amplification matrix (scenes.amplification).

    .venv/bin/python scripts/stability_map.py [--out out] [--serial | --scheduler ADDR] [--workers N]

One task per (method, ζ) through the sweep engine (scripts/cosim/sweep.py, docs/sweeps.md): by
default on a local Dask cluster, --serial in this process.

Writes out/stability_map.csv (largest stable ωH per method and ζ, measured and closed form;
and the spectral radius against ωH at ζ = 0) and out/stability_map.png (drawn from the CSV by
scripts/figures).
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
from cosim.master import METHODS  # noqa: E402

# the event-located methods whose one-step map does not depend on the FMU's extrapolation history
# (they integrate the body from trial evaluations and directional derivatives only)
# (jacobi carries the load of the previous step as state: its one-step map is not a map of
# (x, v) alone, so it is not charted here; it is zoh with one more step of lag)
MAP_METHODS = [m for m in METHODS if m != "jacobi"] + ["linear_path_ev", "implicit_path_ev",
                                                       "linear_exact_ev"]
from cosim.scenes import Oscillator, amplification, bound_closed_form, spectral_radius  # noqa: E402

REPO = Path(__file__).resolve().parents[1]
ZETAS = [0.0, 0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 2.0]
H_LO, H_HI = 1e-3, 1e3
TOL = 1e-9
RHO_H = np.geomspace(1e-2, 1e2, 25)


def tasks():
    """One task per method and ζ: the largest stable ωH (log grid on [H_LO, H_HI] refined by
    bisection, stable = spectral radius <= 1 + TOL), at ζ = 0 also the spectral radius at RHO_H
    (with the same probe)."""
    variant = Oscillator.variant
    sha = engine.fmu_ref(variant)["sha256"]
    return [engine.make_task("stability", "oscillator", method, None, variant=variant, fmu_sha=sha,
                             cost=2e4, zeta=zeta, h_lo=H_LO, h_hi=H_HI, tol=TOL,
                             rho_at=[float(h) for h in RHO_H] if zeta == 0.0 else [])
            for method in MAP_METHODS for zeta in ZETAS]


def log_line(task, r):
    s, fig = task["spec"], r.get("figures") or {}
    if r["status"] != "ok":
        return f"  {s['method']:16s} zeta={s['zeta']:<5g} FAILED {r['message']}"
    return (f"  {s['method']:16s} zeta={s['zeta']:<5g} largest stable wH = "
            f"{fig['largest_stable_omegaH']:.6g}  (closed form {bound_closed_form(s['method'], s['zeta']):.6g})")


def limits_and_rhos(tasks_, results):
    limits, rhos = [], []
    for t, r in zip(tasks_, results):
        s = t["spec"]
        if r["status"] != "ok":
            raise SystemExit(f"error: stability map, {s['method']} at zeta = {s['zeta']}: {r['message']}")
        method, zeta, fig = s["method"], s["zeta"], r["figures"]
        rhos += [{"method": method, "omegaH": h, "rho": rho, "rho_closed_form": closed_rho(method, h)}
                 for h, rho in zip(RHO_H, fig.get("rho", []))]
        limits.append({"method": method, "zeta": zeta,
                       "largest_stable_omegaH": fig["largest_stable_omegaH"],
                       "closed_form": bound_closed_form(method, zeta),
                       "evaluations": fig["evaluations"]})
    return limits, rhos


def closed_rho(method, h):
    """Closed-form spectral radius at ζ = 0 (for ZOH it is sqrt(1 + (ωH)²/2) up to ωH = 4, where
    the eigenvalues turn real and it grows faster)."""
    if method == "rollback" and h * h / 6 >= 1:
        return math.inf            # the iteration diverges
    return spectral_radius(amplification(method, h, 0.0))


def write_csv(limits, rhos, path):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["kind", "method", "zeta", "omegaH", "measured", "closed_form", "evaluations"])
        for r in limits:
            w.writerow(["largest_stable_omegaH", r["method"], r["zeta"], "",
                        f"{r['largest_stable_omegaH']:.6g}", f"{r['closed_form']:.6g}", r["evaluations"]])
        for r in rhos:
            w.writerow(["spectral_radius", r["method"], 0.0, f"{r['omegaH']:.6g}", f"{r['rho']:.12g}",
                        f"{r['rho_closed_form']:.12g}", ""])


def finish(tasks_, results, out, draw=True):
    limits, rhos = limits_and_rhos(tasks_, results)
    write_csv(limits, rhos, out / "stability_map.csv")
    print(f"  wrote {out / 'stability_map.csv'}")
    if draw:                      # out/stability_map.png from the CSV (scripts/figures)
        from figures import publish
        from figures.from_cosim import descriptions
        for path in publish(out, scenes=["stability"], report_page=False, **descriptions()):
            print(f"  wrote {path}")


def main(argv=None):
    from work_precision import add_engine_args, where
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default=str(REPO / "out"))
    add_engine_args(ap)
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print("==> stability map (§7)")
    ts = tasks()
    finish(ts, engine.execute(ts, where(args), log=log_line, workers=args.workers), out)


if __name__ == "__main__":
    main()
