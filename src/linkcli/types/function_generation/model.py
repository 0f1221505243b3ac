"""Function generation: the objective and the constraints, vectorized (numpy only).

A candidate is a row of design values (the free lengths, then the free start angles);
`Model.evaluate` takes N of them on one branch (sign -1 open, +1 crossed; or a sign per
candidate, (N, 1)) with the lengths as (N, 1) columns against the M evaluation points, so
one call scores a whole population.
The evaluation points are phi_k = phi0 + t_k * input_sweep, and

    f = sum_k wrap(psi(phi_k) - psi_target_k)^2            (rad^2, the seed's objective)

with psi from the loop closure (the conventions of docs/format.md, as kinematics.pose). The start phi0, psi0
is given, free, or the extended dead-centre of crank and coupler (|A0 B| = a + b), closed
form from the triangle A0 B0 B (law of cosines):

    cos(g) = ((a + b)^2 + d^2 - c^2) / (2 (a + b) d),   cos(h) = ((a + b)^2 - c^2 - d^2) / (2 c d)
    open: phi0 = g, psi0 = h;   crossed: phi0 = -g, psi0 = -h   (mirror images)

(on the open branch psi = theta_rho - alpha puts B clockwise of B0 -> A seen from B0,
which the extended B with phi0 > 0 is). Constraints, closed form (no sampling), as
violations >= 0 in radians or in units of L, the largest fixed length:
- travel: the input reaches every angle of the sweep without a dead point:
  rho^2 = a^2 + d^2 - 2 a d cos(phi) stays within [(b - c)^2, (b + c)^2] over the sweep;
  rho is extreme at the sweep's ends or at phi = 0, pi (DESIGN numerical notes);
- transmission window on mu, cos(mu) = (b^2 + c^2 - rho^2) / (2 b c), monotone in rho:
  over the full turn (rho = |d - a|, d + a) when the Grashof class asked for makes the
  input a crank (crank-rocker, double-crank), else over the sweep;
- Grashof class: with s the link that must be shortest, 2 (s + x) <= a + b + c + d for
  each other link x (for the crank-rocker: a+b <= c+d, a+c <= b+d, a+d <= b+c), with a
  relative margin so the result is never a change-point; triple-rocker: s + l > p + q;
- the extended dead-centre exists: |c - d| <= a + b <= c + d;
- the law is finite at every point.
`Model.inequalities` gives the same constraints as smooth values g >= 0 for a local solver.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.model import FunctionGenerationProblem
from linkcli.search import linalg
from linkcli.types.function_generation.schema import LAW_LIMIT

GRASHOF_MARGIN = 1e-7  # relative: the Grashof inequalities hold strictly, not at a change-point
FULL_TURN_CLASSES = ("crank-rocker", "double-crank")
SHORTEST = {"crank-rocker": "input", "rocker-crank": "output", "double-crank": "ground",
            "double-rocker": "coupler"}
LINK_ORDER = ("input", "coupler", "output", "ground")  # a, b, c, d
STARTS = ("input_start", "output_start")
BRANCH_SIGN = {"open": -1.0, "crossed": 1.0}
OVERFLOW = 1e6  # a violation (or objective) that overflowed counts as this much
CONSTRAINTS = ("travel", "transmission_low", "transmission_high", "grashof", "extended", "law")


@dataclass
class Batch:
    """One branch evaluated for N candidates."""

    f: np.ndarray  # (N,) objective, rad^2
    err: np.ndarray  # (N, M) residuals psi - psi_target, rad (0 where the law is undefined)
    violation: np.ndarray  # (N, K) >= 0, one column per constraint of Model.names
    penalized: np.ndarray  # (N,) f + W * sum(violation)

    def take(self, rows) -> Batch:
        """The candidates `rows` of the batch."""
        return Batch(self.f[rows], self.err[rows], self.violation[rows], self.penalized[rows])


class Model:
    """Objective and constraints of one problem, vectorized over candidates and points."""

    def __init__(self, problem: FunctionGenerationProblem) -> None:
        self.problem = problem
        self.variables = [k for k in LINK_ORDER if k in problem.bounds] + \
                         [k for k in STARTS if k in problem.start_bounds]
        bounds = {**problem.bounds, **problem.start_bounds}
        self.lo = np.array([bounds[k][0] for k in self.variables], dtype=float)
        self.hi = np.array([bounds[k][1] for k in self.variables], dtype=float)
        # lengths are searched on a log scale (a ratio scale: [0.02, 20] holds 0.5 mid-box,
        # where a linear map would squeeze it into the first 2.5 %), angles linearly
        self.log = np.array([k in problem.bounds for k in self.variables], dtype=bool)
        ratio = np.ones_like(self.hi)
        ratio[self.log] = self.hi[self.log] / self.lo[self.log]  # lengths: 0 < lo < hi
        self.span = np.where(self.log, np.log(ratio), self.hi - self.lo)
        self.t = np.asarray(problem.fractions, dtype=float)
        self.shape = np.asarray(problem.shape, dtype=float)
        self.scale = max(problem.fixed.values())
        self.full_turn = problem.grashof in FULL_TURN_CLASSES
        self.weight = 10.0 * (len(self.t) + 1)  # exact-penalty weight (rad^2 per unit violation)
        self.names = CONSTRAINTS

    @property
    def n_variables(self) -> int:
        return len(self.variables)

    def values(self, u: np.ndarray) -> np.ndarray:
        """Unit box -> design values, (N, n): lengths lo * (hi / lo)^u (log scale), start
        angles lo + u (hi - lo)."""
        u = np.atleast_2d(u)
        with np.errstate(all="ignore"):
            v = np.where(self.log, self.lo * np.exp(u * self.span), self.lo + u * self.span)
        return np.minimum(np.maximum(v, self.lo), self.hi)  # exp rounds: stay within the bounds

    def units(self, v: np.ndarray) -> np.ndarray:
        """Design values -> unit box (the inverse of `values`), clipped to [0, 1]."""
        v = np.atleast_2d(np.asarray(v, dtype=float))
        with np.errstate(all="ignore"):
            u = np.where(self.log, np.log(np.where(self.log, v, 1.0) / self.lo), v - self.lo) / self.span
        return np.clip(np.where(np.isfinite(u), u, 0.5), 0.0, 1.0)

    def linear_values(self, w: np.ndarray) -> np.ndarray:
        """Linear unit box (every variable, the local search's) -> design values, (N, n)."""
        return np.minimum(np.maximum(self.lo + np.atleast_2d(w) * (self.hi - self.lo), self.lo), self.hi)

    def linear_units(self, v: np.ndarray) -> np.ndarray:
        """Design values -> linear unit box, clipped to [0, 1]."""
        return np.clip((np.atleast_2d(np.asarray(v, dtype=float)) - self.lo) / (self.hi - self.lo), 0.0, 1.0)

    def lengths(self, v: np.ndarray):
        """(a, b, c, d), each (N, 1)."""
        n = v.shape[0]
        cols = {k: v[:, i:i + 1] for i, k in enumerate(self.variables)}
        fixed = self.problem.fixed
        return tuple(cols[k] if k in cols else np.full((n, 1), float(fixed[k])) for k in LINK_ORDER)

    def start(self, v, a, b, c, d, sign):
        """(phi0, psi0, extended-violation), each (N, 1)."""
        p = self.problem
        n = v.shape[0]
        if p.start == "extended":
            ab = a + b
            cos_g = (ab * ab + d * d - c * c) / (2.0 * ab * d)
            cos_h = (ab * ab - c * c - d * d) / (2.0 * c * d)
            phi0 = -sign * np.arccos(np.minimum(np.maximum(cos_g, -1.0), 1.0))
            psi0 = -sign * np.arccos(np.minimum(np.maximum(cos_h, -1.0), 1.0))
            viol = np.maximum(0.0, np.maximum(ab - (c + d), np.abs(c - d) - ab)) / self.scale
            return phi0, psi0, viol
        cols = {k: v[:, i:i + 1] for i, k in enumerate(self.variables)}
        given = {"input_start": p.input_start, "output_start": p.output_start}
        phi0, psi0 = (cols[k] if k in cols else np.full((n, 1), float(given[k])) for k in STARTS)
        return phi0, psi0, np.zeros((n, 1))

    def target(self, phi, phi0, psi0):
        """psi_target at the points, (N, M); non-finite where the law is not defined."""
        p = self.problem
        if p.form == "function":
            return psi0 + self.shape * p.output_sweep
        target = p.law(phi=phi, phi0=phi0, psi0=psi0)
        return np.where(np.abs(target) <= LAW_LIMIT, target, np.nan)  # beyond: no digits left

    def evaluate(self, v: np.ndarray, sign: float, detail: bool = False):
        """Objective, violations and penalized objective of N candidates on one branch.
        Overflow (absurd bounds such as 1e308) gives a large finite penalty, never NaN."""
        with np.errstate(all="ignore"):
            return self._evaluate(v, sign, detail)

    def _evaluate(self, v: np.ndarray, sign: float, detail: bool):
        a, b, c, d = self.lengths(v)
        phi0, psi0, v_ext = self.start(v, a, b, c, d, sign)
        sweep = self.problem.input_sweep
        phi = phi0 + self.t * sweep
        with np.errstate(all="ignore"):
            target = self.target(phi, phi0, psi0)
            psi = output_angle(a, b, c, d, phi, sign)
            bad = ~np.isfinite(target)
            err = np.where(bad, 0.0, kin.wrap(psi - np.where(bad, 0.0, target)))
        f = np.sum(err * err, axis=1)
        rho_lo, rho_hi = sweep_rho(a, d, phi0, sweep)
        v_travel = np.maximum(0.0, np.maximum(np.abs(b - c) - rho_lo, rho_hi - (b + c))) / self.scale
        if self.full_turn:
            rho_lo, rho_hi = np.abs(d - a), d + a
        mu_lo = kin.transmission_angle(b, c, rho_lo)
        mu_hi = kin.transmission_angle(b, c, rho_hi)
        window = self.problem.transmission
        if window is None:
            v_low = v_high = np.zeros_like(mu_lo)
        else:
            v_low = np.maximum(0.0, window[0] - mu_lo)
            v_high = np.maximum(0.0, mu_hi - window[1])
        v_grashof = grashof_violation(self.problem.grashof, a, b, c, d) / self.scale
        v_law = np.mean(bad, axis=1, keepdims=True).astype(float)
        violation = np.concatenate([v_travel, v_low, v_high, v_grashof, v_ext, v_law], axis=1)
        violation = np.where(np.isfinite(violation), violation, OVERFLOW)
        f = np.where(np.isfinite(f), f, OVERFLOW)
        penalized = f + self.weight * np.sum(np.minimum(violation, OVERFLOW), axis=1)
        batch = Batch(f=f, err=err, violation=violation, penalized=penalized)
        if detail:
            return batch, dict(phi=phi, phi0=phi0, psi0=psi0, target=target, psi=psi, err=err,
                               mu=(mu_lo, mu_hi), lengths=(a, b, c, d))
        return batch

    def inequalities(self, v: np.ndarray, sign: float) -> np.ndarray:
        """Smooth constraint values g >= 0 (see _inequalities); overflow gives -OVERFLOW."""
        with np.errstate(all="ignore"):
            g = self._inequalities(v, sign)
        return np.where(np.isfinite(g), g, -OVERFLOW)

    def _inequalities(self, v: np.ndarray, sign: float) -> np.ndarray:
        """Smooth constraint values >= 0 for SLSQP, (N, C): the closed forms of the module
        docstring at the sweep's two ends and at the angles of the sweep nearest 0 and pi.
        When 0 (or pi) lies outside the sweep, its nearest angle is an end, and the entry
        would repeat that end's constraint (two identical active constraints stall
        SLSQP): it is raised by the angular distance from the sweep, which keeps it
        continuous and distinct."""
        p = self.problem
        a, b, c, d = self.lengths(v)
        phi0, _, _ = self.start(v, a, b, c, d, sign)
        L2 = self.scale * self.scale
        lo = phi0 if p.input_sweep >= 0 else phi0 + p.input_sweep
        width = abs(p.input_sweep)
        near0, out0 = nearest_in_arc(0.0, lo, width)
        nearpi, outpi = nearest_in_arc(np.pi, lo, width)
        angles = np.concatenate([lo, lo + width, near0, nearpi], axis=1)
        lift = np.concatenate([np.zeros_like(lo), np.zeros_like(lo), out0, outpi], axis=1)
        rho2 = a * a + d * d - 2.0 * a * d * np.cos(angles)
        out = [((b + c) ** 2 - rho2) / L2 + lift, (rho2 - (b - c) ** 2) / L2 + lift]
        if p.transmission is not None:
            if self.full_turn:
                r2, raise_ = np.concatenate([(d - a) ** 2, (d + a) ** 2], axis=1), 0.0
            else:
                r2, raise_ = rho2, lift
            cos_mu = (b * b + c * c - r2) / (2.0 * b * c)
            out += [math.cos(p.transmission[0]) - cos_mu + raise_, cos_mu - math.cos(p.transmission[1]) + raise_]
        out.append(grashof_inequalities(p.grashof, a, b, c, d) / self.scale)
        if p.start == "extended" and p.grashof != "crank-rocker":  # a crank-rocker implies them
            ab = a + b
            out += [((c + d) ** 2 - ab * ab) / L2, (ab * ab - (c - d) ** 2) / L2]
        return np.concatenate(out, axis=1)

    def freudenstein(self, starts: np.ndarray) -> np.ndarray:
        """Candidate designs (unit box, (P', n)) from start-angle pairs (P, 2) = (phi_s,
        psi_s) by Freudenstein's equation fitted to the target at the evaluation points.

        With A = a(cos phi, sin phi) and B = (d + c cos psi, c sin psi), |B - A| = b is
        (Freudenstein 1955, in the conventions of docs/format.md's frame)

            K1 cos(psi) - K2 cos(phi) + K3 = cos(phi - psi),
            K1 = d / a, K2 = d / c, K3 = (a^2 + c^2 + d^2 - b^2) / (2 a c),

        linear in K: least squares over the points (exact through three; the normal
        equations), one small system per pair, all pairs at once. A fit with K1 or K2 <= 0 or b^2 <= 0 gives no
        candidate (a link would point the other way; with free starts, another pair covers it).
        The shape is scaled to the first fixed length; other fixed lengths keep their
        values (the candidate is then only a start for the search). Only for given or
        free start angles, not for the extended start (it depends on the lengths)."""
        p = self.problem
        starts = np.atleast_2d(np.asarray(starts, dtype=float))
        phi_s, psi_s = starts[:, :1], starts[:, 1:2]
        phi = phi_s + self.t * p.input_sweep
        with np.errstate(all="ignore"):
            psi = self.target(phi, phi_s, psi_s) * np.ones_like(phi)
            rows = np.stack([np.cos(psi), -np.cos(phi), np.ones_like(phi)], axis=2)  # (P, M, 3)
            rhs = np.cos(phi - psi)[:, :, None]
            good = np.all(np.isfinite(rows), axis=(1, 2)) & np.all(np.isfinite(rhs), axis=(1, 2))
            rows, rhs = np.where(good[:, None, None], rows, 0.0), np.where(good[:, None, None], rhs, 0.0)
            # the normal equations by elimination (linkcli.search.linalg: no BLAS, so the
            # designs, and the searches they start, are the same under every kernel)
            k = linalg.solve(linalg.gram(rows), np.einsum("pmi,pm->pi", rows, rhs[:, :, 0], optimize=False))
            a, c = 1.0 / k[:, 0], 1.0 / k[:, 1]  # d = 1
            b2 = a * a + c * c + 1.0 - 2.0 * a * c * k[:, 2]
            shape = {"input": a, "coupler": np.sqrt(b2), "output": c, "ground": np.ones_like(a)}
            ok = good & (k[:, 0] > 0) & (k[:, 1] > 0) & (b2 > 0) & np.isfinite(a * c * b2)
            first = next(name for name in LINK_ORDER if name in p.fixed)
            scale = p.fixed[first] / shape[first]
            ok &= np.isfinite(scale) & (scale > 0)
            given = {name: (phi_s[:, 0] if name == "input_start" else psi_s[:, 0]) for name in STARTS}
            cols = [shape[k_] * scale if k_ in shape else given[k_] for k_ in self.variables]
        v = np.column_stack(cols) if cols else np.zeros((len(starts), 0))
        return self.units(v[ok])


def output_angle(a, b, c, d, phi, sign):
    """psi = theta_rho + sign * alpha (the conventions of docs/format.md): the output angle alone, as
    kinematics.pose computes it, without the coupler and transmission angles (the hot
    path); where the linkage cannot assemble, the angle of the nearest toggle."""
    rx = a * np.cos(phi) - d
    ry = a * np.sin(phi)
    rho2 = rx * rx + ry * ry
    cos_alpha = (rho2 + c * c - b * b) / (2.0 * np.sqrt(rho2) * c)
    return np.arctan2(ry, rx) + sign * np.arccos(np.minimum(np.maximum(cos_alpha, -1.0), 1.0))


def sweep_rho(a, d, phi0, sweep):
    """(rho_min, rho_max) over the input arc from phi0 through the signed sweep.

    rho^2 = a^2 + d^2 - 2 a d cos(phi): least where cos is greatest (phi = 0 if inside),
    greatest where cos is least (phi = pi if inside), else at an end."""
    lo = phi0 if sweep >= 0 else phi0 + sweep
    width = abs(sweep)
    c1, c2 = np.cos(lo), np.cos(lo + width)
    has0 = np.mod(-lo, kin.TWO_PI) <= width
    haspi = np.mod(np.pi - lo, kin.TWO_PI) <= width
    cmax = np.where(has0, 1.0, np.maximum(c1, c2))
    cmin = np.where(haspi, -1.0, np.minimum(c1, c2))
    r2 = a * a + d * d
    return (np.sqrt(np.maximum(r2 - 2 * a * d * cmax, 0.0)), np.sqrt(np.maximum(r2 - 2 * a * d * cmin, 0.0)))


def nearest_in_arc(x: float, lo, width: float):
    """(angle, distance): the angle of the arc [lo, lo + width] nearest to x (x itself
    when inside, distance 0), and how far x lies outside the arc (rad)."""
    rel = np.mod(x - lo, kin.TWO_PI)
    inside = rel <= width
    to_end = rel - width
    to_start = kin.TWO_PI - rel
    angle = np.where(inside, lo + rel, np.where(to_end < to_start, lo + width, lo))
    return angle, np.where(inside, 0.0, np.minimum(to_end, to_start))


def grashof_inequalities(kind: str, a, b, c, d) -> np.ndarray:
    """Values g >= 0 that hold exactly for the Grashof class `kind`, (N, k)."""
    links = {"input": a, "coupler": b, "output": c, "ground": d}
    total = a + b + c + d
    margin = GRASHOF_MARGIN * total
    if kind in SHORTEST:
        s = links[SHORTEST[kind]]
        others = [x for k, x in links.items() if k != SHORTEST[kind]]
        return np.hstack([total - 2.0 * (s + x) - margin for x in others])
    srt = np.sort(np.hstack([a, b, c, d]), axis=1)
    if kind == "triple-rocker":
        return (srt[:, :1] + srt[:, 3:]) - (srt[:, 1:2] + srt[:, 2:3]) - margin
    return np.zeros((np.shape(a)[0], 0))


def grashof_violation(kind: str, a, b, c, d) -> np.ndarray:
    g = grashof_inequalities(kind, a, b, c, d)
    if g.shape[1] == 0:
        return np.zeros((np.shape(a)[0], 1))
    return np.maximum(0.0, -g.min(axis=1, keepdims=True))
