"""Plane vectors over rows ((..., 2) arrays): a quarter turn, the cross and dot products, a
turn by rows of cos and sin, and the rates of a direction's angle. numpy only.
"""

from __future__ import annotations

import numpy as np


def perp(v: np.ndarray) -> np.ndarray:
    """v turned by +90 deg."""
    return np.stack([-v[..., 1], v[..., 0]], axis=-1)


def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 0] + u[..., 1] * v[..., 1]


def rotate(v: np.ndarray, c: np.ndarray, s: np.ndarray) -> np.ndarray:
    """R(theta) v for rows of cos, sin (v a (2,) point or (n, 2) rows)."""
    v = np.asarray(v, dtype=float)
    return np.stack([v[..., 0] * c - v[..., 1] * s, v[..., 0] * s + v[..., 1] * c], axis=-1)


def direction_rates(v, dv, ddv):
    """(arg v, d/dt arg v, d2/dt2 arg v) for rows of a vector and its rates."""
    n2 = dot(v, v)
    w = cross(v, dv) / n2
    return np.arctan2(v[..., 1], v[..., 0]), w, cross(v, ddv) / n2 - 2.0 * dot(v, dv) * w / n2
