"""The descriptions the figures need, taken from this project's co-simulation code: a SceneInfo
per scene of scripts/cosim/scenes.py (title, error labels, t_end, θ), the method labels of
scripts/cosim/master.py, and the stability map's closed forms. The only module of the package
that imports scripts/cosim (the drawing modules get plain values from it); it needs scripts/ on
sys.path.
"""
from __future__ import annotations

from .describe import scene_info


def descriptions():
    """{'infos': {scene: SceneInfo}, 'labels': {method: label}, 'bound': f(method, ζ),
    'rho': f(method, ωH), 'stability_labels': {method: legend entry}} (what publish() takes)."""
    from cosim.master import LABELS
    from cosim.scenes import SCENES, Oscillator, amplification, bound_closed_form, spectral_radius

    def rho(method, h):
        if method == "rollback" and h * h / 6 >= 1:
            return float("inf")              # the iteration diverges
        return spectral_radius(amplification(method, h, 0.0))

    theta = getattr(Oscillator, "theta", 1.0)
    stab = {m: m + (f" (θ = {theta:g})" if m.startswith("linear_implicit") else "") for m in LABELS}
    return {"infos": {name: scene_info(s, LABELS) for name, s in SCENES.items()},
            "labels": dict(LABELS), "bound": bound_closed_form, "rho": rho, "stability_labels": stab}
