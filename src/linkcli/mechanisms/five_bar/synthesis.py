"""The five-bar along a path, vectorized over candidate designs (numpy only): what the
path-generation design of a five-bar (types/path_generation/five_bar_solve.py) scores.

A design x = (ground, input, input2, coupler, coupler2, pivot_x, pivot_y, ground_angle)
(VARIABLES; lengths in the length unit, the angle in rad) puts the path (M points, global
frame) into its local frame and solves both 2R chains in their working modes
(kinematics.inverse). Per candidate and row:

* quality, the larger the better, in [0, 1]: "conditioning", 1 / kappa (kappa the
  Jacobian's condition number: 1 isotropic, 0 on a singularity, the local conditioning
  index of Gosselin & Angeles 1991); "transmission", the sines of the three transmission
  angles (at P, at the elbows A and B: 1 at 90 deg, 0 on a singularity), each its own
  column, so that the worst of them is what counts;
* reach: each chain's margin to its workspace boundary, ((a + b)^2 - r^2)(r^2 - (a - b)^2)
  / (a + b)^4 (r = |P - pivot|), >= 0 where the chain reaches P;
* dips: per chain and segment between two rows, (closest distance of the straight segment
  to the pivot - |a - b|) / (a + b), >= 0 unless the segment enters the folded limit;
* side: cross(u, v) / (coupler coupler2) = sin of the angle from A P to B P, whose sign is
  the assembly mode: it must keep the sign of the first row (no type II crossing).

The design's score is the worst quality over the rows (and columns).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.five_bar import kinematics as kin

VARIABLES = ("ground", "input", "input2", "coupler", "coupler2", "pivot_x", "pivot_y", "ground_angle")
MEASURES = ("conditioning", "transmission")


@dataclass
class Along:
    """Candidates x rows: quality (N, M, J) (J = 1 or 3 columns), reach (N, 2, M), dips
    (N, 2, M - 1), side (N, M), and the poses (kinematics.Pose, (N, M))."""

    quality: np.ndarray
    reach: np.ndarray
    dips: np.ndarray
    side: np.ndarray
    pose: kin.Pose

    def worst(self) -> np.ndarray:
        """(N,) the worst quality over rows and columns."""
        return self.quality.min(axis=(1, 2))

    def violation(self, sign=None) -> np.ndarray:
        """(N,) the sum of the constraints' shortfalls: reach, dips, and the side kept (the
        sign of each candidate's first row, or `sign`)."""
        s = np.sign(self.side[:, :1]) if sign is None else np.asarray(sign, dtype=float).reshape(-1, 1)
        s = np.where(s == 0, 1.0, s)
        return (np.maximum(0.0, -self.reach).sum(axis=(1, 2)) + np.maximum(0.0, -self.dips).sum(axis=(1, 2))
                + np.maximum(0.0, -s * self.side).sum(axis=1))


def unpack(x: np.ndarray):
    """(lengths tuple of (N, 1) columns, pivot_x, pivot_y, ground_angle (N, 1))."""
    cols = [x[:, i:i + 1] for i in range(len(VARIABLES))]
    return tuple(cols[:5]), cols[5], cols[6], cols[7]


def along(x: np.ndarray, path: np.ndarray, modes: tuple[float, float], measure: str) -> Along:
    """Every row of the path for every candidate x (N, 8) (module docstring)."""
    lengths, gx, gy, ga = unpack(np.asarray(x, dtype=float))
    d, a1, a2, b1, b2 = lengths
    c, s = np.cos(ga), np.sin(ga)
    X, Y = path[None, :, 0] - gx, path[None, :, 1] - gy
    lx, ly = c * X + s * Y, -s * X + c * Y
    pose, _, _ = kin.inverse(lengths, lx, ly, *modes)
    with np.errstate(invalid="ignore", divide="ignore"):
        if measure == "conditioning":
            kappa = kin.condition(pose)
            quality = np.where(np.isfinite(kappa), 1.0 / kappa, 0.0)[..., None]
        else:
            quality = np.stack([np.sin(m) for m in pose.transmissions()], axis=-1)
    reach = np.stack([_reach(lx, ly, a1, b1), _reach(lx - d, ly, a2, b2)], axis=1)
    dips = np.stack([_dips(lx, ly, a1, b1), _dips(lx - d, ly, a2, b2)], axis=1)
    side = pose.det / (b1 * b2)
    return Along(quality, reach, dips, side, pose)


def _reach(x, y, a, b):
    r2 = x * x + y * y
    return ((a + b) ** 2 - r2) * (r2 - (a - b) ** 2) / (a + b) ** 4


def _dips(x, y, a, b):
    """(closest distance of each segment to the origin - |a - b|) / (a + b)."""
    x0, y0, dx, dy = x[:, :-1], y[:, :-1], np.diff(x, axis=1), np.diff(y, axis=1)
    length2 = dx * dx + dy * dy
    t = np.clip(-(x0 * dx + y0 * dy) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
    closest = np.hypot(x0 + t * dx, y0 + t * dy)
    return (closest - np.abs(a - b)) / (a + b)


def variances(tol) -> tuple[np.ndarray, float]:
    """((5,) the variance of each length's deviation, in VARIABLES order: uniform on [-t, t]
    t^2 / 3, normal with 3 sigma = t (t / 3)^2; the variance of each coordinate of a pin's
    offset, uniform over the disc of radius r: r^2 / 4)."""
    t = np.array([float(tol.lengths.get(k, 0.0)) for k in VARIABLES[:5]])
    var = t * t / 3.0 if tol.distribution == "uniform" else (t / 3.0) ** 2
    return var, float(tol.clearance) ** 2 / 4.0


def first_order_sigma(pose: kin.Pose, length_var: np.ndarray, pin_var: float) -> np.ndarray:
    """sqrt(E |dP|^2) at every row, to first order (the made-part model of tolerance.py):
    sum_i |dP/dl_i|^2 var_i over the lengths, plus pin_var (|G_A|_F^2 2 + |G_B|_F^2 3) for
    the clearance offsets that shift the left distal link's end A (pins A0, A) and the right
    one's B (pins B0, B, P), where G_A = dP/dA = [u; v]^-1 [u; 0] and G_B likewise; inf on
    a type II singularity."""
    part = kin.length_partials(pose)
    total = sum(v * (part[name][0] ** 2 + part[name][1] ** 2) for name, v in zip(VARIABLES[:5], length_var))
    if pin_var > 0:
        (ux, uy), (vx, vy) = pose.u, pose.v
        det = pose.det
        with np.errstate(divide="ignore", invalid="ignore"):
            # dP = [u; v]^-1 (u . dA, 0): |dP/dA|_F^2 = |u|^2 |v|^2 / det^2, likewise for B
            ga = (ux * ux + uy * uy) * (vx * vx + vy * vy) / (det * det)
        total = total + pin_var * 5.0 * ga
    return np.sqrt(total)
