"""Hypervolume and knee of a front (minimization; docs/pareto.md).

Hypervolume: the measure of the region dominated by the front and bounded by the reference
point r (Zitzler & Thiele, "Multiobjective optimization using evolutionary algorithms: a
comparative case study", PPSN V, 1998), computed exactly: two objectives, the sum of the
rectangles of the points sorted by the first; three, slices along the third (each slice's
two-objective area times its depth: Fonseca, Paquete & Lopez-Ibanez, "An improved
dimension-sweep algorithm for the hypervolume indicator", CEC 2006, without their tree).
Points not strictly better than r in every objective add nothing.

The reference point, unless the file gives one: r_k = worst_k + REFERENCE_MARGIN (worst_k -
best_k) over the rows (the nadir pushed out by a tenth of the front's extent, so that the
extreme rows count), r_k = worst_k + REFERENCE_MARGIN |worst_k| (or + REFERENCE_MARGIN) when
the front has no extent in k.

Knee: the row farthest from the line (two objectives) or plane (three) through the extreme
rows (each objective's best), after each objective is normalized by its range over the rows
(Das, "On characterizing the 'knee' of the Pareto curve based on normal-boundary
intersection", Struct. Optim. 18 (1999); Branke et al., "Finding knees in multi-objective
optimization", PPSN VIII, 2004): the distance to the line through the normalized extremes;
a front of two rows or fewer, or one on that line: the row nearest the normalized ideal
point (0, ..., 0). Ties (within TIE) go to the first row.
"""

from __future__ import annotations

import numpy as np

REFERENCE_MARGIN = 0.1
TIE = 1e-9
KNEE_RULE = ("farthest from the line (2 objectives) or plane (3) through the extreme rows, each "
             "objective normalized by its range over the rows; on it (or 2 rows or fewer): nearest "
             "the normalized ideal point")


def reference_point(values: np.ndarray) -> np.ndarray:
    """The default reference point (module docstring)."""
    best, worst = values.min(axis=0), values.max(axis=0)
    extent = worst - best
    pad = np.where(extent > 0, extent, np.where(worst != 0, np.abs(worst), 1.0))
    return worst + REFERENCE_MARGIN * pad


def hypervolume(values: np.ndarray, ref) -> float:
    """The hypervolume of points (n, 2 or 3) against ref (minimization)."""
    ref = np.asarray(ref, dtype=float)
    pts = np.asarray(values, dtype=float)
    pts = pts[np.all(pts < ref, axis=1)]
    if not len(pts):
        return 0.0
    if pts.shape[1] == 2:
        return _area(pts, ref)
    order = np.argsort(pts[:, 2], kind="stable")
    pts = pts[order]
    total = 0.0
    for i in range(len(pts)):  # slice between the i-th third value and the next (or ref)
        top = pts[i + 1, 2] if i + 1 < len(pts) else ref[2]
        depth = top - pts[i, 2]
        if depth > 0:
            total += _area(pts[:i + 1, :2], ref[:2]) * depth
    return float(total)


def _area(pts: np.ndarray, ref: np.ndarray) -> float:
    """The area dominated by 2-D points against ref."""
    order = np.lexsort((pts[:, 1], pts[:, 0]))
    area, floor = 0.0, ref[1]
    for x, y in pts[order]:
        if y < floor:
            area += (ref[0] - x) * (floor - y)
            floor = y
    return float(area)


def knee(values: np.ndarray) -> int:
    """The knee row's index (module docstring)."""
    v = np.asarray(values, dtype=float)
    n, m = v.shape
    lo, hi = v.min(axis=0), v.max(axis=0)
    span = np.where(hi > lo, hi - lo, 1.0)
    z = (v - lo) / span
    ideal = np.sqrt(np.sum(z * z, axis=1))
    if n <= 2:
        return _first(-ideal)
    extremes = [int(np.argmin(v[:, k] + TIE * np.sum(z, axis=1))) for k in range(m)]
    base = z[extremes[0]]
    directions = np.array([z[e] - base for e in extremes[1:]])
    basis = []  # Gram-Schmidt (no LAPACK: the same bits on every machine)
    for d in directions:
        v = d.copy()
        for q in basis:
            v = v - float(np.dot(v, q)) * q
        norm = float(np.sqrt(np.dot(v, v)))
        if norm > TIE:
            basis.append(v / norm)
    rel = z - base
    off = rel.copy()
    for q in basis:
        off = off - np.outer(rel @ q, q)
    dist = np.sqrt(np.sum(off * off, axis=1))
    if float(dist.max()) <= TIE:
        return _first(-ideal)
    return _first(dist)


def _first(score: np.ndarray) -> int:
    """The first index whose score is within TIE of the largest."""
    top = float(np.max(score))
    return int(np.flatnonzero(score >= top - TIE * max(abs(top), 1.0))[0])
