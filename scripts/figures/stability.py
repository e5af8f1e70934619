"""The stability map (scene 7) from out/stability_map.csv: left, the largest stable ωH per method
against the damping ratio ζ (markers measured through the FMU, side by side where methods share a
value; lines the closed forms); right, the spectral radius of the one-step map at ζ = 0 against
ωH. "Never stable" and "stable to the top of the search" are bands of their own, so that a
method's limit is never hidden under another's; the legend lies outside the axes.

Uses matplotlib and this package (data.read_stability, style, legible). A caller may pass
closed-form functions (bound(method, ζ), rho(method, ωH)) to draw the closed forms as smooth
curves; without them the lines join the closed-form values in the CSV.
"""
from __future__ import annotations

import math

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from matplotlib.transforms import ScaledTranslation  # noqa: E402

from . import data, legible  # noqa: E402
from .style import FAMILIES, FAMILY_ORDER, Styles  # noqa: E402

NEVER = "#fbe3e0"
TOP = "#e3f1e3"
DODGE = 4.0         # points between the markers of methods that share a value


def _bands(ax, floor, ceil, lo, hi):
    ax.axhspan(lo, floor * 1.6, color=NEVER, zorder=0, lw=0)
    ax.axhspan(ceil / 1.6, hi, color=TOP, zorder=0, lw=0)


def figure(stab: data.Stability, labels=None, styles=None, bound=None, rho=None, title=None):
    labels = labels or {}          # method -> its legend entry (default: the method's name)
    methods = list(dict.fromkeys([r["method"] for r in stab.limits] + [r["method"] for r in stab.rhos]))
    styles = styles or Styles(methods)
    order = [b for b in styles.bases() if b in methods] + [m for m in methods if m not in styles.looks]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13.6, 5.4), layout="constrained")
    measured = [r["measured"] for r in stab.limits if math.isfinite(r["measured"]) and r["measured"] > 0]
    ceil = max(measured) if measured else 1e3
    floor = min(measured + [1e-3]) / 3
    zetas = sorted({r["zeta"] for r in stab.limits if math.isfinite(r["zeta"])})
    zmax = max(zetas) if zetas else 2.0
    def shown(v):
        return floor if not v > 0 else min(v, ceil)

    groups: dict = {}          # (ζ, value) -> the methods with that value, in legend order
    for method in order:
        for r in stab.limits:
            if r["method"] == method:
                groups.setdefault((r["zeta"], round(math.log10(shown(r["measured"])), 2)), []).append(method)
    for method in order:
        look = styles.look(method)
        rs = sorted((r for r in stab.limits if r["method"] == method), key=lambda r: r["zeta"])
        if not rs:
            continue
        by_shift: dict = {}
        for r in rs:
            g = groups[(r["zeta"], round(math.log10(shown(r["measured"])), 2))]
            by_shift.setdefault(g.index(method) - (len(g) - 1) / 2, []).append(r)
        for k, pts in by_shift.items():
            shift = ScaledTranslation(k * DODGE / 72, 0, fig.dpi_scale_trans)
            ax.plot([r["zeta"] for r in pts], [shown(r["measured"]) for r in pts], ls="none",
                    marker=look.marker, ms=6.5, color=look.color, transform=ax.transData + shift, zorder=3)
        z = np.array([r["zeta"] for r in rs])
        zf, cf = z, np.array([r["closed_form"] for r in rs])
        if bound is not None and not np.all(cf[np.isfinite(cf)] >= ceil):   # smooth where it shows
            zf = np.unique(np.concatenate(([0.0], z, np.geomspace(1e-3, zmax, 40))))
            cf = np.array([bound(method, zz) for zz in zf])
        ok = np.isfinite(cf)
        if ok.any() and not np.all(cf[ok] >= ceil):
            ax.plot(zf[ok], np.clip(np.where(cf[ok] <= 0, floor, cf[ok]), floor, ceil), color=look.color,
                    lw=1.2, ls=look.ls, zorder=2)
    ax.set_xscale("symlog", linthresh=0.01, linscale=0.6)
    ax.set_yscale("log")
    lo, hi = floor / 2.2, ceil * 2.6
    ax.set_ylim(lo, hi)
    _bands(ax, floor, ceil, lo, hi)
    ax.set_xlim(-0.002, zmax * 1.25)
    ax.set_xticks([z for z in (0, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2) if z <= zmax * 1.01])
    ax.set_xticklabels([f"{z:g}" for z in ax.get_xticks()])
    ax.set_xlabel("damping ratio ζ")
    ax.set_ylabel("largest stable ωH")
    ax.set_title("largest stable ωH against damping (markers: measured through the FMU;\n"
                 "lines: closed forms; methods sharing a value stand side by side)", fontsize=9.5)
    ax.grid(True, which="major", alpha=0.35)

    rho_groups: dict = {}      # (ωH, ρ) -> the methods with that measured radius, in legend order
    for method in order:
        for r in stab.rhos:
            if r["method"] == method and math.isfinite(r["measured"]) and r["measured"] > 0:
                rho_groups.setdefault((r["omegaH"], round(math.log10(r["measured"]), 3)), []).append(method)
    for method in order:
        look = styles.look(method)
        rs = sorted((r for r in stab.rhos if r["method"] == method), key=lambda r: r["omegaH"])
        if not rs:
            continue
        x = np.array([r["omegaH"] for r in rs])
        y = np.array([r["measured"] for r in rs])
        fin = np.isfinite(y) & (y > 0)
        by_shift: dict = {}
        for xi, yi in zip(x[fin], y[fin]):
            g = rho_groups[(xi, round(math.log10(yi), 3))]
            by_shift.setdefault(g.index(method) - (len(g) - 1) / 2, []).append((xi, yi))
        for k, pts in by_shift.items():
            shift = ScaledTranslation(k * DODGE / 72, 0, fig.dpi_scale_trans)
            bx.plot([p[0] for p in pts], [p[1] for p in pts], ls="none", marker=look.marker, ms=5.5,
                    color=look.color, zorder=3, transform=bx.transData + shift)
        if (~fin).any():
            bx.plot(x[~fin], np.full((~fin).sum(), 45.0), ls="none", marker="x", ms=6, mew=1.5,
                    color=look.color, zorder=3)
        if rho is not None:
            hh = np.geomspace(x.min(), x.max(), 160)
            try:
                cr = np.array([rho(method, h) for h in hh])
            except ValueError:          # a method without a closed form: its markers only
                continue
        else:
            hh, cr = x, np.array([r["closed_form"] for r in rs])
        bx.plot(hh, np.where(np.isfinite(cr), cr, np.nan), color=look.color, lw=1.1, ls=look.ls, zorder=2)
    bx.axhspan(30, 70, color=NEVER, zorder=0, lw=0)
    bx.axhline(1.0, color="k", lw=0.8)
    bx.set_xscale("log")
    bx.set_yscale("log")
    bx.set_ylim(0.05, 70)
    bx.set_xlabel("ωH")
    bx.set_ylabel("spectral radius of the one-step map")
    bx.set_title("ζ = 0: spectral radius (markers: measured; lines: closed form;\n"
                 "above 1 the coupling is unstable)", fontsize=9.5)
    bx.grid(True, which="major", alpha=0.35)

    handles, texts = [], []
    blank = Patch(visible=False)
    for fam in FAMILY_ORDER:
        members = [m for m in order if styles.look(m).family == fam]
        if members:
            handles.append(blank)
            texts.append(FAMILIES[fam][0])
            for m in members:
                look = styles.look(m)
                handles.append(Line2D([], [], color=look.color, ls=look.ls, marker=look.marker, ms=6))
                texts.append(labels.get(m, m))
    handles += [blank, Patch(facecolor=NEVER, edgecolor="0.6"), Patch(facecolor=TOP, edgecolor="0.6"),
                Line2D([], [], ls="none", marker="x", color="0.3", mew=1.5)]
    texts += ["how to read", "band: unstable at every ωH", f"band: stable to ωH = {ceil:g},\nthe top of the search",
              "×: the iteration did not converge"]
    lg = fig.legend(handles, texts, loc="outside right upper", fontsize=8, frameon=False)
    for t in lg.get_texts():
        if t.get_text() in [FAMILIES[f][0] for f in FAMILIES] + ["how to read"]:
            t.set_fontweight("bold")
    fig.suptitle(title or "§7 co-simulation stability: mass on the connector's spring-damper", fontsize=10.5)
    placer = legible.Placer(fig, legible.freeze(fig))
    tr = ax.get_yaxis_transform()
    placer.place(ax, (0.99, math.sqrt(lo * floor * 1.6)), "unstable at every ωH", color="#b2182b",
                 offsets=((-1, 0),), gap=1, transform=tr, fontsize=7.5)
    placer.place(ax, (0.99, math.sqrt(hi * ceil / 1.6)), f"stable to ωH = {ceil:g} (top of the search)",
                 color="#1b7837", offsets=((-1, 0),), gap=1, transform=tr, fontsize=7.5)
    placer.place(bx, (0.02, 45.0), "× did not converge", color="#b2182b", offsets=((1, 0),), gap=1,
                 transform=bx.get_yaxis_transform(), fontsize=7.5)
    return fig


def draw(csv_path, png_path, labels=None, styles=None, bound=None, rho=None, dpi=100, max_bytes=None):
    """Read stability_map.csv, draw, write the PNG; returns (bytes, problems)."""
    fig = figure(data.read_stability(csv_path), labels, styles, bound, rho)
    found = legible.problems(fig)
    size = legible.save_png(fig, png_path, dpi=dpi, max_bytes=max_bytes)
    plt.close(fig)
    return size, found
