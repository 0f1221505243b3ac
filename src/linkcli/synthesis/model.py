"""A design problem over a population (mechanisms.synthesis.Population) as vectors of
variables, residuals and constraints, vectorized over candidates (numpy only).

Variables of one candidate (the full vector x; a fixed one has lo == hi): the home's (a drawn
linkage: the free joints' x, y), then the timing --

    path, motion, prescribed:  offset (added to every input angle; fixed at 0 without bounds)
    path, motion, free:        q_1, then delta_k >= 0 (k = 2..n): q_k = q_1 + s (delta_2 + ...
                               + delta_k), s = +1 (ccw) or -1 (cw) per candidate; in order
                               within one turn: sum(delta) <= 2 pi
    function:                  phi0, psi0 (the start angles; fixed unless [bounds] frees them)

Drive values q are offsets from the design's drawn position (rad). Target residuals,
dimensionless (L the targets' extent, or the poses' characteristic length):

    path:     (P_k - T_k) / L                     objective sum |P_k - T_k|^2
    motion:   (O_k - T_k) / L, w wrap(theta_k - T_theta,k) / L
                                                  objective sum |O_k - T_k|^2 + (w dtheta_k)^2
    function: wrap(psi_k - psi_target,k)          objective sum dpsi_k^2 (rad^2)

with psi the followed link's turn from its drawn angle, psi_target = law(phi_k, phi0, psi0)
(output form) or psi0 + shape_k output_sweep (function form), phi_k = phi0 + fraction_k sweep.

The drawing's phase: where every joint the drive moves is free, the drawing may be the
linkage's configuration at any drive value -- the drawing at q = d with every drive value
less d is the same design -- and the timing's phase (q_1, the offset, phi0) is redundant
with it (a flat direction of every objective, where Newton's steps are singular). Where the
timing has a free phase, the home's `phase_variable` is then held at its drawn value (a
drawn linkage: the coordinate of the driving link's pin that the turn moves the more): the
drawing's phase is fixed, the timing's stays free, and every box keeps its meaning.

The drawing's place, turn and size: a function's residuals are turns from drawn angles, which
no similarity z -> g + u z of the whole drawing changes. Where every joint is free
(Population.placement_free) that is a 4-dimensional flat direction of the objective: the
settle (search.settled) holds GAUGE_HELD home variables where the search left them, and every
settled design is printed as `canonical` makes it -- the similar copy nearest its starting
drawing in least squares over the joints (Umeyama, IEEE PAMI 13(4), 1991, with scaling) -- a
function of the design's shape alone, the same on every machine.

Constraints, g <= 0 feasible, one per closure and kind (Population.constraints), each the
worst over the drive's travel: the whole turn (`drive = "crank"`: the driving link turns
fully), else the hull of the drawn position and the targets (the linkage moves from its
drawing through every target without a dead point: the drawn branch of every closure). The
worst is taken on a grid of GRID values over a turn (as many a radian over a shorter travel),
then refined where it comes near 0 by successive parabolic interpolation (REFINE steps, each
one more kinematics column), so that it is a smooth function of the design to round-off and
its slope is the closure's at the refined drive value (the envelope theorem): the Jacobians
evaluate only there. Assembly margins are scaled by the starting drawing's size, transmission
angles are in radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

TWO_PI = 2.0 * math.pi
GRID = 72  # drive values of the constraints' grid over a turn (fewer over a shorter travel, >= 9)
REFINE = 4  # parabolic refinements of a grid extreme
NEAR = 5e-3  # a worst value above -NEAR (dimensionless) is refined: between two grid values 5 deg
# apart a margin or an angle rises by about g'' (2.5 deg)^2 / 2, some 1e-3 for g'' ~ 1 (per rad^2)
HUGE = 1e100  # a residual that overflowed or is undefined
CHUNK = 1 << 18  # design-drive rows of one kinematics call in targets_at (a Jacobian's k + 1 designs
# each at every target: with free timing through 200 targets, 4 million rows and 1.2 GB in one call)
FINE = 0.25  # deg: the final check's grid (as the analysis's reach)


@dataclass
class Evaluation:
    """Candidates' residuals and constraints: r (N, m_t) target residuals (dimensionless),
    g (N, M) constraints (dimensionless, <= 0 feasible), each the worst over the travel and the
    targets; at (N, M) the drive value of that worst and anchor (N, M) what it moves with when
    the design does: ANCHORED (nothing: a drive value inside the travel), LOWER / UPPER (the
    travel's end), k >= 0 (target k's drive value); valid (N, n) the targets' assembly;
    q (N, n) their drive values; objective (N,) in the problem's units."""

    r: np.ndarray
    g: np.ndarray
    at: np.ndarray
    anchor: np.ndarray
    valid: np.ndarray
    q: np.ndarray
    objective: np.ndarray


ANCHORED, LOWER, UPPER = -1, -2, -3


class Model:
    """A DrawnDesignProblem (model.drawn_design) over its home's population."""

    def __init__(self, problem, population):
        self.problem, self.pop = problem, population
        self.kind = problem.kind
        self.k_home = len(population.names)
        lo, hi = list(population.lo), list(population.hi)
        names = list(population.names)
        self.timing = problem.timing if self.kind != "function" else "function"
        if self.kind == "path":
            self.targets = np.array(problem.points, dtype=float)
        elif self.kind == "motion":
            self.targets = np.array(problem.poses, dtype=float)
        else:
            self.targets = np.zeros((len(problem.fractions), 0))
        n = self.n = len(self.targets)
        if self.timing == "prescribed":
            off = problem.input_offset or (0.0, 0.0)
            lo.append(off[0])
            hi.append(off[1])
            names.append("input_offset")
            self.base = np.array(problem.input_angles, dtype=float)
        elif self.timing == "free":
            lo += [-TWO_PI] + [0.0] * (n - 1)
            hi += [TWO_PI] + [TWO_PI] * (n - 1)
            names += ["input_1"] + [f"step_{k + 2}" for k in range(n - 1)]
        else:
            for key in ("input_start", "output_start"):
                given = getattr(problem, key)
                r = problem.start_bounds.get(key, (given, given))
                lo.append(r[0])
                hi.append(r[1])
                names.append(key)
        self.names = tuple(names)
        self.lo, self.hi = np.array(lo, dtype=float), np.array(hi, dtype=float)
        self.phase = population.phase_variable()  # held where the drawing's phase is the timing's
        if self.phase is not None and self.hi[self.k_home] > self.lo[self.k_home]:
            self.lo[self.phase] = self.hi[self.phase] = population.drawn[self.phase]
        else:
            self.phase = None
        self.free = self.hi > self.lo
        self.gauge = self.kind == "function" and population.placement_free()
        if self.kind == "path":
            ext = self.targets.max(axis=0) - self.targets.min(axis=0)
            self.scale = float(max(ext.max(), 1e-300))
        elif self.kind == "motion":
            origins = self.targets[:, :2]
            rms = float(np.sqrt(np.mean(np.sum((origins - origins.mean(0)) ** 2, -1))))
            self.scale = rms if rms > 0.0 else 1.0
            self.weight = self.scale if problem.angle_weight is None else float(problem.angle_weight)
        else:
            self.scale = 1.0
        self.size = float(population.size(population.drawn[None])[0]) or 1.0
        self.window = problem.transmission
        self.crank = problem.drive == "crank"
        self.m_t = {"path": 2 * n, "motion": 3 * n, "function": n}[self.kind]
        self.kinds = population.constraints(_empty_motion(len(population.closures)), self.window)[1]
        self.angle_kind = np.array([kind == "transmission" for kind, _ in self.kinds])
        self.unit = np.where(self.angle_kind, 1.0, 1.0 / self.size)  # constraint -> dimensionless
        self.ranks: dict = {}  # a design's (infeasible, violation, objective), search.rank's

    # ------------------------------------------------------------ the gauge
    def canonical(self, x: np.ndarray) -> np.ndarray:
        """x (nx,) with its home pairs (x, y) moved by the similarity z -> d_m + w (z - z_m)
        that brings them nearest the drawn places d in least squares (module docstring):
        w = sum (d - d_m) conj(z - z_m) / sum |z - z_m|^2, m the means. Unchanged without a
        gauge."""
        if not self.gauge:
            return x
        k = self.k_home
        z = x[0:k:2] + 1j * x[1:k:2]
        d = self.pop.drawn[0:k:2] + 1j * self.pop.drawn[1:k:2]
        zc, dc = z - z.mean(), d - d.mean()
        norm = float(np.sum(np.abs(zc) ** 2))
        if not norm > 0.0:
            return x
        w = complex(np.sum(dc * np.conj(zc))) / norm
        moved = d.mean() + w * zc
        out = np.array(x, dtype=float, copy=True)
        out[0:k:2], out[1:k:2] = moved.real, moved.imag
        return out

    def snapped(self, x: np.ndarray) -> np.ndarray:
        """x (nx,) with its round-off as 0 (noise.snap, docs/determinism.md): a free home
        variable within NOISE_FLOOR of the home's scale for it (Population.round_off_scales: a
        drawing's coordinates, its longest link), a free timing angle within NOISE_FLOOR of
        1 rad; kept in its box. A free pivot whose exact place has a coordinate 0 then prints
        0 on every machine, not the 1e-11 a search leaves there; the fixed ones are the file's."""
        from linkcli.noise import snap
        k = self.k_home
        scales = np.ones(len(x))
        scales[:k] = self.pop.round_off_scales(x[None, :k])[0]
        return np.where(self.free, np.clip(snap(x, scales), self.lo, self.hi), x)

    # ------------------------------------------------------------ timing
    def directions(self) -> tuple[float, ...]:
        if self.timing != "free":
            return (1.0,)
        return {"ccw": (1.0,), "cw": (-1.0,)}.get(self.problem.direction, (1.0, -1.0))

    def inputs(self, x: np.ndarray, s: np.ndarray) -> np.ndarray:
        """(N, n) drive values of the targets (rad from the drawn position)."""
        k = self.k_home
        if self.timing == "prescribed":
            return self.base[None, :] + x[:, k:k + 1]
        if self.timing == "free":
            steps = np.concatenate([np.zeros((len(x), 1)), np.cumsum(x[:, k + 1:], axis=1)], axis=1)
            return x[:, k:k + 1] + s[:, None] * steps
        return x[:, k:k + 1] + np.array(self.problem.fractions)[None, :] * self.problem.input_sweep

    def law(self, x: np.ndarray) -> np.ndarray:
        """(N, n) function generation's target angles (rad from the link's drawn angle)."""
        p = self.problem
        phi0, psi0 = x[:, self.k_home:self.k_home + 1], x[:, self.k_home + 1:self.k_home + 2]
        if p.form == "function":
            return psi0 + np.array(p.shape)[None, :] * p.output_sweep
        phi = self.inputs(x, np.ones(len(x)))
        with np.errstate(all="ignore"):
            return np.broadcast_to(p.law(phi=phi, phi0=phi0, psi0=psi0), phi.shape)

    def travel(self, q: np.ndarray):
        """(lo, hi) (N,) each: the drive's travel -- a whole turn, or the hull of 0 and q."""
        if self.crank:
            return np.zeros(len(q)), np.full(len(q), TWO_PI)
        return np.minimum(q.min(axis=1), 0.0), np.maximum(q.max(axis=1), 0.0)

    def grid(self, lo, hi, count: int | None = None) -> np.ndarray:
        """(N, G) drive values over each travel, its ends included (a turn: its start only)."""
        if count is None:
            count = GRID if self.crank else int(np.clip(np.ceil(GRID * np.max(hi - lo) / TWO_PI), 9, GRID))
        t = np.arange(count) / (count if self.crank else count - 1)
        return lo[:, None] + (hi - lo)[:, None] * t[None, :]

    # ------------------------------------------------------------ evaluation
    def target_residuals(self, x, motion, q) -> tuple[np.ndarray, np.ndarray]:
        """(residuals (N, m_t), objective (N,)) from the motion at the targets' columns."""
        if self.kind == "path":
            d = motion.points[:, :, 0, :] - self.targets[None]
            return d.reshape(len(x), -1) / self.scale, np.sum(d * d, axis=(1, 2))
        if self.kind == "motion":
            d = motion.origins[:, :, 0, :] - self.targets[None, :, :2]
            da = _wrap(motion.angles[:, :, 0] - self.targets[None, :, 2])
            r = np.concatenate([d.reshape(len(x), -1), self.weight * da], axis=1)
            return r / self.scale, np.sum(d * d, axis=(1, 2)) + np.sum((self.weight * da) ** 2, axis=1)
        drawn = self.pop.drawn_angles(self.pop.places(x))[:, None, 0]
        da = _wrap(motion.angles[:, :, 0] - drawn - self.law(x))
        return da, np.sum(da * da, axis=1)

    def evaluate(self, x: np.ndarray, s: np.ndarray, refine: bool = True, near: float = NEAR,
                 count: int | None = None) -> Evaluation:
        """Residuals and constraints of candidates x (N, nx), directions s (N,): the worst of
        each constraint over the targets and the travel's grid, the grid's refined where it
        comes within `near` of 0 (module docstring)."""
        n = self.n
        q = self.inputs(x, s)
        lo, hi = self.travel(q)
        grid = self.grid(lo, hi, count)
        with np.errstate(all="ignore"):
            motion = self.pop.kinematics(x, np.concatenate([q, grid], axis=1))
            r, objective = self.target_residuals(x, _columns(motion, slice(0, n)), q)
            g_all, _ = self.pop.constraints(motion, self.window)
        g_all = g_all * self.unit  # (N, n + G, M)
        g_all = np.where(np.isnan(g_all), HUGE, g_all)
        rows = np.arange(len(x))[:, None]
        cols = np.arange(g_all.shape[2])[None, :]
        count = grid.shape[1]
        best = n + np.argmax(g_all[:, n:], axis=1)  # the grid's worst (N, M)
        g, at = g_all[rows, best, cols], grid[rows, best - n]
        anchor = np.full(g.shape, ANCHORED)
        if not self.crank:
            anchor = np.where(best == n, LOWER, np.where(best == n + count - 1, UPPER, ANCHORED))
        if refine:
            g, at, anchor = self._refined(x, grid, g_all[:, n:], best - n, g, at, anchor, near)
            second = self._second_peak(g_all[:, n:], best - n)  # the next peak, apart from the first:
            # its refined value may pass the first's (two near-equal extremes a grid step apart)
            if second is not None:
                g2, at2, anchor2 = self._refined(x, grid, g_all[:, n:], second, g_all[:, n:][rows, second, cols],
                                                 grid[rows, second], np.full(g.shape, ANCHORED), near)
                if not self.crank:
                    anchor2 = np.where(second == 0, LOWER, np.where(second == count - 1, UPPER, ANCHORED))
                here = g2 > g
                g, at, anchor = np.where(here, g2, g), np.where(here, at2, at), np.where(here, anchor2, anchor)
        if n:
            worst = np.argmax(g_all[:, :n], axis=1)  # the targets' worst
            gt = g_all[rows, worst, cols]
            here = gt > g
            g = np.where(here, gt, g)
            at = np.where(here, q[rows, worst], at)
            anchor = np.where(here, worst, anchor)
        valid = motion.valid[:, :n]
        return Evaluation(np.nan_to_num(r, nan=HUGE, posinf=HUGE, neginf=-HUGE), g, at, anchor, valid, q,
                          np.where(np.isfinite(objective), objective, math.inf))

    def _second_peak(self, g_grid, best):
        """(N, M) the grid index of each constraint's highest local maximum other than the one
        at `best` (its neighbours excluded), or None when no constraint has one."""
        count = g_grid.shape[1]
        idx = np.arange(count)
        if self.crank:
            left, right = np.roll(g_grid, 1, axis=1), np.roll(g_grid, -1, axis=1)
            gap = np.abs(idx[None, :, None] - best[:, None, :])
            gap = np.minimum(gap, count - gap)
        else:
            left = np.concatenate([np.full_like(g_grid[:, :1], -np.inf), g_grid[:, :-1]], axis=1)
            right = np.concatenate([g_grid[:, 1:], np.full_like(g_grid[:, :1], -np.inf)], axis=1)
            gap = np.abs(idx[None, :, None] - best[:, None, :])
        peak = (g_grid >= left) & (g_grid >= right) & (gap > 1)
        if not peak.any():
            return None
        masked = np.where(peak, g_grid, -np.inf)
        second = np.argmax(masked, axis=1)
        return np.where(np.isfinite(np.max(masked, axis=1)), second, best)

    def _refined(self, x, grid, g_all, best, g, at, anchor, near):
        """Worst grid values refined by successive parabolic interpolation through the grid
        neighbours (module docstring), only where they come within `near` of 0."""
        count = grid.shape[1]
        todo = (g > -near) & (g < HUGE)
        if not todo.any():
            return g, at, anchor
        rows, cols = np.nonzero(todo)
        i = best[rows, cols]
        if self.crank:
            il, ir = (i - 1) % count, (i + 1) % count
        else:
            il, ir = np.maximum(i - 1, 0), np.minimum(i + 1, count - 1)
        step = grid[rows, 1] - grid[rows, 0]
        # (a, fa), (b, fb), (c, fc) with b the largest: [a, c] brackets the maximum
        b, fb = grid[rows, i], g_all[rows, i, cols]
        a, fa = b - step * (i != il), g_all[rows, il, cols]
        c, fc = b + step * (i != ir), g_all[rows, ir, cols]
        for _ in range(REFINE):
            den = (b - a) * (fb - fc) - (b - c) * (fb - fa)
            num = (b - a) ** 2 * (fb - fc) - (b - c) ** 2 * (fb - fa)
            with np.errstate(all="ignore"):
                t = b - 0.5 * num / den
            ok = np.isfinite(t) & (den != 0.0) & (t > a) & (t < c) & (np.abs(t - b) > 1e-15 * (1 + np.abs(b)))
            if not ok.any():
                break
            t = np.where(ok, t, b)
            ft = self._at_columns(x, rows, cols, t)
            better = ok & (ft > fb)
            left = t < b
            na = np.where(better, np.where(left, a, b), np.where(ok & left, t, a))
            nfa = np.where(better, np.where(left, fa, fb), np.where(ok & left, ft, fa))
            nc = np.where(better, np.where(left, b, c), np.where(ok & ~left, t, c))
            nfc = np.where(better, np.where(left, fb, fc), np.where(ok & ~left, ft, fc))
            b, fb = np.where(better, t, b), np.where(better, ft, fb)
            a, fa, c, fc = na, nfa, nc, nfc
        g, at, anchor = g.copy(), at.copy(), anchor.copy()
        moved = at[rows, cols] != b
        g[rows, cols], at[rows, cols] = fb, b
        anchor[rows, cols] = np.where(moved, ANCHORED, anchor[rows, cols])
        return g, at, anchor

    def _at_columns(self, x, rows, cols, q) -> np.ndarray:
        """Constraint `cols[j]` of candidate `rows[j]` at drive value q[j] (dimensionless)."""
        with np.errstate(all="ignore"):
            motion = self.pop.kinematics(x[rows], self._on_travel(q)[:, None])
            g_all, _ = self.pop.constraints(motion, self.window)
        v = g_all[np.arange(len(rows)), 0, cols] * self.unit[cols]
        return np.where(np.isnan(v), HUGE, v)

    def _on_travel(self, q: np.ndarray) -> np.ndarray:
        """A refined drive value on the travel's grid: a turn's taken modulo the turn (the grid
        wraps: the refinement about its first value brackets it with its last, a turn on)."""
        return np.mod(q, TWO_PI) if self.crank else q

    def constraints_at(self, x, s, at, anchor) -> np.ndarray:
        """(N, M) every constraint at the drive value where a design's worst was (`at`, or what
        `anchor` says it moves with: the travel's end, a target's drive value, for x)."""
        q = self.inputs(x, s)
        lo, hi = self.travel(q)
        target = q[np.arange(len(x))[:, None], np.maximum(anchor, 0)] if self.n else at
        cols = np.where(anchor == LOWER, lo[:, None], np.where(anchor == UPPER, hi[:, None],
                                                               np.where(anchor >= 0, target, self._on_travel(at))))
        with np.errstate(all="ignore"):
            motion = self.pop.kinematics(x, cols)
            g_all, _ = self.pop.constraints(motion, self.window)
        m = g_all.shape[2]
        v = g_all[:, np.arange(m), np.arange(m)] * self.unit[None, :]
        return np.where(np.isnan(v), HUGE, v)

    def targets_at(self, x, s) -> np.ndarray:
        """(N, m_t) the target residuals alone."""
        q = self.inputs(x, s)
        per = max(1, CHUNK // max(1, q.shape[1]))  # designs a call: memory bounded, whatever the targets
        parts = []
        for lo in range(0, len(x), per):
            rows = slice(lo, lo + per)
            with np.errstate(all="ignore"):
                motion = self.pop.kinematics(x[rows], q[rows])
                parts.append(self.target_residuals(x[rows], motion, q[rows])[0])
        r = np.concatenate(parts, axis=0) if len(parts) != 1 else parts[0]
        return np.nan_to_num(r, nan=HUGE, posinf=HUGE, neginf=-HUGE)

    # ------------------------------------------------------------ the final check
    def check(self, x: np.ndarray, s: float):
        """The exact constraints of one design on the fine grid (FINE deg over its travel),
        refined: (evaluation, order excess): what `violations` reads."""
        x1 = x[None, :]
        q = self.inputs(x1, np.array([s]))
        lo, hi = self.travel(q)
        count = max(9, int(math.ceil(math.degrees(float(hi[0] - lo[0])) / FINE)) + 1)
        ev = self.evaluate(x1, np.array([s]), refine=True, near=math.inf, count=count)
        order = 0.0
        if self.timing == "free":
            steps = x[self.k_home + 1:]
            order = float(max(steps.sum() - TWO_PI * (1 + 1e-12), -steps.min() if len(steps) else 0.0, 0.0))
        return ev, order


def _empty_motion(closures: int):
    from linkcli.mechanisms.synthesis import Motion
    z = np.zeros((0, 0, closures))
    return Motion(points=None, angles=None, origins=None, valid=None, margins=z, transmission=z)


def _columns(motion, cols):
    """The motion at some of its drive columns."""
    from dataclasses import fields, replace
    return replace(motion, **{f.name: (getattr(motion, f.name)[:, cols] if getattr(motion, f.name) is not None
                                       else None) for f in fields(motion)})


def _wrap(a):
    return np.mod(a + math.pi, TWO_PI) - math.pi
