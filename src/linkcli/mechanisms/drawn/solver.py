"""Positions, velocities and accelerations of a drawn linkage, vectorized over rows.

A row is one value of the drives (n rows at once): the leading drive's offset q from the
drawing, the others at q times the ratio of their speeds; every drive runs at its constant
speed (its acceleration is 0). The structure's plan runs op by op, each op over all rows:

- `Turn`: the link's angle is its drawn angle plus the drive's offset; omega = the speed.
- `Dyad` (RRR): J on the circles |J - P1| = r1, |J - P2| = r2 (Pyslvs's PLLP):
  with d = P2 - P1, a = (r1^2 - r2^2 + |d|^2) / (2 |d|), h = sqrt(r1^2 - a^2),
  J = P1 + a d / |d| + side h perp(d) / |d|; velocities from (J - Pi) . (vJ - vPi) = d/dt
  (ri^2 / 2), accelerations from (J - Pi) . (aJ - aPi) + |vJ - vPi|^2 = d2/dt2 (ri^2 / 2)
  (a 2 x 2 system, Cramer's rule).
- `OnGuide` (RRP): J = Q + t u on the guide (point Q, direction u of body G) with
  |J - P1| = r: t = (P1 - Q) . u + side sqrt(r^2 - ((P1 - Q) x u)^2) (Pyslvs's PLPP);
  J's velocity is that of G's point at J plus t' u, and its acceleration adds t'' u and
  the Coriolis term 2 omega_G t' perp(u).
- `GuideThrough` (RPR): the guide of G (pinned at the known P) passes the known J: with
  d = J - P and c = u_local x (g - p) in G's frame, the guide direction gamma satisfies
  u(gamma) x d = c: gamma = arg d - atan2(c / |d|, side sqrt(1 - c^2 / |d|^2));
  gamma' = (u x d') / (u . d), gamma'' = (u x d'' - gamma'^2 c - 2 gamma' u . d') / (u . d).
- `Group`: Newton's method on the group's constraint equations (drawn.groups).

A link placed from two of its points P, Q: angle = arg(Q - P) - arg(lQ - lP) (l: the points
in the link's frame), angular velocity and acceleration from d/dt arg(v) = (v x v') / |v|^2,
d2/dt2 arg(v) = (v x v'') / |v|^2 - 2 (v . v') (v x v') / |v|^4. A point l of a body
(origin o, angle theta): p = o + R l, v = o' + omega perp(R l) + R l',
a = o'' + alpha perp(R l) - omega^2 R l + 2 omega perp(R l') + R l'' (l moves only on a
driven slider's guide). Rows where a closure cannot close are invalid (NaN).
Sources: Norton, Design of Machinery, ch. 4, 6, 7 (position, velocity, acceleration
analysis); Uicker, Pennock & Shigley, Theory of Machines and Mechanisms, ch. 2-4.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.drawn.model import SLIDE, Drawn
from linkcli.mechanisms.drawn.state import State
from linkcli.mechanisms.drawn.structure import GROUND, Dyad, GuideThrough, OnGuide, Structure, Turn
from linkcli.mechanisms.drawn.vectors import cross, direction_rates, dot, perp, rotate

# ---------------------------------------------------------------- the drawing's geometry

@dataclass
class Geometry:
    """Each body's points in its own frame (origin at its first joint, x towards its second,
    as drawn; the ground's frame is the global one), each guide (body, point, direction in
    the body's frame). `local[(body, joint)]` is (2,) or (n, 2) (a made part differs per
    row: tolerance); `angle0[body]` the drawn angle of its frame."""

    origin0: dict[str, np.ndarray]
    angle0: dict[str, float]
    local: dict[tuple[str, str], np.ndarray]
    guides: dict[str, tuple[str, np.ndarray, float]]
    driven: dict[str, tuple[int, str]]  # slider joint -> (drive, guide body)

    @classmethod
    def of(cls, drawing: Drawn, structure: Structure) -> Geometry:
        at = {j.name: np.array(j.at, dtype=float) for j in drawing.joints}
        origin0 = {GROUND: np.zeros(2)}
        angle0 = {GROUND: 0.0}
        for link in drawing.links:
            a, b = at[link.joints[0]], at[link.joints[1]]
            origin0[link.name] = a
            angle0[link.name] = math.atan2(b[1] - a[1], b[0] - a[0])
        local = {}
        for body, joints in structure.points.items():
            for joint in joints:
                local[(body, joint)] = to_frame(at[joint], origin0[body], angle0[body])
        guides = {}
        for joint in drawing.joints:
            if joint.slider is not None:
                body = joint.guide or GROUND
                guides[joint.name] = (body, to_frame(at[joint.name], origin0[body], angle0[body]),
                                      joint.slider - angle0[body])
        driven = {d.name: (k, guides[d.name][0]) for k, d in enumerate(drawing.drives) if d.kind == SLIDE}
        return cls(origin0, angle0, local, guides, driven)

    def point(self, body: str, joint: str, q: np.ndarray, speeds: np.ndarray):
        """(l, l', l'') of a joint in a body's frame: fixed, or a driven slider's place on
        its guide, g + q_k u(beta) (its rate speed_k u, no acceleration)."""
        l = self.local[(body, joint)]
        if joint in self.driven and self.driven[joint][1] == body:
            k = self.driven[joint][0]
            _, g, beta = self.guides[joint]
            u = np.array([math.cos(beta), math.sin(beta)])
            l = g + q[:, k, None] * u
            return l, np.broadcast_to(speeds[k] * u, l.shape), np.zeros_like(l)
        zero = np.zeros_like(np.asarray(l, dtype=float))
        return l, zero, zero


def to_frame(point, origin, angle) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    d = np.asarray(point, dtype=float) - origin
    return np.array([c * d[0] + s * d[1], -s * d[0] + c * d[1]])


class Kinematics:
    """The plan of a drawn linkage executed over rows (module docstring)."""

    def __init__(self, drawing: Drawn, structure: Structure, geometry: Geometry | None = None,
                 tracks=None):
        self.drawing = drawing
        self.structure = structure
        self.geometry = geometry or Geometry.of(drawing, structure)
        self.speeds = np.array([d.speed for d in drawing.drives], dtype=float)
        self.ratios = self.speeds / self.speeds[0]
        self.tracks = tracks if tracks is not None else {}  # op index -> groups.Track

    # ------------------------------------------------------------ rows
    def run(self, q1, rates: bool = True, upto: int | None = None, guess=None) -> State:
        """The state at leading-drive offsets q1 (n,): every op of the plan (the first `upto`
        only, when given); rows where a closure cannot close are invalid (NaN)."""
        q1 = np.atleast_1d(np.asarray(q1, dtype=float))
        n = q1.shape[0]
        st = State(n, q1[:, None] * self.ratios[None, :], rates)
        st.valid = np.ones(n, dtype=bool)
        self._body_fixed(st, GROUND, np.zeros((n, 2)), 0.0)
        for j in self.structure.points[GROUND]:
            self._point_of(st, GROUND, j)
        with np.errstate(invalid="ignore", divide="ignore"):
            for index, op in enumerate(self.structure.plan[:upto]):
                before = st.valid.copy()
                if isinstance(op, Turn):
                    self._turn(st, op)
                elif isinstance(op, Dyad):
                    self._dyad(st, op)
                elif isinstance(op, OnGuide):
                    self._on_guide(st, op)
                elif isinstance(op, GuideThrough):
                    self._guide_through(st, op)
                else:
                    from linkcli.mechanisms.drawn.groups import solve_group
                    solve_group(self, st, index, op, guess)
                st.failed[index] = before & ~st.valid
        return st

    # ------------------------------------------------------------ bodies and points
    def _body_fixed(self, st: State, body, origin, theta) -> None:
        n = st.n
        st.theta[body] = np.full(n, theta)
        st.origin[body] = origin
        if st.rates:
            st.omega[body] = np.zeros(n)
            st.alpha[body] = np.zeros(n)
            st.origin_v[body] = np.zeros((n, 2))
            st.origin_a[body] = np.zeros((n, 2))

    def _point_of(self, st: State, body: str, joint: str) -> None:
        """Place `joint` as the point of a placed body."""
        l, dl, ddl = self.geometry.point(body, joint, st.q, self.speeds)
        c, s = np.cos(st.theta[body]), np.sin(st.theta[body])
        rl = rotate(l, c, s)
        st.pos[joint] = st.origin[body] + rl
        if st.rates:
            w, a = st.omega[body][:, None], st.alpha[body][:, None]
            rdl, rddl = rotate(dl, c, s), rotate(ddl, c, s)
            st.vel[joint] = st.origin_v[body] + w * perp(rl) + rdl
            st.acc[joint] = st.origin_a[body] + a * perp(rl) - w * w * rl + 2.0 * w * perp(rdl) + rddl

    def place(self, st: State, body: str, at: str, theta, omega=None, alpha=None) -> None:
        """A body from its angle (and rates) and one of its points `at`, already placed;
        then every other point of it."""
        l, dl, ddl = self.geometry.point(body, at, st.q, self.speeds)
        c, s = np.cos(theta), np.sin(theta)
        rl = rotate(l, c, s)
        st.theta[body] = theta
        st.origin[body] = st.pos[at] - rl
        if st.rates:
            w, a = omega[:, None], alpha[:, None]
            rdl, rddl = rotate(dl, c, s), rotate(ddl, c, s)
            st.omega[body], st.alpha[body] = omega, alpha
            st.origin_v[body] = st.vel[at] - w * perp(rl) - rdl
            st.origin_a[body] = st.acc[at] - a * perp(rl) + w * w * rl - 2.0 * w * perp(rdl) - rddl
        for joint in self.structure.points[body]:
            if joint != at and joint not in st.pos:
                self._point_of(st, body, joint)

    def place_by_two(self, st: State, body: str, first: str, second: str) -> None:
        """A link from two of its points already placed: its angle is arg(Q - P) minus the
        same direction in its own frame (module docstring)."""
        l1 = self.geometry.point(body, first, st.q, self.speeds)
        l2 = self.geometry.point(body, second, st.q, self.speeds)
        d = st.pos[second] - st.pos[first]
        dl = np.broadcast_to(l2[0] - l1[0], d.shape)
        if not st.rates:
            theta = np.arctan2(d[:, 1], d[:, 0]) - np.arctan2(dl[:, 1], dl[:, 0])
            self.place(st, body, first, theta)
            return
        phi, w, a = direction_rates(d, st.vel[second] - st.vel[first], st.acc[second] - st.acc[first])
        psi, wl, al = direction_rates(dl, np.broadcast_to(l2[1] - l1[1], d.shape),
                                      np.broadcast_to(l2[2] - l1[2], d.shape))
        self.place(st, body, first, phi - psi, w - wl, a - al)

    def half_square(self, st: State, body: str, first: str, second: str):
        """(r^2/2, d/dt, d2/dt2) of the distance between two points of one body (constant
        unless one is a driven slider on the body's guide)."""
        l1 = self.geometry.point(body, first, st.q, self.speeds)
        l2 = self.geometry.point(body, second, st.q, self.speeds)
        d, dd, ddd = (np.broadcast_to(np.asarray(b - a, dtype=float), (st.n, 2)) for a, b in zip(l1, l2))
        return 0.5 * dot(d, d), dot(d, dd), dot(dd, dd) + dot(d, ddd)

    def invalidate(self, st: State, bad: np.ndarray) -> None:
        """Rows where a closure cannot close: invalid from here on."""
        st.valid &= ~bad

    # ------------------------------------------------------------ the closed forms
    def _turn(self, st: State, op: Turn) -> None:
        k = op.drive
        theta = self.geometry.angle0[op.link] + st.q[:, k]
        if st.rates:
            self.place(st, op.link, op.pivot, theta, np.full(st.n, self.speeds[k]), np.zeros(st.n))
        else:
            self.place(st, op.link, op.pivot, theta)

    def _dyad(self, st: State, op: Dyad) -> None:
        p1, p2 = st.pos[op.first_at], st.pos[op.second_at]
        h1 = self.half_square(st, op.first, op.first_at, op.joint)
        h2 = self.half_square(st, op.second, op.second_at, op.joint)
        d = p2 - p1
        rho2 = dot(d, d)
        along = (2.0 * h1[0] - 2.0 * h2[0] + rho2) / (2.0 * rho2)  # a / |d|
        r1sq = 2.0 * h1[0]
        across2 = r1sq / rho2 - along * along  # (h / |d|)^2
        bad = ~(across2 >= 0.0)
        self.invalidate(st, bad)
        across = np.sqrt(np.where(bad, np.nan, np.maximum(across2, 0.0)))
        j = p1 + along[:, None] * d + (op.side * across)[:, None] * perp(d)
        st.pos[op.joint] = j
        if st.rates:
            e1, e2 = j - p1, j - p2
            det = cross(e1, e2)
            b1 = h1[1] + dot(e1, st.vel[op.first_at])
            b2 = h2[1] + dot(e2, st.vel[op.second_at])
            v = _cramer(e1, e2, b1, b2, det)
            st.vel[op.joint] = v
            dv1, dv2 = v - st.vel[op.first_at], v - st.vel[op.second_at]
            b1 = h1[2] - dot(dv1, dv1) + dot(e1, st.acc[op.first_at])
            b2 = h2[2] - dot(dv2, dv2) + dot(e2, st.acc[op.second_at])
            st.acc[op.joint] = _cramer(e1, e2, b1, b2, det)
        self.place_by_two(st, op.first, op.first_at, op.joint)
        self.place_by_two(st, op.second, op.second_at, op.joint)

    def guide_line(self, st: State, joint: str):
        """(Q, u, body) of a slider's guide over the rows: a point of it and its direction."""
        body, g, beta = self.geometry.guides[joint]
        c, s = np.cos(st.theta[body]), np.sin(st.theta[body])
        point = st.origin[body] + rotate(g, c, s)
        u = rotate(np.array([math.cos(beta), math.sin(beta)]), c, s)
        return point, u, body

    def _on_guide(self, st: State, op: OnGuide) -> None:
        point, u, body = self.guide_line(st, op.joint)
        p1 = st.pos[op.at]
        h = self.half_square(st, op.link, op.at, op.joint)
        w = p1 - point
        off = cross(u, w)
        disc = 2.0 * h[0] - off * off
        bad = ~(disc >= 0.0)
        self.invalidate(st, bad)
        t = dot(w, u) + op.side * np.sqrt(np.where(bad, np.nan, np.maximum(disc, 0.0)))
        j = point + t[:, None] * u
        st.pos[op.joint] = j
        if st.rates:
            e = j - p1
            arm = j - st.origin[body]
            wg, ag = st.omega[body][:, None], st.alpha[body][:, None]
            v_on = st.origin_v[body] + wg * perp(arm)
            eu = dot(e, u)
            td = (h[1] - dot(e, v_on - st.vel[op.at])) / eu
            v = v_on + td[:, None] * u
            st.vel[op.joint] = v
            a_on = st.origin_a[body] + ag * perp(arm) - wg * wg * arm + 2.0 * wg * td[:, None] * perp(u)
            dv = v - st.vel[op.at]
            tdd = (h[2] - dot(dv, dv) - dot(e, a_on - st.acc[op.at])) / eu
            st.acc[op.joint] = a_on + tdd[:, None] * u
        self.place_by_two(st, op.link, op.at, op.joint)

    def _guide_through(self, st: State, op: GuideThrough) -> None:
        body, g, beta = self.geometry.guides[op.joint]
        lp = self.geometry.local[(body, op.at)]
        ub = np.array([math.cos(beta), math.sin(beta)])
        c = cross(np.broadcast_to(ub, np.shape(g)), np.asarray(g, dtype=float) - lp)
        d = st.pos[op.joint] - st.pos[op.at]
        rho = np.sqrt(dot(d, d))
        sine = c / rho
        bad = ~(np.abs(sine) <= 1.0)
        self.invalidate(st, bad)
        cosine = op.side * np.sqrt(np.where(bad, np.nan, np.maximum(1.0 - sine * sine, 0.0)))
        gamma = np.arctan2(d[:, 1], d[:, 0]) - np.arctan2(sine, cosine)
        theta = gamma - beta
        if not st.rates:
            self.place(st, body, op.at, theta)
            return
        u = np.stack([np.cos(gamma), np.sin(gamma)], axis=-1)
        dd = st.vel[op.joint] - st.vel[op.at]
        ddd = st.acc[op.joint] - st.acc[op.at]
        ud = dot(u, d)
        omega = cross(u, dd) / ud
        alpha = (cross(u, ddd) - omega * omega * c - 2.0 * omega * dot(u, dd)) / ud
        self.place(st, body, op.at, theta, omega, alpha)


def _cramer(e1, e2, b1, b2, det) -> np.ndarray:
    """v with e1 . v = b1, e2 . v = b2."""
    return np.stack([(e2[:, 1] * b1 - e1[:, 1] * b2) / det, (-e2[:, 0] * b1 + e1[:, 0] * b2) / det], axis=-1)
