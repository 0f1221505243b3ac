"""One point of a front: the epsilon-constraint problem (Haimes, Lasdon & Wismer, "On a
bicriterion formulation of the problems of integrated system identification and system
optimization", IEEE Trans. SMC 1 (1971); Miettinen, Nonlinear Multiobjective Optimization,
1999, sec. 3.2), in the unit box of the free design variables:

    minimize f_1(x)  subject to  f_k(x) <= eps_k (k >= 2),  g(x) >= 0,  lo <= x <= hi,

solved by the house's constrained least-squares polish (linkcli.search.polish: Gauss-Newton
SQP steps, then SLSQP that certifies a KKT point). f_1 = `error` is a sum of squares, its
residuals r are the polish's own; any other f_1 is a largest piece, minimized in epigraph
form (an extra variable t, r = t / s_1, every piece <= t). An objective held <= eps is held
piece by piece ((eps - piece) / s_k >= 0), each scaled by s_k (its spread over the front's
anchors). Slopes by differences: the type's residuals and constraints of a whole batch of
shifted designs in one call, the other objectives through the protocol (the size of the whole
batch at once: Measure.pieces_many).

The size lifted (`Scalarized.lifted`, the form a failed Newton settle tries again in): the diagonal of the box is a largest of
joints^4 pieces sqrt((xmax_i - xmin_j)^2 + (ymax_k - ymin_l)^2), and where two joints tie for
one side of the box (the smallest linkages of a front: the optimum balances them) many pieces
bind whose gradients are dependent (rank 5 of 16 for a tie on every side): their multipliers
are not unique, and an active-set Newton method releases one, breaks it, adds it again. Lifted,
the box's four sides are variables X+, X-, Y+, Y- (a max in epigraph form, one variable a
side, as t is for a first objective that is a largest piece), each held beyond every
peak of every joint (X+ >= x of each peak, ...: Measure.boxes_many, two peaks a joint, so that a
joint whose coordinate peaks twice over the motion is two smooth constraints and not one
that bends), and the diagonal sqrt((X+ - X-)^2 + (Y+ - Y-)^2) <= eps (or <= t s, the size the
first objective): tied sides are then constraints with independent gradients, each with its
own multiplier. Its feasible designs are the unlifted problem's, with the same size (but where
the largest row's peak is not the highest refined one: rows 0.5 deg apart, 1e-5 of the diagonal).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.search.budget import Budget

STEP = 1e-7  # unit box: forward difference step (a one-sided Gauss-Newton model)
CENTRAL = 1e-6  # unit box: central difference step (SLSQP's slopes)
HUGE = 1e6  # a piece that cannot be measured (no assembly): far outside any eps


class Scalarized:
    """linkcli.search.polish's problem of one epsilon level (module docstring)."""

    def __init__(self, measure, primary: int, eps: dict, scales: np.ndarray, budget: Budget,
                 weight: float = 1e2) -> None:
        space = measure.space
        self.measure, self.space, self.primary, self.eps = measure, space, primary, dict(eps)
        self.scales, self.budget, self.weight = np.asarray(scales, float), budget, weight
        self.free = np.flatnonzero(space.hi > space.lo)
        self.width = (space.hi - space.lo)[self.free]
        self.epigraph = measure.names[primary] != "error"
        self.k = len(self.free)
        self.n_variables = self.k + (1 if self.epigraph else 0)
        self.t_scale = 1.0  # epigraph: t in [0, 1] is f_1 in [0, t_scale * s_1]
        self.cache: dict = {}
        self.box: int | None = None  # lifted: the size's objective index (module docstring)
        self.box_at = self.n_variables  # lifted: the first of the box's four side variables
        self.box_origin, self.box_span = np.zeros(4), 1.0  # lifted: a side is origin + (u - 1/2) span

    def lifted(self, x) -> Scalarized:
        """This level with its size lifted (module docstring), the box's sides centred on design
        x's own and spanning its diagonal; self where the level neither holds nor minimizes the size."""
        names = self.measure.names
        k = names.index("size") if "size" in names else None
        if k is None or not (k in self.eps or (k == self.primary and self.epigraph)):
            return self
        out = Scalarized(self.measure, self.primary, self.eps, self.scales, self.budget, self.weight)
        out.t_scale, out.box = self.t_scale, k
        out.n_variables += 4
        box = self.measure.boxes_many([self.space.solution(np.asarray(x, float))])[0]
        sides = self._sides(box)
        if not np.all(np.isfinite(sides)):
            return self
        out.box_origin = sides
        out.box_span = max(float(np.hypot(sides[0] - sides[1], sides[2] - sides[3])), 1e-300)
        return out

    @staticmethod
    def _sides(box) -> np.ndarray:
        """(X+, X-, Y+, Y-) of joints' peaks box (4, joints, PEAKS): the box they span."""
        return np.array([np.max(box[0]), np.min(box[1]), np.max(box[2]), np.min(box[3])])

    # ------------------------------------------------------------ variables
    def design(self, u) -> np.ndarray:
        x = np.array(self.space.x0, dtype=float)
        x[self.free] = self.space.lo[self.free] + np.clip(u[:self.k], 0.0, 1.0) * self.width
        return x

    def unit(self, x, t: float | None = None) -> np.ndarray:
        u = (np.asarray(x, float)[self.free] - self.space.lo[self.free]) / self.width
        u = np.clip(u, 0.0, 1.0)
        if self.epigraph:
            u = np.append(u, 0.0 if t is None else min(max(t, 0.0), 1.0))
        if self.box is not None:  # the sides at the design's own box
            box = self.measure.boxes_many([self.space.solution(np.asarray(x, float))])[0]
            u = np.append(u, np.clip(0.5 + (self._sides(box) - self.box_origin) / self.box_span, 0.0, 1.0))
        return u

    # ------------------------------------------------------------ values
    def _all(self, us: np.ndarray):
        """(residuals (K, m), constraints (K, c)) of unit-box points us (K, n_variables), each
        design measured once (an evaluation of the budget)."""
        us = np.atleast_2d(us)
        keys = [u.tobytes() for u in us]
        first: dict = {}  # each point not measured yet, once (its first row)
        for i, key in enumerate(keys):
            if key not in self.cache:
                first.setdefault(key, i)
        todo = list(first.values())
        if todo:
            designs: dict = {}  # each design once (points that differ in t or the box's sides alone share it)
            at = [designs.setdefault(self.design(us[i]).tobytes(), len(designs)) for i in todo]
            self.budget.spend(len(designs))
            xs = np.array([np.frombuffer(key) for key in designs])
            with np.errstate(all="ignore"):
                res = self.space.residuals(xs)
                ineq = self.space.inequalities(xs)
            sols = [self.space.solution(x) for x in xs]
            pieces = self._pieces(xs, sols)
            boxes = self.measure.boxes_many(sols) if self.box is not None else [None] * len(xs)
            for j, i in zip(at, todo):
                self.cache[keys[i]] = self._row(us[i], res[j], ineq[j], pieces[j], boxes[j])
        rows = [self.cache[key] for key in keys]
        return np.array([r for r, _ in rows]), np.array([c for _, c in rows])

    def _pieces(self, xs, sols) -> list:
        """Per design of xs, the measure's pieces of the objectives this level holds or
        minimizes (None each: only `error`, from the residuals), measured at once."""
        names = self.measure.names
        need = [k for k, name in enumerate(names)
                if (k == self.primary and self.epigraph or k in self.eps) and k != self.box]
        if not any(names[k] != "error" for k in need):
            return [None] * len(xs)
        with np.errstate(all="ignore"):
            return self.measure.pieces_many(xs, wanted=set(need), sols=sols)

    def _row(self, u, res, ineq, pieces, box=None):
        names, s = self.measure.names, self.scales
        with np.errstate(all="ignore"):
            cons = [np.where(np.isfinite(ineq), ineq, -HUGE)]
            diagonal = None
            if self.box is not None:  # the sides beyond every peak; the diagonal held below
                sides = self.box_origin + (u[self.box_at:self.box_at + 4] - 0.5) * self.box_span
                for side, sign, peaks in zip(sides, (1.0, -1.0, 1.0, -1.0), box):
                    beyond = sign * (side - peaks.reshape(-1)) / s[self.box]
                    cons.append(np.where(np.isfinite(beyond), beyond, -HUGE))
                diagonal = np.array([math.hypot(sides[0] - sides[1], sides[2] - sides[3])])
            for k in sorted(self.eps):
                p = (np.array([float(res @ res)]) if names[k] == "error" else
                     diagonal if k == self.box else pieces[k])
                cons.append((self.eps[k] - np.where(np.isfinite(p), p, HUGE)) / s[k])
            if self.epigraph:
                p = diagonal if self.primary == self.box else pieces[self.primary]
                t = u[self.k] * self.t_scale
                cons.append(t - np.where(np.isfinite(p), p, HUGE) / s[self.primary])
                r = np.array([t])
            else:
                r = np.where(np.isfinite(res), res, HUGE) / math.sqrt(s[self.primary])
        return r, np.concatenate(cons)

    def value(self, u):
        r, c = self._all(np.asarray(u, float)[None, :])
        return float(r[0] @ r[0]), c[0], r[0]

    def slope(self, u, central: bool = True):
        """(grad f, dc/du, dr/du) by differences, kept inside the box."""
        u = np.asarray(u, float)
        n = len(u)
        up, down = self.shifted(u, central)
        r, c = self._all(np.concatenate([up, down]))
        r_up, r_dn, c_up, c_dn = r[:n], r[n:], c[:n], c[n:]
        span = np.maximum(np.diag(up - down), 1e-300)
        jr = ((r_up - r_dn) / span[:, None]).T
        jc = ((c_up - c_dn) / span[:, None]).T
        r0 = self.value(u)[2]
        return 2.0 * (jr.T @ r0), jc, jr

    @staticmethod
    def shifted(u, central: bool):
        """(up, down) (n, n): the points whose differences are the slopes at u."""
        n = len(u)
        h = CENTRAL if central else STEP
        up = np.clip(u[None, :] + h * np.eye(n), 0.0, 1.0)
        if central:
            down = np.clip(u[None, :] - h * np.eye(n), 0.0, 1.0)
        else:
            down = np.repeat(u[None, :], n, axis=0)
        return up, down

    def prefetch(self, us, central: bool) -> None:
        """Measure in one batch every point that value(u) and slope(u, central) of each u of
        us ask for (then answered from the cache)."""
        us = [np.asarray(u, float) for u in us]
        if us:
            self._all(np.concatenate([np.concatenate([u[None, :], *self.shifted(u, central)]) for u in us]))

    def objective(self, u) -> float:
        """f_1 at u, in its own units (epigraph: the largest piece itself)."""
        x = self.design(u)
        if not self.epigraph:
            r = self.space.residuals(x[None, :])[0]
            return float(r @ r)
        return float(np.max(self.measure.pieces(x)[self.primary]))

    def merit(self, u) -> float:
        """The exact penalty f + weight sum max(0, -c) (linkcli.search.polish's merit)."""
        f, c, _ = self.value(u)
        return float(f + self.weight * np.sum(np.maximum(0.0, -c)))

    def feasible(self, u, tol: float = 1e-7) -> bool:
        return bool(np.all(self.value(u)[1] >= -tol))
