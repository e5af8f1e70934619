"""Everything a reader looks at, drawn from the CSVs in one folder (out/): each scene's figure
out/wp_<scene>.png, the stability map out/stability_map.png, the interactive out/report.html,
and, when asked, copies of the PNGs in docs/img/ (each <= 200 kB) with docs/img/commit.txt
naming the commit they were drawn at and the one the data came from. One Styles for all, so a
method looks the same on every figure. Legibility problems found are printed, not fatal.

Uses this package (data, describe, legible, report, stability, style, wp) and git (for the
commit); the scene descriptions, method labels and closed forms are the caller's.
"""
from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from . import data, describe, report, stability, wp
from .style import Styles

DOCS_MAX_BYTES = 200_000


def commit(repo) -> str:
    """HEAD's short hash, '+changes' when scripts/ or src/ differ from it; '' outside git."""
    try:
        sha = subprocess.run(["git", "-C", str(repo), "rev-parse", "--short=12", "HEAD"], check=True,
                             capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(repo), "diff", "--quiet", "HEAD", "--", "scripts", "src"]
                               ).returncode != 0
        return sha + (" +changes in scripts/ or src/" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return ""


def styles_for(out) -> Styles:
    """One Styles over every method of every CSV in `out`."""
    methods = set()
    for p in data.scene_csvs(out).values():
        methods |= set(data.methods(data.read_runs(p)))
    sm = Path(out) / "stability_map.csv"
    if sm.is_file():
        st = data.read_stability(sm)
        methods |= {r["method"] for r in st.limits + st.rhos}
    return Styles(methods)


def _warn(name, found):
    for p in found:
        print(f"  warning: {name}: {p}", file=sys.stderr)


def publish(out, infos=None, labels=None, scenes=None, docs=None, report_page=True, bound=None, rho=None,
            stability_labels=None, repo=None, data_commit=None, dpi=100):
    """Draw from the CSVs in `out` (only `scenes` if given). infos: {scene: SceneInfo}; labels: the
    method labels for scenes without an info. Returns {file: bytes}."""
    out = Path(out)
    infos = dict(infos or {})
    styles = styles_for(out)
    written = {}
    orders = out / "wp_orders.csv"
    for name, path in data.scene_csvs(out).items():
        if scenes and name not in scenes:
            continue
        info = infos.get(name) or describe.plain(name, labels)
        png = out / f"wp_{name}.png"
        size, found = wp.draw(info, path, png, orders, styles, dpi=dpi, max_bytes=DOCS_MAX_BYTES)
        _warn(png.name, found)
        written[png] = size
    sm = out / "stability_map.csv"
    if sm.is_file() and (not scenes or "stability" in scenes):
        png = out / "stability_map.png"
        size, found = stability.draw(sm, png, stability_labels, styles, bound, rho, dpi=dpi,
                                     max_bytes=DOCS_MAX_BYTES)
        _warn(png.name, found)
        written[png] = size
    if report_page:
        drawn = commit(repo) if repo else ""
        page = out / "report.html"
        report.write(page, infos, out, styles, commit=data_commit or drawn, labels=stability_labels)
        written[page] = page.stat().st_size
    if docs:
        docs = Path(docs)
        docs.mkdir(parents=True, exist_ok=True)
        for png, size in list(written.items()):
            if png.suffix == ".png":
                if size > DOCS_MAX_BYTES:
                    print(f"  warning: {png.name} is {size} bytes, above {DOCS_MAX_BYTES}", file=sys.stderr)
                shutil.copyfile(png, docs / png.name)
                written[docs / png.name] = size
        drawn = commit(repo) if repo else ""
        (docs / "commit.txt").write_text(
            "The PNGs in this folder are written by ./scripts/charts (scripts/figures/publish.py),\n"
            "or redrawn from existing CSVs by: .venv/bin/python scripts/figures --from out --docs docs/img\n"
            f"drawn at commit: {drawn or 'unknown'}\n"
            f"data (out/*.csv) from ./scripts/charts at commit: {data_commit or drawn or 'unknown'}\n")
        written[docs / "commit.txt"] = (docs / "commit.txt").stat().st_size
    return written
