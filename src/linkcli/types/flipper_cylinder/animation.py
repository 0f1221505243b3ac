"""The flipper has no linkage: what moves in its animation and CAD drawing is the platform
turning about its hinge B = (0, 0) and the cylinder from its base pivot C to the rod pivot
A, in the file's frame (as the report gives the pivots): at platform angle t,
X(t) = R(t - start) X_start for A and the centre of mass G (statics.py), C fixed.

As a Skeleton: ground B and C; links `platform` (B, A, G) and `cylinder` (C, A, its
length changing with the stroke); G is traced (its path). The drive rocks from start to
end (ghosted at its end); a CAD drawing shows the start position.
"""

from __future__ import annotations

import numpy as np

from linkcli.animate.scene import Drive, NothingToDraw
from linkcli.mechanisms.protocol import Skeleton, Study

PLATFORM_ANGLE = "platform angle"


def platform_skeleton(rod_pivot, base_pivot, centre, start: float):
    """Skeleton at platform angles t (rad, file's frame) of a platform whose rod pivot
    (and centre of mass, None without) are given at `start`."""
    a0 = np.asarray(rod_pivot, dtype=float)
    c = np.asarray(base_pivot, dtype=float)

    def skeleton(t) -> Skeleton:
        t = np.asarray(t, dtype=float)
        cos, sin = np.cos(t - start), np.sin(t - start)

        def turned(p):
            return np.stack([cos * p[0] - sin * p[1], sin * p[0] + cos * p[1]], axis=-1)

        shape = t.shape + (2,)
        joints = {"B": np.zeros(shape), "C": np.broadcast_to(c, shape).copy(), "A": turned(a0)}
        platform = ("B", "A")
        if centre is not None:
            joints["G"] = turned(np.asarray(centre, dtype=float))
            platform = ("B", "A", "G")
        return Skeleton(joints=joints, links={"platform": platform, "cylinder": ("C", "A")}, ground=("B", "C"),
                        valid=np.ones(t.shape, dtype=bool), traced=("G",) if centre is not None else ())
    return skeleton


def drive(result) -> Drive:
    """The platform's sweep from the report's cylinder design and the problem's [motion]."""
    from linkcli.plots.common import drawn
    problem = result.problem
    cyl = drawn(result).get("cylinder") or {}
    if "rod_pivot" not in cyl or "base_pivot" not in cyl:
        raise NothingToDraw("no cylinder design in the result")
    start, end = (float(problem.shown_angle(x)) for x in (problem.start, problem.end))
    com = getattr(problem, "center_of_mass", None)
    centre = None if com is None else (float(problem.shown_x(com[0])), float(com[1]))
    study = Study(full_turn=False, arc=(min(start, end), max(start, end)))
    return Drive(platform_skeleton(cyl["rod_pivot"], cyl["base_pivot"], centre, start), study,
                 PLATFORM_ANGLE, ghosts=(end,), reference=start)
