"""Statics of a platform turned about its hinge by a hydraulic cylinder (numpy only).

Geometry (docs/format.md, flipper-cylinder). The platform is hinged at B = (0, 0) and turns
counter-clockwise by the platform angle t from `start` to `end`. The rod pivot A and the
centre of mass G are given at the start position and turn with the platform,
X(t) = R(t - start) X_start; the base pivot C is fixed. The cylinder acts along C -> A,
e = (A - C) / L with L = |A - C|; its force F is positive when it pushes (force on A
along +e), negative when it pulls.

Static balance about the hinge (the weight -m g y-hat acts at G, its moment is -m g G_x):

    F (A x e) = m g G_x,   A x e = A x (A - C) / L = (C x A) / L,

so that, with K = C x A = C_x A_y - C_y A_x and the load moment W = m g G_x,

    F(t) = W(t) L(t) / K(t),   moment arm about B: |K| / L.

K(t) = |C| |A| sin(theta_A(t) - theta_C) is a sinusoid of t: over a sweep shorter than
180 deg it has at most one zero tau0, inside the sweep exactly when K has opposite signs
at the two ends (or is zero at one): the cylinder line then passes through the hinge.
Where the load has a moment there (W(tau0) != 0) the force is unbounded: the design cannot
hold the platform. Where it has none, W and K are both multiples of sin(tau - tau0), so
F = c L with c = W'(tau0) / K'(tau0) = -m g G_y(tau0) / (C . A(tau0)), finite everywhere.
Since d(L^2)/dt = 2 K (L^2 = |A|^2 + |C|^2 - 2 A(t) . C and dA/dt = (-A_y, A_x)), L is
monotone while K keeps its sign and has its one extreme at tau0: the closed and the open
lengths are the least and the largest of L(start), L(end) and L(tau0) when tau0 lies in
the sweep.

The peak force (largest |F| over the sweep) is taken on a grid of at most STEP spacing
with both ends exact, then every local maximum of F and of -F on the grid that comes
within 1 % of the largest is refined in its bracket by a zooming grid (ZOOM_POINTS angles,
ZOOM_PASSES times, each pass on the two cells around the best angle of the last, then the
vertex of the parabola through the best three); every
array function here is vectorized over candidates (rows) and angles (columns).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.noise import TIE, first_max

STEP = math.radians(0.5)  # largest spacing of the sweep grid
MIN_POINTS = 33
ZOOM_POINTS = 33  # angles per bracket and pass: the bracket shrinks 16-fold per pass
ZOOM_PASSES = 4  # a 1 deg bracket ends 1.5e-5 deg wide (peak value to ~1e-14 relative)
NEAR_PEAK = 0.99  # local maxima refined: grid value within 1 % of the grid maximum
POLE = 1e-12  # |K| <= POLE |A| |C| (|sin| of the angle C-B-A): the cylinder line is through the hinge
LEVEL = 1e-12  # |W| <= LEVEL m g |G| at the crossing: the load has no moment there (removable)
MEET = 1e-9  # L <= MEET max(|A|, |C|) at the crossing: the rod pivot is at the base pivot


def sweep_grid(sweep: float, step: float = STEP) -> np.ndarray:
    """Turns tau = t - start from 0 to `sweep` (rad), ends exact, spacing <= step."""
    n = max(MIN_POINTS, int(math.ceil(sweep / step - 1e-9)) + 1)
    tau = np.linspace(0.0, sweep, n)
    tau[0], tau[-1] = 0.0, sweep
    return tau


def turn(x0, y0, tau):
    """R(tau) (x0, y0): counter-clockwise about the hinge B = (0, 0)."""
    c, s = np.cos(tau), np.sin(tau)
    return c * x0 - s * y0, s * x0 + c * y0


class Statics:
    """The platform's load and sweep; forces of cylinder designs over the sweep.

    A design is the row (A_x, A_y, C_x, C_y): rod pivot at the start position, base pivot.
    Angles `tau` are turns from the start position (rad).
    """

    def __init__(self, weight: float, center_of_mass: tuple[float, float], sweep: float,
                 step: float = STEP) -> None:
        self.weight = float(weight)  # m g, N
        self.gx0, self.gy0 = (float(v) for v in center_of_mass)
        self.sweep = float(sweep)
        self.grid = sweep_grid(self.sweep, step)

    # -- forces -------------------------------------------------------------------
    def moment(self, tau):
        """Load moment W = m g G_x(tau) about B (N times length unit)."""
        return self.weight * turn(self.gx0, self.gy0, tau)[0]

    def terms(self, designs, tau):
        """K = C x A, L = |A - C| and W for designs (S, 4) at angles tau (N,) or (S, N)."""
        p = np.asarray(designs, dtype=float)
        ax0, ay0, cx, cy = (p[:, i:i + 1] for i in range(4))
        ax, ay = turn(ax0, ay0, tau)
        k = cx * ay - cy * ax
        length = np.hypot(ax - cx, ay - cy)
        return k, length, self.moment(tau)

    def forces(self, designs, tau=None, sing=None):
        """F = W L / K (N), arm |K| / L and L at angles tau (default: the grid), (S, N).

        A design whose line crosses the hinge where the load has no moment has F = c L
        (module doc). Otherwise, at the crossing itself (|K| <= POLE |A| |C|) F is nan (no
        finite force holds the platform there) and the arm is 0.
        """
        p = np.asarray(designs, dtype=float)
        tau = self.grid if tau is None else tau
        k, length, w = self.terms(p, tau)
        sing = self.singular(p) if sing is None else sing
        norm = np.hypot(p[:, 0], p[:, 1]) * np.hypot(p[:, 2], p[:, 3])
        pole = np.abs(k) <= POLE * norm[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            force = w * length / k
            arm = np.where(pole, 0.0, np.abs(k) / length)
        force = np.where(pole, np.nan, force)
        if sing["removable"].any():
            force = np.where(sing["removable"][:, None], sing["ratio"][:, None] * length, force)
        return force, arm, length

    # -- closed forms over the sweep -----------------------------------------------
    def end_lengths(self, designs):
        """Cylinder lengths at the start and at the end of the sweep, each (S,)."""
        k, length, _ = self.terms(designs, np.array([0.0, self.sweep]))
        return length[:, 0], length[:, 1]

    def lengths(self, designs, sing=None):
        """(closed, open, closed_at): the least and the largest cylinder length over the
        sweep and the turn of the least, each (S,). L is monotone except for its one extreme
        at the crossing tau0 (d(L^2)/dt = 2 K), so L(0), L(sweep) and L(tau0) suffice."""
        p = np.asarray(designs, dtype=float)
        sing = self.singular(p) if sing is None else sing
        ls, le = self.end_lengths(p)
        lc = np.where(sing["crosses"], sing["length"], np.inf)
        cand = np.column_stack([ls, le, lc])
        at = np.column_stack([np.zeros(len(p)), np.full(len(p), self.sweep), sing["tau0"]])
        i = np.argmin(cand, axis=1)
        rows = np.arange(len(p))
        opened = np.max(np.where(np.isfinite(cand), cand, -np.inf), axis=1)
        return cand[rows, i], opened, at[rows, i]

    def singular(self, designs) -> dict:
        """Where the cylinder line passes through the hinge B, per design (S,):
        `crosses` (K vanishes in the sweep: changes sign between the ends or is zero at one,
        |K| <= POLE |A| |C|), `tau0` (that turn, in [0, sweep] when it crosses), `moment`
        (W there), `length` (L there), `meet` (the pivots meet there), `removable` (no load
        moment there and the pivots apart: F = ratio L everywhere), `ratio`
        (-m g G_y(tau0) / (C . A(tau0))) and `blocked` (crosses and not removable: no finite
        force holds the platform at tau0, or the cylinder has no length there)."""
        p = np.asarray(designs, dtype=float)
        k, _, _ = self.terms(p, np.array([0.0, self.sweep]))
        norm = np.hypot(p[:, 0], p[:, 1]) * np.hypot(p[:, 2], p[:, 3])
        z0, z1 = np.abs(k[:, 0]) <= POLE * norm, np.abs(k[:, 1]) <= POLE * norm
        crosses = (np.sign(k[:, 0]) * np.sign(k[:, 1]) < 0) | z0 | z1
        if not crosses.any():  # the common case: nothing to locate
            zero, no = np.zeros(len(p)), np.zeros(len(p), dtype=bool)
            return {"crosses": no, "tau0": zero, "moment": zero, "length": zero, "meet": no,
                    "removable": no, "ratio": zero, "blocked": no, "slope": zero}
        theta = np.arctan2(p[:, 1], p[:, 0]) - np.arctan2(p[:, 3], p[:, 2])
        tau0 = np.where(z0, 0.0, np.where(z1, self.sweep, np.clip(np.mod(-theta, math.pi), 0.0, self.sweep)))
        ax, ay = turn(p[:, 0], p[:, 1], tau0)
        gx, gy = turn(self.gx0, self.gy0, tau0)
        length = np.hypot(ax - p[:, 2], ay - p[:, 3])
        moment = self.weight * gx
        meet = length <= MEET * np.maximum(np.hypot(p[:, 0], p[:, 1]), np.hypot(p[:, 2], p[:, 3]))
        removable = (crosses & ~meet & (norm > 0)
                     & (np.abs(moment) <= LEVEL * self.weight * math.hypot(self.gx0, self.gy0)))
        dot = p[:, 2] * ax + p[:, 3] * ay  # K'(tau0) = C . A(tau0) = +-|A| |C| at a crossing
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(removable, -self.weight * gy / dot, 0.0)
        return {"crosses": crosses, "tau0": tau0, "moment": moment, "length": length, "meet": meet,
                "removable": removable, "ratio": ratio, "blocked": crosses & ~removable, "slope": dot}

    def crossing(self, designs):
        """(blocked, tau0): whether no finite force holds the platform somewhere in the sweep
        (the cylinder line passes through the hinge where the load has a moment, or the
        pivots meet), and the turn tau0 where the line passes through the hinge."""
        sing = self.singular(designs)
        return sing["blocked"], sing["tau0"]

    # -- the peak --------------------------------------------------------------------
    def extremes(self, designs, sign: float):
        """Largest value of sign * F over the sweep (grid, then a zooming refinement
        of the near-largest local maxima), and its turn: two arrays (S,)."""
        p = np.asarray(designs, dtype=float)
        tau = self.grid
        f = sign * self.forces(p)[0]
        f = np.where(np.isnan(f), -np.inf, f)
        first = first_max(f, axis=1)  # equal values within the tie rule: the first in sweep order
        best = f[np.arange(len(p)), first]
        at = tau[first]
        left = np.concatenate([np.full((len(p), 1), -np.inf), f[:, :-1]], axis=1)
        right = np.concatenate([f[:, 1:], np.full((len(p), 1), -np.inf)], axis=1)
        thresh = np.where(best > 0, NEAR_PEAK * best, best)
        local = (f >= left) & (f >= right) & (f >= thresh[:, None]) & np.isfinite(f)
        rows, cols = np.nonzero(local)
        if len(rows) == 0:
            return best, at
        n = len(tau)
        lo = tau[np.maximum(cols - 1, 0)]
        hi = tau[np.minimum(cols + 1, n - 1)]
        x, fx = self._zoom(p[rows], lo, hi, sign)
        order = np.lexsort((fx, rows))
        last = np.r_[rows[order][1:] != rows[order][:-1], True]
        r, xv, fv = rows[order][last], x[order][last], fx[order][last]
        better = fv > best[r]
        best[r[better]] = fv[better]
        at[r[better]] = xv[better]
        return best, at

    def _zoom(self, designs, lo, hi, sign):
        """Maximum of sign * F on [lo, hi], one bracket per design row, all brackets at once:
        ZOOM_PASSES grids of ZOOM_POINTS angles, each on the two cells around the best angle
        of the last, then the vertex of the parabola through the best angle and its two
        neighbours when it is higher (a few vectorized calls instead of a sequential search)."""
        u = np.linspace(0.0, 1.0, ZOOM_POINTS)[None, :]
        a, b = lo.astype(float), hi.astype(float)
        rows = np.arange(len(a))

        def value(tau):
            f = sign * self.forces(designs, tau)[0]
            return np.where(np.isnan(f), -np.inf, f)

        for _ in range(ZOOM_PASSES):
            t = a[:, None] + (b - a)[:, None] * u
            f = value(t)
            j = np.argmax(f, axis=1)
            x, fx = t[rows, j], f[rows, j]
            jl, jr = np.maximum(j - 1, 0), np.minimum(j + 1, ZOOM_POINTS - 1)
            a, b = t[rows, jl], t[rows, jr]
        fl, fr = f[rows, jl], f[rows, jr]
        inner = (j > 0) & (j < ZOOM_POINTS - 1) & np.isfinite(fl) & np.isfinite(fr)
        h = (b - a) / 2.0
        with np.errstate(divide="ignore", invalid="ignore"):
            curv = fl - 2.0 * fx + fr
            shift = np.where(inner & (curv < 0), 0.5 * h * (fl - fr) / curv, 0.0)
        xv = np.clip(x + shift, a, b)
        fv = value(xv[:, None])[:, 0]
        better = fv > fx
        return np.where(better, xv, x), np.where(better, fv, fx)

    def peaks(self, designs) -> dict:
        """Largest push and pull over the sweep (N, >= 0) with their turns, and the peak
        (the larger of the two, `push` true when it pushes), arrays (S,)."""
        p = np.asarray(designs, dtype=float)
        push, push_at = self.extremes(p, 1.0)
        pull, pull_at = self.extremes(p, -1.0)
        sing = self.singular(p)
        if sing["blocked"].any():  # unbounded on the side(s) of tau0 inside the sweep
            t0 = sing["tau0"]
            s = np.sign(sing["moment"] * sing["slope"])  # F ~ W / (K'(tau0) (tau - tau0))
            after, before = t0 < self.sweep, t0 > 0.0
            up = sing["blocked"] & ((after & (s >= 0)) | (before & (s <= 0)) | sing["meet"])
            down = sing["blocked"] & ((after & (s <= 0)) | (before & (s >= 0)) | sing["meet"])
            push, push_at = np.where(up, np.inf, push), np.where(up, t0, push_at)
            pull, pull_at = np.where(down, np.inf, pull), np.where(down, t0, pull_at)
        empty = ~np.isfinite(push) & ~np.isfinite(pull) & ~sing["blocked"]  # no finite force at all: worst
        push, pull = np.where(empty, np.inf, push), np.where(empty, np.inf, pull)
        # equal within the tie rule (linkcli.noise): the first in sweep order is the peak
        tie = np.abs(push - pull) <= TIE * np.maximum(np.abs(push), np.abs(pull))
        is_push = np.where(tie & np.isfinite(push), push_at <= pull_at, push > pull)
        return {"push": np.maximum(push, 0.0), "push_at": push_at,
                "pull": np.maximum(pull, 0.0), "pull_at": pull_at,
                "peak": np.where(is_push, push, pull), "peak_at": np.where(is_push, push_at, pull_at),
                "is_push": is_push}

    # -- derivatives for a local solver --------------------------------------------------
    def gradients(self, design, tau):
        """K, L (N,) of one design at angles tau and their gradients (N, 4) with respect
        to (A_x, A_y, C_x, C_y), where A = R(tau) A_start:
        dK/dA_start = R^T (-C_y, C_x), dK/dC = (A_y, -A_x);
        dL/dA_start = R^T (A - C) / L, dL/dC = -(A - C) / L."""
        ax0, ay0, cx, cy = (float(v) for v in design)
        c, s = np.cos(tau), np.sin(tau)
        ax, ay = c * ax0 - s * ay0, s * ax0 + c * ay0
        k = cx * ay - cy * ax
        dx, dy = ax - cx, ay - cy
        length = np.hypot(dx, dy)
        dk = np.column_stack([c * (-cy) + s * cx, -s * (-cy) + c * cx, ay, -ax])
        with np.errstate(divide="ignore", invalid="ignore"):
            ux, uy = dx / length, dy / length
        dl = np.column_stack([c * ux + s * uy, -s * ux + c * uy, -ux, -uy])
        return k, dk, length, dl
