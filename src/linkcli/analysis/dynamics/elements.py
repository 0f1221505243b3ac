"""Force elements and the drive as functions of a geometric coordinate and its rate (SI).

Each spring, damper and constant couple acts through one coordinate g(q) of the linkage: the
distance L between its ends (linear), or an angle (torsional, rotary: a link's angle, or the
second link's minus the first's). Its generalized force on the drive coordinate is, by virtual
work, Q = -F g'(q) for a force F opposing g (tension, restoring torque), or T g'(q) for a couple T
acting on g:

    linear spring   F = preload + k (L - L0)          energy preload (L - L0) + k (L - L0)^2 / 2
    torsional       T = -k (theta - theta0)           energy k (theta - theta0)^2 / 2
    damper          F = c v,  or the table F(v)        v = g' q' (the coordinate's rate)
    constant couple T on a link                       energy -T (theta - theta_start)

A damper's table is interpolated by a monotone piecewise cubic (Law: smooth, no corner at a
row, never overshooting the rows); beyond its ends its end slopes continue. A table whose
speeds are all >= 0 is one half: the other is its mirror, F(-v) = -F(v). A motor's
torque-speed curve is interpolated the same way (no mirror). Angles of links are followed continuously (tables.AngleTrack): a spring wound past a
turn keeps its whole deflection.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass

import numpy as np

from linkcli.model.dynamics import LINEAR, MOTOR, TORQUE


class Law:
    """A smooth monotone law y(x) through the rows: a piecewise cubic Hermite interpolant whose
    slopes keep each segment's monotony (Fritsch & Carlson, SIAM J. Numer. Anal. 17 (1980)
    238-246; the end slopes as scipy.interpolate.PchipInterpolator's), continued beyond its
    ends along its end slopes. Its derivative is continuous: an integrator meets no corner at
    a row. `mirror`: rows given for x >= 0 only are completed as an odd function."""

    def __init__(self, rows, mirror: bool = False) -> None:
        x = [float(r[0]) for r in rows]
        y = [float(r[1]) for r in rows]
        self.mirrored = mirror and x[0] >= 0.0
        if self.mirrored:
            if x[0] > 0.0:
                x, y = [0.0] + x, [0.0] + y
            x = [-v for v in reversed(x[1:])] + x
            y = [-v for v in reversed(y[1:])] + y
        self.x = np.array(x)
        self.y = np.array(y)
        self.xs, self.ys = x, y
        self.slopes = [(y[i + 1] - y[i]) / (x[i + 1] - x[i]) for i in range(len(x) - 1)]
        self.d = _monotone_slopes(x, self.slopes)

    def __call__(self, v):
        v = np.asarray(v, dtype=float)
        x, y, d = self.x, self.y, np.asarray(self.d)
        i = np.clip(np.searchsorted(x, v, side="right") - 1, 0, len(x) - 2)
        h = x[i + 1] - x[i]
        t = (v - x[i]) / h
        out = _hermite(t, h, y[i], y[i + 1], d[i], d[i + 1])
        out = np.where(v < x[0], y[0] + d[0] * (v - x[0]), out)
        return np.where(v > x[-1], y[-1] + d[-1] * (v - x[-1]), out)

    def scalar(self, v: float) -> float:
        """The law at one value, in Python floats (the integrator's hot path)."""
        xs, ys, d = self.xs, self.ys, self.d
        if v <= xs[0]:
            return ys[0] + d[0] * (v - xs[0])
        if v >= xs[-1]:
            return ys[-1] + d[-1] * (v - xs[-1])
        i = bisect.bisect_right(xs, v) - 1
        h = xs[i + 1] - xs[i]
        return _hermite((v - xs[i]) / h, h, ys[i], ys[i + 1], d[i], d[i + 1])

    def row_phase(self, v: float) -> float:
        """A continuous function of v that is zero exactly at the rows (and nowhere else):
        sin(pi r), r = i + (v - x_i) / (x_i+1 - x_i) between rows, continued along its end
        slopes beyond them."""
        xs = self.xs
        if v <= xs[0]:
            return math.pi * (v - xs[0]) / (xs[1] - xs[0])
        last = len(xs) - 1
        if v >= xs[-1]:
            return (-1.0 if last % 2 else 1.0) * math.pi * (v - xs[-1]) / (xs[-1] - xs[-2])
        i = bisect.bisect_right(xs, v) - 1
        return math.sin(math.pi * (i + (v - xs[i]) / (xs[i + 1] - xs[i])))

    @property
    def scale(self) -> float:
        return float(np.max(np.abs(self.y)))

    @property
    def steepest(self) -> float:
        """A bound on |y'|: three times the steepest segment (a monotone cubic's slope within
        a segment is at most that), or an end slope."""
        return max([3.0 * abs(s) for s in self.slopes] + [abs(v) for v in self.d])


def _hermite(t, h, y0, y1, d0, d1):
    """The cubic Hermite interpolant on a segment of width h at t in [0, 1]."""
    t2 = t * t
    t3 = t2 * t
    return ((2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * h * d0
            + (-2 * t3 + 3 * t2) * y1 + (t3 - t2) * h * d1)


def _monotone_slopes(x: list, m: list) -> list:
    """The Fritsch-Carlson slopes at the rows: 0 where the secants change sign or one is flat,
    else their weighted harmonic mean; at the ends the one-sided three-point slope, kept of the
    end secant's sign and at most three times it."""
    n = len(x)
    if n == 2:
        return [m[0], m[0]]
    h = [x[i + 1] - x[i] for i in range(n - 1)]
    d = [0.0] * n
    for k in range(1, n - 1):
        if m[k - 1] * m[k] > 0:
            w1, w2 = 2 * h[k] + h[k - 1], h[k] + 2 * h[k - 1]
            d[k] = (w1 + w2) / (w1 / m[k - 1] + w2 / m[k])

    def edge(h0, h1, m0, m1):
        slope = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
        if slope * m0 <= 0:
            return 0.0
        if m0 * m1 < 0 and abs(slope) > 3 * abs(m0):
            return 3 * m0
        return slope

    d[0] = edge(h[0], h[1], m[0], m[1])
    d[-1] = edge(h[-1], h[-2], m[-1], m[-2])
    return d


@dataclass(frozen=True)
class Coordinate:
    """What an element acts through: ("distance", end, end) or ("angle", first link or None,
    second link) -- the second's angle minus the first's (None: the ground)."""

    kind: str
    first: object
    second: object


@dataclass
class Element:
    """One spring, damper or constant couple on a coordinate; `role` "spring", "damper" or
    "couple"; SI constants (stiffness N/m or N m/rad, free length m or angle rad, preload N,
    coefficient, or a Law, or the couple's torque)."""

    name: str
    role: str
    coordinate: Coordinate
    stiffness: float = 0.0
    free: float = 0.0
    preload: float = 0.0
    coefficient: float = 0.0
    law: Law | None = None
    torque: float = 0.0

    @property
    def linear(self) -> bool:
        return self.coordinate.kind == "distance"

    def force(self, g, rate):
        """The element's force along its coordinate (tension N or restoring torque N m, as the
        history reports it): a spring's from g, a damper's from the rate g' q'; positive
        opposes an increase of g. A couple's is its torque acting on g (negative of that)."""
        if self.role == "spring":
            if self.linear:
                return self.preload + self.stiffness * (g - self.free)
            return self.stiffness * (g - self.free)
        if self.role == "damper":
            return self.law(rate) if self.law is not None else self.coefficient * rate
        return np.full(np.shape(g), -self.torque, dtype=float)

    def energy(self, g):
        """Stored energy of a spring (J); a couple's potential -T g (J, up to a constant); 0 for
        a damper."""
        if self.role == "couple":
            return -self.torque * np.asarray(g, dtype=float)
        if self.role != "spring":
            return np.zeros(np.shape(g))
        d = g - self.free
        return (self.preload * d if self.linear else 0.0) + 0.5 * self.stiffness * d * d


def compile_elements(dyn, graph, metres: float, units) -> list[Element]:
    """The file's springs and dampers and the graph's constant couples as Elements (SI)."""
    out = []
    for s in dyn.springs:
        coordinate = _coordinate(s)
        if s.kind == LINEAR:
            out.append(Element(s.name, "spring", coordinate, stiffness=s.stiffness / metres,
                               free=s.free * metres, preload=s.preload))
        else:
            out.append(Element(s.name, "spring", coordinate, stiffness=s.stiffness, free=s.free))
    for d in dyn.dampers:
        coordinate = _coordinate(d)
        linear = d.kind == LINEAR
        if d.table is not None:
            rows = [(v * metres, f) if linear else (v, f) for v, f in d.table]
            out.append(Element(d.name, "damper", coordinate, law=Law(rows, mirror=True)))
        else:
            out.append(Element(d.name, "damper", coordinate,
                               coefficient=d.coefficient / metres if linear else d.coefficient))
    for body, torque in graph.couples:
        out.append(Element(f"{body} torque", "couple", Coordinate("angle", None, body), torque=torque))
    return out


def _coordinate(element) -> Coordinate:
    if element.kind == LINEAR:
        return Coordinate("distance", element.ends[0], element.ends[1])
    links = tuple(None if k == "ground" else k for k in element.links)
    if len(links) == 1:
        return Coordinate("angle", None, links[0])
    return Coordinate("angle", links[0], links[1])


class DriveLaw:
    """The drive's torque on its body as a function of its speed (N m; rad/s)."""

    def __init__(self, drive) -> None:
        self.kind = drive.kind
        self.constant = drive.torque if drive.kind == TORQUE else 0.0
        self.law = Law(drive.curve) if drive.kind == MOTOR else None

    def __call__(self, speed):
        if self.law is not None:
            return self.law(speed)
        return np.full(np.shape(speed), self.constant, dtype=float)

    def scalar(self, speed: float) -> float:
        return self.law.scalar(speed) if self.law is not None else self.constant

    @property
    def scale(self) -> float:
        return self.law.scale if self.law is not None else abs(self.constant)
