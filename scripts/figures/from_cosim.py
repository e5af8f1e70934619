"""The descriptions the figures need, taken from this project's co-simulation code: a SceneInfo
per scene of scripts/cosim/scenes.py (title, error labels, t_end, θ), the method labels of
scripts/cosim/master.py, and the stability map's closed forms (scripts/stability_map.py). The
only module of the package that imports scripts/cosim and the chart scripts (the drawing modules
get plain values from it); it needs scripts/ on sys.path.
"""
from __future__ import annotations

from .describe import scene_info


def descriptions():
    """{'infos': {scene: SceneInfo}, 'labels': {method: label}, 'bound': f(method, ζ),
    'rho': f(method, ωH), 'stability_labels': {method: legend entry}} (what publish() takes)."""
    from cosim.master import LABELS
    from cosim.scenes import SCENES, Oscillator, bound_closed_form
    from stability_map import closed_rho

    theta = getattr(Oscillator, "theta", 1.0)
    stab = {m: m + (f" (θ = {theta:g})" if m.startswith("linear_implicit") else "") for m in LABELS}
    return {"infos": {name: scene_info(s, LABELS) for name, s in SCENES.items()},
            "labels": dict(LABELS), "bound": bound_closed_form, "rho": closed_rho, "stability_labels": stab}
