"""Legibility of a matplotlib figure, made and checked with the same geometry (display pixels,
matplotlib's own bounding boxes):

- `Placer` puts point labels where they cover no data point, no other label and stay inside
  their axes, trying a few positions around the point and dropping the label where none is free;
- `problems(fig)` lists what a reader could not read: a legend over an axes' data area, over
  another legend or over an axis' labels; a caption (figure text) over any of those; a point label
  over another label, over a data point or outside its axes or the figure;
- `save_png(fig, path)` writes a palette PNG (small enough for the docs) and returns its size.

Uses matplotlib, and Pillow (which matplotlib needs) for the palette PNG; reads no data.
"""
from __future__ import annotations

import io
import math

import numpy as np
from matplotlib.text import Annotation, Text
from matplotlib.transforms import Bbox

TOL = 0.5          # px: boxes that share less than this are apart (a touching edge is not an overlap)
PAD = 1.5          # px: the margin the placer keeps around what it avoids


def renderer_of(fig):
    fig.draw_without_rendering()
    return fig.canvas.get_renderer()


def freeze(fig):
    """Lay the figure out once and keep that layout, so labels placed afterwards stay where they
    were placed (a layout engine would move the axes under them)."""
    renderer = renderer_of(fig)
    fig.set_layout_engine("none")
    return renderer


def overlap(a: Bbox, b: Bbox, tol=TOL) -> bool:
    return (a.x0 < b.x1 - tol and b.x0 < a.x1 - tol and a.y0 < b.y1 - tol and b.y0 < a.y1 - tol)


def inside(a: Bbox, b: Bbox, tol=TOL) -> bool:
    return a.x0 >= b.x0 - tol and a.x1 <= b.x1 + tol and a.y0 >= b.y0 - tol and a.y1 <= b.y1 + tol


def _has_marker(line) -> bool:
    return (line.get_visible() and line.get_marker() not in (None, "None", "none", "", " ")
            and line.get_markersize() > 0)


def marker_boxes(ax, renderer) -> list[Bbox]:
    """The box of every drawn data point (line markers and scatter points) of `ax`, in pixels; points
    clipped away by the axes are not drawn and not listed."""
    area = ax.get_window_extent(renderer)
    px = ax.figure.dpi / 72.0
    out = []

    def add(xy, half, clip):
        for x, y in xy:
            if not (math.isfinite(x) and math.isfinite(y)):
                continue
            if clip and not (area.x0 - half <= x <= area.x1 + half and area.y0 - half <= y <= area.y1 + half):
                continue
            out.append(Bbox([[x - half, y - half], [x + half, y + half]]))

    for line in ax.get_lines():
        if _has_marker(line):
            xy = line.get_transform().transform(np.asarray(line.get_xydata(), float))
            half = 0.5 * (line.get_markersize() + line.get_markeredgewidth()) * px
            add(xy, half, line.get_clip_on())
    for coll in ax.collections:
        offs = coll.get_offsets() if coll.get_visible() else []
        sizes = getattr(coll, "get_sizes", lambda: [])()
        if len(offs) and len(sizes):
            xy = coll.get_offset_transform().transform(np.asarray(offs, float))
            half = 0.5 * math.sqrt(float(np.max(sizes))) * px
            add(xy, half, coll.get_clip_on())
    return out


def text_box(text, renderer) -> Bbox | None:
    if not text.get_visible() or not text.get_text().strip():
        return None
    if isinstance(text, Annotation):
        text.update_positions(renderer)
    return Text.get_window_extent(text, renderer)     # the text itself, without an annotation's arrow


def legends(fig) -> list:
    out = list(fig.legends)
    for ax in fig.axes:
        if ax.get_legend() is not None:
            out.append(ax.get_legend())
    return [lg for lg in out if lg.get_visible()]


def decorations(ax, renderer) -> list[tuple[str, Bbox]]:
    """What labels an axes from outside: title, axis labels and tick labels."""
    out = []
    for t in (ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label):
        b = text_box(t, renderer)
        if b is not None:
            out.append((f"'{t.get_text()[:30]}'", b))
    area = ax.get_window_extent(renderer)
    for axis, lo, hi in ((ax.xaxis, area.x0, area.x1), (ax.yaxis, area.y0, area.y1)):
        for t in axis.get_ticklabels(which="both"):
            b = text_box(t, renderer)
            mid = None if b is None else (b.x0 + b.x1) / 2 if axis is ax.xaxis else (b.y0 + b.y1) / 2
            if b is not None and lo - 1 <= mid <= hi + 1:      # a tick outside the view is not drawn
                out.append((f"tick label '{t.get_text()}'", b))
    return out


def captions(fig) -> list:
    out = list(fig.texts)
    for name in ("_suptitle", "_supxlabel", "_supylabel"):
        t = getattr(fig, name, None)
        if t is not None and all(t is not o for o in out):
            out.append(t)
    return out


def _name(ax) -> str:
    return f"axes '{ax.get_title() or ax.get_label() or id(ax)}'"


def problems(fig) -> list[str]:
    """Everything on `fig` a reader could not read (empty: legible)."""
    r = renderer_of(fig)
    page = fig.bbox
    axes = [ax for ax in fig.axes if ax.get_visible()]
    areas = [(ax, ax.get_window_extent(r)) for ax in axes]
    decos = [(ax, what, b) for ax in axes for what, b in decorations(ax, r)]
    out = []
    lgs = [(lg, lg.get_window_extent(r)) for lg in legends(fig)]
    for i, (lg, b) in enumerate(lgs):
        for ax, a in areas:
            if overlap(b, a):
                out.append(f"legend {i} lies over the data area of {_name(ax)}")
        for j in range(i):
            if overlap(b, lgs[j][1]):
                out.append(f"legend {i} lies over legend {j}")
        for ax, what, d in decos:
            if overlap(b, d):
                out.append(f"legend {i} lies over {what} of {_name(ax)}")
        if not inside(b, page):
            out.append(f"legend {i} reaches outside the figure")
    caps = [(t, text_box(t, r)) for t in captions(fig)]
    caps = [(t, b) for t, b in caps if b is not None]
    for i, (t, b) in enumerate(caps):
        what = f"caption '{t.get_text()[:40]}'"
        for ax, a in areas:
            if overlap(b, a):
                out.append(f"{what} lies over the data area of {_name(ax)}")
        for _, lb in lgs:
            if overlap(b, lb):
                out.append(f"{what} lies over a legend")
        for ax, dw, d in decos:
            if overlap(b, d):
                out.append(f"{what} lies over {dw} of {_name(ax)}")
        for t2, b2 in caps[:i]:
            if overlap(b, b2):
                out.append(f"{what} lies over caption '{t2.get_text()[:40]}'")
        if not inside(b, page):
            out.append(f"{what} reaches outside the figure")
    labels = [(ax, t, text_box(t, r)) for ax in axes for t in ax.texts]
    labels = [(ax, t, b) for ax, t, b in labels if b is not None]
    points = [(ax, marker_boxes(ax, r)) for ax in axes]
    for i, (ax, t, b) in enumerate(labels):
        what = f"label '{t.get_text()}' in {_name(ax)}"
        for ax2, t2, b2 in labels[:i]:
            if overlap(b, b2):
                out.append(f"{what} lies over label '{t2.get_text()}'")
        for ax2, boxes in points:
            if any(overlap(b, p) for p in boxes):
                out.append(f"{what} lies over a data point of {_name(ax2)}")
        for _, lb in lgs:
            if overlap(b, lb):
                out.append(f"{what} lies over a legend")
        if not inside(b, ax.get_window_extent(r)) or not inside(b, page):
            out.append(f"{what} reaches outside its axes")
    return out


def crosses(b: Bbox, p, q) -> bool:
    """Whether the segment p-q passes through box b (Liang-Barsky clipping)."""
    t0, t1 = 0.0, 1.0
    dx, dy = q[0] - p[0], q[1] - p[1]
    for d, lo, hi, v in ((dx, b.x0, b.x1, p[0]), (dy, b.y0, b.y1, p[1])):
        if d == 0:
            if not lo <= v <= hi:
                return False
            continue
        a, c = (lo - v) / d, (hi - v) / d
        t0, t1 = max(t0, min(a, c)), min(t1, max(a, c))
        if t0 > t1:
            return False
    return True


OFFSETS = ((1, 1), (1, -1), (-1, 1), (-1, -1), (0, 1), (0, -1), (1, 0), (-1, 0))
HA = {1: "left", 0: "center", -1: "right"}
VA = {1: "bottom", 0: "center", -1: "top"}


class Placer:
    """Puts labels on a frozen figure (`freeze`) where they are legible; what it cannot place it
    drops. Labels it placed and extra boxes (`block`) are avoided by the labels after them."""

    def __init__(self, fig, renderer):
        self.fig, self.r = fig, renderer
        self.taken: list[Bbox] = []
        self._points: dict = {}

    def points(self, ax):
        if ax not in self._points:
            self._points[ax] = [b for a in self.fig.axes for b in marker_boxes(a, self.r)]
        return self._points[ax]

    def segments(self, ax):
        """The drawn line segments of `ax` (display pixels), which labels prefer not to cross."""
        if ("seg", ax) not in self._points:
            segs = []
            for line in ax.get_lines():
                if line.get_visible() and line.get_linestyle() not in ("None", "none", "", " "):
                    xy = line.get_transform().transform(np.asarray(line.get_xydata(), float))
                    segs += [(p, q) for p, q in zip(xy[:-1], xy[1:]) if np.isfinite([*p, *q]).all()]
            self._points[("seg", ax)] = segs
        return self._points[("seg", ax)]

    def block(self, box: Bbox):
        self.taken.append(box)

    def free(self, ax, b: Bbox) -> bool:
        area = ax.get_window_extent(self.r)
        if not inside(b, Bbox([[area.x0 + 1, area.y0 + 1], [area.x1 - 1, area.y1 - 1]])):
            return False
        grown = Bbox([[b.x0 - PAD, b.y0 - PAD], [b.x1 + PAD, b.y1 + PAD]])
        return not any(overlap(grown, o, 0) for o in self.taken) and \
            not any(overlap(grown, p, 0) for p in self.points(ax))

    def place(self, ax, xy, text, color="0.2", gap=5.0, offsets=OFFSETS, fontsize=7.5,
              transform=None, **kw):
        """A label beside the point xy (data coordinates, or `transform`'s), at the first of
        `offsets` (directions: right/left, up/down) where it is free; None where none is. The gap
        (points) grows to clear the largest marker drawn at xy."""
        x, y = (transform or ax.transData).transform(xy)
        own = [b.width / 2 for b in self.points(ax)
               if abs((b.x0 + b.x1) / 2 - x) < 0.5 and abs((b.y0 + b.y1) / 2 - y) < 0.5]
        gap = max([gap] + [(h + PAD + 1) * 72.0 / self.fig.dpi for h in own])
        for strict in (True, False):          # first where it crosses no line, then anywhere free
            for dx, dy in offsets:
                t = ax.annotate(text, xy, xycoords=transform or "data", xytext=(dx * gap, dy * gap),
                                textcoords="offset points", ha=HA[dx], va=VA[dy], fontsize=fontsize,
                                color=color, annotation_clip=False, **kw)
                b = text_box(t, self.r)
                if b is not None and self.free(ax, b) and not (
                        strict and any(crosses(b, p, q) for p, q in self.segments(ax))):
                    self.taken.append(b)
                    return t
                t.remove()
        return None


def save_png(fig, path, dpi=100, max_bytes=None) -> int:
    """Write `fig` as a palette PNG (256 colours, fewer if needed to stay under max_bytes); returns
    the size in bytes."""
    from PIL import Image
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    img = Image.open(io.BytesIO(buf.getvalue())).convert("RGB")
    for colours in (256, 128, 64, 32):
        data = io.BytesIO()
        img.quantize(colors=colours, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE) \
           .save(data, format="png", optimize=True)
        if max_bytes is None or data.tell() <= max_bytes:
            break
    with open(path, "wb") as f:
        f.write(data.getvalue())
    return data.tell()
