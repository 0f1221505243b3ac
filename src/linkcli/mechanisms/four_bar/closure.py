"""The four-bar's loop closure as unit vectors, for the searches (numpy only): path
generation's candidates at every target, motion generation's body poses
(motion_generation.assemble.body_frames).

`four_bar.pose` gives the angles (arccos, two arctan2, then cos and sin of them again for
the coupler point); the searches need only directions, so this closure keeps them as
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

    def take(self, rows) -> Frame:
        """The closure of the candidates `rows` (indices into the first axis)."""
        return Frame(*(getattr(self, f.name)[rows] for f in fields(self)))

    def coupler_point(self, a, px, py):
        """Coupler point P = A + (px + i py) e^{i theta}, in the frame of A0 and B0."""
        return (a * self.cphi + px * self.ct - py * self.st,
                a * self.sphi + px * self.st + py * self.ct)


def frame(a, b, c, d, phi, sign) -> Frame:
    """The closure at input angles phi on the branch `sign` (-1 open, +1 crossed; arrays
    broadcast like the lengths). Written in place where it can be (a search calls it on
    every candidate at every target): the same operations in the same order as the
    equations above, so the same bits, with fewer temporaries."""
    cphi, sphi = np.cos(phi), np.sin(phi)
    ax, ay = a * cphi, a * sphi
    rx = ax - d
    rho = np.hypot(rx, ay)
    assembles = rho > 0.0
    safe = np.where(assembles, rho, 1.0)
    with np.errstate(over="ignore", invalid="ignore"):
        cos_alpha = rho * rho
        cos_alpha += c * c
        cos_alpha -= b * b
        cos_alpha /= safe * (2.0 * c)  # = 2 safe c: doubling is exact
    valid = np.abs(cos_alpha) <= 1.0 + ASSEMBLY_SLACK
    valid &= assembles
    ca = cos_alpha
    ca[np.isnan(ca)] = 1.0
    np.clip(ca, -1.0, 1.0, out=ca)
    sa = 1.0 - ca
    sa *= 1.0 + ca
    np.sqrt(sa, out=sa)
    sa = sign * sa
    with np.errstate(invalid="ignore", divide="ignore"):
        ux = np.divide(rx, safe, out=rx)
    ux[~assembles] = 1.0
    uy = np.divide(ay, safe, out=safe)
    cpsi, spsi = ux * ca, ux * sa
    cpsi -= uy * sa
    spsi += uy * ca
    bx = c * cpsi
    bx += d
    bx -= ax
    by = c * spsi
    by -= ay
    length = np.hypot(bx, by)
    long = length > 0.0
    safe_len = np.where(long, length, 1.0)
    ct = np.divide(bx, safe_len, out=bx)
    ct[~long] = 1.0
    st = np.divide(by, safe_len, out=by)
    shape = ct.shape
    return Frame(cphi=np.broadcast_to(cphi, shape), sphi=np.broadcast_to(sphi, shape), ct=ct, st=st,
                 cpsi=cpsi, spsi=spsi, rho=np.broadcast_to(rho, shape),
                 valid=np.broadcast_to(valid, shape))
