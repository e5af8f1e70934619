"""What the figures read: the CSVs written by scripts/work_precision.py and scripts/stability_map.py
(out/wp_<scene>.csv, out/wp_orders.csv, out/stability_map.csv), read tolerantly (unknown columns
kept, missing ones blank, methods whatever they are), the description of a scene a caller passes
(SceneInfo), and the choices made from the numbers alone: the Pareto front, the best run at an H,
within a CPU budget or for an error target, and whether a second reference tells anything new.

Uses the standard library and numpy only; imports nothing of scripts/cosim.
"""
from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path

from .style import split


@dataclass
class SceneInfo:
    """A scene as the figures need it. `second` lists further error columns (column, label) drawn
    beside `error` where they tell something it does not; `labels` maps a base method name to its
    long label (a method without one is shown by its name)."""
    name: str
    title: str = ""
    error_label: str = "error"
    t_end: float | None = None
    theta: float | None = None
    second: tuple = ()
    labels: dict = field(default_factory=dict)

    def label(self, method: str) -> str:
        base = split(method)[0]
        text = self.labels.get(base, base)
        if self.theta is not None and base.startswith("linear_implicit") and "θ" not in text:
            text += f", θ = {self.theta:g}"
        return text


def number(text) -> float:
    """A CSV cell as a float; blank or unreadable -> nan."""
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


@dataclass
class Run:
    """One row of wp_<scene>.csv."""
    method: str
    H: float
    cpu: float
    row: dict

    def value(self, column="error") -> float:
        return number(self.row.get(column))

    def ok(self, column="error") -> bool:
        """A result: not failed, and a finite positive error in `column`."""
        v = self.value(column)
        return not (self.row.get("failed") or "").strip() and math.isfinite(v) and v > 0

    @property
    def why_not(self) -> str:
        return (self.row.get("failed") or "").strip() or "no measurable result"

    @property
    def fmi_calls(self) -> str:
        v = number(self.row.get("fmi_calls"))
        return f"{v:.0f}" if math.isfinite(v) else "?"


def read_runs(path) -> list[Run]:
    """Every run of a wp_<scene>.csv, in file order (rows without a method or H skipped)."""
    with open(path, newline="") as f:
        out = []
        for row in csv.DictReader(f):
            H = number(row.get("H"))
            if row.get("method") and math.isfinite(H) and H > 0:
                out.append(Run(row["method"], H, number(row.get("cpu_s")), row))
    return out


def methods(runs) -> list[str]:
    return list(dict.fromkeys(r.method for r in runs))


def read_orders(path) -> dict:
    """{(scene, method): (order or None, points, H_range text)} from wp_orders.csv ({} if absent)."""
    path = Path(path)
    if not path.is_file():
        return {}
    with open(path, newline="") as f:
        out = {}
        for r in csv.DictReader(f):
            o = number(r.get("order"))
            out[(r.get("scene"), r.get("method"))] = (o if math.isfinite(o) else None,
                                                      r.get("points", ""), r.get("H_range", ""))
    return out


def order_range(orders, scene) -> tuple[float, float] | None:
    """The H range the orders of `scene` were fitted over ('0.0001-0.002' -> (1e-4, 2e-3))."""
    for (s, _), (_, _, text) in orders.items():
        if s == scene and text and "-" in text:
            lo, hi = (number(t) for t in text.split("-", 1))
            if math.isfinite(lo) and math.isfinite(hi):
                return lo, hi
    return None


def pareto(runs, column="error") -> list[Run]:
    """The runs no other run beats on both CPU and error (cheapest for their error), by CPU."""
    pts = sorted((r for r in runs if r.ok(column) and math.isfinite(r.cpu)),
                 key=lambda r: (r.cpu, r.value(column)))
    front, best = [], math.inf
    for r in pts:
        if r.value(column) < best:
            front.append(r)
            best = r.value(column)
    return front


def same_h(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-9 * max(abs(a), abs(b))


def best_at(runs, H, column="error"):
    """The run with the smallest error at macro step H (the cheaper one of equals), or None."""
    c = [r for r in runs if same_h(r.H, H) and r.ok(column)]
    return min(c, key=lambda r: (r.value(column), r.cpu)) if c else None


def best_within(runs, cpu_max, column="error"):
    """The run with the smallest error that took at most cpu_max s of CPU, or None."""
    c = [r for r in runs if r.ok(column) and r.cpu <= cpu_max]
    return min(c, key=lambda r: (r.value(column), r.cpu)) if c else None


def cheapest_for(runs, err_max, column="error"):
    """The cheapest run whose error is at most err_max, or None."""
    c = [r for r in runs if r.ok(column) and r.value(column) <= err_max]
    return min(c, key=lambda r: (r.cpu, r.value(column))) if c else None


def tells_more(runs, column, first="error", factor=2.0, share=0.2):
    """Whether error column `column` tells something `first` does not: at least `share` of the runs
    with both differ by more than `factor`, or one has results where the other has none.
    Returns (bool, a sentence saying why)."""
    if not any(r.ok(column) for r in runs):
        return False, f"{column}: no result in the CSV"
    both = [r for r in runs if r.ok(column) and r.ok(first)]
    only = [r for r in runs if r.ok(column) != r.ok(first)]
    apart = [r for r in both if abs(math.log(r.value(column) / r.value(first))) > math.log(factor)]
    if only or (both and len(apart) >= share * len(both)):
        return True, (f"{column} differs from {first} by more than ×{factor:g} at {len(apart)} of "
                      f"{len(both)} runs" + (f"; a result in one only at {len(only)}" if only else ""))
    return False, (f"{column} within ×{factor:g} of {first} at {len(both) - len(apart)} of "
                   f"{len(both)} runs: same picture, not drawn")


@dataclass
class Stability:
    """stability_map.csv: largest stable ωH per method and ζ, and the spectral radius at ζ = 0."""
    limits: list      # dicts: method, zeta, measured, closed_form
    rhos: list        # dicts: method, omegaH, measured, closed_form


def read_stability(path) -> Stability:
    limits, rhos = [], []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            kind = r.get("kind")
            if kind == "largest_stable_omegaH":
                limits.append({"method": r.get("method", ""), "zeta": number(r.get("zeta")),
                               "measured": number(r.get("measured")),
                               "closed_form": number(r.get("closed_form"))})
            elif kind == "spectral_radius":
                rhos.append({"method": r.get("method", ""), "omegaH": number(r.get("omegaH")),
                             "measured": number(r.get("measured")),
                             "closed_form": number(r.get("closed_form"))})
    return Stability(limits, rhos)


def scene_csvs(out) -> dict:
    """{scene name: path} of every out/wp_<scene>.csv but the orders."""
    return {p.stem[3:]: p for p in sorted(Path(out).glob("wp_*.csv")) if p.stem != "wp_orders"}
