"""How a coupling method looks on every figure: its family (from its name, one table), its colour
(one hue per family, a shade per method), its marker, its line, and the FMI version of a run
(`method@fmi3` = the same method through FMI 3.0, drawn as the hollow marker of that method).

Uses only the standard library and matplotlib's colour names; reads no CSV and imports nothing
of scripts/cosim (the method names are plain strings).
"""
from __future__ import annotations

from dataclasses import dataclass

FMI3_SUFFIX = "@fmi3"

# THE table: method name (or '*suffix') -> family, first match wins; a new method needs one line
# here, or none if a rule already covers it. Anything not matched is implicit/iterative.
FAMILY_OF = (
    ("*_ev", "event"),              # event-located: the macro step is cut at the FMU's event
    ("zoh", "explicit"),
    ("extrapolation", "explicit"),
    ("jacobi", "explicit"),
    ("linear_implicit", "implicit"),
    ("rollback", "implicit"),
)
DEFAULT_FAMILY = "implicit"

# per family: heading, line style, and the shades of its hue (dark to light, all legible on white)
FAMILIES = {
    "explicit": ("explicit", "-", ("#d94801", "#a63603", "#f16913", "#7f2704", "#fd8d3c")),
    "implicit": ("implicit / iterative", "-", ("#08519c", "#4292c6", "#08306b", "#2171b5", "#6baed6")),
    "event": ("event-located", "--", ("#238b45", "#00441b", "#52bd8f", "#5c8d1a", "#006d5b", "#86c06c")),
}
FAMILY_ORDER = ("explicit", "implicit", "event")
MARKERS = ("o", "s", "D", "^", "v", "P", "X", "*", "p", "h", "<", ">")
# matplotlib marker -> plotly symbol (the report page)
PLOTLY_SYMBOL = {"o": "circle", "s": "square", "D": "diamond", "^": "triangle-up",
                 "v": "triangle-down", "P": "cross", "X": "x", "*": "star", "p": "pentagon",
                 "h": "hexagon", "<": "triangle-left", ">": "triangle-right"}


def split(method: str) -> tuple[str, int]:
    """'linear_exact_ev@fmi3' -> ('linear_exact_ev', 3); 'zoh' -> ('zoh', 2)."""
    if method.endswith(FMI3_SUFFIX):
        return method[:-len(FMI3_SUFFIX)], 3
    return method, 2


def family(method: str) -> str:
    """The family key ('explicit', 'implicit', 'event') of a method name (with or without @fmi3)."""
    base = split(method)[0]
    for pattern, fam in FAMILY_OF:
        if (pattern.startswith("*") and base.endswith(pattern[1:])) or base == pattern:
            return fam
    return DEFAULT_FAMILY


def _table_rank(base: str) -> int:
    for i, (pattern, _) in enumerate(FAMILY_OF):
        if base == pattern:
            return i
    return len(FAMILY_OF)


@dataclass(frozen=True)
class Look:
    """How one base method is drawn."""
    color: str
    marker: str
    ls: str
    family: str


class Styles:
    """Colours and markers of a set of methods, assigned once so that every figure drawn with the
    same Styles shows a method alike: within a family, methods in table order, then by name."""

    def __init__(self, methods):
        bases = sorted({split(m)[0] for m in methods},
                       key=lambda b: (FAMILY_ORDER.index(family(b)), _table_rank(b), b))
        self.looks: dict[str, Look] = {}
        used = {f: 0 for f in FAMILIES}
        n_marker = 0
        for base in bases:
            fam = family(base)
            _, ls, shades = FAMILIES[fam]
            self.looks[base] = Look(shades[used[fam] % len(shades)], MARKERS[n_marker % len(MARKERS)],
                                    ls, fam)
            used[fam] += 1
            n_marker += 1

    def look(self, method: str) -> Look:
        base = split(method)[0]
        if base not in self.looks:          # a method the Styles was not built with: still drawn
            fam = family(base)
            _, ls, shades = FAMILIES[fam]
            self.looks[base] = Look(shades[-1], MARKERS[len(self.looks) % len(MARKERS)], ls, fam)
        return self.looks[base]

    def bases(self):
        """Base methods in legend order (family, then table order)."""
        return list(self.looks)


def fmt_h(H: float) -> str:
    """A macro step for a point label: '10 ms', '0.5 ms', '20 µs'."""
    if H >= 1.0:
        return f"{H:g} s"
    if H >= 1e-4 * 0.999:
        return f"{H * 1e3:g} ms"
    return f"{H * 1e6:g} µs"


def fmi_version(method: str) -> str:
    return "3.0" if split(method)[1] == 3 else "2.0"
