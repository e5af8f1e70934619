"""The figures of scripts/figures, checked as a reader would look at them: drawn from the CSVs in
tests/data/figures (a copy of one ./scripts/charts run's out/*.csv), each figure is checked with
matplotlib's bounding boxes (no legend over an axes' data area, no two point labels over each
other, no label over a data point; legible.problems lists everything), written as a PNG of at
most 200 kB, and every run without a result is marked on it. Negative controls show that each
check fails on a figure made illegible on purpose. The default scene's figure
(scripts/default_scene.py, ./scripts/run) gets the same check. Also: the family table, the
Pareto front and the best-run choices, and that unknown columns and methods do not break a figure.

Uses pytest, matplotlib and scripts/figures (scripts/cosim for the scene descriptions, and fmpy
with dist/Bushing.fmu for the default scene).
"""
from __future__ import annotations

import csv
import shutil
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402
from matplotlib.transforms import IdentityTransform  # noqa: E402

import conftest  # noqa: F401,E402  (puts scripts/ on sys.path)
from figures import data, legible, stability, style, wp  # noqa: E402
from figures.from_cosim import descriptions  # noqa: E402
from figures.publish import DOCS_MAX_BYTES, publish, styles_for  # noqa: E402

FIXTURES = Path(__file__).resolve().parents[1] / "data" / "figures"
SCENES = sorted(data.scene_csvs(FIXTURES))
DESC = descriptions()


# -- the checks, written out with matplotlib's boxes --------------------------------------------
def legends_over_data(fig):
    """(legend, axes) pairs where a legend's box overlaps an axes' data area."""
    r = legible.renderer_of(fig)
    out = []
    for lg in legible.legends(fig):
        box = lg.get_window_extent(r)
        out += [(lg, ax) for ax in fig.axes if legible.overlap(box, ax.get_window_extent(r))]
    return out


def labels_over_labels(fig):
    """Pairs of point labels (the texts of every axes) whose boxes overlap."""
    r = legible.renderer_of(fig)
    boxes = [(t, legible.text_box(t, r)) for ax in fig.axes for t in ax.texts]
    boxes = [(t, b) for t, b in boxes if b is not None]
    return [(t1.get_text(), t2.get_text()) for i, (t1, b1) in enumerate(boxes)
            for t2, b2 in boxes[:i] if legible.overlap(b1, b2)]


def scene_figure(name, folder=FIXTURES):
    runs = data.read_runs(folder / f"wp_{name}.csv")
    info = DESC["infos"].get(name) or data.SceneInfo(name=name)
    return wp.figure(info, runs, data.read_orders(folder / "wp_orders.csv"), styles_for(folder)), runs


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


@pytest.mark.parametrize("name", SCENES)
def test_scene_figure_is_legible(name):
    fig, _ = scene_figure(name)
    assert fig.legends, "the legend is a figure legend, outside the axes"
    assert not legends_over_data(fig)
    assert not labels_over_labels(fig)
    assert legible.problems(fig) == []
    assert sum(len(ax.texts) for ax in fig.axes) >= 3, "some H labels are placed"
    assert all(ax.get_legend() is None for ax in fig.axes)
    assert len([ax for ax in fig.axes if ax.get_xlabel().startswith("macro step H")]) >= 1, \
        "a convergence panel (error against H) stands beside the work-precision panel"


@pytest.mark.parametrize("name", SCENES)
def test_every_run_without_a_result_is_marked_at_its_H(name):
    """The strip above the convergence panel holds a marker at the H of every run without a result."""
    fig, runs = scene_figure(name)
    bad = {(style.split(r.method)[0], r.H) for r in runs if not r.ok()}
    strips = [ax for ax in fig.axes if ax.get_facecolor()[:3] == matplotlib.colors.to_rgb(wp.NO_RESULT)]
    if not bad:
        assert not strips
        return
    strip = strips[0]
    marked = {(round(y), x) for line in strip.get_lines() for x, y in line.get_xydata()}
    rows = [b for b in styles_for(FIXTURES).bases() if any(b == m for m, _ in bad)]
    for base, H in bad:
        assert (rows.index(base), H) in marked, (base, H)
    key = [ax for ax in fig.axes if not ax.axison][0]          # the rows' names, beside the strip
    assert [t.get_text().split()[0] for t in key.texts] == rows


def test_stability_figure_is_legible():
    fig = stability.figure(data.read_stability(FIXTURES / "stability_map.csv"), DESC["stability_labels"],
                           styles_for(FIXTURES), DESC["bound"], DESC["rho"])
    assert not legends_over_data(fig)
    assert not labels_over_labels(fig)
    assert legible.problems(fig) == []


def test_publish_writes_small_pngs_a_commit_file_and_the_report(tmp_path):
    out = tmp_path / "out"
    shutil.copytree(FIXTURES, out)
    written = publish(out, docs=tmp_path / "img", repo=conftest.REPO, data_commit="abc1234", **DESC)
    pngs = sorted(p.name for p in (tmp_path / "img").glob("*.png"))
    assert pngs == sorted([f"wp_{n}.png" for n in SCENES] + ["stability_map.png"])
    for p in (tmp_path / "img").glob("*.png"):
        assert p.stat().st_size <= DOCS_MAX_BYTES, p
        assert p.read_bytes() == (out / p.name).read_bytes()
    assert "abc1234" in (tmp_path / "img" / "commit.txt").read_text()
    assert (out / "report.html") in written


def test_unknown_columns_and_methods_do_not_break_a_figure(tmp_path):
    """A CSV with a new column (brand_new), error_rigid within ×2 of error, a plain method added
    (jacobi, taken out first), a new event-located one, one method gone: drawn, legible (the
    legend taller than in any charts run), the new methods in their families."""
    with open(FIXTURES / "wp_belt.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["method"] not in ("rollback", "jacobi")]
    extra = []
    for r in rows:
        r["error_rigid"] = str(2 * float(r["error"])) if r["error"] not in ("", "nan") else "nan"
        r["brand_new"] = "x"
        if r["method"] in ("zoh", "linear_path_ev", "linear_path_ev@fmi3"):
            new = dict(r, method={"zoh": "jacobi", "linear_path_ev": "linear_fancy_ev",
                                  "linear_path_ev@fmi3": "linear_fancy_ev@fmi3"}[r["method"]])
            new["cpu_s"] = str(float(r["cpu_s"]) * 1.3)
            extra.append(new)
    with open(tmp_path / "wp_belt.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows + extra)
    runs = data.read_runs(tmp_path / "wp_belt.csv")
    fig = wp.figure(DESC["infos"]["belt"], runs)
    assert legible.problems(fig) == []
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert any(t.startswith("jacobi") for t in legend)
    assert not any(t.startswith("rollback") for t in legend)
    assert style.family("jacobi") == "explicit" and style.family("linear_fancy_ev@fmi3") == "event"
    # error_rigid here is 2 × error everywhere: the same picture, so no third panel
    assert not any("rigid" in ax.get_title() for ax in fig.axes)


def test_families_come_from_one_table():
    assert [style.family(m) for m in ("zoh", "extrapolation", "jacobi")] == ["explicit"] * 3
    assert [style.family(m) for m in ("linear_implicit", "rollback", "something_new")] == ["implicit"] * 3
    assert [style.family(m) for m in ("extrapolation_ev", "linear_path_ev@fmi3")] == ["event"] * 2
    s = style.Styles(["zoh", "linear_exact_ev", "linear_exact_ev@fmi3", "rollback"])
    assert s.look("linear_exact_ev") == s.look("linear_exact_ev@fmi3"), "FMI 3.0: the same method's look"
    assert s.look("zoh").color != s.look("rollback").color
    assert style.split("linear_exact_ev@fmi3") == ("linear_exact_ev", 3)


def _run(method, H, cpu, err, failed=""):
    return data.Run(method, H, cpu, {"error": str(err), "failed": failed, "fmi_calls": "10"})


def test_pareto_front_and_best_runs():
    runs = [_run("a", 1e-2, 1.0, 1e-2), _run("a", 1e-3, 5.0, 1e-4), _run("b", 1e-2, 2.0, 1e-3),
            _run("b", 1e-3, 3.0, 1e-2), _run("c", 1e-3, 0.5, "nan"), _run("c", 1e-2, 0.1, 1e-5, "diverged")]
    assert [(r.method, r.H) for r in data.pareto(runs)] == [("a", 1e-2), ("b", 1e-2), ("a", 1e-3)]
    assert data.best_at(runs, 1e-3).method == "a"
    assert data.best_within(runs, 2.5).method == "b"
    assert data.cheapest_for(runs, 1e-2).method == "a"
    assert data.best_within(runs, 0.2) is None


def test_a_second_reference_is_drawn_only_where_it_tells_more():
    """(Within ×2 of error at every run: test_unknown_columns_and_methods_do_not_break_a_figure.)"""
    belt = data.read_runs(FIXTURES / "wp_belt.csv")
    puck1 = data.read_runs(FIXTURES / "wp_puck1.csv")
    bounce = data.read_runs(FIXTURES / "wp_bounce.csv")
    # the rigid Karnopp cycle is a floor (~1e-5) under which the model's error converges on
    assert data.tells_more(belt, "error_rigid")[0] is True
    assert data.tells_more(puck1, "error2")[0] is True          # model error against convergence
    assert data.tells_more(belt, "error2") == (False, "error2: no result in the CSV")
    assert data.tells_more(bounce, "error_rigid")[0] is False  # an empty column
    for name, panels in (("puck1", 2), ("belt", 2), ("bounce", 1)):
        fig, _ = scene_figure(name)
        assert sum(ax.get_xlabel().startswith("macro step H") for ax in fig.axes) == panels, name


# -- negative controls: each check fails on a figure made illegible on purpose -------------------
def _plain():
    fig, ax = plt.subplots(layout="constrained")
    ax.plot([1, 2, 3], [1, 4, 9], marker="o", label="data")
    ax.plot([1, 2, 3], [9, 4, 1], marker="s", label="more")
    return fig, ax


def test_control_a_legend_over_the_data_is_found():
    fig, ax = _plain()
    ax.legend(loc="center")
    assert legends_over_data(fig)
    assert any("legend" in p and "data area" in p for p in legible.problems(fig))


def test_control_two_labels_over_each_other_are_found():
    fig, ax = _plain()
    ax.annotate("1 ms", (2, 6), fontsize=8)
    ax.annotate("2 ms", (2.02, 6.1), fontsize=8)
    assert labels_over_labels(fig)
    assert any("lies over label" in p for p in legible.problems(fig))


def test_control_a_label_over_a_data_point_is_found():
    fig, ax = _plain()
    ax.annotate("here", (2, 4), ha="center", va="center")
    assert any("over a data point" in p for p in legible.problems(fig))


def test_control_a_caption_over_the_axes_is_found():
    fig, ax = _plain()
    fig.text(0.5, 0.5, "a caption across the middle of the figure")
    assert any("caption" in p and "data area" in p for p in legible.problems(fig))


def test_control_the_old_belt_figure_is_found_illegible():
    """The figure as scripts/work_precision.py drew it before (legends at 'best' inside the axes,
    a label at every point) fails the same checks."""
    runs = data.read_runs(FIXTURES / "wp_belt.csv")
    fig, ax = plt.subplots(figsize=(7.5, 6), layout="constrained")
    for m in data.methods(runs):
        ok = [r for r in runs if r.method == m and r.ok()]
        if ok:
            ax.loglog([r.cpu for r in ok], [r.value() for r in ok], marker="o", label=m)
            for r in ok:
                ax.annotate(f"{r.H:.0e}", (r.cpu, r.value()), textcoords="offset points", xytext=(4, 3),
                            fontsize=6.5)
    ax.legend(fontsize=7, loc="best")
    assert legends_over_data(fig)
    assert labels_over_labels(fig)


def test_the_placer_drops_a_label_that_has_no_free_place():
    fig, ax = _plain()
    placer = legible.Placer(fig, legible.freeze(fig))
    assert placer.place(ax, (2, 4), "first") is not None
    crowded = [placer.place(ax, (2, 4), f"again {i}") for i in range(12)]
    assert None in crowded
    assert legible.problems(fig) == []


# -- the default scene (./scripts/run) ---------------------------------------------------------
def test_default_scene_figure_is_legible():
    conftest.fmu_path("Bushing")
    import default_scene
    fig = default_scene.figure(default_scene.simulate())
    assert not legends_over_data(fig)
    assert not labels_over_labels(fig)
    assert legible.problems(fig) == []


# -- negative controls for every other kind of problem (each fails when its check is removed) ---
PIXELS = IdentityTransform()     # anchors in display pixels, where the boxes are measured


def _legend_box(fig, lg):
    return lg.get_window_extent(legible.renderer_of(fig))


def _kinds(fig, *words):
    """The problems whose message holds every one of `words`."""
    return [p for p in legible.problems(fig) if all(w in p for w in words)]


def _room_right():
    """A figure whose axes leave the right 40 % of the page empty (no layout engine)."""
    fig, ax = plt.subplots(figsize=(6, 4))
    fig.subplots_adjust(left=0.12, right=0.6, bottom=0.15, top=0.85)
    ax.plot([1, 2, 3], [1, 4, 9], marker="o", label="data")
    ax.plot([1, 2, 3], [9, 4, 1], marker="s", label="more")
    return fig, ax


def test_control_a_legend_over_another_legend_is_found():
    fig, ax = _room_right()
    fig.legend(loc="center right", fontsize=8)
    fig.legend(loc="center right", fontsize=8, bbox_to_anchor=(0.98, 0.52))
    assert _kinds(fig, "legend 1 lies over legend 0")
    assert not _kinds(fig, "data area"), "apart from the data: only the two legends meet"


def test_control_a_legend_over_the_tick_labels_is_found():
    """A figure legend over the x tick labels, below the data area: found through the axes'
    decorations (tick labels), and not as a legend over the data."""
    fig, ax = _room_right()
    r = legible.renderer_of(fig)
    ticks = [b for what, b in legible.decorations(ax, r) if what.startswith("tick label")]
    assert ticks, "decorations lists the drawn tick labels"
    xt = [b for b in ticks if b.y1 < ax.get_window_extent(r).y0]          # below the axes
    mid = xt[len(xt) // 2]
    fig.legend(handles=ax.get_lines()[:1], loc="center", fontsize=6, borderpad=0.1,
               bbox_to_anchor=((mid.x0 + mid.x1) / 2, (mid.y0 + mid.y1) / 2),
               bbox_transform=PIXELS)
    assert _kinds(fig, "legend 0 lies over tick label")
    assert not _kinds(fig, "data area")


def test_control_a_legend_over_an_axis_label_is_found():
    fig, ax = _room_right()
    ax.set_ylabel("a long axis label on the left")
    r = legible.renderer_of(fig)
    lab = legible.text_box(ax.yaxis.label, r)
    fig.legend(handles=ax.get_lines()[:1], loc="center", fontsize=6, borderpad=0.1,
               bbox_to_anchor=((lab.x0 + lab.x1) / 2, (lab.y0 + lab.y1) / 2), bbox_transform=PIXELS)
    assert _kinds(fig, "legend 0 lies over 'a long axis label")


def test_control_a_legend_off_the_page_is_found():
    fig, ax = _room_right()
    fig.legend(loc="center left", bbox_to_anchor=(0.9, 0.5), fontsize=8)
    assert _kinds(fig, "legend 0 reaches outside the figure")
    assert not _kinds(fig, "data area")


def test_control_a_caption_over_a_legend_is_found():
    fig, ax = _room_right()
    lg = fig.legend(loc="center right", fontsize=8)
    b = _legend_box(fig, lg)
    fig.text((b.x0 + b.x1) / 2, (b.y0 + b.y1) / 2, "caption", transform=None, ha="center", va="center")
    assert _kinds(fig, "caption 'caption' lies over a legend")
    assert not _kinds(fig, "caption", "data area")


def test_control_a_caption_over_the_title_is_found():
    fig, ax = _room_right()
    ax.set_title("the title of the axes")
    fig.text(0.36, 0.87, "a caption on the title", ha="center", va="bottom")
    assert _kinds(fig, "caption 'a caption on the title' lies over 'the title of the axes'")
    assert not _kinds(fig, "caption", "data area")


def test_control_two_captions_over_each_other_are_found():
    fig, ax = _room_right()
    fig.text(0.8, 0.1, "first caption")
    fig.text(0.8, 0.1, "second caption")
    assert _kinds(fig, "caption 'second caption' lies over caption 'first caption'")


def test_control_a_caption_off_the_page_is_found():
    fig, ax = _room_right()
    fig.text(0.9, 0.5, "a caption that runs off the right edge")
    assert _kinds(fig, "caption 'a caption that runs off the right edge' reaches outside the figure")


def test_control_a_label_over_a_legend_is_found():
    fig, ax = _plain()
    lg = ax.legend(loc="upper left")
    b = lg.get_texts()[0].get_window_extent(legible.renderer_of(fig))
    ax.annotate("on the legend", ((b.x0 + b.x1) / 2, (b.y0 + b.y1) / 2), xycoords="figure pixels",
                ha="center", va="center", fontsize=7)
    assert _kinds(fig, "label 'on the legend'", "lies over a legend")


def test_control_a_label_outside_its_axes_is_found():
    fig, ax = _plain()
    ax.annotate("outside", (3.2, 9.5), xytext=(40, 20), textcoords="offset points",
                annotation_clip=False)
    assert _kinds(fig, "label 'outside'", "reaches outside its axes")
    # a label of the same text well inside the axes is not reported
    fig2, ax2 = _plain()
    ax2.annotate("outside", (1.2, 7.0))
    assert not _kinds(fig2, "reaches outside")
