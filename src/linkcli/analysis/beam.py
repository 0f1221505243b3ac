"""Internal forces of a binary link taken as a straight beam between its two joints (docs/
strength.md), at every row at once.

The link's axis runs from its first joint to its second (x along it, y to its left). Every
load on the link (protocol.LinkLoad: pin forces, a coupler force, the drive's or a load's
torque, its mass's weight and inertia at the centre) is carried to the axis: at x = (Q - J1) . e
as an axial force F . e, a transverse force F . n and the couple C - y (F . e) (a force off the
axis, at y = (Q - J1) . n, turns the beam too). With the loads sorted along x, the internal
axial force (tension positive) and bending moment (the moment of everything to its left about
the cut) just right of load k are, by the equilibrium of that part (shear-force and
bending-moment diagrams: Shigley's Mechanical Engineering Design, "load and stress analysis",
or any strength of materials text):

    N_k = - sum_{j <= k} F_a,j,        M_k(x) = sum_{j <= k} (C'_j - (x - x_j) F_t,j)

M is linear between loads, so its extremes over the link -- and those of the fibre stress
N/A +- M/Z -- lie at the ends of the segments between consecutive loads, where they are
evaluated. A link's loads are fixed points of the link, so their order along x is the same at
every row.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class BeamForces(NamedTuple):
    axial: np.ndarray  # (n, S) N, tension positive, on each of the S segments between loads
    moment: np.ndarray  # (n, S, 2) N m at the left and right end of each segment
    length: float  # m, between the two joints (the column length)


def internal_forces(loads, valid) -> BeamForces:
    """The internal forces of a link whose `loads` start with its two joints' (the axis runs
    from the first to the second); `valid` (n,) marks the rows that count (the order of the
    loads along the axis and the length are taken at the first of them)."""
    first, second = loads[0].at, loads[1].at
    axis = second - first
    with np.errstate(invalid="ignore", divide="ignore"):
        length = np.hypot(axis[:, 0], axis[:, 1])
        e = axis / length[:, None]
    normal = np.stack([-e[:, 1], e[:, 0]], axis=-1)
    at = np.stack([load.at for load in loads], axis=1) - first[:, None, :]  # (n, K, 2)
    force = np.stack([load.force for load in loads], axis=1)
    couple = np.stack([load.couple for load in loads], axis=1)
    x = np.einsum("nkj,nj->nk", at, e)
    y = np.einsum("nkj,nj->nk", at, normal)
    f_axial = np.einsum("nkj,nj->nk", force, e)
    f_normal = np.einsum("nkj,nj->nk", force, normal)
    moment = couple - y * f_axial
    first_valid = int(np.argmax(valid)) if np.any(valid) else 0  # the positions are the link's own
    order = np.argsort(x[first_valid], kind="stable")
    x, f_axial, f_normal, moment = x[:, order], f_axial[:, order], f_normal[:, order], moment[:, order]
    shear = np.cumsum(f_normal, axis=1)[:, :-1]
    lever = np.cumsum(f_normal * x, axis=1)[:, :-1]
    turned = np.cumsum(moment, axis=1)[:, :-1]
    left = turned + lever - x[:, :-1] * shear
    right = turned + lever - x[:, 1:] * shear
    axial = -np.cumsum(f_axial, axis=1)[:, :-1]
    return BeamForces(axial, np.stack([left, right], axis=-1), float(length[first_valid]))
