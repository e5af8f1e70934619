"""One scene's figure: work-precision (error against CPU time) beside convergence (error against
the macro step H, with slope-1 and slope-2 guides and the H range the orders are fitted over),
and beside that the convergence against each further reference that tells something the first
does not (data.tells_more). The Pareto front (cheapest run for its error) is a band the eye finds
first, its points ringed; H labels are placed only where they cover nothing (front points first,
then decades); a strip above the convergence panels marks every run without a result at its H.
One colour per family, a marker per method, hollow = FMI 3.0; the legend lies outside the axes.

Uses matplotlib and this package only: data.py (the CSVs and SceneInfo), style.py, legible.py.
"""
from __future__ import annotations

import math
import textwrap

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

from . import data, legible  # noqa: E402
from .style import FAMILIES, FAMILY_ORDER, Styles, fmt_h, split  # noqa: E402

FRONT = "#ffc61a"           # the Pareto band
NO_RESULT = "#fbe3e0"       # the no-result strip
GUIDE = "0.35"


def _series(styles, methods):
    """Methods in legend order: by base method, FMI 2.0 before FMI 3.0."""
    order = {b: i for i, b in enumerate(styles.bases())}
    return sorted(methods, key=lambda m: (order.get(split(m)[0], 99), split(m)[1]))


def _draw(ax, styles, series, runs, x_of, column):
    """Each method's runs with a result: FMI 2.0 a line with filled markers, FMI 3.0 hollow markers."""
    for method in series:
        pts = sorted((r for r in runs if r.method == method and r.ok(column)), key=lambda r: -r.H)
        pts = [r for r in pts if math.isfinite(x_of(r)) and x_of(r) > 0]
        if not pts:
            continue
        look = styles.look(method)
        x, y = [x_of(r) for r in pts], [r.value(column) for r in pts]
        if split(method)[1] == 3:
            ax.plot(x, y, ls="none", marker=look.marker, ms=8.5, mfc="none", mec=look.color, mew=1.3,
                    zorder=3)
        else:
            ax.plot(x, y, ls=look.ls, lw=1.4, color=look.color, marker=look.marker, ms=5.5, zorder=3,
                    alpha=0.9)


def _axes_style(ax, xlabel, title):
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("relative error")
    ax.set_title(title, fontsize=9.5)
    ax.grid(True, which="major", alpha=0.35)
    ax.grid(True, which="minor", alpha=0.12)


def _front(ax, runs):
    front = data.pareto(runs)
    if front:
        x, y = [r.cpu for r in front], [r.value() for r in front]
        ax.plot(x, y, color=FRONT, lw=11, alpha=0.55, solid_capstyle="round", zorder=1)
        ax.plot(x, y, ls="none", marker="o", ms=12, mfc="none", mec="0.1", mew=1.0, zorder=4)
    return front


def _guides(ax, runs, column):
    """Slope-1 and slope-2 lines over a decade of H from the largest H, starting low enough that
    both stay inside the data's error range (widened downwards if it is narrower)."""
    pts = [r for r in runs if r.ok(column)]
    if not pts:
        return []
    h_hi = max(r.H for r in runs)
    lo, hi = min(r.value(column) for r in pts), max(r.value(column) for r in pts)
    span = 10.0
    y0 = min(hi, lo * span ** 2)
    h = [h_hi, h_hi / span]
    lines = []
    for p, ls in ((1, (0, (5, 3))), (2, (0, (1.5, 2)))):
        y = [y0, y0 / span ** p]
        ax.plot(h, y, color=GUIDE, lw=1.2, ls=ls, zorder=2)
        lines.append((f"slope {p}", (h[1], y[1])))
    ax.set_ylim(min(lo, y0 / span ** 2) / 2, max(hi, y0) * 2)
    return lines


def _strip(ax, styles, rows, runs, column):
    """The runs without a result, at their H: one row per base method (rows: legend order), the
    FMI 3.0 route as the hollow marker of the same row."""
    ax.set_facecolor(NO_RESULT)
    for i, base in enumerate(rows):
        look = styles.look(base)
        for version in (2, 3):
            hs = [r.H for r in runs if split(r.method) == (base, version) and not r.ok(column)]
            if hs and version == 2:
                ax.plot(hs, [i] * len(hs), ls="none", marker=look.marker, ms=5.5, color=look.color)
            elif hs:
                ax.plot(hs, [i] * len(hs), ls="none", marker=look.marker, ms=8.5, mfc="none",
                        mec=look.color, mew=1.3)
    ax.set_ylim(len(rows) - 0.45, -0.55)
    ax.set_yticks([])
    ax.tick_params(axis="x", which="both", labelbottom=False)
    ax.grid(True, axis="x", which="major", alpha=0.35)


def _legend_handles(info, styles, methods, orders, failing):
    handles, labels = [], []
    blank = Patch(visible=False)
    present = {split(m)[0] for m in methods}
    for fam in FAMILY_ORDER:
        bases = [b for b in styles.bases() if b in present and styles.look(b).family == fam]
        if not bases:
            continue
        handles.append(blank)
        labels.append(FAMILIES[fam][0])
        for base in bases:
            look = styles.look(base)
            only3 = all(split(m)[1] == 3 for m in methods if split(m)[0] == base)
            handles.append(Line2D([], [], color=look.color, ls="none" if only3 else look.ls,
                                  marker=look.marker, ms=6, mfc="none" if only3 else look.color))
            text = base + (f" (θ = {info.theta:g})" if info.theta is not None
                           and base.startswith("linear_implicit") else "")
            o = orders.get((info.name, base), (None,))[0]
            labels.append(text + (f"   order {abs(o) if round(o, 2) == 0 else o:.2f}" if o is not None
                                  else "   order –"))
    keys = [(blank, "how to read")]
    if any(split(m)[1] == 3 for m in methods):
        keys.append((Line2D([], [], ls="none", marker="o", ms=8, mfc="none", mec="0.2", mew=1.3),
                     "hollow: same method, FMI 3.0"))
    keys.append((Line2D([], [], color=FRONT, lw=9, alpha=0.6, marker="o", ms=10, mfc="none", mec="0.1"),
                 "Pareto front: cheapest for its error"))
    if failing:
        keys.append((Patch(facecolor=NO_RESULT, edgecolor="0.6"), "strip: no result at that H"))
    keys += [(Line2D([], [], color=GUIDE, ls=(0, (5, 3))), "slope 1 (first order)"),
             (Line2D([], [], color=GUIDE, ls=(0, (1.5, 2))), "slope 2 (second order)")]
    return handles + [h for h, _ in keys], labels + [t for _, t in keys]


ROW = 0.15         # in: one row of the no-result strip
PANEL = (4.6, 4.1)  # in: one convergence panel (the work-precision panel is 10 % wider)
LEGEND = 2.7       # in: the legend column


def figure(info: data.SceneInfo, runs, orders=None, styles=None):
    """The scene's figure (a matplotlib Figure, laid out and labelled)."""
    orders = orders or {}
    methods = data.methods(runs)
    styles = styles or Styles(methods)
    series = _series(styles, methods)
    columns, notes = [("error", "convergence: error against H")], []
    for column, label in info.second:
        more, why = data.tells_more(runs, column)
        if more:
            columns.append((column, textwrap.fill("convergence, error " + label.replace("\n", " "), 58)))
        elif any(r.ok(column) for r in runs):
            notes.append(f"{column} ({textwrap.shorten(label.replace(chr(10), ' '), 60, placeholder=' …')}): {why}")
    bases = list(dict.fromkeys(split(m)[0] for m in series))
    failing = [b for b in bases if any(split(r.method)[0] == b and not r.ok(c)
                                       for r in runs for c, _ in columns)]
    strip = ROW * len(failing) + 0.1 if failing else 0.0
    fig = plt.figure(figsize=(PANEL[0] * (1.1 + len(columns)) + LEGEND, PANEL[1] + strip + 1.5),
                     layout="constrained")
    gs = fig.add_gridspec(2, 1 + len(columns), height_ratios=[max(strip, 0.01), PANEL[1]],
                          width_ratios=[1.1] + [1] * len(columns))
    wp = fig.add_subplot(gs[1, 0])
    _draw(wp, styles, series, runs, lambda r: r.cpu, "error")
    _axes_style(wp, "CPU time of the run [s]", "work-precision: error against CPU time")
    front = _front(wp, runs)
    rng = data.order_range(orders, info.name)
    conv = []
    for j, (column, title) in enumerate(columns, start=1):
        ax = fig.add_subplot(gs[1, j])
        _draw(ax, styles, series, runs, lambda r: r.H, column)
        _axes_style(ax, "macro step H [s]   (finer →)", "" if failing else title)
        ax.invert_xaxis()
        if failing:
            st = fig.add_subplot(gs[0, j], sharex=ax)
            _strip(st, styles, failing, runs, column)
            st.set_title(title, fontsize=9.5)
        if rng:
            ax.axvspan(rng[0], rng[1], color="0.92", zorder=0, lw=0)
        conv.append((ax, _guides(ax, runs, column)))
    key = None
    if failing:
        key = fig.add_subplot(gs[0, 0])
        key.set_axis_off()
        key.set_ylim(len(failing) - 0.45, -0.55)
    handles, labels = _legend_handles(info, styles, methods, orders, failing)
    lg = fig.legend(handles, labels, loc="outside right upper", fontsize=8, frameon=False,
                    handlelength=2.6, borderaxespad=0.2)
    heads = [FAMILIES[f][0] for f in FAMILIES] + ["how to read"]
    for t in lg.get_texts():
        if t.get_text() in heads:
            t.set_fontweight("bold")
    # the title is centred over the panels and wrapped to their width, so that it never reaches
    # into the legend's column however tall the legend grows
    panels = PANEL[0] * (1.1 + len(columns))
    error = textwrap.shorten(info.error_label.replace("\n", " "), 120, placeholder=" …")
    fig.suptitle(f"{info.title or info.name}: accuracy against cost"
                 + (f", t_end = {info.t_end:g} s" if info.t_end else "") + "\n"
                 + textwrap.fill("error: " + error, int(panels * 11)),
                 x=0.5 * panels / fig.get_size_inches()[0], fontsize=10.5)
    if rng:
        notes.insert(0, f"order (legend): least-squares slope of log error against log H over the runs "
                        f"with a result, H = {fmt_h(rng[0])} – {fmt_h(rng[1])} (shaded); from wp_orders.csv")
    if notes:
        fig.supxlabel("\n".join(notes), x=0.01, ha="left", fontsize=7.5, color="0.3")
    placer = legible.Placer(fig, legible.freeze(fig))
    if key is not None:
        for i, base in enumerate(failing):
            key.text(1.0, i, base + "  no result at", ha="right", va="center", fontsize=7,
                     color=styles.look(base).color, transform=key.get_yaxis_transform())
    _labels(wp, placer, styles, runs, front)
    for ax, lines in conv:
        for text, end in lines:
            placer.place(ax, end, text, color=GUIDE, offsets=((1, 0), (1, -1), (-1, -1), (0, -1)),
                         fontsize=7.5, gap=3)
        if rng:
            placer.place(ax, (math.sqrt(rng[0] * rng[1]), 1.0), "orders fitted over this H range",
                         color="0.4", offsets=((0, -1),), gap=2, fontsize=7,
                         transform=ax.get_xaxis_transform())
    return fig


def _labels(ax, placer, styles, runs, front):
    """H labels on the work-precision panel: every point of the front, then the decades."""
    done = set()
    firsts = [r for r in front]
    decades = [r for r in runs if r.ok() and abs(math.log10(r.H) - round(math.log10(r.H))) < 1e-6
               and r not in front]
    decades.sort(key=lambda r: (split(r.method)[1], r.H))
    for r in firsts + decades:
        key = (split(r.method)[0], r.H)
        if key in done:
            continue
        ring = r in front
        if placer.place(ax, (r.cpu, r.value()), fmt_h(r.H), color=styles.look(r.method).color,
                        fontsize=7.5, gap=2.0, fontweight="bold" if ring else "normal"):
            done.add(key)


def draw(info, csv_path, png_path, orders_path=None, styles=None, dpi=100, max_bytes=None):
    """Read the scene's CSV (and the orders), draw, write the PNG; returns (bytes, problems)."""
    runs = data.read_runs(csv_path)
    orders = data.read_orders(orders_path) if orders_path else {}
    fig = figure(info, runs, orders, styles)
    found = legible.problems(fig)
    size = legible.save_png(fig, png_path, dpi=dpi, max_bytes=max_bytes)
    plt.close(fig)
    return size, found
