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

A damper's table is interpolated linearly between its rows; beyond its ends, its end segments
continue (linear extrapolation). A table whose speeds are all >= 0 is one half: the other is
its mirror, F(-v) = -F(v). A motor's torque-speed curve is interpolated the same way (no
mirror). Angles of links are followed continuously (tables.AngleTrack): a spring wound past a
turn keeps its whole deflection.
"""

from __future__ import annotations

from dataclasses import dataclass

import bisect

import numpy as np

from linkcli.dynamics.model import LINEAR, MOTOR, TORQUE


class Law:
    """A piecewise-linear law y(x) through the rows, continued linearly beyond its ends
    (module docstring); `mirrored`: rows given for x >= 0 only, odd."""

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

    def __call__(self, v):
        v = np.asarray(v, dtype=float)
        out = np.interp(v, self.x, self.y)
        lo, hi = self.x[0], self.x[-1]
        out = np.where(v < lo, self.y[0] + self.slopes[0] * (v - lo), out)
        return np.where(v > hi, self.y[-1] + self.slopes[-1] * (v - hi), out)

    def scalar(self, v: float) -> float:
        """The law at one value, in Python floats (the integrator's hot path)."""
        xs = self.xs
        if v <= xs[0]:
            return self.ys[0] + self.slopes[0] * (v - xs[0])
        if v >= xs[-1]:
            return self.ys[-1] + self.slopes[-1] * (v - xs[-1])
        i = bisect.bisect_right(xs, v) - 1
        return self.ys[i] + self.slopes[i] * (v - xs[i])

    @property
    def scale(self) -> float:
        return float(np.max(np.abs(self.y)))


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
