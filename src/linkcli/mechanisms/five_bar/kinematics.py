"""The planar five-bar, vectorized over rows and samples (numpy only).

Local frame (model.py): A0 = (0, 0), B0 = (d, 0); A = a1 e^{i phi1}, B = B0 + a2 e^{i phi2}
(d = ground, a1 = input, a2 = input2, b1 = coupler = |A P|, b2 = coupler2 = |B P|).

Positions. Both the forward and the inverse problem are one construction, `meet`: the point
at distance r1 from a centre C1 and r2 from C2 on a given side of the line C1 -> C2. With
c = |C1 C2| and t, n the unit vectors along and to the left of C1 -> C2,

    X = C1 + x t + s h n,   x = (c^2 + r1^2 - r2^2) / (2 c),
    h = sqrt((r1 + r2 - c)(r1 + r2 + c)(c - |r1 - r2|)(c + |r1 - r2|)) / (2 c)

(s = +1 left, -1 right; the product form keeps full precision where the circles touch).
Forward: P = meet(A, B, b1, b2, branch). Inverse, one 2R chain at a time: the elbow
A = meet(A0, P, a1, b1, mode1), B = meet(B0, P, a2, b2, mode2), then phi1 = arg A,
phi2 = arg(B - B0) (Tsai, Robot Analysis, 1999, sec. 2.5: the planar 2R chain).

Rates. With u = P - A and v = P - B, differentiating |u|^2 = b1^2 and |v|^2 = b2^2 gives

    u . dP = u . dA,   v . dP = v . dB                                   (velocity)
    u . aP = u . aA - |vP - vA|^2,   v . aP = v . aB - |vP - vB|^2        (acceleration)

one 2 x 2 system [u; v] X = (r1, r2) (`along`). For unit input speeds dA = A x k (the crank
turned), so the Jacobian J = dP/d(phi1, phi2) has columns
J_1 = cross(A, u) (v_y, -v_x) / D and J_2 = cross(B - B0, v) (-u_y, u_x) / D, D = cross(u, v)
(Gosselin & Angeles, "Singularity analysis of closed-loop kinematic chains", IEEE Trans.
Robotics and Automation 6(3), 1990: J = Jx^-1 Jq). Singularities: type I (serial,
det Jq = 0) where a chain is stretched or folded, cross(A, u) = 0 or cross(B - B0, v) = 0,
the workspace boundary; type II (parallel, det Jx = D = 0) where the distal links are in
line. Condition number of J (2 x 2, closed form): with T = |J|_F^2 and
T^2 - 4 det^2 = ((j11 - j22)^2 + (j12 + j21)^2)((j11 + j22)^2 + (j12 - j21)^2),
kappa = (T + sqrt(T^2 - 4 det^2)) / (2 |det|), in [1, inf]; it is that of D J (the same
matrix scaled), so it stays finite-or-inf without dividing by D.

Transmission angles: at P between the distal links, at each elbow between crank and distal
link, each the angle of a triangle from its three sides (four_bar.kinematics.
transmission_angle): mu_P from (b1, b2, |A B|), mu_A from (a1, b1, |A0 P|), mu_B from
(a2, b2, |B0 P|); 0 or 180 deg is a singularity (type II at P, type I at an elbow).

Every function broadcasts: lengths of shape (N, 1) against rows of shape (M,) give (N, M).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.four_bar.kinematics import transmission_angle

ASSEMBLY_SLACK = 1e-12  # relative (to (r1 + r2)^2): circles that miss by round-off still meet
SINGULAR_SIN = 1e-9  # |sin| of a transmission angle at or below: on the singularity (rates inf)


def meet(c1x, c1y, c2x, c2y, r1, r2, side):
    """(x, y, valid): the point at distance r1 from C1 and r2 from C2 on `side` (+1: left of
    C1 -> C2, -1: right), by the formula of the module docstring. Where the circles do not
    meet, `valid` is False and the point is the nearest touching one (finite)."""
    dx, dy = c2x - c1x, c2y - c1y
    c = np.hypot(dx, dy)
    safe = np.where(c > 0.0, c, 1.0)
    spread = np.abs(r1 - r2)
    outer = (r1 + r2 - c) * (r1 + r2 + c)
    inner = (c - spread) * (c + spread)
    slack = ASSEMBLY_SLACK * (r1 + r2) ** 2
    valid = (outer >= -slack) & (inner >= -slack) & (c > 0.0)
    h = np.sqrt(np.maximum(outer, 0.0) * np.maximum(inner, 0.0)) / (2.0 * safe)
    x = (c * c + (r1 - r2) * (r1 + r2)) / (2.0 * safe)
    tx, ty = dx / safe, dy / safe
    return c1x + x * tx - side * h * ty, c1y + x * ty + side * h * tx, valid


def cross(ax, ay, bx, by):
    """z component of a x b."""
    return ax * by - ay * bx


def along(ux, uy, vx, vy, r1, r2, det):
    """X with u . X = r1 and v . X = r2 (det = cross(u, v) != 0): Cramer's rule."""
    return (vy * r1 - uy * r2) / det, (ux * r2 - vx * r1) / det


@dataclass
class Pose:
    """The five-bar at rows (local frame): elbows A, B, output point P (x, y arrays of the
    broadcast shape), the drive angles and where it assembles (`valid`). `lengths` = (d, a1,
    a2, b1, b2), each broadcastable against the rows."""

    phi1: np.ndarray
    phi2: np.ndarray
    ax: np.ndarray
    ay: np.ndarray
    bx: np.ndarray
    by: np.ndarray
    px: np.ndarray
    py: np.ndarray
    valid: np.ndarray
    lengths: tuple

    @property
    def u(self):
        """P - A (the left distal link)."""
        return self.px - self.ax, self.py - self.ay

    @property
    def v(self):
        """P - B (the right distal link)."""
        return self.px - self.bx, self.py - self.by

    @property
    def det(self):
        """D = cross(u, v) = b1 b2 sin(angle from u to v): 0 on a type II singularity."""
        return cross(*self.u, *self.v)

    def levers(self):
        """(cross(A - A0, u), cross(B - B0, v)): each input's lever on P, 0 where its
        chain is stretched or folded (type I)."""
        d = self.lengths[0]
        return cross(self.ax, self.ay, *self.u), cross(self.bx - d, self.by, *self.v)

    def coupler_angles(self):
        """(theta1, theta2): directions of A -> P and B -> P."""
        return np.arctan2(self.u[1], self.u[0]), np.arctan2(self.v[1], self.v[0])

    def transmissions(self):
        """(mu_P, mu_A, mu_B) in [0, pi] (module docstring)."""
        d, a1, a2, b1, b2 = self.lengths
        return (transmission_angle(b1, b2, np.hypot(self.bx - self.ax, self.by - self.ay)),
                transmission_angle(a1, b1, np.hypot(self.px, self.py)),
                transmission_angle(a2, b2, np.hypot(self.px - d, self.py)))

    def modes(self):
        """Each chain's working mode as a sign: +1 when its elbow lies left of the line from
        its ground pivot to P, -1 right, 0 on the line (the chain stretched or folded)."""
        d = self.lengths[0]
        left = cross(self.px, self.py, self.ax, self.ay)
        right = cross(self.px - d, self.py, self.bx - d, self.by)
        return np.sign(left), np.sign(right)

    def side(self):
        """+1 where P lies left of A -> B, -1 right, 0 on the line (type II)."""
        return np.sign(cross(self.bx - self.ax, self.by - self.ay, *self.u))


def cranks(d, a1, a2, phi1, phi2):
    """Elbows (ax, ay, bx, by) at the drive angles."""
    return a1 * np.cos(phi1), a1 * np.sin(phi1), d + a2 * np.cos(phi2), a2 * np.sin(phi2)


def forward(lengths, phi1, phi2, side: float) -> Pose:
    """P at drive angles (phi1, phi2) on the branch `side` (+1 left of A -> B, -1 right)."""
    d, a1, a2, b1, b2 = (np.asarray(v, dtype=float) for v in lengths)
    phi1, phi2 = np.asarray(phi1, dtype=float), np.asarray(phi2, dtype=float)
    ax, ay, bx, by = cranks(d, a1, a2, phi1, phi2)
    px, py, valid = meet(ax, ay, bx, by, b1, b2, side)
    shape = np.broadcast_shapes(np.shape(px), np.shape(phi1), np.shape(phi2))
    return Pose(np.broadcast_to(phi1, shape), np.broadcast_to(phi2, shape),
                *(np.broadcast_to(x, shape) for x in (ax, ay, bx, by, px, py)),
                np.broadcast_to(valid, shape), (d, a1, a2, b1, b2))


def inverse(lengths, px, py, mode1: float, mode2: float) -> tuple[Pose, np.ndarray, np.ndarray]:
    """The drive angles that put P at (px, py) (local frame) with the chains in their working
    modes (+1/-1, model.py): (pose, reach1, reach2), reach_k where chain k reaches P."""
    d, a1, a2, b1, b2 = (np.asarray(v, dtype=float) for v in lengths)
    px, py = np.asarray(px, dtype=float), np.asarray(py, dtype=float)
    ax, ay, reach1 = meet(0.0, 0.0, px, py, a1, b1, mode1)
    bx, by, reach2 = meet(d, 0.0, px, py, a2, b2, mode2)
    phi1, phi2 = np.arctan2(ay, ax), np.arctan2(by, bx - d)
    shape = np.broadcast_shapes(np.shape(ax), np.shape(bx))
    pose = Pose(*(np.broadcast_to(x, shape) for x in (phi1, phi2, ax, ay, bx, by, px, py)),
                np.broadcast_to(reach1 & reach2, shape), (d, a1, a2, b1, b2))
    return pose, reach1, reach2


# ---------------------------------------------------------------- rates

def _singular(p: Pose):
    """Where the rates are undefined: a type II singularity (|sin mu_P| <= SINGULAR_SIN)."""
    b1, b2 = p.lengths[3], p.lengths[4]
    return np.abs(p.det) <= SINGULAR_SIN * b1 * b2


def jacobian(p: Pose):
    """((j11, j21), (j12, j22)): the columns dP/dphi1 and dP/dphi2 (length per rad, local
    frame), inf on a type II singularity."""
    (ux, uy), (vx, vy) = p.u, p.v
    lever1, lever2 = p.levers()
    bad = _singular(p)
    det = np.where(bad, 1.0, p.det)
    zero = np.zeros_like(lever1)
    c1 = along(ux, uy, vx, vy, lever1, zero, det)
    c2 = along(ux, uy, vx, vy, zero, lever2, det)
    return tuple(tuple(np.where(bad, np.inf, x) for x in col) for col in (c1, c2))


def condition(p: Pose):
    """Condition number of J (module docstring): 1 (isotropic) .. inf (a singularity)."""
    (ux, uy), (vx, vy) = p.u, p.v
    lever1, lever2 = p.levers()
    # D J = [[v_y l1, -u_y l2], [-v_x l1, u_x l2]]: the same condition number, never inf
    m11, m12, m21, m22 = vy * lever1, -uy * lever2, -vx * lever1, ux * lever2
    t = m11 * m11 + m12 * m12 + m21 * m21 + m22 * m22
    det = np.abs(m11 * m22 - m12 * m21)
    spread = np.sqrt(((m11 - m22) ** 2 + (m12 + m21) ** 2) * ((m11 + m22) ** 2 + (m12 - m21) ** 2))
    d, a1, a2, b1, b2 = p.lengths
    on = (_singular(p) | (np.abs(lever1) <= SINGULAR_SIN * a1 * b1)
          | (np.abs(lever2) <= SINGULAR_SIN * a2 * b2))
    with np.errstate(divide="ignore", invalid="ignore"):
        kappa = (t + spread) / (2.0 * np.where(on, 1.0, det))
    return np.where(on, np.inf, kappa)


def velocity(p: Pose, w1, w2):
    """P's velocity (local frame, length per s) for drive speeds w1, w2 (rad/s): J w."""
    (j11, j21), (j12, j22) = jacobian(p)
    with np.errstate(invalid="ignore"):
        return j11 * w1 + j12 * w2, j21 * w1 + j22 * w2


def acceleration(p: Pose, w1, w2, al1, al2):
    """P's acceleration (local frame, length per s^2) for drive speeds w (rad/s) and
    accelerations al (rad/s^2), by the second system of the module docstring; inf on a
    type II singularity."""
    d = p.lengths[0]
    (ux, uy), (vx, vy) = p.u, p.v
    bad = _singular(p)
    det = np.where(bad, 1.0, p.det)
    lever1, lever2 = p.levers()
    with np.errstate(invalid="ignore"):
        vpx, vpy = along(ux, uy, vx, vy, lever1 * w1, lever2 * w2, det)
        # crank pins: vA = w1 k x A, aA = al1 k x A - w1^2 A (about A0; B about B0)
        rx, ry = p.bx - d, p.by
        vax, vay = -w1 * p.ay, w1 * p.ax
        vbx, vby = -w2 * ry, w2 * rx
        aax, aay = -al1 * p.ay - w1 * w1 * p.ax, al1 * p.ax - w1 * w1 * p.ay
        abx, aby = -al2 * ry - w2 * w2 * rx, al2 * rx - w2 * w2 * ry
        r1 = ux * aax + uy * aay - ((vpx - vax) ** 2 + (vpy - vay) ** 2)
        r2 = vx * abx + vy * aby - ((vpx - vbx) ** 2 + (vpy - vby) ** 2)
        apx, apy = along(ux, uy, vx, vy, r1, r2, det)
    return np.where(bad, np.inf, apx), np.where(bad, np.inf, apy)


def length_partials(p: Pose) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """dP/dl (local frame, length per length) for each link at fixed drive angles, from
    u . dP = u . dA + b1 db1 and v . dP = v . dB + b2 db2 (dA = e1 da1; dB = e2 da2 + x dd:
    a longer ground moves B0 along the ground line); inf on a type II singularity."""
    d, a1, a2, b1, b2 = p.lengths
    (ux, uy), (vx, vy) = p.u, p.v
    bad = _singular(p)
    det = np.where(bad, 1.0, p.det)
    zero = np.zeros_like(ux)
    rhs = {"ground": (zero, vx), "input": ((ux * p.ax + uy * p.ay) / a1, zero),
           "input2": (zero, (vx * (p.bx - d) + vy * p.by) / a2),
           "coupler": (b1 + zero, zero), "coupler2": (zero, b2 + zero)}
    out = {}
    for name, (r1, r2) in rhs.items():
        x, y = along(ux, uy, vx, vy, r1, r2, det)
        out[name] = (np.where(bad, np.inf, x), np.where(bad, np.inf, y))
    return out


# ---------------------------------------------------------------- the workspace

def type_two_curve(lengths, phi1, mode1: float, mode2: float):
    """Points P (local frame, (2, n) arrays x, y; NaN where none) where the distal links are
    in line (type II), swept over phi1, kept only where both chains are in the given working
    modes: for each phi1, B lies on the crank circle about B0 at |A B| = b1 + b2 or |b1 - b2|
    (both intersections), and P on the line A B at b1 from A."""
    d, a1, a2, b1, b2 = (float(v) for v in lengths)
    ax, ay = a1 * np.cos(phi1), a1 * np.sin(phi1)
    xs, ys = [], []

    def keep(px, py, ax, ay, bx, by, ok):
        m1 = np.sign(cross(px, py, ax, ay))
        m2 = np.sign(cross(px - d, py, bx - d, by))
        good = ok & (m1 == mode1) & (m2 == mode2)
        xs.append(np.where(good, px, np.nan))
        ys.append(np.where(good, py, np.nan))

    for reach, sign in ((b1 + b2, 1.0), (abs(b1 - b2), -1.0 if b1 < b2 else 1.0)):
        if reach <= CHANGE_POINT_RTOL * (b1 + b2):
            # equal distal links folded: A on B, where the crank circles cross; P anywhere on
            # the circle of radius b1 about that point (phi1 sweeps it)
            for side in (1.0, -1.0):
                cx, cy, ok = meet(0.0, 0.0, d, 0.0, a1, a2, side)
                px, py = cx + b1 * np.cos(phi1), cy + b1 * np.sin(phi1)
                keep(px, py, cx, cy, cx, cy, np.full(np.shape(phi1), bool(ok)))
            continue
        for side in (1.0, -1.0):
            bx, by, ok = meet(ax, ay, d, 0.0, reach, a2, side)
            px = ax + sign * b1 * (bx - ax) / reach
            py = ay + sign * b1 * (by - ay) / reach
            keep(px, py, ax, ay, bx, by, ok)
    return np.array(xs), np.array(ys)


# ---------------------------------------------------------------- class

LINK_NAMES = ("ground", "input", "input2", "coupler", "coupler2")
CLASSES = ("grashof", "change-point", "non-grashof")
CHANGE_POINT_RTOL = 1e-9  # as the four-bar's: the sums equal within this (relative) meet


def grashof(lengths) -> dict:
    """The five-bar Grashof criterion (Ting, "Five-bar Grashof criteria", ASME J. Mech. Trans.
    Autom. Des. 108, 1986): with s1 <= s2 the two shortest links, l the longest and p, q the
    other two, the linkage is of class I ("grashof": the two shortest links can turn fully
    relative to every other link) when s1 + s2 + l < p + q, of class II ("non-grashof")
    when s1 + s2 + l > p + q, and "change-point" when the two sums are equal within a
    relative 1e-9 (the five links can lie in line). Lengths equal within the tie rule
    (noise.same) are one length: the first in the order ground, input, input2, coupler,
    coupler2 is named."""
    from linkcli.noise import same
    values = [float(v) for v in lengths]
    order: list[int] = []
    for _ in range(2):
        rest = [i for i in range(5) if i not in order]
        low = min(values[i] for i in rest)
        order.append(next(i for i in rest if same(values[i], low)))
    high = max(values)
    longest = next(i for i in range(5) if same(values[i], high) and i not in order)
    others = [i for i in range(5) if i not in order and i != longest]
    short_long = values[order[0]] + values[order[1]] + values[longest]
    other = values[others[0]] + values[others[1]]
    if abs(short_long - other) <= CHANGE_POINT_RTOL * other:
        kind = "change-point"
    else:
        kind = "grashof" if short_long < other else "non-grashof"
    return {"class": kind, "shortest": [LINK_NAMES[order[0]], LINK_NAMES[order[1]]],
            "longest": LINK_NAMES[longest], "two_shortest_plus_longest": short_long,
            "other_two": other}
