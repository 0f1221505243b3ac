"""The equation of motion of a one-drive linkage (Lagrange, with the drive value q as the one
generalized coordinate):

    M(q) q'' + M'(q) q'^2 / 2 = Q(q, q') = -V'(q) - sum_e F_e g_e'(q) + T_drive(q') + Q_friction

M and V from the bodies (dynamics.bodies), F_e the force of each element on its coordinate g_e
(dynamics.elements), T_drive the drive's torque on its body (whose angle is theta0 + q, so its
rate coefficient is 1), Q_friction the pins' and guides' Coulomb friction (dynamics.friction).
Sources: Uicker, Pennock & Shigley, Theory of Machines and Mechanisms, ch. 16 (the equation of
motion of a one-degree-of-freedom machine from its kinematic coefficients); Paul, Kinematics
and Dynamics of Planar Machinery, ch. 13.

A `System` holds the linkage's home, its BodyGraph, the elements and the drive; `exact(q)`
evaluates everything from the home's coefficients, vectorized over q, and `table` is the
tabulated form the integrator uses (dynamics.tables). Drive values inside are "internal": the
file's values plus `offset` (a whole number of turns that puts a rocking drive's start inside
the arc its home reports).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.analysis.dynamics import bodies
from linkcli.analysis.dynamics.elements import DriveLaw, compile_elements
from linkcli.angles import wrap
from linkcli.errors import SolveInputError

TWO_PI = 2.0 * math.pi
DOMAIN_LOCK = 0.5  # a rocking drive's table stops where |sin mu| = this x sin(dead_point)


def located_error(dyn, path, key: str, expected: str, got: str) -> SolveInputError:
    """An error found when solved, at the line of its key (or of [dynamics])."""
    full = key if key.split(".")[0] in ("dynamics", "springs", "dampers") else f"dynamics.{key}"
    line = dyn.lines.get(key) or dyn.lines.get(full.split(".", 1)[1] if full != key else key) \
        or dyn.lines.get("dynamics")
    return SolveInputError(expected, got, path=path, line=line, key=full)


@dataclass
class Exact:
    """The exact functions at rows q (internal values): the coefficients, M, M', V, V', each
    coordinate's (g, g') with angles as the home gives them (not followed), lock, valid."""

    q: np.ndarray
    coef: object
    inertia: np.ndarray
    d_inertia: np.ndarray
    potential: np.ndarray
    d_potential: np.ndarray
    coords: list
    lock: np.ndarray
    valid: np.ndarray


class System:
    """A linkage with its force elements and drive, ready to integrate (module docstring)."""

    def __init__(self, mech, dyn, case, units, metres: float, path: str | None = None) -> None:
        self.mech, self.dyn, self.units, self.metres, self.path = mech, dyn, units, metres, path
        from linkcli.model import LoadCase
        case = case or LoadCase()
        self.case = case
        graph = mech.body_graph(case, metres)
        if graph is None:
            raise self.error("dynamics", "a linkage whose home gives its dynamics (one drive, a link "
                             "that turns) for [dynamics]", f"a {mech.name} without them")
        self.graph = graph
        self.elements = compile_elements(dyn, graph, metres, units)
        self.coordinates = []
        self.coordinate_of = []
        for element in self.elements:
            if element.coordinate not in self.coordinates:
                self.coordinates.append(element.coordinate)
            self.coordinate_of.append(self.coordinates.index(element.coordinate))
        self.drive = DriveLaw(dyn.drive)
        self.flywheel = dyn.flywheel_inertia
        self._domain()
        self._tabulate()
        self.friction_rhs = None
        if dyn.friction:
            from linkcli.analysis.dynamics.friction import FrictionModel
            self.friction_rhs = FrictionModel(self)

    # ------------------------------------------------------------ errors
    def error(self, key: str, expected: str, got: str) -> SolveInputError:
        return located_error(self.dyn, self.path, key, expected, got)

    # ------------------------------------------------------------ the drive's range
    def _domain(self) -> None:
        """The drive's range: a full turn (periodic tables over [0, 2 pi)) or the arc holding the
        start (offset: the turns added to the file's values to put the start in it), cut where
        a closure comes within DOMAIN_LOCK x sin(dead_point) of locking."""
        start = self.dyn.start[0] if self.dyn.start else None
        study = self.mech.study(start)
        if study is None:
            raise self.error("dynamics", "a linkage that assembles", "none at any drive angle")
        self.full_turn = study.full_turn
        self.offset = 0.0
        self.threshold = math.sin(self.dyn.dead_point)
        if self.full_turn:
            self.lo, self.hi = 0.0, TWO_PI
            return
        lo, hi = study.arc
        if start is not None:
            k = math.floor((start - lo) / TWO_PI)
            shifted = start - TWO_PI * k
            if not lo <= shifted <= hi:
                u = self.units
                raise self.error("start.angle", f"an initial angle within the drive's range of motion "
                                 f"[{u.from_rad(lo):.6g}, {u.from_rad(hi):.6g}] ({u.angle})",
                                 f"{u.from_rad(start):.6g}")
            self.offset = -TWO_PI * k
        q = np.linspace(lo, hi, 4097)[1:-1]
        lock = self._lock(q)
        good = np.nonzero(lock >= DOMAIN_LOCK * self.threshold)[0]
        if not len(good):
            raise self.error("dynamics", "a drive range away from its dead points",
                             f"every closure within {self.units.from_rad(self.dyn.dead_point):g} "
                             f"{self.units.angle} of locking")
        a = self._edge(q[good[0] - 1] if good[0] > 0 else lo, q[good[0]])
        b = self._edge(q[good[-1] + 1] if good[-1] + 1 < len(q) else hi, q[good[-1]])
        self.lo, self.hi = a, b

    def _lock(self, q) -> np.ndarray:
        coef = self.mech.coefficients(np.asarray(q, dtype=float), self.metres)
        return np.where(coef.valid, coef.lock, 0.0)

    def _edge(self, bad: float, good: float) -> float:
        """The drive value between `bad` and `good` where lock = DOMAIN_LOCK x threshold
        (bisection to round-off: 60 halvings)."""
        target = DOMAIN_LOCK * self.threshold
        for _ in range(60):
            mid = 0.5 * (bad + good)
            if self._lock([mid])[0] >= target:
                good = mid
            else:
                bad = mid
        return good

    def internal(self, q):
        """A file's drive value (rad) as the integrator's."""
        return q + self.offset

    def external(self, q):
        return q - self.offset

    # ------------------------------------------------------------ exact functions
    def exact(self, q) -> Exact:
        q = np.atleast_1d(np.asarray(q, dtype=float))
        coef = self.mech.coefficients(q, self.metres)
        graph = self.graph
        m, dm = bodies.inertia(graph, coef, self.flywheel)
        v, dv = bodies.potential(graph, coef)
        coords = [self._coordinate(c, coef) for c in self.coordinates]
        return Exact(q, coef, m, dm, v, dv, coords, coef.lock, coef.valid)

    def _coordinate(self, c, coef):
        """(g, g') of a coordinate: a distance and its rate coefficient, or an angle (the
        home's, not followed) and its rate coefficient."""
        if c.kind == "distance":
            p1, dp1, _ = bodies.end_point(self.graph, coef, c.first, self.metres)
            p2, dp2, _ = bodies.end_point(self.graph, coef, c.second, self.metres)
            d = p2 - p1
            length = np.hypot(d[:, 0], d[:, 1])
            with np.errstate(all="ignore"):
                rate = bodies.dot(d, dp2 - dp1) / length
            return length, rate
        t2, dt2, _ = bodies.angle(coef, c.second or bodies.GROUND)
        t1, dt1, _ = bodies.angle(coef, c.first or bodies.GROUND)
        return t2 - t1, dt2 - dt1

    # ------------------------------------------------------------ the table
    def _columns(self, q, reference: float | None = None) -> np.ndarray:
        """Columns M, V, each distance, each angle (continuous along the sorted q, from the
        reference drive value: the first node), lock."""
        ref = self.lo if reference is None else reference
        e = self.exact(np.concatenate([[ref], q]))
        if not np.all(e.valid):
            bad = e.q[~e.valid][0]
            raise self.error("dynamics", "a linkage that assembles over the drive's range",
                             f"none at drive angle {self.units.from_rad(self.external(bad)):.6g}")
        cols = [e.inertia, e.potential]
        for k, c in enumerate(self.coordinates):
            g = e.coords[k][0]
            if c.kind == "angle":
                g = np.unwrap(g) - self.winding[k] * e.q
            cols.append(g)
        cols.append(e.lock)
        return np.stack(cols, axis=1)[1:]

    def _tabulate(self) -> None:
        from linkcli.analysis.dynamics.tables import nodes, refined
        self.winding = [0] * len(self.coordinates)
        if self.full_turn:
            e = self.exact(np.linspace(self.lo, self.hi, 4097))
            for k, c in enumerate(self.coordinates):
                if c.kind == "angle":
                    u = np.unwrap(e.coords[k][0])
                    self.winding[k] = int(round((u[-1] - u[0]) / TWO_PI))
        lock_column = 2 + len(self.coordinates)
        table, self.nodes, self.table_error = refined(
            self._columns, self.lo, self.hi, self.full_turn, relative=(0,), skip=(lock_column,))
        self.table = table
        self.lock_column = lock_column
        values, _ = table.many(nodes(self.lo, self.hi, self.nodes))
        if not np.all(values[:, 0] > 0):
            raise self.error("dynamics", "masses that move with the drive (the simulation needs inertia: "
                             "[masses] or flywheel_inertia)", "no inertia at some drive angle")
        self.node_values = values
        self.turns = [0] * len(self.coordinates)
        if self.dyn.start is not None:  # each angle starts in (-pi, pi], the file's convention
            q0 = self.internal(self.dyn.start[0])
            raw = self.exact([q0]).coords
            for k, c in enumerate(self.coordinates):
                if c.kind == "angle":
                    wrapped = float(wrap(raw[k][0][0]))
                    tracked = float(self.branch(k, q0, raw[k][0])[0])
                    self.turns[k] = int(round((wrapped - tracked) / TWO_PI))

    # ------------------------------------------------------------ continuous angles
    def branch(self, k: int, q, raw):
        """The angle coordinate k at internal values q followed continuously (the home's `raw`
        angles moved by whole turns onto the table's branch)."""
        values, _ = self.table.many(np.atleast_1d(q))
        tracked = self.winding[k] * np.asarray(q) + values[:, 2 + k]
        return raw + TWO_PI * np.round((tracked - raw) / TWO_PI)

    def angle(self, k: int, q, raw):
        """The angle coordinate k as its elements see it: followed continuously from its value at
        the start, taken in (-pi, pi] (the convention of the file's free angles)."""
        return self.branch(k, q, raw) + TWO_PI * self.turns[k]
