"""The five-bar has no dynamics: two drives (two degrees of freedom) and no modelled loads
(docs/dynamics.md). Pure Python."""

from __future__ import annotations

from linkcli.dynamics.model import Parts


def parts(root, kind: str) -> Parts:
    return Parts(points={}, links=(), pins=(),
                 refused="a one-drive linkage (four-bar, slider-crank or a drawn linkage with one "
                         "turning drive): the five-bar's two drives and its loads are not modelled")
