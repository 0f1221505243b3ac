"""The names [springs], [dampers] and [dynamics] use on a slider-crank (docs/dynamics.md).
Pure Python (`check` reads them without numpy)."""

from __future__ import annotations

from linkcli.dynamics.model import Parts

CARRIED = {"A0": ("ground", "input"), "A": ("input", "coupler"), "B": ("coupler", "slider")}


def parts(root, kind: str) -> Parts:
    """Joints A0, A, B (the slider pin; and the coupler point P when the linkage has one);
    turning links input and coupler (the slider only translates); pins A0, A, B (the guide
    is no pin: its friction needs no diameter)."""
    from linkcli.io.loads import has_coupler_point
    points = dict(CARRIED)
    if has_coupler_point(root, kind):
        points["P"] = ("coupler",)
    return Parts(points=points, links=("input", "coupler"), pins=tuple(CARRIED))
