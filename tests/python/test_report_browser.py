"""The interactive report (out/report.html, scripts/figures/report.py) as a reader opens it:
built from the CSVs in tests/data/figures, it is one self-contained file (plotly's JavaScript
embedded, nothing fetched), and in headless Chromium (Debian's `chromium`) every chart is drawn
(one plotly figure per scene and the stability map, each with its SVGs and traces), no console
error is logged, no network request leaves the page, the table at the top names per scene the
best runs that Python computes, and changing the CPU budget recomputes it. The out/report.html
of a ./scripts/charts run gets the same checks and its screenshot is kept as out/report.png.
Negative controls: a page that fetches a script and logs an error is caught.

The report of a charts run: out/report.html where one exists, otherwise the same `publish`
./scripts/charts ends with, run on the fixtures, so CI checks it too.

The browser tests skip, saying so, where chromium is not on PATH (./scripts/test says it too;
.ci/run installs chromium, so CI runs them). Uses pytest and scripts/figures (browser.py drives
Chromium over its DevTools pipe; standard library only).
"""
from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import pytest

import conftest  # noqa: F401  (puts scripts/ on sys.path)
from figures import browser, data, report  # noqa: E402
from figures.from_cosim import descriptions  # noqa: E402
from figures.publish import publish  # noqa: E402

FIXTURES = Path(__file__).resolve().parents[1] / "data" / "figures"
OUT_REPORT = conftest.REPO / "out" / "report.html"
needs_chromium = pytest.mark.skipif(
    browser.executable() is None,
    reason="SKIPPED: chromium is not on PATH, so the report was not opened in a browser "
           "(Debian: apt-get install chromium; .ci/run installs it)")

PROBE = """JSON.stringify({
  drawn: document.body.dataset.chartsDrawn || null,
  charts: [...document.querySelectorAll('div.chart')].map(d => ({
      id: d.id, svgs: d.querySelectorAll('svg.main-svg').length,
      traces: d.querySelectorAll('g.trace').length,
      legend: d.querySelectorAll('g.legend g.traces').length})),
  rows: [...document.querySelectorAll('#best tr')].slice(1).map(tr => [tr.id,
      ...[...tr.cells].slice(1).map(c => (c.querySelector('b') || {textContent: ''}).textContent)])
})"""


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The report built from the fixtures: (path, {scene: runs}, infos)."""
    tmp = tmp_path_factory.mktemp("report")
    out = tmp / "out"
    shutil.copytree(FIXTURES, out)
    infos = descriptions()["infos"]
    n = report.write(out / "report.html", infos, out, commit="fixture")
    runs = {name: data.read_runs(p) for name, p in data.scene_csvs(out).items()}
    assert n == len(runs) + 1
    return out / "report.html", runs, infos


def expected_rows(runs, infos, budget=0.1, target=1e-3):
    rows = {}
    for name, rs in runs.items():
        t_end = infos[name].t_end or 1.0
        picks = (data.best_at(rs, 1e-3), data.best_at(rs, 1e-2), data.best_within(rs, budget * t_end),
                 data.cheapest_for(rs, target))
        rows[f"row-{name}"] = [p.method.split("@")[0] if p else "" for p in picks]
    return rows


def test_the_page_is_self_contained(built):
    path, runs, _ = built
    text = path.read_text(encoding="utf-8")
    assert "<script src" not in text and "<link" not in text, "everything inline"
    markup = re.sub(r"<script>.*?</script>", "", text, flags=re.S)   # the page without its scripts
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", markup), "no URL to fetch"
    assert "Content-Security-Policy" in text and "default-src 'none'" in text
    assert len(text) > 3_000_000, "plotly.js embedded"
    for name in runs:
        assert f"id='chart-{name}'" in text and f"id='row-{name}'" in text


@needs_chromium
def test_the_report_opens_offline_in_chromium(built, tmp_path):
    path, runs, infos = built
    seen = browser.visit(path, value=PROBE, screenshot=tmp_path / "report.png")
    check(seen, len(runs) + 1)
    got = json.loads(seen.value)
    want = expected_rows(runs, infos)
    assert {r[0]: r[1:] for r in got["rows"]} == want
    assert (tmp_path / "report.png").stat().st_size > 50_000


@needs_chromium
def test_changing_the_budget_recomputes_the_table(built):
    path, runs, infos = built
    change = ("(() => { const b = document.getElementById('budget'); b.value = '1000';"
              " b.dispatchEvent(new Event('change'));"
              " const t = document.getElementById('target'); t.value = '1e-5';"
              " t.dispatchEvent(new Event('change')); return " + PROBE + "; })()")
    seen = browser.visit(path, value=change)
    assert seen.ready and not seen.console_errors
    got = {r[0]: r[1:] for r in json.loads(seen.value)["rows"]}
    want = expected_rows(runs, infos, budget=1000, target=1e-5)
    assert {k: v[2:] for k, v in got.items()} == {k: v[2:] for k, v in want.items()}


@needs_chromium
def test_the_report_of_a_charts_run(tmp_path):
    """The report as ./scripts/charts writes it: out/report.html where a charts run left one (its
    screenshot is kept as out/report.png). Where none is (CI never runs the charts: they take
    hours), the charts' own last step, `publish` (every PNG, then the page), runs on a copy of
    tests/data/figures (the out/*.csv of one charts run) and its page gets the same checks. What
    CI does not check: the report of CSVs newer than those fixtures."""
    page = OUT_REPORT
    if not page.is_file():
        out = tmp_path / "out"
        shutil.copytree(FIXTURES, out)
        written = publish(out, docs=tmp_path / "img", repo=conftest.REPO, data_commit="fixture",
                          **descriptions())
        page = out / "report.html"
        assert page in written
    expected = len(data.scene_csvs(page.parent)) + (page.parent / "stability_map.csv").is_file()
    seen = browser.visit(page, value=PROBE, screenshot=page.with_suffix(".png"))
    check(seen, expected)


def check(seen, expected):
    assert seen.ready, f"the page did not finish drawing: {seen.value}"
    assert seen.console_errors == []
    assert seen.requests == [], "requests left the page"
    got = json.loads(seen.value)
    assert got["drawn"] == str(expected)
    assert len(got["charts"]) == expected
    for c in got["charts"]:
        assert c["svgs"] >= 2, c          # plotly's main SVG and its hover layer
        assert c["traces"] >= 4, c
        assert c["legend"] >= 4, c        # one entry per method: click hides it


@needs_chromium
def test_control_a_fetch_and_a_console_error_are_caught(tmp_path):
    page = tmp_path / "bad.html"
    page.write_text("<!DOCTYPE html><html><body><script src='http://127.0.0.1:9/plotly.js'></script>"
                    "<img src='https://example.invalid/x.png'>"
                    "<script>console.error('boom'); document.body.dataset.chartsDrawn = '0';</script>"
                    "</body></html>")
    seen = browser.visit(page, value="document.body.dataset.chartsDrawn", timeout=20)
    assert any("127.0.0.1:9" in u for u in seen.requests)
    assert any("example.invalid" in u for u in seen.requests)
    assert any("boom" in e for e in seen.console_errors)
