"""The five-bar's kinematic coefficients: every body's frame origin and angle, with their first
partial derivatives with respect to the two drive angles (phi1, phi2) and the mixed second ones,
from the closed forms of `kinematics` (written once for numpy rows and for Python floats).

Local frame (model.py): A = a1 e(phi1), B = B0 + a2 e(phi2), P = meet(A, B, b1, b2, side);
u = P - A, v = P - B, D = cross(u, v). The distal links keep their lengths, |u|^2 = b1^2 and
|v|^2 = b2^2; differentiated once and twice (Gosselin & Angeles 1990; the velocity and
acceleration systems of `kinematics`, per drive):

    u . P_j = u . A_j,                     v . P_j = v . B_j
    u . P_ij = u . A_ij - u_i . u_j,        v . P_ij = v . B_ij - v_i . v_j

(u_j = P_j - A_j, v_j = P_j - B_j), each a 2 x 2 system [u; v] X = r solved by Cramer's rule
with D. The cranks: A_1 = perp(A), A_11 = -A (A_2 = A_12 = A_22 = 0); B_2 = perp(B - B0),
B_22 = -(B - B0). A distal link turns at theta_j = cross(u, u_j) / b1^2 (u_j is normal to u),
theta_ij = cross(u, u_ij) / b1^2 (the right link: v, b2). Any velocity and acceleration follow:
x' = sum_j x_j w_j, x'' = sum_j x_j al_j + sum_ij x_ij w_i w_j (Uicker, Pennock & Shigley, Theory
of Machines and Mechanisms, ch. 4: kinematic coefficients, here of two inputs).

Bodies (the forces section's and the dynamics' names): `input` (frame A0 -> A, angle gamma +
phi1), `input2` (B0 -> B, gamma + phi2), `coupler` (A -> P), `coupler2` (B -> P), global frame
(A0 at ground_pivot, the ground line at gamma = ground_angle), lengths times `metres`.
`lock`: |sin| of the transmission angle at P (0 where the distal links are in line: type II,
the dead point of both drives); `watched`: |sin| at the elbows ("I left", "I right": type I,
a chain stretched or folded, which driven cranks pass).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.five_bar.kinematics import ASSEMBLY_SLACK
from linkcli.mechanisms.protocol import Coefficients, PointCoefficients

BODIES = ("input", "input2", "coupler", "coupler2")
WATCHED = ("I left", "I right")  # the type I singularities, as the kinematics rows name them


@dataclass(frozen=True)
class _Ops:
    """The functions the construction needs: numpy's over rows, or math's over floats."""

    cos: object
    sin: object
    sqrt: object
    hypot: object
    atan2: object
    maximum: object


NUMPY = _Ops(np.cos, np.sin, np.sqrt, np.hypot, np.arctan2, np.maximum)
FLOATS = _Ops(math.cos, math.sin, math.sqrt, math.hypot, math.atan2, max)


def _local(lengths, side: float, q1, q2, ops: _Ops) -> dict:
    """The construction of the module docstring in the local frame (rows or floats): points,
    first and second partials of A, B, P, the distal links' angles and rates, lock and
    watched sines, and `valid` (the distal links meet)."""
    d, a1, a2, b1, b2 = lengths
    ax, ay = a1 * ops.cos(q1), a1 * ops.sin(q1)
    rx, ry = a2 * ops.cos(q2), a2 * ops.sin(q2)  # B - B0
    bx, by = d + rx, ry
    dx, dy = bx - ax, by - ay
    c = ops.hypot(dx, dy)
    spread = abs(b1 - b2)
    outer = (b1 + b2 - c) * (b1 + b2 + c)
    inner = (c - spread) * (c + spread)
    slack = ASSEMBLY_SLACK * (b1 + b2) ** 2
    valid = (outer >= -slack) & (inner >= -slack) & (c > 0.0)
    h = ops.sqrt(ops.maximum(outer, 0.0) * ops.maximum(inner, 0.0)) / (2.0 * c)
    x = (c * c + (b1 - b2) * (b1 + b2)) / (2.0 * c)
    tx, ty = dx / c, dy / c
    px, py = ax + x * tx - side * h * ty, ay + x * ty + side * h * tx
    ux, uy = px - ax, py - ay
    vx, vy = px - bx, py - by
    det = ux * vy - uy * vx

    def along(r1, r2):
        return (vy * r1 - uy * r2) / det, (ux * r2 - vx * r1) / det

    lever1 = ax * uy - ay * ux  # u . A_1 = cross(A, u)
    lever2 = rx * vy - ry * vx  # v . B_2 = cross(B - B0, v)
    p1 = along(lever1, 0.0 * lever1)
    p2 = along(0.0 * lever2, lever2)
    u1, u2 = (p1[0] + ay, p1[1] - ax), p2
    v1, v2 = p1, (p2[0] + ry, p2[1] - rx)

    def dot(a, b):
        return a[0] * b[0] + a[1] * b[1]

    p11 = along(-(ux * ax + uy * ay) - dot(u1, u1), -dot(v1, v1))
    p12 = along(-dot(u1, u2), -dot(v1, v2))
    p22 = along(-dot(u2, u2), -(vx * rx + vy * ry) - dot(v2, v2))
    u11, u12, u22 = (p11[0] + ax, p11[1] + ay), p12, p22
    v11, v12, v22 = p11, p12, (p22[0] + rx, p22[1] + ry)

    def turn(w, w1, w2, w11, w12, w22, length2):
        def cross(b):
            return (w[0] * b[1] - w[1] * b[0]) / length2
        return ops.atan2(w[1], w[0]), (cross(w1), cross(w2)), ((cross(w11), cross(w12)), (cross(w12), cross(w22)))

    return {"A": (ax, ay), "r": (rx, ry), "B": (bx, by), "P": (px, py), "A1": (-ay, ax), "B2": (-ry, rx),
            "coupler": turn((ux, uy), u1, u2, u11, u12, u22, b1 * b1),
            "coupler2": turn((vx, vy), v1, v2, v11, v12, v22, b2 * b2),
            "lock": abs(det) / (b1 * b2), "watched": (abs(lever1) / (a1 * b1), abs(lever2) / (a2 * b2)),
            "valid": valid}


def _frames(fb, metres: float, q1, q2, ops: _Ops):
    """Every body's (origin, its partials, its second partials) and (angle, partials, second
    partials) in the global frame, as nested tuples of (x, y) pairs (rows or floats)."""
    lengths = tuple(v * metres for v in fb.lengths)
    side = 1.0 if fb.branch != "right" else -1.0
    loc = _local(lengths, side, q1, q2, ops)
    gamma = fb.ground_angle
    cg, sg = math.cos(gamma), math.sin(gamma)
    gx, gy = fb.ground_pivot[0] * metres, fb.ground_pivot[1] * metres

    def turned(p):
        return (cg * p[0] - sg * p[1], sg * p[0] + cg * p[1])

    def placed(p):
        t = turned(p)
        return (gx + t[0], gy + t[1])

    zero = 0.0 * q1
    z2 = (zero, zero)
    a, r = loc["A"], loc["r"]
    origin = {
        "input": (placed((zero, zero)), (z2, z2), ((z2, z2), (z2, z2))),
        "input2": (placed((zero + lengths[0], zero)), (z2, z2), ((z2, z2), (z2, z2))),
        "coupler": (placed(a), (turned(loc["A1"]), z2), ((turned((-a[0], -a[1])), z2), (z2, z2))),
        "coupler2": (placed(loc["B"]), (z2, turned(loc["B2"])), ((z2, z2), (z2, turned((-r[0], -r[1]))))),
    }
    one = zero + 1.0
    t3, t4 = loc["coupler"], loc["coupler2"]
    angle = {
        "input": (gamma + q1, (one, zero), ((zero, zero), (zero, zero))),
        "input2": (gamma + q2, (zero, one), ((zero, zero), (zero, zero))),
        "coupler": (gamma + t3[0], t3[1], t3[2]),
        "coupler2": (gamma + t4[0], t4[1], t4[2]),
    }
    return origin, angle, loc


def coefficients(fb, q, metres: float) -> Coefficients:
    """The coefficients at rows q (n, 2) of drive angles (phi1, phi2) (rad, local), numpy:
    origin[body] = (x (n, 2), dx (n, 2, 2), ddx (n, 2, 2, 2)), angle[body] = (theta (n,),
    dtheta (n, 2), ddtheta (n, 2, 2)); rows where the distal links do not meet, or lie in line,
    are not valid (their values are not finite or meaningless)."""
    q = np.asarray(q, dtype=float).reshape(-1, 2)
    with np.errstate(all="ignore"):
        origin, angle, loc = _frames(fb, metres, q[:, 0], q[:, 1], NUMPY)
        out_origin = {}
        for body, (x, first, second) in origin.items():
            out_origin[body] = (np.stack(x, axis=-1),
                                np.stack([np.stack(c, axis=-1) for c in first], axis=-1),
                                np.stack([np.stack([np.stack(c, axis=-1) for c in row], axis=-1)
                                          for row in second], axis=-1))
        out_angle = {body: (np.asarray(t, dtype=float), np.stack(first, axis=-1),
                            np.stack([np.stack(row, axis=-1) for row in second], axis=-1))
                     for body, (t, first, second) in angle.items()}
        lock = loc["lock"]
        valid = np.asarray(loc["valid"], dtype=bool) & (lock > 0) & np.isfinite(lock)
        for body in BODIES:
            valid &= np.all(np.isfinite(out_origin[body][2]), axis=(1, 2, 3))
            valid &= np.all(np.isfinite(out_angle[body][2]), axis=(1, 2))
    return Coefficients(q=q, origin=out_origin, angle=out_angle, valid=valid,
                        lock=np.where(valid, lock, 0.0),
                        watched={name: np.where(valid, value, 0.0) for name, value in zip(WATCHED, loc["watched"])})


def coefficients_at(fb, q, metres: float) -> PointCoefficients:
    """The coefficients at one state q = (phi1, phi2) in Python floats (the integrator's hot
    path): the same construction as `coefficients`, not valid where the distal links do not
    meet or lie in line."""
    q1, q2 = float(q[0]), float(q[1])
    try:
        origin, angle, loc = _frames(fb, metres, q1, q2, FLOATS)
    except ZeroDivisionError:  # A on B, or the distal links exactly in line: no rates
        return PointCoefficients(origin={}, angle={}, lock=0.0, watched={name: 0.0 for name in WATCHED},
                                 valid=False)
    valid = bool(loc["valid"]) and loc["lock"] > 0.0
    return PointCoefficients(origin=origin, angle=angle, lock=loc["lock"] if valid else 0.0,
                             watched=dict(zip(WATCHED, loc["watched"])), valid=valid)
