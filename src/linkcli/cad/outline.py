"""A link's outline for CAD: the pins it carries wrapped at a distance r = width / 2 --
the convex hull of the pin centres offset outward by r, i.e. a straight segment along
each hull edge and an arc around each hull vertex (for a bar of two pins, the familiar
slot: two lines and two half circles). Counter-clockwise; pure numpy.
"""

from __future__ import annotations

import math

import numpy as np


def hull(points) -> np.ndarray:
    """Convex hull of (m, 2) points, counter-clockwise, no collinear vertices (Andrew's
    monotone chain); two points when they are all on one line, one when they coincide."""
    pts = sorted({(float(x), float(y)) for x, y in np.asarray(points, dtype=float)})
    if len(pts) <= 2:
        return np.array(pts, dtype=float).reshape(-1, 2)

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1], dtype=float)


def outline(points, width: float) -> list[tuple]:
    """The outline of a link carrying `points` (m, 2) with `width`: ("line", start, end)
    and ("arc", centre, radius, start_deg, end_deg) pieces, counter-clockwise, arcs from
    start_deg to end_deg counter-clockwise (DXF's ARC)."""
    r = 0.5 * float(width)
    v = hull(points)
    if len(v) == 1:
        return [("arc", tuple(v[0]), r, 0.0, 360.0)]
    m = len(v)
    normals = []
    for i in range(m):
        d = v[(i + 1) % m] - v[i]
        d = d / math.hypot(*d)
        normals.append(np.array([d[1], -d[0]]))  # outward of a counter-clockwise edge
    pieces: list[tuple] = []
    for i in range(m):
        n_in, n_out = normals[i - 1], normals[i]
        start = math.degrees(math.atan2(n_in[1], n_in[0])) % 360.0
        end = math.degrees(math.atan2(n_out[1], n_out[0])) % 360.0
        pieces.append(("arc", tuple(v[i]), r, start, end))
        pieces.append(("line", tuple(v[i] + r * n_out), tuple(v[(i + 1) % m] + r * n_out)))
    return pieces
