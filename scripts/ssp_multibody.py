#!/usr/bin/env python3
"""The measurements of docs/ssp.md and docs/cosim.md for the multi-body scenes (chain,
chain_damped, engine_mount, engine_mount_damped: scripts/sspkit/multibody.py), their held-input
archives (every connector at cosim.extrapolation = 0), in one run:

(a) per scene, tool (libcosim, Ecos) and H (10, 1, 0.1 ms): the error against the scene's
    reference (position, and the energy error of the undamped cases), whether the run is stable
    (it ran to the end, no step refused, error below 1), and the CPU seconds per simulated
    second of the stepping loop (one step() and one read of the sampled outputs from Python per
    step, as ./scripts/ssp does; the median of --repeat runs);
(b) per scene and H: the largest relative difference of libcosim's trajectory to Ecos's, each
    on its own time grid (sample k against sample k), over the whole run and up to the time the
    difference first exceeds 1e-9;
(c) the engine's references: the six linearised frequencies, the monolithic reference's
    convergence in rtol, its energy drift, and its difference to the linear response at full
    and at a hundredth of the amplitude; and the figure docs/img/engine_mount_modes.png (the
    response beside its modes).

Writes out/ssp_multibody.csv and prints the tables as markdown.
Usage (from the repository root, after ./scripts/run):
  .venv/bin/python scripts/ssp_multibody.py [--repeat 3] [--scenes chain,...] [--no-figure]
"""
from __future__ import annotations

import argparse
import csv
import math
import statistics
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from cosim.connectors import REPO  # noqa: E402
from sspkit import cli, engine_mount, engine_reference as ref, multibody, systems, tools  # noqa: E402

STEPS = (1e-2, 1e-3, 1e-4)
FIGURE = REPO / "docs" / "img" / "engine_mount_modes.png"


def fmt(x):
    if x is None or not math.isfinite(x):
        return "–"
    return f"{x:.2g}" if 1e-3 <= abs(x) < 1e4 else f"{x:.1e}"


def frozen_steps(run):
    """Steps after which no sampled output changed although the motion had not stopped: the
    Body refused the step (Ecos goes on after a refused step, its step() reports nothing)."""
    x = np.column_stack(list(run.samples.values()))
    moving = np.abs(x[:, -3:]).max(axis=1)[:-1] > 0
    return int(((x[1:] == x[:-1]).all(axis=1) & moving).sum())


def part(a, b):
    """(largest relative difference of a to b over the run, the time it first exceeds 1e-9)."""
    diffs = np.zeros(len(a.t))
    for n in a.samples:
        scale = max(np.abs(b[n]).max(), 1e-300)
        diffs = np.maximum(diffs, np.abs(a[n] - b[n]) / scale)
    over = np.nonzero(diffs > 1e-9)[0]
    return float(diffs.max()), (float(a.t[over[0]]) if len(over) else None)


def tables(names, repeat):
    rows, eq = [], []
    for name in names:
        path, system = cli.packaged(name, systems.HELD)   # the held-input archive (docs/ssp.md)
        scene = system.scene
        for H in STEPS:
            runs = {}
            for tool in tools.TOOLS:
                cpus = []
                for _ in range(repeat):
                    r = tools.run_multi(tool, path, system, H)
                    cpus.append(r.cpu / scene.t_end)
                runs[tool] = r
                m = scene.measure(r) if r.failed is None else {"error": math.nan, "energy": None}
                frozen = frozen_steps(r)
                rows.append({"scene": name, "H": H, "tool": tool, "error": m["error"],
                             "energy": m.get("energy"), "stable": r.failed is None and not frozen and m["error"] < 1,
                             "failed": r.failed or "", "stopped": r.t[-1] if r.failed else None,
                             "frozen": frozen, "cpu": statistics.median(cpus)})
                print(f"{name} {tool} H={H:g}: error {fmt(m['error'])}, energy {fmt(m.get('energy'))}, "
                      f"cpu {rows[-1]['cpu']:.3g} s/s {r.failed or ''}", flush=True)
            if runs["libcosim"].failed is None and runs["ecos"].failed is None:
                d, at = part(runs["libcosim"], runs["ecos"])
                eq.append({"scene": name, "H": H, "difference": d, "parts_at": at})
    return rows, eq


def engine_figures():
    geo = engine_mount.EngineMount
    w, _ = ref.modes(geo)
    t = np.linspace(0.0, geo.T_END, 2001)
    conv = ref.convergence(geo, 0, t)
    best = ref.monolithic(geo, 0)
    r, q, v, om = best.at(t)
    mounts = ref.Mounts(geo, 0)
    try:
        E = mounts.energy(r[::10], q[::10], v[::10], om[::10])
    finally:
        mounts.close()
    lin = []
    for scale in (1.0, 0.01):
        rr, qq, _, _ = (best if scale == 1.0 else ref.Monolithic(geo, 0, scale=scale)).at(t)
        z = ref.linear(geo, 0, t, scale)
        rot = ref.rotation_vector(qq)
        lin.append((scale, np.abs(rr - z[:, :3]).max() / np.abs(z[:, :3]).max(),
                    np.abs(rot - z[:, 3:6]).max() / np.abs(z[:, 3:6]).max(),
                    np.abs(rot).max(), np.abs(rr).max()))
    return {"omega": w, "convergence": conv, "energy": float(np.abs(E - E[0]).max() / E[0]),
            "evaluations": best.evaluations, "linear": lin}


def modal_frequencies(t, x, phi, M):
    """Each modal coordinate η_i = φ_iᵀ M x of the response x (rows of δr, δθ), and its
    frequency from its zero crossings (rad/s)."""
    eta = x @ (M @ phi)
    out = []
    for i in range(eta.shape[1]):
        s = np.signbit(eta[:, i])
        k = np.nonzero(s[1:] != s[:-1])[0]
        # times of the crossings by linear interpolation; half a period between neighbours
        tc = t[k] - eta[k, i] * (t[k + 1] - t[k]) / (eta[k + 1, i] - eta[k, i])
        out.append(math.pi * (len(tc) - 1) / (tc[-1] - tc[0]) if len(tc) > 2 else math.nan)
    return eta, np.array(out)


def figure(path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    geo = engine_mount.EngineMount
    w, phi = ref.modes(geo)
    M, _, _ = ref.matrices(geo, 0)
    t = np.linspace(0.0, geo.T_END, 8001)
    r, q, _, _ = ref.monolithic(geo, 0).at(t)
    rot = ref.rotation_vector(q)
    eta, measured = modal_frequencies(t, np.column_stack([r, rot]), phi, M)
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 5.2), gridspec_kw={"width_ratios": [1.2, 1]})
    for j, lab in enumerate(("x", "y", "z")):
        a.plot(t, 1e3 * r[:, j], lw=0.9, color=f"C{j}", label=f"r_{lab} (mm)")
    for j, lab in enumerate(("x", "y", "z")):
        a.plot(t, 1e3 * rot[:, j], lw=0.9, ls="--", color=f"C{j}", label=f"θ_{lab} (mrad)")
    a.set_xlabel("t (s)")
    a.set_ylabel("mm, mrad")
    a.set_title("response: the block's pose (monolithic reference, case 0)")
    a.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=6, fontsize=8, frameon=False)
    a.grid(alpha=0.3)
    show = t <= 0.5
    span = np.abs(eta[show]).max(axis=0)
    for i in range(6):
        b.plot(t[show], 2.0 * i + eta[show, i] / span[i] * 0.8, lw=0.9)
        b.text(0.505, 2.0 * i, f"mode {i + 1}: ω = {w[i]:.3f} rad/s\n(response: {measured[i]:.3f})",
               va="center", fontsize=8)
    b.set_xlim(0.0, 0.78)
    b.set_yticks([])
    b.set_xlabel("t (s)")
    b.set_title("its modal coordinates φᵢᵀ M (δr, δθ), each scaled")
    fig.suptitle("Engine block on four inclined Bushings: the response beside its six linearised modes")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return measured


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--scenes", default=",".join(multibody.NAMES))
    ap.add_argument("--no-figure", action="store_true")
    args = ap.parse_args(argv)
    names = [n for n in args.scenes.split(",") if n]
    if not args.no_figure:
        measured = figure(FIGURE)
        print(f"wrote {FIGURE.relative_to(REPO)}; modal frequencies of the response: "
              + ", ".join(f"{x:.3f}" for x in measured))
    if "engine_mount" in names:
        f = engine_figures()
        print("engine: ω =", ", ".join(f"{x:.3f}" for x in f["omega"]), "rad/s;",
              f"reference: {f['evaluations']} evaluations, energy drift {f['energy']:.2g}")
        for rtol, p, o, n in f["convergence"]:
            print(f"  rtol {rtol:g}: position {p:.2g}, rotation {o:.2g} from the 1e-10 run ({n} evaluations)")
        for scale, p, o, amax, rmax in f["linear"]:
            print(f"  amplitude ×{scale:g} (max rotation {amax:.3g} rad, translation {rmax:.3g} m): "
                  f"to the linear response position {p:.2g}, rotation {o:.2g}")
    if not names:
        return
    rows, eq = tables(names, args.repeat)
    out = REPO / "out" / "ssp_multibody.csv"
    out.parent.mkdir(exist_ok=True)
    with out.open("w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(rows[0]))
        wr.writeheader()
        wr.writerows(rows)
    def cell(r):
        if r["failed"]:
            return f"stopped at t = {r['stopped']:.3g} s (the Body refused a step)"
        extra = f" ({r['frozen']} refused steps run past)" if r["frozen"] else ""
        return fmt(r["error"]) + extra

    print("\n| scene | H | libcosim error | Ecos error | energy error (libcosim / Ecos) | stable | "
          "CPU s/s libcosim | CPU s/s Ecos |\n|---|---|---|---|---|---|---|---|")
    for name in names:
        for H in STEPS:
            lc, ec = (next(r for r in rows if r["scene"] == name and r["H"] == H and r["tool"] == t)
                      for t in tools.TOOLS)
            en = ("–" if lc["energy"] is None and ec["energy"] is None
                  else f"{fmt(lc['energy'])} / {fmt(ec['energy'])}")
            st = "yes" if lc["stable"] and ec["stable"] else "no"
            cpu = [("–" if r["failed"] else f"{r['cpu']:.3g}") for r in (lc, ec)]
            print(f"| {name} | {H * 1e3:g} ms | {cell(lc)} | {cell(ec)} | {en} | {st} | {cpu[0]} | {cpu[1]} |")
    print("\n| scene | H | libcosim vs Ecos, whole run | first above 1e-9 at |\n|---|---|---|---|")
    for e in eq:
        at = "never" if e["parts_at"] is None else f"t = {e['parts_at']:.3g} s"
        print(f"| {e['scene']} | {e['H'] * 1e3:g} ms | {e['difference']:.2g} | {at} |")


if __name__ == "__main__":
    main()
