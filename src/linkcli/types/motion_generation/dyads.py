"""Dyads for rigid-body guidance: a ground pivot G (global) and a moving pivot M (body
frame) whose positions M_i = T_i(M) lie on one circle about G.

Equal distances written against pose 1 (index 0), with T_i(M) = R_i M + o_i:

    f_i(G, M) = |T_i M - G|^2 - |T_1 M - G|^2
              = k_i + g_i . G + m_i . M + M^T B_i G = 0,     i = 2..n,
    k_i = |o_i|^2 - |o_1|^2,  g_i = -2 (o_i - o_1),
    m_i = 2 (R_i^T o_i - R_1^T o_1),  B_i = -2 (R_i - R_1)^T.

|G|^2 and |M|^2 cancel: f_i is bilinear, linear in M for a given G (the inversion of
Sandor & Erdman, Advanced Mechanism Design vol. 2, sec. 2.6-2.7) and linear in G for a
given M (the perpendicular bisectors of M_1 M_i). The same dyad in Sandor & Erdman's
standard form (ch. 2): W (e^{i beta_j} - 1) + Z (e^{i alpha_j} - 1) = delta_j, W = M_1 - G,
Z = P_1 - M_1, alpha_j the body rotation, beta_j the link rotation, delta_j = P_j - P_1.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .poses import as_poses, characteristic_length, to_global

SINGULAR_RTOL = 1e-10  # relative determinant below this: the linear system is degenerate


@dataclass
class Coefficients:
    """f_i = k[i] + g[i] . G + m[i] . M + M^T B[i] G for the poses after the first."""

    k: np.ndarray  # (n-1,)
    g: np.ndarray  # (n-1, 2)
    m: np.ndarray  # (n-1, 2)
    B: np.ndarray  # (n-1, 2, 2)

    def residuals(self, ground, moving) -> np.ndarray:
        """f_i for G (..., 2) and M (..., 2): shape (..., n-1)."""
        ground, moving = np.asarray(ground, float), np.asarray(moving, float)
        bg = np.einsum("...iab,...b->...ia", self.B, ground)
        return (self.k + np.einsum("...ia,...a->...i", self.g, ground)
                + np.einsum("...ia,...a->...i", self.m, moving)
                + np.einsum("...a,...ia->...i", moving, bg))

    def moving_rows(self, ground) -> np.ndarray:
        """Rows [m_i + B_i G, k_i + g_i . G] of the system that is linear in (M, 1): (..., n-1, 3)."""
        ground = np.asarray(ground, float)
        lin = self.m + np.einsum("...iab,...b->...ia", self.B, ground)
        const = self.k + np.einsum("...ia,...a->...i", self.g, ground)
        return np.concatenate([lin, const[..., None]], -1)

    def ground_rows(self, moving) -> np.ndarray:
        """Rows [g_i + B_i^T M, k_i + m_i . M] of the system linear in (G, 1): (..., n-1, 3)."""
        moving = np.asarray(moving, float)
        lin = self.g + np.einsum("...iba,...b->...ia", self.B, moving)
        const = self.k + np.einsum("...ia,...a->...i", self.m, moving)
        return np.concatenate([lin, const[..., None]], -1)

    def jacobian(self, ground, moving) -> np.ndarray:
        """d f_i / d(G, M) at G (..., 2) and M (..., 2): rows [g_i + B_i^T M, m_i + B_i G],
        shape (..., n-1, 4)."""
        jg = self.g + np.einsum("...iba,...b->...ia", self.B, moving)
        jm = self.m + np.einsum("...iab,...b->...ia", self.B, ground)
        return np.concatenate([jg, jm], -1)

    def take(self, sets) -> Coefficients:
        """The coefficients of a stack of pose sets (`coefficients` of (S, n, 3)) picked by
        `sets`: one pose set a point, whose leading axes the points' then match."""
        return Coefficients(self.k[sets], self.g[sets], self.m[sets], self.B[sets])


def coefficients(poses) -> Coefficients:
    """The bilinear coefficients of f_i (module docstring) for poses (n, 3), or a stack of
    pose sets (..., n, 3) (each array then with the stack's leading axes)."""
    poses = np.asarray(poses, dtype=float)
    if poses.ndim < 2 or poses.shape[-1] != 3:
        raise ValueError(f"poses must have shape (n, 3), got {poses.shape}")
    o, ang = poses[..., :2], poses[..., 2]
    c, s = np.cos(ang), np.sin(ang)
    rt_o = np.stack([c * o[..., 0] + s * o[..., 1], -s * o[..., 0] + c * o[..., 1]], -1)  # R^T o
    rot = np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)
    k = np.sum(o[..., 1:, :] ** 2, -1) - np.sum(o[..., 0, :] ** 2, -1)[..., None]
    g = -2.0 * (o[..., 1:, :] - o[..., :1, :])
    m = 2.0 * (rt_o[..., 1:, :] - rt_o[..., :1, :])
    B = -2.0 * np.swapaxes(rot[..., 1:, :, :] - rot[..., :1, :, :], -1, -2)
    return Coefficients(k, g, m, B)


def circle_residuals(poses, ground, moving) -> np.ndarray:
    """|T_i M - G| - |T_1 M - G| for i = 2..n (a length): shape (..., n-1)."""
    poses = as_poses(poses)
    ground, moving = np.asarray(ground, float), np.asarray(moving, float)
    pts = to_global(poses, moving[..., None, :])  # (..., n, 2)
    r = np.linalg.norm(pts - ground[..., None, :], axis=-1)
    return r[..., 1:] - r[..., :1]


def standard_form(poses, ground, moving):
    """Sandor & Erdman's standard form of one dyad: (W, Z, alpha, beta, residual), W, Z
    complex, alpha_j, beta_j (j = 2..n) the body and link rotations from pose 1 and
    residual_j = W (e^{i beta_j} - 1) + Z (e^{i alpha_j} - 1) - delta_j (zero for a dyad)."""
    poses = as_poses(poses)
    pts = to_global(poses, np.asarray(moving, float))
    link = (pts[:, 0] - ground[0]) + 1j * (pts[:, 1] - ground[1])
    origin = poses[:, 0] + 1j * poses[:, 1]
    w, z = link[0], origin[0] - (pts[0, 0] + 1j * pts[0, 1])
    alpha = poses[1:, 2] - poses[0, 2]
    beta = np.angle(link[1:] / link[0])
    residual = w * (np.exp(1j * beta) - 1) + z * (np.exp(1j * alpha) - 1) - (origin[1:] - origin[0])
    return w, z, alpha, beta, residual


@dataclass
class DyadSolution:
    """A dyad found from given data, or why none: status "ok", "any" (every point is a
    solution: the data do not fix it) or "degenerate" (no finite solution)."""

    ground: np.ndarray
    moving: np.ndarray
    status: str
    message: str = ""


@dataclass
class Line:
    """Points p + t * direction (t real); status "ok", "any" (whole plane), "none"."""

    point: np.ndarray
    direction: np.ndarray
    status: str


def _line(normal, const) -> Line:
    """The line normal . X + const = 0."""
    nn = float(normal @ normal)
    scale = max(abs(const), 1.0)
    if nn <= (SINGULAR_RTOL * scale) ** 2:
        status = "any" if abs(const) <= SINGULAR_RTOL * scale else "none"
        return Line(np.full(2, np.nan), np.full(2, np.nan), status)
    return Line(-const * normal / nn, np.array([-normal[1], normal[0]]) / np.sqrt(nn), "ok")


def moving_pivot_line(poses, ground) -> Line:
    """Two poses, given G: M lies on the body-frame line f_2(G, M) = 0 ("any" if G is the pole)."""
    poses = as_poses(poses)[:2]
    row = coefficients(poses).moving_rows(np.asarray(ground, float))[0]
    return _line(row[:2], row[2])


def ground_pivot_line(poses, moving) -> Line:
    """Two poses, given M: G lies on the perpendicular bisector of M_1 M_2 ("any" if M_1 = M_2)."""
    poses = as_poses(poses)[:2]
    row = coefficients(poses).ground_rows(np.asarray(moving, float))[0]
    return _line(row[:2], row[2])


def _nearest_on(line: Line, near) -> np.ndarray:
    near = np.asarray(near, float)
    if line.status == "any":
        return near.copy()
    return line.point + ((near - line.point) @ line.direction) * line.direction


def two_pose_dyad(poses, ground=None, moving=None, near=None) -> DyadSolution:
    """Two poses, closed form. Given G: M is the point of its line nearest `near` (body frame,
    default the body origin). Given M: G is the point of the bisector nearest `near`
    (global, default the centroid of the two pose origins). Both given: checked."""
    poses = as_poses(poses)[:2]
    if (ground is None) == (moving is None):
        if ground is None:
            raise ValueError("two_pose_dyad needs the ground or the moving pivot")
        ground, moving = np.asarray(ground, float), np.asarray(moving, float)
        err = abs(float(circle_residuals(poses, ground, moving)[0]))
        ok = err <= 1e-9 * characteristic_length(poses)
        return DyadSolution(ground, moving, "ok" if ok else "degenerate",
                            "" if ok else f"pivots off the dyad condition by {err:.3g}")
    if ground is not None:
        ground = np.asarray(ground, float)
        line = moving_pivot_line(poses, ground)
        if line.status == "none":
            return DyadSolution(ground, np.full(2, np.nan), "degenerate",
                                "no moving pivot: the poses differ by a translation along the ground pivot's normal")
        moving = _nearest_on(line, np.zeros(2) if near is None else near)
        return DyadSolution(ground, moving, line.status,
                            "ground pivot at the pole: every moving pivot works" if line.status == "any" else "")
    moving = np.asarray(moving, float)
    line = ground_pivot_line(poses, moving)
    if line.status == "none":
        return DyadSolution(np.full(2, np.nan), moving, "degenerate", "no ground pivot")
    ground = _nearest_on(line, poses[:, :2].mean(0) if near is None else near)
    return DyadSolution(ground, moving, line.status,
                        "moving pivot does not move: every ground pivot works" if line.status == "any" else "")


def _solve2(rows):
    """Solve rows[..., :2] X = -rows[..., 2] (two rows), with a relative singularity flag."""
    mat, rhs = rows[..., :2, :2], -rows[..., :2, 2]
    det = mat[..., 0, 0] * mat[..., 1, 1] - mat[..., 0, 1] * mat[..., 1, 0]
    scale = np.max(np.abs(rows[..., :2, :]), axis=(-1, -2)) ** 2  # rows include the constant
    singular = np.abs(det) <= SINGULAR_RTOL * np.where(scale > 0, scale, 1.0)
    safe = np.where(singular, 1.0, det)
    x = (mat[..., 1, 1] * rhs[..., 0] - mat[..., 0, 1] * rhs[..., 1]) / safe
    y = (mat[..., 0, 0] * rhs[..., 1] - mat[..., 1, 0] * rhs[..., 0]) / safe
    out = np.stack([x, y], -1)
    return np.where(singular[..., None], np.nan, out), singular


def moving_pivots_for_ground(poses, ground):
    """Three poses, given G (..., 2): M by inversion, the two linear equations
    (m_i + B_i G) . M = -(k_i + g_i . G), i = 2, 3. Returns (M (..., 2), singular (...))
    with NaN where the system is singular (M at infinity or not unique: G on the pole
    triangle's circle of degenerate choices). Vectorized over G."""
    rows = coefficients(as_poses(poses)[:3]).moving_rows(ground)
    return _solve2(rows)


def ground_pivots_for_moving(poses, moving):
    """Three poses, given M (..., 2): G = circumcentre of M_1, M_2, M_3, the two linear
    equations (g_i + B_i^T M) . G = -(k_i + m_i . M). NaN where M_1, M_2, M_3 are collinear
    (a slider, not a crank) or coincide. Vectorized over M."""
    rows = coefficients(as_poses(poses)[:3]).ground_rows(moving)
    return _solve2(rows)


def three_pose_dyad(poses, ground=None, moving=None) -> DyadSolution:
    """Three poses, exactly one pivot given: the other by the linear system above."""
    poses = as_poses(poses)[:3]
    if (ground is None) == (moving is None):
        raise ValueError("three_pose_dyad needs exactly one of ground, moving")
    if ground is not None:
        ground = np.asarray(ground, float)
        moving, singular = moving_pivots_for_ground(poses, ground)
        if singular:
            return DyadSolution(ground, moving, "degenerate",
                                "the moving pivot is at infinity or not unique for this ground pivot")
        return DyadSolution(ground, moving, "ok")
    moving = np.asarray(moving, float)
    ground, singular = ground_pivots_for_moving(poses, moving)
    if singular:
        return DyadSolution(ground, moving, "degenerate",
                            "the moving pivot's three positions are collinear (the ground pivot is at infinity)")
    return DyadSolution(ground, moving, "ok")

