"""The small description the figures need of a scene, taken from a scene object of the caller's
(duck-typed: name, title, error_label, and where present t_end, theta, error2_label and
error_rigid_label), and the method labels the caller has (a dict base name -> label).

Uses only data.SceneInfo; imports nothing of scripts/cosim (the caller passes its objects in).
"""
from __future__ import annotations

from .data import SceneInfo

# further error columns a scene's CSV may hold: (column, the scene's attribute naming it, a label
# used when the scene has none)
SECOND_REFERENCES = (
    ("error2", "error2_label", "against a second reference (error2)"),
    ("error_rigid", "error_rigid_label", "against the rigid closed form (error_rigid)"),
)


def scene_info(scene, labels=None) -> SceneInfo:
    """SceneInfo of a scene object; further references are listed whether or not the CSV has them
    (a column without results is not drawn)."""
    second = []
    for column, attr, default in SECOND_REFERENCES:
        label = getattr(scene, attr, None)
        second.append((column, label or default))
    return SceneInfo(name=scene.name, title=getattr(scene, "title", "") or scene.name,
                     error_label=getattr(scene, "error_label", "") or "error",
                     t_end=getattr(scene, "t_end", None), theta=getattr(scene, "theta", None),
                     second=tuple(second), labels=dict(labels or {}))


def plain(name, labels=None) -> SceneInfo:
    """A SceneInfo from the name alone (when no scene object is at hand)."""
    return SceneInfo(name=name, title=name, second=tuple((c, d) for c, _, d in SECOND_REFERENCES),
                     labels=dict(labels or {}))
