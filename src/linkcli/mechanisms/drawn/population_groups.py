"""A group that is not a dyad (a class-III triad and the like) over a population of drawings:
drawn.groups's continuation and rows, vectorized over N designs (drawn.population).

Unknowns, the group reduced to its rigid hubs: a group link pinned at three joints or more (a
triad's ternary link) is `kept`, its pose the place a of its first pinned joint and its turn
theta from the drawn pose (a point K of it: a + (K0 - A0) e^{i theta}); a joint where only
binary group links meet is a `free` point (its place); a binary group link (two pinned
joints J1, J2) is eliminated into its length, (|p(J1) - p(J2)|^2 - r^2) / (2 r) = 0, r as
drawn (length unit). A kept link's pinned joint whose place is known, or held by another
kept link, gives p_b(J) - p(J) = 0 (two rows). A Stephenson II triad is then three unknowns
(the ternary's pose) and three lengths, against drawn.groups's twelve (every link's pose): the
same roots, and since each eliminated link leaves the factor |J1 - J2|^2 / (r |J1 - J2|^2)
> 0 in the determinant (a Schur complement), the sign of det J -- the branch -- is the
full system's up to a constant sign: compared with the drawn sign, the same branch test.
Only pinned groups: a group carrying a slider's guide or block is refused for synthesis
(synthesis.schema.closed_form_problem).

Continuation (drawn.groups._follow's rules): two lanes per design, forward and back from the
drawing (an exact solution at q = 0) as far as the design's drive values need (to the next
quarter turn, at most BOUND, groups.bound's turn); each step predicted by the parabola through
the last three points (the secant of two, after a restart), corrected by at most
TRACK_ITERATIONS Newton steps (to TRACK_RTOL: a track point only guides the rows), accepted
when every closure before the group closes, Newton converges on the drawn sign of det J, no
hub turns by pi / 4 and the correction is at most CORRECTION of the predicted move; the step
then doubles (up to the grid step BOUND / TRACK_STEPS), else halves, and a lane whose step
falls below MIN_STEP of the grid step ends there (a dead point). A step refused for its
correction alone restarts the predictor (the next step predicts with the last point only: a
chord longer than the step would otherwise refuse every shorter one). The one loop is over
steps: each is array work over the lanes still moving. Against groups.py for one drawing:
larger grid steps (10 deg, not 2) and the dead point located to 1e-6 of a step, not 1e-12 --
the search's cost is these steps -- with the same rows valid (tests/synthesis/
test_drawn_triads.py: 60 designs x 40 drive values of three triads, row for row). The tracks
a population followed are kept (TrackCache, a ring of slots by the design's variables): the
same design at other drive values takes its track, and a design within NEAR of a followed
one in every variable (a difference probe) solves its rows from that one's track, when it
reached its drive values without a dead point. A design within CARRY of such a one (a
search's step) has that track carried over (`transport`: Newton at all its nodes at once,
kept where every node solves on the drawn branch and no hub turns by pi / 4 between nodes;
else followed): one batched solve instead of some forty sequential steps.

Rows (N, S): Newton (ROW_ITERATIONS) batched over all rows from the track interpolated at their
drive values (the parabola through the two track points about a value and a third beside);
invalid where Newton does not converge, lands on the other sign of det J or
turns a hub by pi / 2 from the guess (groups.solve_group), or where the drive value lies past
the track's end (a dead point first, in the drive's direction of travel). A design whose
forward lane turns the whole BOUND and comes back to its drawing is periodic: its branch is
closed, every drive value is taken modulo a turn on it, and its track serves any value. Invalid rows keep the track's place
(interpolated, or held at its end): positions stay finite and continuous.

Margin of the group's closures (length unit): where a row closes, s(J) = L |det J| /
prod_j |J_:,j|, L the design's size (drawn.sections.size) and the determinant over the
product of the column norms (Hadamard's ratio, in [0, 1]: 1 for orthogonal columns, 0
exactly where the group locks) -- independent of the units of the columns (lengths and
turns), as the dyads' margins are in length; past the track's end
-L |q - q_end| (how far the drive would still have to go, as an arc at the design's size:
it leads a search to push the dead point out of the travel); a row within END_BAND of a grid
step before a lane's dead point that does not solve is at it within the end's accuracy: margin
0, not unknown. Transmission angles: as for the
dyads (population.kinematics), at each closure of the group.

Linear systems: `solve_small`, written with elementwise numpy and returning the determinant's
sign and size too: up to three unknowns (a triad reduced to its ternary link's pose) by
cofactors, beyond by Gaussian elimination with partial pivoting (the first of equal
candidates): the same bits on every CPU (no LAPACK, no BLAS). The Jacobian is formed entry by
entry where it varies (`_tables`' pattern), never as an (L, E, m) array.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.drawn.groups import CORRECTION, NEWTON_ITERATIONS, RESIDUAL_RTOL
from linkcli.mechanisms.drawn.structure import GROUND, Group, Structure

BOUND = 2.0 * math.pi  # groups.bound for a turning drive: the track's reach either way
TRACK_STEPS = 36  # largest steps over BOUND (groups.TRACK_STEPS: 180; see the module docstring)
MIN_STEP = 1e-6  # relative to the grid step: a lane ends where its step falls below (groups.MIN_STEP: 1e-12)
TRACK_ITERATIONS = 4  # Newton steps per continuation step (groups._follow: 12; a step that needs more is halved)
TRACK_RTOL = 1e-8  # a track point converged (relative to the size): it only guides the rows, which
# are solved to groups.RESIDUAL_RTOL
ROW_ITERATIONS = NEWTON_ITERATIONS
COMPACT = 0.5  # Newton drops its stopped lanes when fewer than this share of those it computes still move
# (each drop copies every lane's data: a few rows stopping early are cheaper computed on)
POLISH_ABOVE = 0.01  # of the rows' tolerance (RESIDUAL_RTOL: 1e-15 of the size, round-off in the
# lengths' squares): a row converged below it is not polished (one more step would move it by round-off)
PERIOD_RTOL = 1e-6  # a lane back at its drawing after a turn: within this of the size
END_BAND = 1e-4  # of the grid step: a row this close before a lane's dead point that does not solve is
# at the dead point (the end is placed by steps refused below MIN_STEP from points converged to
# TRACK_RTOL, and near a fold the two branches are sqrt(distance) apart: rows within some 1e-6 rad
# of it may not solve; measured on benchmarks/drawn_population.py's 489 dead points: 1e-6 rad at most)


class PopulationGroup:
    """One group of the plan over arrays of lanes (module docstring)."""

    def __init__(self, structure: Structure, op: Group, placed: set[str]):
        self.op = op
        pins = structure.pins
        inside = set(op.links)
        pinned = {b: [j for j in structure.points[b] if len(pins[j]) >= 2] for b in op.links}
        self.kept = [b for b in op.links if len(pinned[b]) >= 3]
        self.binary = [b for b in op.links if len(pinned[b]) == 2]
        if len(self.kept) + len(self.binary) != len(op.links):
            raise ValueError(f"a group of links pinned at two joints or more, not {', '.join(op.links)}")
        self.anchor = {b: pinned[b][0] for b in self.kept}
        self.points = {b: structure.points[b] for b in op.links}
        joints = list(dict.fromkeys(j for b in op.links for j in pinned[b]))
        self.owner: dict[str, str] = {}  # joint -> GROUND-known marker "", a kept link, or "free"
        self.free: list[str] = []
        for j in joints:
            if any(b in placed for b in pins[j]):
                self.owner[j] = GROUND  # known
            else:
                keeper = next((b for b in self.kept if b in pins[j]), None)
                if keeper is not None:
                    self.owner[j] = keeper
                else:
                    self.owner[j] = "free"
                    self.free.append(j)
        self.joints = joints
        col = 0
        self.col: dict[str, int] = {}
        for b in self.kept:
            self.col[b] = col
            col += 3
        for j in self.free:
            self.col[j] = col
            col += 2
        self.m = col
        self.pin_rows = [(b, j) for b in self.kept for j in pinned[b]
                         if self.owner[j] != b]  # p_b(J) = p(J): two rows each
        self.lengths = [(b, pinned[b][0], pinned[b][1]) for b in self.binary]
        rows = 2 * len(self.pin_rows) + len(self.lengths)
        if rows != self.m or self.m == 0 or not inside:
            raise ValueError(f"a group of as many equations as unknowns, not {rows} for {self.m}")
        self.angle_cols = np.array([self.col[b] + 2 for b in self.kept], dtype=int)
        scale = np.ones(self.m, dtype=bool)  # True: a length column (scaled by the size)
        scale[self.angle_cols] = False
        self.length_col = scale
        self._tables()

    def _tables(self) -> None:
        """The equations as index tables over `endpoints` -- (joint, holder): a joint's place as
        the kept link `holder` carries it, or as its owner gives it (holder None) -- so that a
        residual and its Jacobian are a few array operations whatever the group."""
        self.known = [j for j in self.joints if self.owner[j] == GROUND]
        ends: list[tuple[str, str | None]] = []

        def end(joint, holder):
            key = (joint, holder if holder is not None else self.owner[joint])
            if key not in ends:
                ends.append(key)
            return ends.index(key)

        pins = [(end(j, b), end(j, None)) for b, j in self.pin_rows]
        lengths = [(end(j1, None), end(j2, None)) for _, j1, j2 in self.lengths]
        nk, nkn = len(self.kept), len(self.known)
        base, kept_of, c0, theta = [], [], np.zeros((len(ends), self.m), complex), np.zeros((len(ends), self.m))
        for e, (joint, holder) in enumerate(ends):
            if holder == GROUND:
                base.append(self.known.index(joint))
                kept_of.append(-1)
            elif holder == "free":
                i = self.free.index(joint)
                base.append(nkn + nk + i)
                kept_of.append(-1)
                c0[e, self.col[joint]], c0[e, self.col[joint] + 1] = 1.0, 1j
            else:
                k = self.kept.index(holder)
                base.append(nkn + k)
                kept_of.append(k)
                c0[e, self.col[holder]], c0[e, self.col[holder] + 1] = 1.0, 1j
                theta[e, self.col[holder] + 2] = 1.0
        self.ends = ends
        self.base = np.array(base, dtype=int)
        self.kept_of = np.array(kept_of, dtype=int)
        self.c0, self.theta = c0, theta
        self.pin_a = np.array([a for a, _ in pins], dtype=int)
        self.pin_b = np.array([b for _, b in pins], dtype=int)
        self.len_a = np.array([a for a, _ in lengths], dtype=int)
        self.len_b = np.array([b for _, b in lengths], dtype=int)
        self.kept_cols = np.array([self.col[b] for b in self.kept], dtype=int)
        self.free_cols = np.array([self.col[j] for j in self.free], dtype=int)
        # the Jacobian's pattern: d place(e) / d z = c0[e] + 1j arm_e theta[e] (theta: one angle
        # column at most); for an equation over endpoints (a, b): the constant part c0[a] - c0[b]
        # (every lane's), and the entries (row, column, a turns there, b turns there) that vary
        def varying(a_idx, b_idx):
            return [(i, c, bool(theta[a, c]), bool(theta[b, c])) for i, (a, b) in enumerate(zip(a_idx, b_idx))
                    for c in range(self.m) if theta[a, c] or theta[b, c]]
        npin = len(pins)
        pin_const = c0[self.pin_a] - c0[self.pin_b] if npin else np.zeros((0, self.m), complex)
        self.pin_const = np.concatenate([pin_const.real, pin_const.imag], axis=0)  # (2P, m)
        len_const = c0[self.len_a] - c0[self.len_b] if len(lengths) else np.zeros((0, self.m), complex)
        self.len_const = (len_const.real, len_const.imag)  # (l, m) each
        self.pin_varying = varying(self.pin_a, self.pin_b)
        self.len_varying = varying(self.len_a, self.len_b)
        self.triad = self._triad_shape()

    def _triad_shape(self):
        """(the kept link's end of each length, the known end's column of `known`) where the group
        is one kept link held by lengths to known joints alone (a six-bar's triad: `_triad`
        computes it in real arithmetic); None for any other group."""
        if len(self.kept) != 1 or self.free or self.pin_rows:
            return None
        kept, known = [], []
        for a, b in zip(self.len_a, self.len_b):
            if (self.kept_of[a] >= 0) == (self.kept_of[b] >= 0):
                return None
            kept.append(a if self.kept_of[a] >= 0 else b)
            known.append(self.base[b] if self.kept_of[a] >= 0 else self.base[a])
        return np.array(kept, dtype=int), np.array(known, dtype=int)

    # ------------------------------------------------------------ unknowns and points
    def constants(self, z0, lanes: np.ndarray) -> dict:
        """What the equations read of each lane's drawing (flat lanes; `lanes` (L,): the design
        of each): each endpoint's arm K0 - A0 on its kept link (0 for the others), (L, E); the
        binary links' lengths (L, l)."""
        arms = np.zeros((len(lanes), len(self.ends)), complex)
        for e, (joint, holder) in enumerate(self.ends):
            if self.kept_of[e] >= 0:
                arms[:, e] = (z0[joint][:, 0] - z0[self.anchor[holder]][:, 0])[lanes]
        lengths = np.zeros((len(lanes), len(self.lengths)))
        for i, (_, j1, j2) in enumerate(self.lengths):
            lengths[:, i] = np.abs(z0[j1][:, 0] - z0[j2][:, 0])[lanes]
        if self.triad is not None:  # each length's arm on the kept link, in real arithmetic
            arm = arms[:, self.triad[0]]
            return {"arm_x": arm.real.copy(), "arm_y": arm.imag.copy(), "lengths": lengths}
        return {"arms": arms, "lengths": lengths}

    def stack_known(self, known: dict, lanes: int) -> np.ndarray:
        """(L, K) the known joints' places."""
        if not self.known:
            return np.zeros((lanes, 0), complex)
        return np.stack([np.broadcast_to(known[j], (lanes,)) for j in self.known], axis=-1)

    def drawn(self, z0, lanes: np.ndarray) -> np.ndarray:
        """(L, m) the unknowns of each lane's drawing (q = 0)."""
        out = np.zeros((len(lanes), self.m))
        for b in self.kept:
            a = z0[self.anchor[b]][lanes, 0]
            out[:, self.col[b]], out[:, self.col[b] + 1] = a.real, a.imag
        for j in self.free:
            f = z0[j][lanes, 0]
            out[:, self.col[j]], out[:, self.col[j] + 1] = f.real, f.imag
        return out

    # ------------------------------------------------------------ equations, lanes last
    # Newton works on arrays whose last axis is the lanes -- z (m, L), f (m, L), J (m, m, L) --
    # so that each unknown, equation and Jacobian entry is one contiguous (L,) row: the
    # elementwise products and the largest residual are then plain array operations, not
    # gathers of a column or reductions along a short last axis (the rows' Newton over 51,000
    # lanes: 38 ms rather than 49). The arithmetic is the same, operation for operation.
    def _data(self, known, const) -> dict:
        """What the equations read, lanes last, from `known` (L, K) (stack_known) and
        `constants` (lanes first)."""
        if self.triad is not None:
            k = known[:, self.triad[1]]
            return {"ax": np.ascontiguousarray(const["arm_x"].T), "ay": np.ascontiguousarray(const["arm_y"].T),
                    "r": np.ascontiguousarray(const["lengths"].T), "kx": np.ascontiguousarray(k.real.T),
                    "ky": np.ascontiguousarray(k.imag.T)}
        return {"known": np.ascontiguousarray(known.T), "arms": np.ascontiguousarray(const["arms"].T),
                "lengths": np.ascontiguousarray(const["lengths"].T)}

    def _ends(self, z, data):
        """(P (E, L) every endpoint's place, R (E, L) its arm turned), z (m, L)."""
        kc, fc = self.kept_cols, self.free_cols
        hub = z[kc] + 1j * z[kc + 1]
        turn = np.cos(z[kc + 2]) + 1j * np.sin(z[kc + 2])
        places = np.concatenate([data["known"], hub, z[fc] + 1j * z[fc + 1]], axis=0)
        arm = data["arms"] * (turn[np.maximum(self.kept_of, 0)] if len(kc) else 0.0)
        return places[self.base] + arm, arm

    @staticmethod
    def _pins(z, data):
        """(p_x, p_y, u_x, u_y) (3, L) of a triad (z (3, L)): each length's pin on the kept
        link, p = a + u, its drawn arm from the hub turned, u = u0 e^{i theta}."""
        c, s = np.cos(z[2]), np.sin(z[2])
        ax, ay = data["ax"], data["ay"]
        ux, uy = ax * c - ay * s, ax * s + ay * c
        return z[0] + ux, z[1] + uy, ux, uy

    def _triad(self, z, data, jacobian: bool):
        """`_equations` of a triad (`_triad_shape`), in real arithmetic: with e = p - k from a
        length's known end k to its pin p (`_pins`), g = (|e|^2 - r^2) / (2 r) and
        dg / d(a_x, a_y, theta) = (e_x, e_y, e x (i u)) / r. The general path's values within
        round-off; its complex products may fuse their multiply-adds on some CPUs, these real
        ones are rounded alike everywhere."""
        px, py, ux, uy = self._pins(z, data)
        ex, ey = px - data["kx"], py - data["ky"]
        r = data["r"]
        f = ((ex * ex + ey * ey) - r * r) / (2.0 * r)
        if not jacobian:
            return f, None
        jac = np.empty((3, 3, z.shape[1]))
        jac[:, 0], jac[:, 1] = ex / r, ey / r
        jac[:, 2] = (ex * -uy + ey * ux) / r
        return f, jac

    def _equations(self, z, data, jacobian: bool = True):
        """(f (m, L) length unit, J (m, m, L) or None) over lanes last (z (m, L), `_data`):
        the pins' rows (x, then y), then the lengths' (module docstring). J from `_tables`'s
        pattern: its constant part at once, then the entries that turn with a kept link's angle
        one by one (no (E, m, L) array); a triad's by `_triad`."""
        if self.triad is not None:
            return self._triad(z, data, jacobian)
        p, arm = self._ends(z, data)
        e = p[self.pin_a] - p[self.pin_b]
        d = p[self.len_a] - p[self.len_b]
        r = data["lengths"]
        g = ((d.real * d.real + d.imag * d.imag) - r * r) / (2.0 * r)
        f = np.concatenate([e.real, e.imag, g], axis=0)
        if not jacobian:
            return f, None
        npin = len(self.pin_a)
        jac = np.empty((self.m, self.m, z.shape[1]))
        jac[:2 * npin] = self.pin_const[..., None]
        c_re, c_im = self.len_const
        jac[2 * npin:] = (d.real[:, None, :] * c_re[..., None] + d.imag[:, None, :] * c_im[..., None]) / r[:, None, :]
        w_re, w_im = -arm.imag, arm.real  # 1j arm: a place's turn with its link's angle

        def turning(a, b, turns_a, turns_b):  # the varying part of d (place(a) - place(b)) / d z_c
            re = w_re[a] if turns_a else 0.0
            im = w_im[a] if turns_a else 0.0
            if turns_b:
                re, im = re - w_re[b], im - w_im[b]
            return re, im

        for i, c, turns_a, turns_b in self.pin_varying:
            re, im = turning(self.pin_a[i], self.pin_b[i], turns_a, turns_b)
            jac[i, c] = self.pin_const[i, c] + re
            jac[npin + i, c] = self.pin_const[npin + i, c] + im
        for k, c, turns_a, turns_b in self.len_varying:
            re, im = turning(self.len_a[k], self.len_b[k], turns_a, turns_b)
            jac[2 * npin + k, c] = (d.real[k] * (c_re[k, c] + re) + d.imag[k] * (c_im[k, c] + im)) / r[k]
        return f, jac

    def residual(self, z, known, const, jacobian: bool = True):
        """`_equations` lanes first: (f (L, m), J (L, m, m) or None) at z (L, m)."""
        f, jac = self._equations(np.ascontiguousarray(np.asarray(z, dtype=float).T), self._data(known, const),
                                 jacobian)
        return f.T, None if jac is None else jac.transpose(2, 0, 1)

    def newton(self, z, known, const, tol, iterations: int, stall: int = 0, ratio: bool = True,
               polish: bool = False):
        """(z (L, m), converged, det J, Hadamard's ratio |det J| / prod |columns| or None) over
        flat lanes (known: (L, K), stack_known); a lane stops moving once every residual is
        within `tol` (or one is not finite: groups.GroupSolver.newton), and only the lanes
        still moving are computed. `stall` (> 0): a lane whose largest residual has not halved in
        an iteration from iteration `stall` on stops too (a continuation step that would not
        converge: near a dead point Newton's rate falls to a halving an iteration, and a far
        guess diverges; the step is then halved anyway). `polish`: one more Newton step on the lanes
        that converged with a residual above POLISH_ABOVE of `tol` (quadratic convergence takes
        them to round-off: the rows' places then do not depend on the guess, and a search's
        differences see the design, not the tolerance; below it they are there already)."""
        z = np.array(np.asarray(z, dtype=float).T)  # (m, L): lanes last (`_data`)
        data = self._data(known, const)
        lanes = z.shape[1]
        done = np.zeros(lanes, dtype=bool)
        det = np.zeros(lanes)
        hadamard = np.zeros(lanes) if ratio else None
        polished = np.full((self.m, lanes), np.nan)  # a converged lane's polish step's end
        idx, zk, dk, tk = np.arange(lanes), z, data, tol  # the lanes computed
        live = np.ones(lanes, dtype=bool)  # those of them still moving (the others dropped in COMPACT steps)
        before = np.full(lanes, np.inf)
        for it in range(iterations + 1):
            f, jac = self._equations(zk, dk)
            worst = np.max(np.abs(f), axis=0)
            converged = worst <= tk
            move = ~converged & np.isfinite(worst)
            if stall and it >= stall:
                move &= worst < 0.5 * before
            if it == iterations:
                move[:] = False
            stop = live & ~move
            move &= live
            if stop.any():  # the lanes that stop: their places, and det J where they stop (or polished)
                at = idx[stop]
                z[:, at], done[at] = zk[:, stop], converged[stop]
                again = stop & converged & (worst > POLISH_ABOVE * tk) if polish else np.zeros(len(stop), dtype=bool)
                if again.any():
                    polished[:, idx[again]] = zk[:, again] - solve_small(jac[..., again], f[:, again])[0]
                here = stop & ~again
                det[idx[here]], h = _measure(jac[..., here], ratio)
                if ratio:
                    hadamard[idx[here]] = h
            if not move.any():
                break
            live = move
            if np.count_nonzero(live) < COMPACT * len(live):  # drop the stopped lanes
                idx, zk, dk, tk = idx[live], zk[:, live], _take(dk, live), tk[live]
                worst, jac, f, live = worst[live], jac[..., live], f[:, live], live[live]
            step = solve_small(jac, f)[0]
            if not live.all():
                step[:, ~live] = 0.0  # a stopped lane stays where it stopped
            zk = zk - step
            before = worst
        at = np.flatnonzero(~np.isnan(polished[0]))
        if len(at):  # one more Newton step where it keeps the residual within tol
            moved = polished[:, at]
            f2, jac2 = self._equations(moved, _take(data, at))
            better = np.all(np.isfinite(moved), axis=0) & (np.max(np.abs(f2), axis=0) <= tol[at])
            z[:, at[better]] = moved[:, better]
            if not better.all():  # det J where they stay
                _, jac2[..., ~better] = self._equations(z[:, at[~better]], _take(data, at[~better]))
            det[at], h = _measure(jac2, ratio)
            if ratio:
                hadamard[at] = h
        return np.ascontiguousarray(z.T), done, det, hadamard

    def places(self, z, known, const) -> dict:
        """The group's pinned joints' places (L,) from its unknowns z (L, m) (the kept and free ones)."""
        zt, data = np.ascontiguousarray(np.asarray(z, dtype=float).T), self._data(known, const)
        if self.triad is not None:
            px, py, _, _ = self._pins(zt, data)
            return {self.ends[e][0]: px[i] + 1j * py[i] for i, e in enumerate(self.triad[0])}
        p, _ = self._ends(zt, data)
        return {joint: p[e] for e, (joint, holder) in enumerate(self.ends)
                if holder != GROUND and (holder == "free" or self.owner[joint] == holder)}


def subset(const: dict, idx) -> dict:
    """`constants` of some lanes."""
    return {key: value[idx] for key, value in const.items()}


def _take(data: dict, idx) -> dict:
    """`_data` of some lanes (the last axis)."""
    return {key: value[..., idx] for key, value in data.items()}


# ---------------------------------------------------------------- the track and the rows

class Track:
    """Each design's continuation, two lanes (forward, back): q (N, 2, T) drive values by
    |q| increasing (padded with the last), z (N, 2, T, m), count (N, 2) points, end (N, 2)
    the drive value where a lane ended at a dead point (nan: it went as far as it needed),
    sign (N,) the drawn sign of det J (0: the drawing does not solve), periodic (N,)."""

    def __init__(self, q, z, count, end, sign, periodic):
        self.q, self.z, self.count, self.end, self.sign, self.periodic = q, z, count, end, sign, periodic

    def subset(self, designs) -> Track:
        return Track(self.q[designs], self.z[designs], self.count[designs], self.end[designs],
                     self.sign[designs], self.periodic[designs])


def follow(group: PopulationGroup, prefix, z0, scale, reach) -> Track:
    """The continuation of every design both ways (module docstring). `prefix(designs, q)`:
    the known joints' places (K, known: stack_known) and whether every earlier closure closes (K,) for those
    designs at drive values q (K,); `scale` (N,) the designs' RESIDUAL_RTOL scale; reach (N, 2)
    how far each lane goes (forward, back). Only the lanes still moving are computed."""
    n = len(reach)
    design = np.repeat(np.arange(n), 2)  # lane -> design
    direction = np.tile([1.0, -1.0], n)
    reach = reach.reshape(-1)
    full = BOUND / TRACK_STEPS
    tol = TRACK_RTOL * scale[design]
    const = group.constants(z0, design)
    z, sign0 = _drawings(group, prefix, z0, scale)
    size = np.where(group.length_col[None, :], scale[design][:, None], 1.0)
    last_q, prev_q, older_q = np.zeros(2 * n), np.zeros(2 * n), np.zeros(2 * n)
    last_z, prev_z, older_z = z[design], z[design], z[design]
    behind = np.zeros(2 * n, dtype=int)  # points before the last one the predictor may use (0, 1, 2)
    count = np.ones(2 * n, dtype=int)
    fresh = np.ones(2 * n, dtype=bool)  # no secant to predict the next step: the drawing, or a restart
    h = np.full(2 * n, full / 8)
    end = np.where(sign0[design] == 0.0, 0.0, np.nan)
    active = (reach > 0.0) & (sign0[design] != 0.0)
    rec_lane, rec_q, rec_z = [np.arange(2 * n)], [np.zeros(2 * n)], [z[design]]
    while active.any():
        act = np.flatnonzero(active)
        lq, lz = last_q[act], last_z[act]
        step_q = direction[act] * np.minimum(np.abs(lq) + h[act], reach[act])
        first = fresh[act]
        guess = _predict(step_q, lq, lz, prev_q[act], prev_z[act], older_q[act], older_z[act],
                         np.where(first, 0, behind[act]))
        known, valid = prefix(design[act], step_q)
        znew, conv, det, _ = group.newton(guess, known, subset(const, act), tol[act], TRACK_ITERATIONS, stall=2,
                                          ratio=False)
        scaled = size[act]
        moved = np.max(np.abs(guess - lz) / scaled, axis=-1)
        corrected = np.max(np.abs(znew - guess) / scaled, axis=-1)
        calm = np.all(np.abs(znew - lz)[:, group.angle_cols] < math.pi / 4, axis=-1)
        closes = valid & conv & (np.sign(det) == sign0[design[act]]) & calm
        good = closes & (first | (corrected <= CORRECTION * moved + 1e-9))
        fresh[act] = ~good & (first | closes)  # only the secant was wrong (a chord longer than the step): restart
        took = act[good]
        older_q[took], older_z[took] = prev_q[took], prev_z[took]
        prev_q[took], prev_z[took] = lq[good], lz[good]
        behind[took] = np.where(first[good], 1, np.minimum(behind[took] + 1, 2))
        last_q[took], last_z[took] = step_q[good], znew[good]
        count[took] += 1
        rec_lane.append(took)
        rec_q.append(step_q[good])
        rec_z.append(znew[good])
        h[act] = np.where(good, np.minimum(2.0 * h[act], full), 0.5 * h[act])
        dead = act[~good & (h[act] < MIN_STEP * full)]
        end[dead] = last_q[dead]
        active[dead] = False
        active[took] = np.abs(last_q[took]) < reach[took]
    lanes = np.concatenate(rec_lane)
    order = np.argsort(lanes, kind="stable")  # by lane, in the order accepted
    lanes = lanes[order]
    qs, zs = np.concatenate(rec_q)[order], np.concatenate(rec_z)[order]
    width = int(count.max())
    start = np.concatenate([[0], np.cumsum(count)[:-1]])
    slot = np.arange(len(lanes)) - start[lanes]
    q_track = np.repeat(last_q[:, None], width, axis=1)
    z_track = np.repeat(last_z[:, None, :], width, axis=1)
    q_track[lanes, slot], z_track[lanes, slot] = qs, zs
    periodic = _periodic(group, last_q[0::2], last_z[0::2], z, end[0::2], sign0, size[0::2])
    m = group.m
    return Track(q_track.reshape(n, 2, width), z_track.reshape(n, 2, width, m), count.reshape(n, 2),
                 end.reshape(n, 2), sign0, periodic)


def _drawings(group, prefix, z0, scale):
    """(z (N, m), sign0 (N,)): each design's drawing solved at q = 0 (it is a solution: Newton
    checks it to RESIDUAL_RTOL) and the sign of det J there, its branch (0: it does not solve)."""
    ones = np.arange(len(scale))
    known0, _ = prefix(ones, np.zeros(len(scale)))
    z, ok, det, _ = group.newton(group.drawn(z0, ones), known0, group.constants(z0, ones),
                                 RESIDUAL_RTOL * scale, ROW_ITERATIONS, ratio=False)
    return z, np.where(ok, np.sign(det), 0.0)


def _periodic(group, last_q, last_z, z, end, sign0, size) -> np.ndarray:
    """(N,) the forward lanes that turned the whole BOUND without a dead point and came back to
    their drawings z (N, m) within PERIOD_RTOL of the size."""
    back = last_z - z
    back[:, group.angle_cols] = np.mod(back[:, group.angle_cols] + math.pi, 2 * math.pi) - math.pi
    return (np.isnan(end) & (np.abs(last_q) >= BOUND) & (sign0 != 0.0)
            & np.all(np.abs(back) <= PERIOD_RTOL * size, axis=-1))


def transport(group: PopulationGroup, prefix, z0, scale, source: Track) -> tuple[Track, np.ndarray]:
    """(track, carried (N,)): each design's continuation carried over from a neighbour's
    (`source`: whole lanes, no dead point, reaching as far as the design needs) instead of
    followed step by step: Newton at every node of the neighbour's lanes at once (its drive
    values; its places there the guesses; TRACK_RTOL), the drawing itself at q = 0. A design's
    track is `carried` only where every node solves with Newton's residual at least halving
    from its first iteration (the neighbour's place lies in the basin of the design's own: a
    far or ambiguous start does not contract at once), on the drawn sign of det J, with every
    closure before the group closing and no hub turning by pi / 4 between nodes, and where it
    comes back to its drawing after a turn as the neighbour's did (periodic); else it is
    followed. A dead point between two nodes that the neighbour lacks shows as rows that do not
    solve: the design is then followed (DrawnPopulation._group, as for a probe)."""
    n, _, width = source.q.shape
    ones = np.arange(n)
    drawn, sign0 = _drawings(group, prefix, z0, scale)
    count = source.count
    k = np.arange(width)
    design, lane, node = np.nonzero((k >= 1) & (k < count[..., None]))
    known, valid = prefix(design, source.q[design, lane, node])
    z_node, conv, det, _ = group.newton(source.z[design, lane, node], known, group.constants(z0, design),
                                         TRACK_RTOL * scale[design], ROW_ITERATIONS, stall=1, ratio=False)
    z = np.empty_like(source.z)
    z[:, :, 0] = drawn[:, None, :]
    z[design, lane, node] = z_node
    last = np.minimum(k, count[..., None] - 1)  # past a lane's count: its last node, as follow pads
    z = np.take_along_axis(z, last[..., None], axis=2)
    calm = np.all(np.abs(z_node - z[design, lane, node - 1])[:, group.angle_cols] < math.pi / 4, axis=-1)
    size = np.where(group.length_col[None, :], scale[:, None], 1.0)
    q = source.q
    good = valid & conv & (np.sign(det) == sign0[design]) & calm
    end = np.full((n, 2), np.nan)
    last_fwd = count[:, 0] - 1
    periodic = _periodic(group, q[ones, 0, last_fwd], z[ones, 0, last_fwd], drawn, end[:, 0], sign0, size)
    carried = (sign0 != 0.0) & (sign0 == source.sign) & (periodic == source.periodic)
    np.logical_and.at(carried, design, good)
    return Track(q.copy(), z, count.copy(), end, sign0, periodic), carried


def _predict(t, q2, z2, q1, z1, q0, z0, behind):
    """The continuation's guess at drive values t (L,) from its last points: z2 (the last,
    at q2) where `behind` is 0, the secant through (q1, z1) where 1, the parabola through
    (q0, z0) too where 2 (Newton's divided differences; a chord's error falls from O(h^2) to
    O(h^3), so fewer steps are refused for their correction and fewer iterations correct them)."""
    with np.errstate(all="ignore"):
        s21 = (z2 - z1) / (q2 - q1)[:, None]
        s10 = (z1 - z0) / (q1 - q0)[:, None]
        curve = (s21 - s10) / (q2 - q0)[:, None]
        d2 = (t - q2)[:, None]
        line = z2 + d2 * s21
        bend = line + d2 * (t - q1)[:, None] * curve
    return np.where((behind == 0)[:, None], z2, np.where((behind == 1)[:, None], line, bend))


def needed_reach(q) -> np.ndarray:
    """(N, 2) how far each design's lanes go for its drive values q (N, S): to the largest and
    the least, rounded up to a quarter turn (the calls that refine a worst value between the
    grid's values then find the track they need made), within BOUND (a full BOUND forward
    where some value lies beyond it: the periodic test needs the whole turn)."""
    quarter = 0.25 * BOUND
    hi = np.minimum(np.ceil(np.clip(np.max(q, axis=1), 0.0, None) / quarter) * quarter, BOUND)
    lo = np.minimum(np.ceil(np.clip(-np.min(q, axis=1), 0.0, None) / quarter) * quarter, BOUND)
    beyond = np.max(np.abs(q), axis=1) > BOUND
    return np.stack([np.where(beyond, BOUND, hi), lo], axis=-1)


def padded(track: Track, width: int) -> Track:
    """The track with T = width (each lane's last point repeated)."""
    extra = width - track.q.shape[-1]
    if extra <= 0:
        return track
    q = np.concatenate([track.q, np.repeat(track.q[..., -1:], extra, axis=-1)], axis=-1)
    z = np.concatenate([track.z, np.repeat(track.z[:, :, -1:], extra, axis=2)], axis=2)
    return Track(q, z, track.count, track.end, track.sign, track.periodic)


def joined(parts: list[tuple[np.ndarray, Track]], n: int) -> Track:
    """One Track of n designs from (designs, Track) parts."""
    width = max(t.q.shape[-1] for _, t in parts)
    m = parts[0][1].z.shape[-1]
    q, z = np.zeros((n, 2, width)), np.zeros((n, 2, width, m))
    count, end = np.ones((n, 2), dtype=int), np.zeros((n, 2))
    sign, periodic = np.zeros(n), np.zeros(n, dtype=bool)
    for rows, part in parts:
        part = padded(part, width)
        q[rows], z[rows], count[rows], end[rows] = part.q, part.z, part.count, part.end
        sign[rows], periodic[rows] = part.sign, part.periodic
    return Track(q, z, count, end, sign, periodic)


class TrackCache:
    """The tracks of the designs a population last followed (CAP at most), by the design's
    variables: a search evaluates the same design at other drive values (a worst value
    refined, the constraints where they bind), whose track is then taken, not followed again.
    A track is taken only when it reaches as far as the call needs. Kept in a ring of CAP
    slots (a store writes its designs' slots only, the oldest replaced first; a design stored
    again leaves its older slot empty), so a store costs its own designs, not the cache's."""

    CAP = 4096
    RECENT = 256  # the neighbours `near` looks among: the designs last stored (a probe's own design, an
    # iterate before the step)

    def __init__(self) -> None:
        self.x = np.zeros((0, 0))
        self.keys = np.zeros(0, dtype=np.uint64)
        self.reach = np.zeros((0, 2))
        self.filled = np.zeros(0, dtype=bool)
        self.track: Track | None = None
        self.next = 0  # the ring's next slot
        self.order: np.ndarray | None = None  # `find`'s filled slots by key (None: changed since)

    @staticmethod
    def row_keys(x: np.ndarray) -> np.ndarray:
        """(N,) a 64-bit hash of each row's bits (FNV-1a over the columns)."""
        bits = np.ascontiguousarray(x, dtype=float).view(np.uint64)
        h = np.full(len(x), 14695981039346656037, dtype=np.uint64)
        with np.errstate(over="ignore"):
            for j in range(bits.shape[1]):
                h = (h ^ bits[:, j]) * np.uint64(1099511628211)
        return h

    def _usable(self, x: np.ndarray) -> bool:
        return self.track is not None and self.x.shape[1] == x.shape[1] and bool(self.filled.any())

    def _reaches(self, slot: np.ndarray, reach: np.ndarray) -> np.ndarray:
        """Whether the tracks in `slot` serve drive values as far as `reach` (N, 2): their lanes
        went as far, or the branch is closed (periodic: any value, modulo a turn)."""
        assert self.track is not None
        return np.all(self.reach[slot] >= reach, axis=-1) | self.track.periodic[slot]

    def find(self, x: np.ndarray, keys: np.ndarray, reach: np.ndarray) -> np.ndarray:
        """(N,) each design's slot in the cache, -1 where it has none reaching `reach`."""
        if not self._usable(x):
            return np.full(len(x), -1)
        if self.order is None:  # the filled slots by key, sorted again after a store
            slots = np.flatnonzero(self.filled)
            self.order = slots[np.argsort(self.keys[slots], kind="stable")]
        order = self.order
        at = np.minimum(np.searchsorted(self.keys[order], keys), len(order) - 1)
        slot = order[at]
        hit = ((self.keys[slot] == keys) & np.all(self.x[slot] == x, axis=1) & self._reaches(slot, reach))
        return np.where(hit, slot, -1)

    def near(self, x: np.ndarray, reach: np.ndarray, spacing: np.ndarray, closest: bool = False) -> np.ndarray:
        """(N,) for each design the slot of a cached design within `spacing` (per variable)
        of it in every variable whose lanes both reached as far as needed without a dead
        point (-1: none; the first slot of several, or with `closest` the nearest in the
        largest of the distances over `spacing`, then the first): a search's difference probes
        of one design, whose tracks are the same branch to within the probe -- its rows are then
        solved from the neighbour's track (Newton converges to the design's own places; a
        dead point the neighbour does not have shows as rows that do not converge or change
        sign: invalid) -- or a design to carry a track to (`transport`). Looked for among the
        RECENT designs last stored (a search's probes and steps start from the design it has
        just evaluated), their pairs found along the first variable (sorted: a window of
        +-spacing each), then checked in every variable: a call costs its pairs, not N x CAP."""
        if not self._usable(x) or not x.shape[1]:
            return np.full(len(x), -1)
        assert self.track is not None
        slots = (self.next - 1 - np.arange(min(self.RECENT, self.CAP))) % self.CAP  # the latest stored first
        slots = slots[self.filled[slots] & np.isnan(self.track.end[slots]).all(axis=1) & (self.track.sign[slots] != 0.0)]
        if not len(slots):
            return np.full(len(x), -1)
        order = slots[np.argsort(self.x[slots, 0], kind="stable")]
        first = self.x[order, 0]
        lo = np.searchsorted(first, x[:, 0] - spacing[0], side="left")
        hi = np.searchsorted(first, x[:, 0] + spacing[0], side="right")
        counts = np.maximum(hi - lo, 0)
        query = np.repeat(np.arange(len(x)), counts)
        offset = np.arange(len(query)) - np.repeat(np.cumsum(counts) - counts, counts)
        slot = order[np.repeat(lo, counts) + offset]
        with np.errstate(all="ignore"):
            apart = np.max(np.where(spacing > 0.0, np.abs(x[query] - self.x[slot]) / spacing, 0.0), axis=-1)
        close = (np.all(np.abs(x[query] - self.x[slot]) <= spacing[None, :], axis=-1)
                 & self._reaches(slot, reach[query]))
        query, slot, apart = query[close], slot[close], apart[close]
        if closest and len(query):  # per query: the least distance, then the least slot
            pick = np.lexsort((slot, apart, query))  # slot: ties to the first of the ring's slots
            query, slot = query[pick], slot[pick]
            first_of = np.r_[True, query[1:] != query[:-1]]
            query, slot = query[first_of], slot[first_of]
        out = np.full(len(x), len(self.keys))
        np.minimum.at(out, query, slot)
        return np.where(out < len(self.keys), out, -1)

    def take(self, slots: np.ndarray) -> Track:
        assert self.track is not None
        return self.track.subset(slots)

    def store(self, x: np.ndarray, keys: np.ndarray, reach: np.ndarray, track: Track) -> None:
        """Keep these designs' tracks in the ring's next slots (the oldest replaced; an older
        slot of the same design emptied)."""
        n = len(x)
        if self.track is None or self.x.shape[1] != x.shape[1]:
            self._allocate(x.shape[1], track)
        assert self.track is not None
        if n > self.CAP:
            x, keys, reach, track = x[-self.CAP:], keys[-self.CAP:], reach[-self.CAP:], track.subset(
                np.arange(n - self.CAP, n))
            n = self.CAP
        self.filled &= ~np.isin(self.keys, keys)
        self.order = None
        width = max(self.track.q.shape[-1], track.q.shape[-1])
        if width > self.track.q.shape[-1]:
            self.track = padded(self.track, width)
        track = padded(track, width)
        slots = (self.next + np.arange(n)) % self.CAP
        self.next = int((self.next + n) % self.CAP)
        self.x[slots], self.keys[slots], self.reach[slots], self.filled[slots] = x, keys, reach, True
        t = self.track
        t.q[slots], t.z[slots], t.count[slots], t.end[slots] = track.q, track.z, track.count, track.end
        t.sign[slots], t.periodic[slots] = track.sign, track.periodic

    def _allocate(self, k: int, like: Track) -> None:
        cap, width, m = self.CAP, like.q.shape[-1], like.z.shape[-1]
        self.x, self.keys = np.zeros((cap, k)), np.zeros(cap, dtype=np.uint64)
        self.reach, self.filled, self.next = np.zeros((cap, 2)), np.zeros(cap, dtype=bool), 0
        self.track = Track(np.zeros((cap, 2, width)), np.zeros((cap, 2, width, m)), np.ones((cap, 2), dtype=int),
                           np.zeros((cap, 2)), np.zeros(cap), np.zeros(cap, dtype=bool))


def at_rows(track: Track, q):
    """(inside (N, S), past (N, S) how far past its lane's end, z guess (N, S, m), edge (N, S))
    at drive values q (N, S): the lane of each value's sign (forward for q >= 0), interpolated;
    `edge`: inside, within END_BAND of the grid step before the lane's dead point."""
    n, s = q.shape
    q = np.where(track.periodic[:, None], np.mod(q, BOUND), q)  # a closed branch: any value, modulo a turn
    lane = np.where(q >= 0.0, 0, 1)
    t = np.abs(q)
    tq = np.abs(track.q)  # (N, 2, T), |q| increasing along each lane
    width = tq.shape[-1]
    spacing = 4.0 * BOUND  # every |q| of a lane lies below it: lanes apart on one sorted line
    keys = (np.arange(2 * n, dtype=float)[:, None] * spacing + tq.reshape(2 * n, width)).reshape(-1)
    which = np.arange(n)[:, None] * 2 + lane
    found = np.searchsorted(keys, which * spacing + t, side="right") - 1 - which * width
    count = track.count.reshape(-1)[which]
    idx = np.clip(found, 0, np.maximum(count - 2, 0))
    nxt = np.minimum(idx + 1, count - 1)
    flat_q, flat_z = tq.reshape(2 * n, width), track.z.reshape(2 * n, width, -1)
    q_a, q_b = flat_q[which, idx], flat_q[which, nxt]
    z_a, z_b = flat_z[which, idx], flat_z[which, nxt]
    with np.errstate(all="ignore"):
        frac = np.clip(np.where(q_b > q_a, (t - q_a) / (q_b - q_a), 0.0), 0.0, 1.0)
    guess = z_a + (z_b - z_a) * frac[..., None]
    # between two points of a lane of three or more: the parabola through a third, the one
    # before (after, at the lane's start): Newton's rows start an order of h closer
    third = np.where(idx > 0, idx - 1, idx + 2)
    bend = (count >= 3) & (t > q_a) & (t < q_b)
    third = np.where(bend, np.minimum(third, count - 1), idx)
    q_c, z_c = flat_q[which, third], flat_z[which, third]
    with np.errstate(all="ignore"):
        curve = ((z_c - z_a) / (q_c - q_a)[..., None] - (z_b - z_a) / (q_b - q_a)[..., None]) / (q_c - q_b)[..., None]
        bent = guess + ((t - q_a) * (t - q_b))[..., None] * curve
    guess = np.where(bend[..., None] & np.isfinite(bent), bent, guess)
    top = flat_q[which, count - 1]  # the lane's last |q|
    inside = (t <= top) & (track.sign[:, None] != 0.0)
    past = np.maximum(t - top, 0.0)
    edge = inside & np.isfinite(track.end.reshape(-1)[which]) & (top - t <= END_BAND * BOUND / TRACK_STEPS)
    return inside, past, guess, edge


# ---------------------------------------------------------------- small systems

def solve_small(a: np.ndarray, b: np.ndarray):
    """(x (m, L), det a (L,)) for stacks a (m, m, L), b (m, L), lanes last: up to m = 3 by
    cofactors (`_cramer`), beyond by Gaussian elimination with partial pivoting
    (a row below swaps up where its entry is larger than the pivot's: the largest comes up,
    the first of equal candidates) and back substitution, elementwise (exactly rounded on every
    CPU: no BLAS, no LAPACK, no sums in another order); NaN x and det 0 where a pivot is 0 or
    not finite."""
    m = a.shape[0]
    if m <= 3:
        return _cramer(a, b)
    w = np.concatenate([a, b[:, None, :]], axis=1)  # (m, m + 1, L)
    det = np.ones(w.shape[-1])
    with np.errstate(all="ignore"):
        for k in range(m):
            for i in range(k + 1, m):
                up = np.abs(w[i, k]) > np.abs(w[k, k])
                if up.any():
                    low, top = w[i].copy(), w[k].copy()
                    w[k] = np.where(up, low, top)
                    w[i] = np.where(up, top, low)
                    det = np.where(up, -det, det)
            pivot = w[k, k]
            det = det * pivot
            if k + 1 < m:
                w[k + 1:, k:] = w[k + 1:, k:] - (w[k + 1:, k] / pivot)[:, None, :] * w[None, k, k:]
        x = np.empty((m, w.shape[-1]))
        for k in range(m - 1, -1, -1):
            acc = w[k, m]
            for j in range(k + 1, m):
                acc = acc - w[k, j] * x[j]
            x[k] = acc / w[k, k]
    good = np.isfinite(det) & (det != 0.0)
    return np.where(good, x, np.nan), np.where(good, det, 0.0)


def _cramer(a: np.ndarray, b: np.ndarray):
    """solve_small for m <= 3 by cofactors: x = adj(a) b / det a (Cramer's rule), det a by the
    first row's cofactors; a few elementwise products over the lanes (a triad's m = 3: its
    elimination costs twice its residual, these a tenth). Cramer's rule solves a 3 x 3 system
    to within its condition number of round-off, as elimination does (Higham, Accuracy and
    Stability of Numerical Algorithms, 2nd ed., sec. 1.10.1): enough for Newton's steps, whose
    fixed point is set by the residual, not by the solve."""
    m = a.shape[0]
    with np.errstate(all="ignore"):
        if m == 1:
            det = a[0, 0]
            x = (b[0] / det)[None, :]
        elif m == 2:
            a00, a01, a10, a11 = a[0, 0], a[0, 1], a[1, 0], a[1, 1]
            det = a00 * a11 - a01 * a10
            x = np.stack([(a11 * b[0] - a01 * b[1]) / det, (a00 * b[1] - a10 * b[0]) / det])
        else:
            a00, a01, a02 = a[0, 0], a[0, 1], a[0, 2]
            a10, a11, a12 = a[1, 0], a[1, 1], a[1, 2]
            a20, a21, a22 = a[2, 0], a[2, 1], a[2, 2]
            det, c00, c01, c02 = _first_row(a)
            c10, c11, c12 = a02 * a21 - a01 * a22, a00 * a22 - a02 * a20, a01 * a20 - a00 * a21
            c20, c21, c22 = a01 * a12 - a02 * a11, a02 * a10 - a00 * a12, a00 * a11 - a01 * a10
            b0, b1, b2 = b[0], b[1], b[2]
            x = np.stack([(c00 * b0 + c10 * b1 + c20 * b2) / det, (c01 * b0 + c11 * b1 + c21 * b2) / det,
                          (c02 * b0 + c12 * b1 + c22 * b2) / det])
    good = np.isfinite(det) & (det != 0.0)
    return np.where(good, x, np.nan), np.where(good, det, 0.0)


def det_small(a: np.ndarray) -> np.ndarray:
    """(L,) det a of stacks a (m, m, L), 0 where not finite: up to m = 3 by the first row's
    cofactors (the determinant `_cramer` divides by), beyond by solve_small's elimination."""
    m = a.shape[0]
    if m > 3:
        return solve_small(a, np.zeros(a.shape[1:]))[1]
    with np.errstate(all="ignore"):
        if m == 1:
            det = a[0, 0].copy()
        elif m == 2:
            det = a[0, 0] * a[1, 1] - a[0, 1] * a[1, 0]
        else:
            det = _first_row(a)[0]
    return np.where(np.isfinite(det), det, 0.0)  # 0: not finite (solve_small's rule)


def _first_row(a: np.ndarray):
    """(det a, c00, c01, c02) of stacks a (3, 3, L): the first row's cofactors and the
    determinant by them, one order of products for `_cramer` and `det_small` (the same bits)."""
    a00, a01, a02 = a[0, 0], a[0, 1], a[0, 2]
    a10, a11, a12 = a[1, 0], a[1, 1], a[1, 2]
    a20, a21, a22 = a[2, 0], a[2, 1], a[2, 2]
    c00, c01, c02 = a11 * a22 - a12 * a21, a12 * a20 - a10 * a22, a10 * a21 - a11 * a20
    return a00 * c00 + a01 * c01 + a02 * c02, c00, c01, c02


def _measure(jac: np.ndarray, ratio: bool):
    """(det J, Hadamard's ratio |det J| / prod_j |J_:,j| in [0, 1] or None) of stacks J (m, m, L)."""
    det = det_small(jac)
    if not ratio:
        return det, None
    norms = np.ones(jac.shape[-1])
    for k in range(jac.shape[1]):
        column = jac[:, k]
        square = column[0] * column[0]
        for i in range(1, len(column)):  # summed in order (numpy's sum over a short row: the same bits)
            square = square + column[i] * column[i]
        norms = norms * np.sqrt(square)
    with np.errstate(all="ignore"):
        return det, np.where(norms > 0.0, np.abs(det) / norms, 0.0)
