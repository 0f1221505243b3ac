"""The Grashof class and the transmission window of a motion-generation design as smooth
constraint functions g <= 0 (length unit), for the least-squares search to hold them,
not only to screen its results (screen.py judges the result the same way).

Design vector x (..., 10 + ...) in PARAM_NAMES order: ground d = x[3], input a = x[4],
coupler b = x[5], output c = x[6]; the input angles phi (..., n) at the poses.

- Grashof class with shortest link s (crank-rocker: the input; double-crank: the ground;
  rocker-crank: the output; double-rocker: the coupler): s + x_j - (the other two) <= 0
  for each other link x_j, which together say s is shortest and s + l <= p + q (Norton,
  Design of Machinery, sec. 2.12); triple-rocker: p + q - s - l <= 0 (sorted lengths).
  Each held CLASS_MARGIN (relative to p + q) inside, off the change point: sums within
  kin.CHANGE_POINT_RTOL of each other are the change-point class, and a design settled on
  the limit would be judged that class by round-off.
- Transmission window [mu_lo, mu_hi]: cos(mu) = (b^2 + c^2 - rho^2) / (2 b c) falls as
  rho = |A B0| grows, so L (cos mu(rho_min) - cos mu_lo) <= 0 and
  L (cos mu_hi - cos mu(rho_max)) <= 0; rho over the full turn (|d - a| and d + a) when
  the class makes the input a crank, else rho at every pose (the working span's ends and
  its interior extremes at phi = 0, pi are among the poses or between them: the result's
  screen checks the span exactly).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin

FULL_TURN = ("crank-rocker", "double-crank")
CLASS_MARGIN = 2.0 * kin.CHANGE_POINT_RTOL  # relative to p + q: off the change point
WINDOW_TOL = 1e-12  # rad: a transmission angle this far outside its window is on it (round-off)
SHORTEST = {"crank-rocker": 4, "double-crank": 3, "rocker-crank": 6, "double-rocker": 5}  # x index


def count(grashof: str | None, window, n_poses: int) -> int:
    """How many constraint functions `values` returns."""
    k = 3 if grashof in SHORTEST else (1 if grashof == "triple-rocker" else 0)
    if window is not None:
        k += 2 if grashof in FULL_TURN else 2 * n_poses
    return k


def values(x, phi, grashof: str | None, window, scale: float) -> np.ndarray:
    """(..., count) constraint functions g (length unit; g <= 0 feasible)."""
    x = np.asarray(x, float)
    links = {j: x[..., j] for j in (3, 4, 5, 6)}
    cols = []
    if grashof in SHORTEST:
        k = SHORTEST[grashof]
        others = [j for j in (3, 4, 5, 6) if j != k]
        for j in others:
            rest = [o for o in others if o != j]
            pq = links[rest[0]] + links[rest[1]]
            cols.append(links[k] + links[j] - pq * (1.0 - CLASS_MARGIN))
    elif grashof == "triple-rocker":
        srt = np.sort(np.stack([links[j] for j in (3, 4, 5, 6)], axis=-1), axis=-1)
        pq = srt[..., 1] + srt[..., 2]
        cols.append(pq * (1.0 + CLASS_MARGIN) - srt[..., 0] - srt[..., 3])
    out = np.stack(cols, axis=-1) if cols else np.zeros(x.shape[:-1] + (0,))
    if window is None:
        return out
    d, a, b, c = (links[j][..., None] for j in (3, 4, 5, 6))
    if grashof in FULL_TURN:
        r2_min, r2_max = (d - a) ** 2, (d + a) ** 2
    else:
        r2_min = r2_max = kin.ground_distance(a, d, np.asarray(phi, float)) ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        cos_lo = (b * b + c * c - r2_min) / (2.0 * b * c)
        cos_hi = (b * b + c * c - r2_max) / (2.0 * b * c)
    return np.concatenate([out, scale * (cos_lo - math.cos(window[0])),
                           scale * (math.cos(window[1]) - cos_hi)], axis=-1)
