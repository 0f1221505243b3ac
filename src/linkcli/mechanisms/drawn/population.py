"""A population of drawings of one topology, vectorized over designs x drive values: the
drawn home's side of the shared synthesis search (mechanisms.synthesis.Population).

A design is the places of the free joints (x, y each, in the order of [bounds]); every other
joint stays where the starting drawing has it. Lengths, link shapes and the side of every
closure follow from each design's own drawing, as for a drawing given in a file: a link is
rigid with the shape it is drawn with; a dyad keeps the side sign((P2 - P1) x (J - P1)) it is
drawn on, an RRP or RPR the sign of (J - P) . u along the guide (drawn.structure). The drive
turns the driving link about its ground joint by q from the design's drawn position.

The plan -- the Assur groups from the drive outwards -- is the starting drawing's (the
topology does not change with the places), run over arrays (N designs, S drive values) of
points as complex numbers z = x + i y, every body carried by its rotation R from its drawn
pose (a point K of a body placed at its known point A: K = A + (K0 - A0) R):

- the driving link: R = e^{i q} about its ground pivot;
- RRR at J (Pyslvs's PLLP, drawn.solver's dyad): with d = P2 - P1, rho^2 = |d|^2 and the
  drawn lengths r1 = |J0 - P1_0|, r2 = |J0 - P2_0|: a = (r1^2 - r2^2 + rho^2) / (2 rho^2),
  h^2 = r1^2 / rho^2 - a^2, J = P1 + d (a + i side h); each link turns by R = (J - P1) /
  (J0 - P1_0), normalized;
- RRP (PLPP): the guide of body G through Q = G's place of J0, direction u = e^{i beta0} R_G;
  with w = P - Q: J = Q + u (Re(conj(u) w) + side sqrt(r^2 - Im(conj(u) w)^2));
- RPR: the guide body G pinned at P passes J: with d = J - P and its offset
  c = u0 x (J0 - P0) as drawn, e^{i gamma} = d / |d| (cos - i sin), sin = c / |d|,
  cos = side sqrt(1 - sin^2), and R = e^{i (gamma - beta0)}.

A closure that cannot close (h^2 < 0, a rod shorter than its pin's distance from the guide, a
guide offset larger than |d|) makes the row invalid; it is still placed as near as it comes
(the square root held at 0: the links in line), so that positions stay finite and continuous
and a search can be led back. Each closure's margin to locking (length unit, >= 0 where it
closes, 0 at the dead point): RRR min(rho - |r1 - r2|, r1 + r2 - rho); RRP r - |Im(conj(u) w)|;
RPR |d| - |c|. Transmission angles as the analysis measures them (drawn.motion.transmission):
at a pin the angle between the two links' lines at the joint, at a slider arccos(|u x r| / |r|)
(r the rod, or the arm from the guide body's pivot). A group that is not a dyad (a class-III
triad: Stephenson II, some Stephenson III inversions) has no closed form: it is followed from
each design's drawing by continuation, over all designs at once, and its rows solved by
batched Newton on the drawn branch (drawn.population_groups: its margin and the rows past a
dead point there); a group carrying a slider is refused for synthesis
(synthesis.schema.closed_form_problem). The same computation as the analysis's solver
(drawn.solver, drawn.groups), in another algebra: tests/synthesis/test_drawn_synthesis.py and
test_drawn_triads.py check the two against each other.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from linkcli.mechanisms.drawn.model import Drawn
from linkcli.mechanisms.drawn.structure import GROUND, Dyad, Group, GuideThrough, OnGuide, Structure, Turn, placed_by
from linkcli.mechanisms.synthesis import Motion, Population

NEAR = 2e-4  # of each box's width: a design this near a followed one borrows its track (a difference probe)
CARRY = 0.05  # of each box's width: a design this near a followed one has its track carried over (transport)
GROUP_COST = 10  # an evaluation of a plan with a group (a triad, followed by continuation) over a plan of
# dyads' in a search (docs/six_bars.md: 0.54 ms against 0.03 to 0.05 ms a design): the default budget's
# divisor (Population.evaluation_cost), and a topology sweep's weight of such a choice


@dataclass
class Placed:
    """The plan run over N designs x S drive values: pos (joint -> (N, S) complex), rot (body
    -> rotation from its drawn pose, (N, S) complex), margins and valid as the module docstring."""

    pos: dict
    rot: dict
    margins: dict
    valid: np.ndarray


class DrawnPopulation(Population):
    """Drawings whose `free` joints move within `boxes` ({joint: ((x lo, x hi), (y lo, y hi))});
    `traced` joints (their paths) and `followed` links (their frames) are reported."""

    def __init__(self, drawing: Drawn, structure: Structure, free: tuple[str, ...], boxes: dict,
                 traced: tuple[str, ...] = (), followed: tuple[str, ...] = ()):
        self.drawing, self.structure = drawing, structure
        self.held = idle_joints(structure, drawing, free, traced, followed)
        self.evaluation_cost = GROUP_COST if any(isinstance(op, Group) for op in structure.plan) else 1.0
        self.free = tuple(j for j in free if j not in self.held)
        self.names = tuple(f"{j}.{c}" for j in self.free for c in ("x", "y"))
        self.lo = np.array([boxes[j][k][0] for j in self.free for k in (0, 1)], dtype=float)
        self.hi = np.array([boxes[j][k][1] for j in self.free for k in (0, 1)], dtype=float)
        self.drawn = np.array([drawing.joint(j).at[k] for j in self.free for k in (0, 1)], dtype=float)
        self.traced, self.followed = tuple(traced), tuple(followed)
        self.closure_list = structure.closures()
        self.closures = tuple(c.joint for c in self.closure_list)
        self.joints = tuple(j.name for j in drawing.joints)
        self.fixed = {j.name: complex(*j.at) for j in drawing.joints if j.name not in self.free}
        self.slider = {j.name: j.slider for j in drawing.joints if j.slider is not None}
        self.guide_of = {j.name: (j.guide or GROUND) for j in drawing.joints if j.slider is not None}

    def phase_variable(self) -> int | None:
        """Where every joint the drive moves is free (in both coordinates), a design's drawing may
        be its configuration at any drive value, the timing shifted back: the same design, a
        flat direction of every objective. The variable that breaks it: the coordinate of the
        driving link's pin that its turn moves the more (x where the pin's tangent runs nearer
        to x), held at its drawn place (the pin still moves along the other); None when some
        moving joint is held. A joint that moves nothing measured (`idle_joints`: on one body
        alone, held where drawn whether given a box or not) does not count: every objective is
        as flat in the phase with it held (a point X added to a rocker of
        problems/drawn_six_bar_path.toml left the phase free: not-converged, four times the
        evaluations)."""
        names = tuple(j.name for j in self.drawing.joints)
        idle = set(idle_joints(self.structure, self.drawing, names, self.traced, self.followed))
        moving = [j.name for j in self.drawing.joints if not j.ground and j.name not in idle]
        free = {name: k for k, name in enumerate(self.free)
                if self.hi[2 * k] > self.lo[2 * k] and self.hi[2 * k + 1] > self.lo[2 * k + 1]}
        if not all(name in free for name in moving):
            return None
        link = self.drawing.link(self.drawing.drives[0].name)
        pivot = next(j for j in link.joints if self.drawing.joint(j).ground)
        pin = next(j for j in link.joints if j != pivot)
        (px, py), (ax, ay) = self.drawing.joint(pivot).at, self.drawing.joint(pin).at
        tangent_x, tangent_y = -(ay - py), ax - px
        return 2 * free[pin] + (0 if abs(tangent_x) >= abs(tangent_y) else 1)

    def placement_free(self) -> bool:
        """Every joint is free (the ground's too): the whole drawing may be moved, turned and
        scaled within the boxes (the starts fit its placement in closed form)."""
        return len(self.free) == len(self.joints) and bool(np.all(self.hi > self.lo))

    # ------------------------------------------------------------ geometry
    def places(self, x) -> dict[str, np.ndarray]:
        """Each joint's drawn place (N, 1) complex, N designs."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        n = len(x)
        out = {name: np.full((n, 1), at) for name, at in self.fixed.items()}
        for k, name in enumerate(self.free):
            out[name] = (x[:, 2 * k] + 1j * x[:, 2 * k + 1])[:, None]
        return out

    def geometry(self, x) -> dict[str, np.ndarray]:
        """Each joint's drawn place (N, 2) of N designs."""
        return {name: np.stack([z[:, 0].real, z[:, 0].imag], axis=-1) for name, z in self.places(x).items()}

    def size(self, x) -> np.ndarray:
        """(N,) each drawing's scale: its longest distance between two joints of one link or of
        the ground (drawn.sections.size)."""
        return self.size_of(self.places(x))

    def size_of(self, places) -> np.ndarray:
        """`size` from the designs' `places`."""
        ground = [j.name for j in self.drawing.joints if j.ground]
        best = np.zeros(len(next(iter(places.values()))))
        for joints in [ground] + [k.joints for k in self.drawing.links]:
            for i, a in enumerate(joints):
                for b in joints[i + 1:]:
                    best = np.maximum(best, np.abs(places[a] - places[b])[:, 0])
        return best

    # ------------------------------------------------------------ the plan over arrays
    def run(self, x, q, z0=None, upto: int | None = None, tracks: dict | None = None) -> Placed:
        """The plan over N designs x S drive values q (N, S) (module docstring); z0: the
        designs' `places` when the caller has them; `upto`: the first ops only; `tracks`:
        each group's continuation (op index -> population_groups.Track), made here when
        absent, as far as q needs."""
        z0 = self.places(x) if z0 is None else z0
        q = np.asarray(q, dtype=float)
        tracks = {} if tracks is None else tracks
        pos = {j: z0[j] for j in self.joints if self.drawing.joint(j).ground}
        rot = {GROUND: np.ones((1, 1))}
        anchor = {GROUND: None}
        margins = {}
        valid = np.ones(q.shape, dtype=bool)

        def place(body, at, r):
            rot[body], anchor[body] = r, at
            for k in self.structure.points[body]:
                if k not in pos:
                    pos[k] = pos[at] + (z0[k] - z0[at]) * r

        def turn_of(at, joint):  # a link's rotation from P -> J, normalized (rigid)
            r = (pos[joint] - pos[at]) / (z0[joint] - z0[at])
            return r / np.abs(r)

        def guide(joint):  # (Q, u) of the guide a slider joint runs on, in the current pose
            body = self.guide_of[joint]
            u0 = complex(math.cos(self.slider[joint]), math.sin(self.slider[joint]))
            if body == GROUND:
                return z0[joint], u0 * np.ones((1, 1))
            a = anchor[body]
            return pos[a] + (z0[joint] - z0[a]) * rot[body], u0 * rot[body]

        def side_of(a, b, j):  # the drawn side of J from A -> B, per design (N, 1)
            d, e = z0[b] - z0[a], z0[j] - z0[a]
            return np.where((d.real * e.imag - d.imag * e.real) >= 0.0, 1.0, -1.0)

        def side_on_guide(at, joint):
            e = (z0[joint] - z0[at]) * complex(math.cos(self.slider[joint]), -math.sin(self.slider[joint]))
            return np.where(e.real >= 0.0, 1.0, -1.0)

        with np.errstate(invalid="ignore", divide="ignore"):
            for index, op in enumerate(self.structure.plan[:upto]):
                if isinstance(op, Turn):
                    place(op.link, op.pivot, np.exp(1j * q))
                elif isinstance(op, Dyad):
                    p1, p2 = pos[op.first_at], pos[op.second_at]
                    r1sq = _abs2(z0[op.joint] - z0[op.first_at])
                    r2sq = _abs2(z0[op.joint] - z0[op.second_at])
                    d = p2 - p1
                    rho2 = _abs2(d)
                    along = (r1sq - r2sq + rho2) / (2.0 * rho2)
                    across2 = r1sq / rho2 - along * along
                    r1, r2, rho = np.sqrt(r1sq), np.sqrt(r2sq), np.sqrt(rho2)
                    margins[op.joint] = np.minimum(rho - np.abs(r1 - r2), r1 + r2 - rho)
                    valid &= across2 >= 0.0
                    side = side_of(op.first_at, op.second_at, op.joint)
                    pos[op.joint] = p1 + d * (along + 1j * side * np.sqrt(np.maximum(across2, 0.0)))
                    place(op.first, op.first_at, turn_of(op.first_at, op.joint))
                    place(op.second, op.second_at, turn_of(op.second_at, op.joint))
                elif isinstance(op, OnGuide):
                    p1 = pos[op.at]
                    point, u = guide(op.joint)
                    w = (p1 - point) * np.conj(u)
                    rsq = _abs2(z0[op.joint] - z0[op.at])
                    disc = rsq - w.imag * w.imag
                    margins[op.joint] = np.sqrt(rsq) - np.abs(w.imag)
                    valid &= disc >= 0.0
                    t = w.real + side_on_guide(op.at, op.joint) * np.sqrt(np.maximum(disc, 0.0))
                    pos[op.joint] = point + t * u
                    place(op.link, op.at, turn_of(op.at, op.joint))
                elif isinstance(op, GuideThrough):
                    p, j = pos[op.at], pos[op.joint]
                    u0 = complex(math.cos(self.slider[op.joint]), math.sin(self.slider[op.joint]))
                    e0 = (z0[op.joint] - z0[op.at]) * np.conj(u0)
                    c = e0.imag  # u0 x (J0 - P0): the guide's offset from the pivot
                    d = j - p
                    size = np.abs(d)
                    margins[op.joint] = size - np.abs(c)
                    sine = c / size
                    valid &= np.abs(sine) <= 1.0
                    sine = np.clip(sine, -1.0, 1.0)
                    cosine = side_on_guide(op.at, op.joint) * np.sqrt(np.maximum(1.0 - sine * sine, 0.0))
                    direction = d / size * (cosine - 1j * sine)
                    place(op.link, op.at, direction * np.conj(u0))
                else:
                    good, turns = self._group(index, x, q, z0, pos, margins, valid, tracks)
                    valid &= good
                    group = self.group_solver(index)
                    for b in group.kept:
                        place(b, group.anchor[b], turns[b])
                    for b, first, second in group.lengths:
                        place(b, first, turn_of(first, second))
        return Placed(pos, rot, margins, valid)  # entries (N, S) or broadcastable to it

    # ------------------------------------------------------------ groups (population_groups)
    def group_solver(self, index: int):
        """The plan's op `index` (a Group) as population_groups solves it."""
        from linkcli.mechanisms.drawn.population_groups import PopulationGroup
        cache = self.__dict__.setdefault("_groups", {})
        if index not in cache:
            placed = {GROUND}
            for op in self.structure.plan[:index]:
                placed |= placed_by(op)
            cache[index] = PopulationGroup(self.structure, self.structure.plan[index], placed)
        return cache[index]

    def _track(self, index, group, x, q, z0, scale, tracks, borrow: bool = True):
        """(track, borrowed): the group's continuation for designs x (population_groups.follow),
        those the cache holds taken from it (TrackCache); a design within CARRY of one it holds
        (a search's step from its last iterate) has that one's track carried over where it can
        be (population_groups.transport), the others are followed, once a design; `borrowed`
        (N,) the designs whose track is a neighbour's (a difference probe: TrackCache.near) or
        carried from one, never with `borrow` False."""
        from linkcli.mechanisms.drawn import population_groups as pg
        n = len(q)
        reach = pg.needed_reach(q)
        x = None if x is None else np.atleast_2d(np.asarray(x, dtype=float))[:, :len(self.lo)]  # the home's variables
        cache = self.__dict__.setdefault("_tracks", {}).setdefault(index, pg.TrackCache()) \
            if x is not None and len(x) == n else None
        keys = cache.row_keys(x) if cache is not None else None
        slots = cache.find(x, keys, reach) if cache is not None else np.full(n, -1)
        borrowed = np.zeros(n, dtype=bool)
        if cache is not None and borrow and (slots < 0).any():  # a difference probe: its design's track
            probe = np.flatnonzero(slots < 0)
            slots[probe] = cache.near(x[probe], reach[probe], NEAR * (self.hi - self.lo))
            borrowed[probe] = slots[probe] >= 0
        parts = []
        if (slots >= 0).any():
            hit = np.flatnonzero(slots >= 0)
            parts.append((hit, cache.take(slots[hit])))

        def prefix_of(miss):
            def prefix(designs, lanes):
                rows = miss[designs]
                sub = {j: v[rows] for j, v in z0.items()}
                earlier = {k: t.subset(rows) for k, t in tracks.items()}
                placed = self.run(None, lanes[:, None], sub, upto=index, tracks=earlier)
                known = {j: np.broadcast_to(placed.pos[j], (len(lanes), 1))[:, 0] for j in group.known}
                return group.stack_known(known, len(lanes)), np.broadcast_to(placed.valid, (len(lanes), 1))[:, 0]
            return prefix

        miss = np.flatnonzero(slots < 0)
        if cache is not None and borrow and len(miss):  # a track carried from a near design
            source = cache.near(x[miss], reach[miss], CARRY * (self.hi - self.lo), closest=True)
            near = miss[source >= 0]
            if len(near):
                new, carried = pg.transport(group, prefix_of(near), {j: v[near] for j, v in z0.items()}, scale[near],
                                            cache.take(source[source >= 0]))
                if carried.any():
                    rows, new = near[carried], new.subset(np.flatnonzero(carried))
                    parts.append((rows, new))
                    cache.store(x[rows], keys[rows], reach[rows], new)
                    borrowed[rows] = True
                    miss = np.setdiff1d(miss, rows)
        if len(miss):  # followed, once a design (a call may hold one several times: its constraints)
            first, inverse = np.arange(len(miss)), np.arange(len(miss))
            if x is not None:
                _, first, inverse = np.unique(x[miss], axis=0, return_index=True, return_inverse=True)
                inverse = inverse.reshape(-1)
            lead = miss[first]
            need = np.zeros((len(lead), 2))
            np.maximum.at(need, inverse, reach[miss])
            new = pg.follow(group, prefix_of(lead), {j: v[lead] for j, v in z0.items()}, scale[lead], need)
            parts.append((lead, new) if len(lead) == len(miss) else (miss, new.subset(inverse)))
            if cache is not None:
                cache.store(x[lead], keys[lead], need, new)
        whole = len(parts) == 1 and len(parts[0][0]) == n and np.array_equal(parts[0][0], np.arange(n))
        return (parts[0][1] if whole else pg.joined(parts, n)), borrowed

    def _group(self, index, x, q, z0, pos, margins, valid, tracks):
        """The group at op `index` over the rows (population_groups): its pinned joints into
        `pos`, its closures' margins into `margins`; (where it closes (N, S), each kept
        link's turn from its drawn pose). A design that borrowed a neighbour's track (a
        difference probe) and has a row on it that does not solve follows its own track and
        solves its rows again: the neighbour may not share a dead point of its own, whose
        margin (past it) only its own track gives."""
        from linkcli.mechanisms.drawn import population_groups as pg
        group = self.group_solver(index)
        n, s = q.shape
        scale = np.maximum(1.0, _extent(z0))  # groups.GroupSolver.size, per design
        borrowed = np.zeros(n, dtype=bool)
        if index not in tracks:
            tracks[index], borrowed = self._track(index, group, x, q, z0, scale, tracks)
        design = np.repeat(np.arange(n), s)
        known = group.stack_known({j: np.broadcast_to(pos[j], (n, s)).reshape(-1) for j in group.known}, n * s)
        const = group.constants(z0, design)
        open_rows = np.broadcast_to(valid, (n, s))
        z, good, ratio, past, edge = self._rows(group, tracks[index], q, known, const, scale, open_rows)
        again = np.flatnonzero(borrowed & np.any(~good & (past == 0.0) & open_rows, axis=1))
        if len(again):  # a probe with a row its neighbour's track does not solve: its own track
            own, _ = self._track(index, group, x[again], q[again], {j: v[again] for j, v in z0.items()},
                                 scale[again], {k: t.subset(again) for k, t in tracks.items()}, borrow=False)
            rows = (again[:, None] * s + np.arange(s)[None, :]).reshape(-1)
            z2, good2, ratio2, past2, edge2 = self._rows(group, own, q[again], known[rows], pg.subset(const, rows),
                                                         scale[again], open_rows[again])
            z[rows], good[again], ratio[again], past[again], edge[again] = z2, good2, ratio2, past2, edge2
            tracks[index] = _replaced(tracks[index], again, own)
        size = self.size_of(z0)[:, None]
        margin = np.where(good, size * ratio, np.where((past > 0.0) | edge, -size * past, np.nan))
        for c in self.closure_list:
            if c.links[0] in group.op.links and c.links[1] in group.op.links:
                margins[c.joint] = margin
        for j, place in group.places(z, known, const).items():
            pos[j] = place.reshape(n, s)
        turns = {b: (np.cos(z[:, group.col[b] + 2]) + 1j * np.sin(z[:, group.col[b] + 2])).reshape(n, s)
                 for b in group.kept}
        return good, turns

    @staticmethod
    def _rows(group, track, q, known, const, scale, open_rows):
        """(z (N S, m), good (N, S), Hadamard's ratio (N, S), past (N, S), edge (N, S)) of the
        group's rows at drive values q (N, S) from `track`: Newton from it (groups.solve_group)
        on the rows it reaches among `open_rows` (every closure before the group closes); `edge`
        (pg.at_rows): at a lane's dead point within the accuracy of its place."""
        from linkcli.mechanisms.drawn import population_groups as pg
        n, s = q.shape
        inside, past, guess, edge = pg.at_rows(track, q)
        design = np.repeat(np.arange(n), s)
        z = guess.reshape(n * s, -1)
        rows = np.flatnonzero(inside.reshape(-1) & open_rows.reshape(-1))
        good = np.zeros(n * s, dtype=bool)
        ratio = np.zeros(n * s)
        if rows.size:  # the rows the track reaches: Newton from it (groups.solve_group)
            zr, ok, det, ratio[rows] = group.newton(z[rows], known[rows], pg.subset(const, rows),
                                                      pg.RESIDUAL_RTOL * scale[design[rows]], pg.ROW_ITERATIONS,
                                                      polish=True)
            turned = np.abs(zr - z[rows])[:, group.angle_cols]
            good[rows] = ok & (np.sign(det) == track.sign[design[rows]]) & np.all(turned < 0.5 * math.pi, axis=-1)
            z[rows] = np.where(good[rows, None], zr, z[rows])
        return z, good.reshape(n, s), ratio.reshape(n, s), past, edge

    def kinematics(self, x, q) -> Motion:
        """Traced points, followed links' frames, each closure's margin and transmission angle
        at drive values q (N, S)."""
        z0 = self.places(x)
        placed = self.run(x, q, z0)
        pos, rot = placed.pos, placed.rot
        shape = np.shape(q)

        def full(v):
            return np.broadcast_to(v, shape)

        points = _xy(np.stack([full(pos[j]) for j in self.traced], axis=-1)) if self.traced \
            else np.zeros(shape + (0, 2))
        turned = np.stack([np.angle(full(rot[k])) for k in self.followed], axis=-1) if self.followed \
            else np.zeros(shape + (0,))
        origins = _xy(np.stack([full(pos[self.drawing.link(k).joints[0]]) for k in self.followed], axis=-1)) \
            if self.followed else np.zeros(shape + (0, 2))
        mu = []
        with np.errstate(invalid="ignore", divide="ignore"):
            for c in self.closure_list:
                if c.kind == "pin":
                    psi = np.angle((pos[c.second] - pos[c.joint]) * np.conj(pos[c.first] - pos[c.joint]))
                    mu.append(full(np.abs(psi)))
                else:
                    body = self.guide_of[c.joint]
                    u = complex(math.cos(self.slider[c.joint]), math.sin(self.slider[c.joint])) * rot[body]
                    psi = np.angle((pos[c.joint] - pos[c.first]) * np.conj(u))
                    mu.append(full(0.5 * np.pi - np.abs(psi - np.pi * np.round(psi / np.pi))))
        drawn = self.drawn_angles(z0)
        return Motion(points=points, angles=drawn[:, None, :] + turned, origins=origins, valid=placed.valid,
                      margins=np.stack([full(placed.margins[c]) for c in self.closures], axis=-1),
                      transmission=np.stack(mu, axis=-1))

    def drawn_angles(self, z0) -> np.ndarray:
        """(N, L) each followed link's drawn angle (its frame: first joint -> second)."""
        n = len(next(iter(z0.values())))
        out = [np.angle(z0[self.drawing.link(k).joints[1]] - z0[self.drawing.link(k).joints[0]])[:, 0]
               for k in self.followed]
        return np.stack(out, axis=-1) if out else np.zeros((n, 0))

    # ------------------------------------------------------------ starts and the result
    def starts(self, rng, count: int) -> np.ndarray:
        """The drawing first, then draws around it (a normal spread of a quarter of each box,
        clipped into it) and uniform draws in the boxes, half and half."""
        k = len(self.lo)
        out = np.empty((count, k))
        out[0] = self.drawn
        rest = count - 1
        near = rest // 2
        width = self.hi - self.lo
        out[1:1 + near] = np.clip(self.drawn + 0.25 * width * rng.standard_normal((near, k)), self.lo, self.hi)
        out[1 + near:] = self.lo + width * rng.random((rest - near, k))
        return out

    def linkage(self, x) -> Drawn:
        """The designed drawing: the starting drawing with the free joints at x."""
        x = np.asarray(x, dtype=float).reshape(-1)
        moved = {name: (float(x[2 * k]), float(x[2 * k + 1])) for k, name in enumerate(self.free)}
        joints = tuple(replace(j, at=moved.get(j.name, j.at)) for j in self.drawing.joints)
        return replace(self.drawing, joints=joints, designed=True)


def idle_joints(structure: Structure, drawing: Drawn, free, traced, followed) -> tuple[str, ...]:
    """The `free` joints that move nothing a design measures: on one body alone (no closure,
    no slider), not traced, not one of a followed link's first two joints (its frame). Every
    objective and constraint is flat in their places -- a search would leave them wherever its
    path ended, another place on every seed and CPU -- so they are held where drawn."""
    frame = {j for k in followed for j in drawing.link(k).joints[:2]}
    return tuple(j for j in free if len(structure.pins.get(j, ())) == 1 and drawing.joint(j).slider is None
                 and j not in traced and j not in frame)


def _replaced(track, rows, own):
    """`track` with the designs `rows` given their `own` tracks (population_groups.joined)."""
    from linkcli.mechanisms.drawn import population_groups as pg
    n = len(track.sign)
    keep = np.setdiff1d(np.arange(n), rows)
    return pg.joined([(keep, track.subset(keep)), (rows, own)], n)


def _extent(places) -> np.ndarray:
    """(N,) the larger side of each drawing's bounding box (groups._extent)."""
    z = np.concatenate(list(places.values()), axis=1)
    return np.maximum(np.ptp(z.real, axis=1), np.ptp(z.imag, axis=1))


def _abs2(z):
    return z.real * z.real + z.imag * z.imag


def _xy(z) -> np.ndarray:
    """(..., P) complex -> (..., P, 2)."""
    return np.stack([z.real, z.imag], axis=-1)
