"""The planar four-bar, vectorized over angles and over candidate populations (numpy only).

Conventions (the conventions of docs/format.md): A0 at the origin, B0 = (d, 0); a = input, b = coupler,
c = output, d = ground. Loop closure a e^{i phi} + b e^{i theta} = d + c e^{i psi}.
With rho = |A B0| and theta_rho the direction of B0 -> A,

    cos(alpha) = (rho^2 + c^2 - b^2) / (2 rho c),   psi = theta_rho -+ alpha  (open / crossed)
    cos(mu)    = (b^2 + c^2 - rho^2) / (2 b c)       (transmission angle at B)

Velocities and accelerations are the closed-form derivatives of the loop equation
(Norton, Design of Machinery, ch. 6-7):

    w3 = a w2 sin(psi - phi) / (b sin(theta - psi)),  w4 = a w2 sin(phi - theta) / (c sin(psi - theta))

Every function broadcasts: lengths of shape (N, 1) against angles of shape (M,) give (N, M).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from linkcli.angles import TWO_PI, WRAP_SNAP, wrap  # noqa: F401  (the one wrap, kin.wrap to its users)

# |cos alpha| up to 1 + ASSEMBLY_SLACK still assembles (clipped): round-off at a toggle.
ASSEMBLY_SLACK = 1e-12
TOGGLE_RTOL = 64 * 2.0**-52  # relative: rho this close to b + c or |b - c| is a toggle


@dataclass
class Pose:
    """The linkage at input angles phi: every array has the broadcast shape. The
    transmission angle mu is computed when first asked for (most searches need only rho)."""

    phi: np.ndarray
    psi: np.ndarray  # output angle
    theta: np.ndarray  # coupler angle (direction A -> B)
    rho: np.ndarray  # |A B0|
    valid: np.ndarray  # bool: the linkage assembles here
    b: np.ndarray  # coupler and output lengths (broadcastable), for mu
    c: np.ndarray
    ax: np.ndarray | None = None  # the crank pin A = a e^{i phi}, as computed by `pose`
    ay: np.ndarray | None = None
    _mu: np.ndarray | None = field(default=None, repr=False)

    @property
    def mu(self) -> np.ndarray:
        """Transmission angle, [0, pi] (`transmission_angle`)."""
        if self._mu is None:
            self._mu = np.broadcast_to(transmission_angle(self.b, self.c, self.rho), self.psi.shape)
        return self._mu

    def coupler_point(self, a, px, py):
        """Coupler point P = A + px e^{i theta} + py i e^{i theta}, local frame."""
        if self.ax is not None:
            ax, ay = self.ax, self.ay
        else:
            ax, ay = a * np.cos(self.phi), a * np.sin(self.phi)
        ct, st = np.cos(self.theta), np.sin(self.theta)
        return ax + px * ct - py * st, ay + px * st + py * ct


def transmission_angle(b, c, rho):
    """mu in [0, pi] from cos(mu) = (b^2 + c^2 - rho^2) / (2 b c), by its half angle

        tan(mu / 2) = sqrt((rho - |b - c|)(rho + |b - c|)) / sqrt((b + c - rho)(b + c + rho)),

    which keeps full precision near mu = 0 and 180 deg, where arccos loses half the digits.
    rho outside [|b - c|, b + c] gives the nearest limit, 0 or pi."""
    b, c, rho = (np.asarray(v, dtype=float) for v in (b, c, rho))
    lo = np.abs(b - c)
    num = np.sqrt(np.maximum((rho - lo) * (rho + lo), 0.0))
    den = np.sqrt(np.maximum((b + c - rho) * (b + c + rho), 0.0))
    return 2.0 * np.arctan2(num, den)


def ground_distance(a, d, phi):
    """rho = |A B0| = sqrt((a - d)^2 + 4 a d sin^2(phi / 2)): the law of cosines written
    without the cancellation of a^2 + d^2 - 2 a d cos(phi) when a ~ d and phi ~ 0."""
    s = np.sin(np.asarray(phi, dtype=float) / 2.0)
    return np.sqrt((a - d) ** 2 + 4.0 * a * d * s * s)


def branch_sign(branch) -> float:
    """-1 for the open branch (psi = theta_rho - alpha), +1 for crossed."""
    if isinstance(branch, str):
        return -1.0 if branch == "open" else 1.0
    return np.asarray(branch, dtype=float)


def pose(a, b, c, d, phi, branch="open") -> Pose:
    """Closure of the loop at input angles phi on a branch (the conventions of docs/format.md).

    `branch` is "open", "crossed", or an array of signs (-1 open, +1 crossed) that
    broadcasts like the lengths. Where the linkage cannot assemble, `valid` is False and
    the angles are those of the nearest toggle (finite, never NaN).
    """
    a, b, c, d, phi = (np.asarray(v, dtype=float) for v in (a, b, c, d, phi))
    ax, ay = a * np.cos(phi), a * np.sin(phi)
    rx, ry = ax - d, ay
    rho = np.hypot(rx, ry)
    theta_rho = np.arctan2(ry, rx)
    safe_rho = np.where(rho > 0.0, rho, 1.0)
    with np.errstate(over="ignore"):  # a rho of 1e-300 gives inf: no assembly, said by `valid`
        cos_alpha = (rho * rho + c * c - b * b) / (2.0 * safe_rho * c)
    valid = (np.abs(cos_alpha) <= 1.0 + ASSEMBLY_SLACK) & (rho > 0.0)
    alpha = np.arccos(np.clip(cos_alpha, -1.0, 1.0))
    psi = theta_rho + branch_sign(branch) * alpha
    bx = d + c * np.cos(psi) - ax
    by = c * np.sin(psi) - ay
    theta = np.arctan2(by, bx)
    return Pose(phi=np.broadcast_to(phi, psi.shape), psi=psi, theta=theta, rho=rho,
                valid=np.broadcast_to(valid, psi.shape), b=b, c=c, ax=ax, ay=ay)


DEAD_CENTRE_SIN = 1e-9  # |sin(psi - theta)| at or below: coupler and output in line


def velocities(a, b, c, p: Pose, w2):
    """Angular velocities (w3 coupler, w4 output) for input speed w2 (closed form).

    Undefined at a dead centre of the output (coupler and output in line, |sin(psi -
    theta)| <= DEAD_CENTRE_SIN, which holds round-off at a change point too): returned as
    inf there, never NaN or a quotient of round-off errors.
    """
    s = np.sin(p.psi - p.theta)
    dead = np.abs(s) <= DEAD_CENTRE_SIN
    with np.errstate(divide="ignore", invalid="ignore"):
        w3 = a * w2 * np.sin(p.psi - p.phi) / (b * -s)
        w4 = a * w2 * np.sin(p.phi - p.theta) / (c * s)
    return np.where(dead, np.inf, w3), np.where(dead, np.inf, w4)


def accelerations(a, b, c, p: Pose, w2, alpha2=0.0):
    """Angular accelerations (alpha3, alpha4) from the differentiated loop equation.

    i b a3 e^{i theta} - i c a4 e^{i psi} = K, K = -a(i alpha2 - w2^2) e^{i phi}
    + b w3^2 e^{i theta} - c w4^2 e^{i psi}; project on e^{i psi} and e^{i theta}.
    """
    w3, w4 = velocities(a, b, c, p, w2)
    with np.errstate(divide="ignore", invalid="ignore"):
        kx = (a * w2 * w2 * np.cos(p.phi) + a * alpha2 * np.sin(p.phi)
              + b * w3 * w3 * np.cos(p.theta) - c * w4 * w4 * np.cos(p.psi))
        ky = (a * w2 * w2 * np.sin(p.phi) - a * alpha2 * np.cos(p.phi)
              + b * w3 * w3 * np.sin(p.theta) - c * w4 * w4 * np.sin(p.psi))
        s = np.sin(p.theta - p.psi)
        re_psi = kx * np.cos(p.psi) + ky * np.sin(p.psi)
        re_theta = kx * np.cos(p.theta) + ky * np.sin(p.theta)
        a3 = -re_psi / (b * s)
        a4 = re_theta / (c * -s)
    dead = np.abs(s) <= DEAD_CENTRE_SIN
    return np.where(dead, np.inf, a3), np.where(dead, np.inf, a4)


# ---------------------------------------------------------------- Grashof class

GRASHOF_CLASSES = ("crank-rocker", "rocker-crank", "double-crank", "double-rocker",
                   "change-point", "triple-rocker")
CHANGE_POINT_RTOL = 1e-9


def grashof_code(a, b, c, d):
    """Index into GRASHOF_CLASSES, vectorized: s + l vs p + q and which link is shortest."""
    links = np.stack(np.broadcast_arrays(*(np.asarray(v, float) for v in (a, b, c, d))))
    srt = np.sort(links, axis=0)
    s_plus_l = srt[0] + srt[3]
    p_plus_q = srt[1] + srt[2]
    shortest = np.argmin(links, axis=0)  # 0 input, 1 coupler, 2 output, 3 ground
    by_shortest = np.array([0, 3, 1, 2])[shortest]
    change = np.abs(s_plus_l - p_plus_q) <= CHANGE_POINT_RTOL * p_plus_q
    return np.where(change, 4, np.where(s_plus_l > p_plus_q, 5, by_shortest))


def same_lengths(x: float, y: float) -> bool:
    """Two lengths equal within the change-point tolerance (relative CHANGE_POINT_RTOL)."""
    return abs(x - y) <= CHANGE_POINT_RTOL * max(abs(x), abs(y))


def grashof(a, b, c, d) -> dict:
    """Grashof class of one linkage with the figures that decide it."""
    from linkcli.noise import same
    names = {"input": a, "coupler": b, "output": c, "ground": d}
    vals = sorted(names.values())
    # lengths equal within the tie rule (noise.same, relative 1e-9) are one length: the
    # first in the order input, coupler, output, ground is named, whatever the round-off
    shortest = next(k for k in names if same(names[k], vals[0]))
    longest = next(k for k in names if same(names[k], vals[3]))
    return {
        "class": GRASHOF_CLASSES[int(grashof_code(a, b, c, d))],
        "shortest": shortest,
        "longest": longest,
        "s_plus_l": vals[0] + vals[3],
        "p_plus_q": vals[1] + vals[2],
    }


# ---------------------------------------------------------------- range of motion

def input_arcs(a, b, c, d):
    """Reachable input angles: None if the input turns fully, [] if it never assembles,
    else a list of arcs (lo, hi), each running counter-clockwise from lo to hi (rad).

    rho^2 = (a - d)^2 + 4 a d sin^2(phi / 2) must lie in [(b - c)^2, (b + c)^2]; an arc
    ends where rho = r (r = b + c or |b - c|), at phi = 2 atan2(sqrt(N), sqrt(M)) with
    N = (r - |a - d|)(r + |a - d|), M = (a + d - r)(a + d + r): half-angle forms that keep
    full precision at toggles near 0 and 180 deg. Lengths are first divided by the
    longest (angles do not depend on scale), so no length can overflow.
    """
    big = max(a, b, c, d)
    a, b, c, d = (float(x) / big for x in (a, b, c, d))
    near, far = abs(a - d), a + d  # rho at phi = 0 and at phi = 180
    r_lo, r_hi = abs(b - c), b + c
    # a change point (two pairs of links of equal sum within CHANGE_POINT_RTOL, as
    # grashof() says) joins two arcs there: the input passes where all links are in line
    if abs(r_lo - near) <= CHANGE_POINT_RTOL * far:
        r_lo = near
    if abs(r_hi - far) <= CHANGE_POINT_RTOL * far:
        r_hi = far
    if r_lo <= near and r_hi >= far:
        return None
    if r_lo > far or r_hi < near:
        return []

    def end(r: float) -> float:
        n = max((r - near) * (r + near), 0.0)
        m = max((far - r) * (far + r), 0.0)
        return 2.0 * math.atan2(math.sqrt(n), math.sqrt(m))

    if r_lo <= near:  # one arc through phi = 0
        g = end(r_hi)
        return [(-g, g)]
    if r_hi >= far:  # one arc through phi = 180
        g = end(r_lo)
        return [(g, TWO_PI - g)]
    g1, g2 = end(r_lo), end(r_hi)
    return [(g1, g2), (-g2, -g1)]


def arc_contains(arc, phi) -> bool:
    lo, hi = arc
    return (np.mod(phi - lo, TWO_PI) <= (hi - lo) + 1e-12)


def choose_arc(arcs, near=None):
    """The arc holding angle `near` (default: the upper one, or the first)."""
    if near is not None:
        for arc in arcs:
            if arc_contains(arc, near):
                return arc
    return arcs[0]


def transmission_extremes(a, b, c, d, lo, hi):
    """(mu_min, phi_at_min, mu_max, phi_at_max) over the input arc lo -> hi (ccw).

    mu grows with rho and rho^2 = a^2 + d^2 - 2 a d cos(phi) is extreme only at phi = 0
    and phi = pi, so the extremes lie at the arc ends or at those two angles: no sampling.
    """
    cands = [lo, hi] + [x for x in (0.0, np.pi) if arc_contains((lo, hi), x)]
    phi = np.array(cands)
    rho = ground_distance(a, d, phi)
    mu = transmission_angle(b, c, rho)
    # an end of a rocking input's arc is a toggle (rho = b + c or |b - c|): the round-off of
    # its angle would cost sqrt(eps) in mu there, so a toggle met to round-off is exact
    toggle = TOGGLE_RTOL * (b + c)
    mu = np.where(np.abs(rho - (b + c)) <= toggle, np.pi, np.where(np.abs(rho - abs(b - c)) <= toggle, 0.0, mu))
    i, j = int(np.argmin(mu)), int(np.argmax(mu))
    return float(mu[i]), float(phi[i]), float(mu[j]), float(phi[j])


def collinear_inputs(a, b, c, d, branch):
    """Input angles where crank and coupler are collinear on the branch (output extremes).

    |A0 B| = a + b (extended) or |a - b| (folded); triangle A0 B0 B gives the angle of B,
    the sign is the one whose closure on the branch actually puts B there.
    """
    out = {}
    for name, length in (("extended", a + b), ("folded", abs(a - b))):
        cos_g = (length * length + d * d - c * c) / (2 * length * d) if length * d > 0 else 2.0
        if abs(cos_g) > 1.0 + 1e-12:
            continue
        g = float(np.arccos(np.clip(cos_g, -1, 1)))
        best = None
        for phi in (g, -g) if name == "extended" else (g + np.pi, -g + np.pi):
            p = pose(a, b, c, d, phi, branch)
            if not bool(p.valid):
                continue
            bx = d + c * np.cos(p.psi)
            by = c * np.sin(p.psi)
            miss = abs(np.hypot(bx, by) - length)
            if best is None or miss < best[0]:
                best = (miss, float(wrap(phi)))
        if best is not None and best[0] <= 1e-7 * max(a, b, c, d):
            out[name] = best[1]
    return out


@dataclass(frozen=True)
class Motion:
    """The range of motion of a four-bar on one branch (angles in rad). `input_arc` is
    (0, 2 pi) for a full turn; `output_range` is None when the output turns fully;
    `time_ratio` and `toggle_inputs` (extended, folded crank angles) only for a crank
    whose output rocks between two collinear positions."""

    assembles: bool
    input_full_turn: bool = False
    input_arc: tuple[float, float] | None = None
    output_full_turn: bool = False
    output_range: tuple[float, float] | None = None
    output_swing: float = 0.0
    time_ratio: float | None = None
    toggle_inputs: tuple[float, float] | None = None


def motion(a, b, c, d, branch, near=None) -> Motion:
    """Range of motion: full turn or the arc of the input, output range, swing, time ratio.

    Output extremes are at the arc ends or where crank and coupler are collinear; the
    quick-return ratio of a crank-rocker is the ratio of the crank arcs between the two
    collinear positions, reported as >= 1 (Norton, ch. 3).
    """
    arcs = input_arcs(a, b, c, d)
    if arcs == []:
        return Motion(assembles=False)
    full = arcs is None
    lo, hi = (0.0, TWO_PI) if full else choose_arc(arcs, near)
    phi = np.linspace(lo, hi, 2049)
    p = pose(a, b, c, d, phi, branch)
    keep = p.valid if p.valid.any() else slice(None)  # not where A meets B0 (rho = 0): no psi there
    phi, psi = phi[keep], np.unwrap(p.psi[keep])
    if full and abs(psi[-1] - psi[0]) > np.pi:
        return Motion(True, full, (lo, hi), output_full_turn=True, output_range=None, output_swing=TWO_PI)
    cands = [] if full else [lo, hi]
    col = collinear_inputs(a, b, c, d, branch)
    cands += [x for x in col.values() if full or arc_contains((lo, hi), x)]
    vals = []
    for x in cands:
        k = int(np.argmin(np.abs(wrap(phi - x))))
        px = pose(a, b, c, d, x, branch)
        if not bool(px.valid):  # A on B0: no output angle there
            continue
        vals.append(psi[k] + float(wrap(float(px.psi) - psi[k])))
    vals = vals or [float(psi.min()), float(psi.max())]
    vals += [float(psi.min()), float(psi.max())]  # never narrower than the samples
    o_lo, o_hi = min(vals), max(vals)
    shift = float(wrap(o_lo)) - o_lo
    ratio = toggles = None
    if full and "extended" in col and "folded" in col:
        t1 = float(np.mod(col["folded"] - col["extended"], TWO_PI))
        ratio = max(t1, TWO_PI - t1) / min(t1, TWO_PI - t1)
        toggles = (col["extended"], col["folded"])
    return Motion(True, full, (lo, hi), output_full_turn=False, output_range=(o_lo + shift, o_hi + shift),
                  output_swing=o_hi - o_lo, time_ratio=ratio, toggle_inputs=toggles)
