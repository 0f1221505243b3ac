"""The design box of a motion generator's many-pose search (least squares) and of its front,
in assemble.PARAM_NAMES order. numpy only.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.io.bounds import MAX_LENGTH

from . import least_squares


def design_box(problem, poses, scale):
    """(lo, hi) in assemble.PARAM_NAMES order: the file's bounds, the core's defaults
    (least_squares.default_bounds) elsewhere, a missing length bound raised to twice the
    distance from the poses' centroid to the farthest ground pivot allowed; given ground
    pivots are fixed."""
    lo, hi = least_squares.default_bounds(poses)
    lo, hi = np.maximum(lo, -MAX_LENGTH), np.minimum(hi, MAX_LENGTH)  # within the sizes any file accepts
    reach = 0.0  # a missing length bound must reach the poses from the farthest ground pivot allowed
    cen = poses[:, :2].mean(0)
    corners = ([p for p in problem.ground_pivots] if problem.ground_pivots is not None else []) + (
        [(x, y) for x in problem.ground_pivot[0] for y in problem.ground_pivot[1]]
        if problem.ground_pivot is not None else [])
    if corners:
        reach = 2.0 * float(np.max(np.linalg.norm(np.array(corners, float) - cen, axis=1)))
    for k, name in ((3, "ground"), (4, "input"), (5, "coupler"), (6, "output")):
        r = problem.lengths.get(name)
        if r is not None:
            lo[k], hi[k] = max(r[0], 1e-6 * r[1]), r[1]
        else:
            hi[k] = min(max(hi[k], reach), MAX_LENGTH)
    if problem.ground_pivot is not None:
        (lo[0], hi[0]), (lo[1], hi[1]) = problem.ground_pivot
    if problem.ground_angle is not None:
        lo[2], hi[2] = problem.ground_angle
    if problem.ground_pivots is not None:
        a0, b0 = (np.array(p, float) for p in problem.ground_pivots)
        link = b0 - a0
        lo[0], lo[1] = hi[0], hi[1] = a0
        lo[2] = hi[2] = math.atan2(link[1], link[0])
        lo[3] = hi[3] = float(np.hypot(*link))
    return lo, hi
