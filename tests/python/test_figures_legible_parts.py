"""The parts of scripts/figures/legible.py the figure checks rest on, each against an answer it
does not compute itself: `crosses` against a dense sampling of the segment, `Placer.free` against
the boxes it must keep clear of (axes interior, data points, placed labels, PAD), the segments
and points a placer avoids against matplotlib's own transforms, `freeze` against a layout engine
that would move the axes, `save_png` against the file it writes (Pillow reads it back).

Uses pytest, numpy, matplotlib and Pillow. (./scripts/mutants runs these with the negative
controls of test_figures_legible.py: `-k "control or placer or parts"`.)
"""
from __future__ import annotations

import random

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.transforms import Bbox  # noqa: E402
from PIL import Image  # noqa: E402

import conftest  # noqa: F401,E402  (puts scripts/ on sys.path)
from figures import legible  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def _sampled_crossing(b, p, q, n=4001):
    """Whether any of n evenly spaced points of the segment p-q lies strictly inside b, and
    whether one lies within 1e-3 of b's edge (a case the sampling cannot decide)."""
    t = np.linspace(0.0, 1.0, n)
    x, y = p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])
    inside = (x > b.x0) & (x < b.x1) & (y > b.y0) & (y < b.y1)
    dist = np.minimum.reduce([np.abs(x - b.x0), np.abs(x - b.x1), np.abs(y - b.y0), np.abs(y - b.y1)])
    near = ((x >= b.x0 - 1e-3) & (x <= b.x1 + 1e-3) & (y >= b.y0 - 1e-3) & (y <= b.y1 + 1e-3)
            & (dist < 1e-3))
    return bool(inside.any()), bool(near.any())


def test_parts_crosses_agrees_with_a_sampled_segment():
    """Random boxes and segments (oblique, horizontal, vertical, inside, outside, through):
    `crosses` says what 4001 points along the segment say, wherever the sampling is decisive
    (no sample within 1e-3 px of an edge: the sampling step is ≤ 1/4000 of the segment)."""
    rng = random.Random(7)
    decided = crossing = 0
    for i in range(3000):
        x0, y0 = rng.uniform(0, 10), rng.uniform(0, 10)
        b = Bbox([[x0, y0], [x0 + rng.uniform(0.5, 4), y0 + rng.uniform(0.5, 4)]])
        p = (rng.uniform(-2, 16), rng.uniform(-2, 16))
        q = (rng.uniform(-2, 16), rng.uniform(-2, 16))
        if i % 2:                               # every other one aimed through the box
            c = (rng.uniform(b.x0, b.x1), rng.uniform(b.y0, b.y1))
            s = rng.choice((0.4, 1.0, 2.5))     # ends short of the box, at it, or beyond
            q = (c[0] + s * (c[0] - p[0]), c[1] + s * (c[1] - p[1])) if s > 1 else \
                (p[0] + s * 0.9 * (c[0] - p[0]), p[1] + s * 0.9 * (c[1] - p[1]))
        if i % 3 == 1:
            q = (q[0], p[1])                    # horizontal: dy = 0
        elif i % 3 == 2:
            q = (p[0], q[1])                    # vertical: dx = 0
        want, near = _sampled_crossing(b, p, q)
        if near:
            continue
        decided += 1
        crossing += want
        assert legible.crosses(b, p, q) == want, (b, p, q)
    assert decided > 2500 and 50 < crossing < decided - 50, (decided, crossing)


def test_parts_crosses_a_segment_inside_the_box_and_one_that_ends_short():
    b = Bbox([[0, 0], [10, 10]])
    assert legible.crosses(b, (2, 2), (3, 4))             # wholly inside
    assert not legible.crosses(b, (-5, 5), (-1, 5))       # ends before the box
    assert not legible.crosses(b, (11, 5), (15, 5))       # starts after it
    assert legible.crosses(b, (-5, 5), (15, 5))           # through
    assert not legible.crosses(b, (-5, 12), (15, 11))     # above, never inside


def _frozen_placer():
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot([0, 1, 2, 3], [0, 1, 0, 1], marker="o", markersize=6, label="zigzag")
    ax.set_xlim(-0.5, 3.5)
    ax.set_ylim(-0.5, 1.5)
    return fig, ax, legible.Placer(fig, legible.freeze(fig))


def test_parts_freeze_keeps_the_layout_labels_were_placed_on():
    """After `freeze`, no layout engine moves the axes when a label is added; before it, the
    constrained layout does (so the check has something to see)."""
    fig, ax = plt.subplots(layout="constrained")
    ax.plot([1, 2], [1, 2])
    legible.renderer_of(fig)
    before = ax.get_position().bounds
    ax.set_ylabel("a label\nover\nfour lines\nthat takes room")
    legible.renderer_of(fig)
    assert ax.get_position().bounds != before, "the control: a layout engine moves the axes"
    r = legible.freeze(fig)
    assert r is fig.canvas.get_renderer()
    held = ax.get_position().bounds
    ax.set_xlabel("another label\nover\nthree lines")
    legible.renderer_of(fig)
    assert ax.get_position().bounds == held


def test_parts_free_keeps_clear_of_points_labels_and_the_axes_edge():
    fig, ax, placer = _frozen_placer()
    r = legible.renderer_of(fig)
    area = ax.get_window_extent(r)
    pts = legible.marker_boxes(ax, r)
    assert len(placer.points(ax)) == len(pts) == 4
    # a small box half-way between the first two markers, well clear of the line's points
    cx, cy = 0.5 * (area.x0 + area.x1), area.y0 + 0.9 * area.height
    small = Bbox([[cx - 5, cy - 3], [cx + 5, cy + 3]])
    assert placer.free(ax, small)
    # over a data point, or within PAD of its box: not free
    p = pts[1]
    assert not placer.free(ax, Bbox([[p.x1 - 1, p.y0], [p.x1 + 9, p.y1]]))
    gap = legible.PAD - 0.25
    assert not placer.free(ax, Bbox([[p.x1 + gap, p.y0], [p.x1 + gap + 10, p.y1]]))
    clear = legible.PAD + 0.25
    assert placer.free(ax, Bbox([[p.x1 + clear, p.y0], [p.x1 + clear + 10, p.y1]]))
    # against the axes' edge: 1 px inside is the limit
    edge = Bbox([[area.x1 - 11.5, cy - 3], [area.x1 - 1.5, cy + 3]])
    assert placer.free(ax, edge)
    assert not placer.free(ax, Bbox([[area.x1 - 8, cy - 3], [area.x1 + 2, cy + 3]]))
    assert not placer.free(ax, Bbox([[area.x0 - 2, cy - 3], [area.x0 + 8, cy + 3]]))
    assert not placer.free(ax, Bbox([[cx - 5, area.y1 - 4], [cx + 5, area.y1 + 2]]))
    assert not placer.free(ax, Bbox([[cx - 5, area.y0 - 2], [cx + 5, area.y0 + 4]]))
    # a blocked box is kept clear of, with the same PAD
    placer.block(small)
    assert not placer.free(ax, small)
    beside = Bbox([[small.x1 + gap, small.y0], [small.x1 + gap + 10, small.y1]])
    assert not placer.free(ax, beside)
    assert placer.free(ax, Bbox([[small.x1 + clear, small.y0], [small.x1 + clear + 10, small.y1]]))


def test_parts_points_are_every_marker_of_the_figure():
    """A placer avoids the markers of every axes of the figure (a label may reach into a
    neighbouring panel's points), each box centred on matplotlib's own transform of the data."""
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(6, 3))
    a1.plot([1, 2, 3], [1, 2, 3], marker="s", markersize=5)
    a2.plot([1, 2], [3, 1], marker="o", markersize=5)
    a2.plot([1, 2], [1, 3])                               # no markers: no boxes
    placer = legible.Placer(fig, legible.freeze(fig))
    boxes = placer.points(a1)
    assert len(boxes) == 5 and [b.bounds for b in placer.points(a2)] == [b.bounds for b in boxes]
    want = np.vstack([a1.transData.transform([[1, 1], [2, 2], [3, 3]]),
                      a2.transData.transform([[1, 3], [2, 1]])])
    got = np.array([[(b.x0 + b.x1) / 2, (b.y0 + b.y1) / 2] for b in boxes])
    assert np.allclose(np.sort(got, axis=0), np.sort(want, axis=0), atol=1e-9)


def test_parts_segments_are_the_drawn_lines():
    fig, ax = plt.subplots()
    ax.plot([0, 1, 2, 3], [0, 1, np.nan, 1])              # a gap: the segments beside it go
    ax.plot([0, 1, 2], [1, 0, 1], linestyle="none", marker="o")   # markers only: no segments
    hidden, = ax.plot([0, 3], [0.5, 0.5])
    hidden.set_visible(False)
    placer = legible.Placer(fig, legible.freeze(fig))
    segs = placer.segments(ax)
    xy = ax.transData.transform([[0, 0], [1, 1]])
    assert len(segs) == 1
    assert np.allclose(segs[0][0], xy[0]) and np.allclose(segs[0][1], xy[1])
    assert placer.segments(ax) is segs, "computed once per axes"


def test_parts_a_label_prefers_a_place_that_crosses_no_line():
    """With a line through two of the offsets, the label goes to one the line does not cross;
    where every free offset is crossed it still goes to a free one (the second pass)."""
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot([0, 1], [0.5, 0.5], marker="o", markersize=4)      # a horizontal line through the point
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1)
    placer = legible.Placer(fig, legible.freeze(fig))
    right_then_up = ((1, 0), (0, 1))
    t = placer.place(ax, (0.5, 0.5), "label", offsets=right_then_up)
    assert t is not None
    r = legible.renderer_of(fig)
    b = legible.text_box(t, r)
    assert not any(legible.crosses(b, p, q) for p, q in placer.segments(ax))
    assert t.get_va() == "bottom", "above the line, not on it to the right"
    t2 = placer.place(ax, (0.25, 0.5), "on the line", offsets=((1, 0),))
    assert t2 is not None and t2.get_ha() == "left"
    assert any(legible.crosses(legible.text_box(t2, r), p, q) for p, q in placer.segments(ax))


def test_parts_save_png_writes_a_palette_png_of_the_size_it_returns(tmp_path):
    fig, ax = plt.subplots(figsize=(4, 3))
    for k in range(12):
        ax.plot(np.linspace(0, 1, 50), np.sin(np.linspace(0, 6, 50) + k), label=f"{k}")
    ax.imshow(np.random.default_rng(1).random((40, 40)), extent=(0, 1, -1, 1), aspect="auto")
    path = tmp_path / "a.png"
    size = legible.save_png(fig, path, dpi=50)
    assert size == path.stat().st_size
    img = Image.open(path)
    assert img.format == "PNG" and img.mode == "P" and img.size == (200, 150)
    assert len(img.getcolors(256) or []) <= 256
    # a byte limit between the smallest palette's size and the full one: fewer colours, under it
    small = legible.save_png(fig, tmp_path / "s.png", dpi=50, max_bytes=1)
    assert small < size
    limit = (small + size) // 2
    got = legible.save_png(fig, tmp_path / "m.png", dpi=50, max_bytes=limit)
    assert got <= limit and got == (tmp_path / "m.png").stat().st_size
    assert len(Image.open(tmp_path / "m.png").getcolors(256)) <= 128
