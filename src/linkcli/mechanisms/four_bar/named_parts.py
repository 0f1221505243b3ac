"""The names [springs], [dampers] and [dynamics] use on a four-bar (docs/dynamics.md). Pure
Python (`check` reads them without numpy)."""

from __future__ import annotations

from linkcli.dynamics.model import Parts

CARRIED = {"A0": ("ground", "input"), "A": ("input", "coupler"), "B": ("coupler", "output"),
           "B0": ("ground", "output")}


def parts(root, kind: str) -> Parts:
    """Joints A0, A, B, B0 (and the coupler point P when the linkage has one); links input,
    coupler, output; pins A0, A, B, B0; counterweights on input and output (Berkof-Lowen)."""
    from linkcli.io.loads import has_coupler_point
    points = dict(CARRIED)
    if has_coupler_point(root, kind):
        points["P"] = ("coupler",)
    return Parts(points=points, links=("input", "coupler", "output"), pins=tuple(CARRIED),
                 counterweighted=("input", "output"))
