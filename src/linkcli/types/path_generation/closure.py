"""The four-bar's loop closure as unit vectors, for the path search (numpy only).

`four_bar.pose` gives the angles (arccos, two arctan2, then cos and sin of them again for
the coupler point); the search needs only directions, so this closure keeps them as
cosine-sine pairs (the conventions of docs/format.md, the same construction):

    A = a e^{i phi},  rho e^{i theta_rho} = A - d,
    cos alpha = (rho^2 + c^2 - b^2) / (2 rho c),  sin alpha = sqrt((1 - cos)(1 + cos)),
    e^{i psi} = e^{i theta_rho} (cos alpha + i sign sin alpha)   (sign -1 open, +1 crossed),
    e^{i theta} = (d + c e^{i psi} - A) / |d + c e^{i psi} - A|.

Where the linkage cannot assemble, cos alpha is clipped to [-1, 1] (the nearest toggle,
as `four_bar.pose`) and `valid` is False. Five transcendental calls per point instead of
ten.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from linkcli.mechanisms.four_bar.kinematics import ASSEMBLY_SLACK


@dataclass
class Frame:
    """The linkage at input angles phi: unit vectors of the crank (cphi, sphi), the
    coupler (ct, st: A -> B) and the output (cpsi, spsi), rho = |A B0| and whether it
    assembles; every array has the broadcast shape of the lengths and the angles."""

    cphi: np.ndarray
    sphi: np.ndarray
    ct: np.ndarray
    st: np.ndarray
    cpsi: np.ndarray
    spsi: np.ndarray
    rho: np.ndarray
    valid: np.ndarray

    def take(self, rows) -> "Frame":
        """The closure of the candidates `rows` (indices into the first axis)."""
        return Frame(*(getattr(self, f.name)[rows] for f in fields(self)))

    def coupler_point(self, a, px, py):
        """Coupler point P = A + (px + i py) e^{i theta}, in the frame of A0 and B0."""
        return (a * self.cphi + px * self.ct - py * self.st,
                a * self.sphi + px * self.st + py * self.ct)


def frame(a, b, c, d, phi, sign) -> Frame:
    """The closure at input angles phi on the branch `sign` (-1 open, +1 crossed; arrays
    broadcast like the lengths). Lengths are square roots of sums of squares (exactly
    rounded, as `hypot`, but a third of its time; the lengths a file accepts are far from
    overflow), and each length divides once (its reciprocal multiplies both components)."""
    cphi, sphi = np.cos(phi), np.sin(phi)
    ax, ay = a * cphi, a * sphi
    rx = ax - d
    rho2 = rx * rx + ay * ay
    rho = np.sqrt(rho2)
    apart = rho > 0.0
    inv_rho = 1.0 / np.where(apart, rho, 1.0)
    with np.errstate(over="ignore", invalid="ignore"):
        cos_alpha = (rho2 + (c * c - b * b)) * inv_rho / (2.0 * c)
    valid = (np.abs(cos_alpha) <= 1.0 + ASSEMBLY_SLACK) & apart
    ca = np.clip(cos_alpha, -1.0, 1.0)
    ca[np.isnan(ca)] = 1.0  # 0 / 0 (a zero coupler and rocker): a toggle, not assembled
    sa = sign * np.sqrt((1.0 - ca) * (1.0 + ca))
    ux, uy = np.where(apart, rx * inv_rho, 1.0), ay * inv_rho
    cpsi, spsi = ux * ca - uy * sa, ux * sa + uy * ca
    bx, by = d + c * cpsi - ax, c * spsi - ay
    length = np.sqrt(bx * bx + by * by)
    joined = length > 0.0
    inv_len = 1.0 / np.where(joined, length, 1.0)
    ct, st = np.where(joined, bx * inv_len, 1.0), by * inv_len
    shape = ct.shape
    return Frame(cphi=np.broadcast_to(cphi, shape), sphi=np.broadcast_to(sphi, shape), ct=ct, st=st,
                 cpsi=cpsi, spsi=spsi, rho=np.broadcast_to(rho, shape),
                 valid=np.broadcast_to(valid, shape))
