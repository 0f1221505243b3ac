"""Motion generation as the Pareto search sees it (linkcli.pareto.space): a four-bar's
ten parameters (assemble.PARAM_NAMES: ground pivot, ground angle, the four lengths, the
body's origin and angle on the coupler) and its timing, on the branch of the type's own
design; residuals the pose misses in the type's own weighting (least_squares.residuals:
dx_i, dy_i, w dangle_i; error = sum |P_i - T_i|^2 + (w dangle_i)^2, length unit^2).

Timing, as path generation's (types/path_generation/model.py): prescribed, one offset added
to every input angle; free, phi_1 and the increments delta_k >= 0 (k = 2..n) in the turning
direction s of the type's design, phi_k = phi_1 + s (delta_2 + ... + delta_k): the poses stay
in order by the box, and within one turn by sum(delta) <= 2 pi (two poses on a crank: the
shorter way round, <= pi, the travel the report measures).

Constraints (g >= 0, each of order one: lengths over the poses' characteristic length L,
screen.py judges the finished design by the same rules): assembly at every pose
(|b - c| <= rho_i <= b + c), no dead point inside the travel (the same at phi = 0 and pi
when the travel holds them), the Grashof class asked for (constraints.values), the
transmission window over the full turn for a class whose input turns fully, else over the
travel (rho's extremes on it: path_generation.model.rho2_extremes). The box: the least-squares
search's (box.design_box: the file's bounds, the default span about the poses elsewhere),
widened to hold the type's design (an exact synthesis may place a pivot beyond the default
span); given ground pivots fix A0, the ground angle and length, given moving pivots the
coupler, the body's origin and angle on it; a full-turn angle spans x0 +- 2 pi."""

from __future__ import annotations

import math

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.mechanisms.four_bar.model import FourBar
from linkcli.solution import Solution, SolverRecord, Status
from linkcli.types.path_generation.model import rho2_extremes

from . import constraints as design_constraints
from .least_squares import residuals as pose_residuals
from .screen import arcs

N_PARAMS = 10
HUGE = 1e6  # a constraint or residual that overflowed: far on the wrong side


def direction(params, phi) -> float:
    """+1 when the input reaches the poses counter-clockwise (in order, within a turn), -1
    clockwise: along the arc of a rocker, or for two poses on a crank the shorter way
    round (screen.travel's rule)."""
    p = np.asarray(params, float)[None, :]
    phi = np.asarray(phi, float)[None, :]
    full, lo, _, _ = arcs(p, phi)
    n = phi.shape[1]
    ccw = np.mod(phi[0] - phi[0, 0], kin.TWO_PI)[1:]
    if not full[0]:
        along = np.mod(phi[0] - lo[0, 0], kin.TWO_PI)
        return 1.0 if along[-1] >= along[0] else -1.0
    if n == 2:
        return 1.0 if ccw[0] <= math.pi else -1.0
    return 1.0 if np.all(np.diff(ccw) > 0) and ccw[0] > 0 else -1.0


class MotionSpace:
    """linkcli.pareto.space.Space of a four-bar motion-generation problem, from the type's
    design (params (10,), input angles at the poses (n,), branch sign)."""

    error_kind = "length"

    def __init__(self, problem, poses, scale: float, params, phi, sign: float, weight: float,
                 lo, hi, method: str) -> None:
        self.problem, self.poses, self.scale = problem, np.asarray(poses, float), float(scale)
        self.sign, self.weight, self.method = float(sign), float(weight), method
        n = self.n = len(self.poses)
        self.full_turn = problem.grashof in design_constraints.FULL_TURN
        self.grashof = problem.grashof if problem.grashof not in (None, "any") else None
        self.window = problem.transmission
        self.groups = np.concatenate([np.repeat(np.arange(n), 2), np.arange(n)])
        params = np.asarray(params, float)
        phi = np.asarray(phi, float)
        lo, hi = np.array(lo, float), np.array(hi, float)
        if problem.timing == "prescribed":
            self.t_angles = np.asarray(problem.input_angles, float)
            off_lo, off_hi = problem.input_offset or (0.0, 0.0)
            off = float(kin.wrap(phi[0] - self.t_angles[0]))
            if off_hi > off_lo:
                off = off_lo + float(np.mod(off - off_lo, kin.TWO_PI))
                off = min(max(off, off_lo), off_hi)
            else:
                off = off_lo
            timing, tlo, thi = np.array([off]), np.array([off_lo]), np.array([off_hi])
            self.s, self.turn_limit = 1.0, None
        else:
            self.t_angles = None
            self.s = direction(params, phi)
            steps = np.mod(self.s * np.diff(phi), kin.TWO_PI)
            timing = np.concatenate([[phi[0]], steps])
            tlo = np.concatenate([[phi[0] - kin.TWO_PI], np.zeros(n - 1)])
            thi = np.concatenate([[phi[0] + kin.TWO_PI], np.full(n - 1, kin.TWO_PI)])
            full = bool(arcs(params[None], phi[None])[0][0])
            self.turn_limit = math.pi if (n == 2 and full) else kin.TWO_PI
        for j in (2, 9):  # a full-turn angle: about the design's own, a turn either side
            if hi[j] - lo[j] >= kin.TWO_PI * (1.0 - 1e-12):
                lo[j], hi[j] = params[j] - kin.TWO_PI, params[j] + kin.TWO_PI
        if problem.moving_pivots is not None:  # the coupler, the body's origin and angle on it
            lo[[5, 7, 8, 9]] = hi[[5, 7, 8, 9]] = params[[5, 7, 8, 9]]
        free = hi > lo
        lo = np.where(free, np.minimum(lo, params), lo)
        hi = np.where(free, np.maximum(hi, params), hi)
        self.x0 = np.concatenate([params, timing])
        self.lo = np.concatenate([lo, tlo])
        self.hi = np.concatenate([hi, thi])
        self.x0 = np.clip(self.x0, self.lo, self.hi)

    # ------------------------------------------------------------ the timing
    def input_angles(self, x) -> np.ndarray:
        """(N, n) input angles of designs x (N, nx)."""
        if self.t_angles is not None:
            return self.t_angles[None, :] + x[:, N_PARAMS:N_PARAMS + 1]
        steps = np.concatenate([np.zeros((len(x), 1)), np.cumsum(x[:, N_PARAMS + 1:], axis=1)], axis=1)
        return x[:, N_PARAMS:N_PARAMS + 1] + self.s * steps

    def span(self, phi):
        """(lo, width) of the travel from the first pose to the last, each (N,)."""
        lo = phi.min(axis=1)
        return lo, phi.max(axis=1) - lo

    # ------------------------------------------------------------ the hook
    def residuals(self, x) -> np.ndarray:
        """(N, 3n): dx_i, dy_i (interleaved), then w dangle_i (length unit)."""
        x = np.atleast_2d(np.asarray(x, float))
        phi = self.input_angles(x)
        full = np.concatenate([x[:, :N_PARAMS], phi], axis=1)
        with np.errstate(all="ignore"):
            r = pose_residuals(full, self.poses, self.sign, self.weight, None)[:, :3 * self.n]
        return np.where(np.isfinite(r), r, HUGE)

    def inequalities(self, x) -> np.ndarray:
        """The module docstring's constraints, g >= 0 (dimensionless)."""
        x = np.atleast_2d(np.asarray(x, float))
        phi = self.input_angles(x)
        d, a, b, c = (x[:, k] for k in (3, 4, 5, 6))
        L = self.scale
        with np.errstate(all="ignore"):
            rho = np.hypot(a[:, None] * np.cos(phi) - d[:, None], a[:, None] * np.sin(phi))
            bc_lo, bc_hi = np.abs(b - c)[:, None], (b + c)[:, None]
            cols = [(bc_hi - rho) / L, (rho - bc_lo) / L]
            lo_span, width = self.span(phi)
            for at, r in ((0.0, np.abs(a - d)), (math.pi, a + d)):
                inside = np.mod(at - lo_span, kin.TWO_PI) <= width
                v = np.minimum(r - np.abs(b - c), (b + c) - r) / L
                cols.append(np.where(inside, v, np.maximum(v, 0.0))[:, None])
            cols.append(-design_constraints.values(x[:, :N_PARAMS], phi, self.grashof, None, L) / L)
            if self.window is not None:
                if self.full_turn:
                    r2_min, r2_max = (d - a) ** 2, (d + a) ** 2
                else:
                    r2_min, r2_max = rho2_extremes(a, d, lo_span, width)
                cos_mu = lambda r2: (b * b + c * c - r2) / (2.0 * b * c)
                cols.append((math.cos(self.window[0]) - cos_mu(r2_min))[:, None])
                cols.append((cos_mu(r2_max) - math.cos(self.window[1]))[:, None])
            if self.turn_limit is not None:
                cols.append((self.turn_limit - x[:, N_PARAMS + 1:].sum(axis=1))[:, None])
            g = np.concatenate([np.atleast_2d(col).reshape(len(x), -1) for col in cols], axis=1)
        return np.where(np.isfinite(g), g, -HUGE)

    def linkage(self, x) -> FourBar:
        gx, gy, gang, d, a, b, c, px, py, cang = (float(v) for v in x[:N_PARAMS])
        return FourBar(ground=d, input=a, coupler=b, output=c, branch="open" if self.sign < 0 else "crossed",
                       coupler_point=(px, py), ground_pivot=(gx, gy), ground_angle=gang, coupler_angle=cang)

    def solution(self, x) -> Solution:
        """The linkage of x and its travel from the first pose to the last (cheap)."""
        x = np.asarray(x, float)
        phi = self.input_angles(x[None])
        lo, width = self.span(phi)
        return Solution(status=Status.OK, linkage=self.linkage(x), working_span=(float(lo[0]), float(width[0])))

    def final(self, x) -> Solution:
        """The type's Solution of x: screened as the type screens its own designs (screen.py:
        assembly, branch and order defects, the Grashof class, the transmission window, the
        file's bounds and branch), its positions and error sections."""
        from .result import solution
        from .screen import screen
        x = np.asarray(x, float)
        params = x[:N_PARAMS]
        phi = self.input_angles(x[None])[0]
        signs = np.full(self.n, self.sign)
        with np.errstate(all="ignore"):
            res = screen(self.problem, self.poses, params[None], phi[None], signs[None], self.scale, exact=False)
        feasible = bool(res["count"][0] == 0)
        solver = SolverRecord(self.method, self.problem.meta.solver.seed, 0, True)
        return solution(self.problem, self.poses, self.scale, params, kin.wrap(phi), signs, res, 0, feasible,
                         solver, {}, [], objective=None, weight=self.weight)


def front(problem, poses, scale: float, chosen, found: Solution) -> Solution:
    """The front of a four-bar motion-generation problem (linkcli.pareto.run), from the
    type's design `chosen` (params, input angles, branch sign, angle weight)."""
    from linkcli.pareto.run import solve_front

    from .box import design_box
    params, phi, sign, weight = chosen
    lo, hi = design_box(problem, poses, scale)
    method = found.solver.method if found.solver is not None else "motion"
    space = MotionSpace(problem, poses, scale, params, phi, sign, weight, lo, hi, method)
    return solve_front(problem, space, found)
