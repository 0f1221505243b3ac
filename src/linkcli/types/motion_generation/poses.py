"""Poses of a rigid body and the displacements between them (numpy only, vectorized).

A pose (x, y, angle) places the body frame: a body point m has the global position
T(m) = R(angle) m + (x, y). The displacement from pose i to pose j is the global rigid
motion D_ij = T_j T_i^-1, D_ij(p) = R(angle_j - angle_i)(p - o_i) + o_j. Its fixed point is
the pole P_ij (Sandor & Erdman, Advanced Mechanism Design vol. 2, sec. 2.3):

    (I - R) P = t   =>   P = (t + cot(theta / 2) J t) / 2,   J = rotation by +90 deg,

with D_ij(p) = R p + t; a pure translation (theta = 0) has its pole at infinity (NaN here).
"""

from __future__ import annotations

import numpy as np

POLE_MIN_ROTATION = 1e-12  # rad: |sin(theta / 2)| below this is a translation (pole at infinity)


def as_poses(poses) -> np.ndarray:
    """(n, 3) float array of poses (x, y, angle in rad)."""
    arr = np.asarray(poses, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"poses must have shape (n, 3), got {arr.shape}")
    return arr


def rotation(angle) -> np.ndarray:
    """Rotation matrices R(angle), shape angle.shape + (2, 2)."""
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)


def to_global(poses, points) -> np.ndarray:
    """T(m) = R(angle) m + o, broadcasting poses (..., 3) against body points (..., 2)."""
    poses = np.asarray(poses, dtype=float)
    points = np.asarray(points, dtype=float)
    c, s = np.cos(poses[..., 2]), np.sin(poses[..., 2])
    x = c * points[..., 0] - s * points[..., 1] + poses[..., 0]
    y = s * points[..., 0] + c * points[..., 1] + poses[..., 1]
    return np.stack([x, y], -1)


def to_body(poses, points) -> np.ndarray:
    """T^-1(p) = R(angle)^T (p - o), broadcasting like to_global."""
    poses = np.asarray(poses, dtype=float)
    points = np.asarray(points, dtype=float)
    c, s = np.cos(poses[..., 2]), np.sin(poses[..., 2])
    dx, dy = points[..., 0] - poses[..., 0], points[..., 1] - poses[..., 1]
    return np.stack([c * dx + s * dy, -s * dx + c * dy], -1)


def relative_displacement(pose_i, pose_j):
    """(theta, t) of D_ij = T_j T_i^-1 as D_ij(p) = R(theta) p + t; broadcasts."""
    pose_i, pose_j = np.asarray(pose_i, float), np.asarray(pose_j, float)
    theta = pose_j[..., 2] - pose_i[..., 2]
    c, s = np.cos(theta), np.sin(theta)
    xi, yi = pose_i[..., 0], pose_i[..., 1]
    t = np.stack([pose_j[..., 0] - (c * xi - s * yi), pose_j[..., 1] - (s * xi + c * yi)], -1)
    return theta, t


def pole(pose_i, pose_j) -> np.ndarray:
    """Pole P_ij (fixed point of D_ij); NaN for a pure translation. Broadcasts."""
    theta, t = relative_displacement(pose_i, pose_j)
    half = theta / 2.0
    s = np.sin(half)
    translation = np.abs(s) <= POLE_MIN_ROTATION
    cot = np.cos(half) / np.where(translation, 1.0, s)
    px = 0.5 * (t[..., 0] - cot * t[..., 1])
    py = 0.5 * (t[..., 1] + cot * t[..., 0])
    out = np.stack([px, py], -1)
    return np.where(translation[..., None], np.nan, out)


def poles(poses) -> np.ndarray:
    """All poles, shape (n, n, 2): poles[i, j] = P_ij (NaN on the diagonal)."""
    poses = as_poses(poses)
    return pole(poses[:, None, :], poses[None, :, :])


def characteristic_length(poses) -> float:
    """RMS distance of the pose origins from their centroid: the default angle weight w
    (a length) of the least-squares objective and the scale of every tolerance here.
    1.0 if every origin coincides (pure rotations about one point)."""
    origins = as_poses(poses)[:, :2]
    rms = float(np.sqrt(np.mean(np.sum((origins - origins.mean(0)) ** 2, -1))))
    return rms if rms > 0.0 else 1.0
