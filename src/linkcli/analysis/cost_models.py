"""Cost-tolerance models: what a tolerance +-t costs to make ([tolerance.cost], docs/tolerance.md).

The classic empirical laws (Chase, Greenwood, Loosli & Hauglund 1990, "Least cost tolerance
allocation for mechanical assemblies with automated process selection", Manufacturing
Review 3(1); Wu, Elmaraghy & Elmaraghy 1988, "Evaluation of cost-tolerance algorithms for
design tolerance analysis and synthesis", Manufacturing Review 1(3)):

    reciprocal         c(t) = a + b / t                (Chase & Greenwood 1988)
    reciprocal-power   c(t) = a + b / t^k              (Sutherland & Roth 1975; k = 2: Spotts 1973)
    exponential        c(t) = a + b exp(-k t)          (Speckhart 1972)
    michael-siddall    c(t) = a t^-k exp(-b t)         (Michael & Siddall 1981)

Each is convex and decreasing in t. The allocation (analysis.allocation) needs its marginal
cost per unit tolerance squared, m(t) = -c'(t) / t (decreasing in t), and the inverse of
m: the tolerance at which m(t) = y, within the bounds a process can hold. Vectorized over
dimensions; numpy only.
"""

from __future__ import annotations

import numpy as np

INVERSE_STEPS = 64  # bisection steps on log t within the bounds: to round-off


class Costs:
    """The cost models of n dimensions, as arrays (one entry per dimension)."""

    def __init__(self, models) -> None:
        self.kind = np.array([m.model for m in models])
        self.a = np.array([m.a for m in models], dtype=float)
        self.b = np.array([m.b for m in models], dtype=float)
        self.k = np.array([m.k for m in models], dtype=float)
        self.lo = np.array([m.bounds[0] if m.bounds else 0.0 for m in models], dtype=float)
        self.hi = np.array([m.bounds[1] if m.bounds else np.inf for m in models], dtype=float)

    def cost(self, t) -> np.ndarray:
        """c(t) per dimension."""
        t = np.asarray(t, dtype=float)
        a, b, k = self.a, self.b, self.k
        with np.errstate(divide="ignore", over="ignore"):
            return np.select([self.kind == "michael-siddall", self.kind == "exponential"],
                             [a * t ** -k * np.exp(-b * t), a + b * np.exp(-k * t)],
                             a + b * t ** -k)  # reciprocal (k = 1) and reciprocal-power

    def log_marginal(self, t) -> np.ndarray:
        """log m(t), m(t) = -c'(t) / t: the cost of one more unit of t^2, per dimension.

        reciprocal(-power): k b t^-(k+2); exponential: k b exp(-k t) / t; michael-siddall:
        a t^-(k+1) exp(-b t) (k / t + b)."""
        t = np.asarray(t, dtype=float)
        a, b, k = self.a, self.b, self.k
        log_t = np.log(t)
        with np.errstate(divide="ignore", invalid="ignore"):
            power = np.log(k * b) - (k + 2) * log_t
            expo = np.log(k * b) - k * t - log_t
            ms = np.log(a) - (k + 1) * log_t - b * t + np.log(k / t + b)
        return np.select([self.kind == "michael-siddall", self.kind == "exponential"], [ms, expo], power)

    def at_marginal(self, log_y) -> np.ndarray:
        """The t in [lo, hi] with log m(t) = log_y per dimension (lo where m(lo) is already
        below y, hi where m(hi) is still above): closed form for the reciprocal laws,
        t = (k b / y)^(1 / (k + 2)); by bisection on log t for the others (m decreases)."""
        log_y = np.broadcast_to(np.asarray(log_y, dtype=float), self.lo.shape)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            t = np.exp((np.log(self.k * self.b) - log_y) / (self.k + 2))  # k b t^-(k+2) = y
        other = (self.kind == "exponential") | (self.kind == "michael-siddall")
        if other.any():
            sub = Costs.__new__(Costs)
            for name in ("kind", "a", "b", "k", "lo", "hi"):
                setattr(sub, name, getattr(self, name)[other])
            lo, hi = np.log(sub.lo), np.log(sub.hi)
            y = log_y[other]
            for _ in range(INVERSE_STEPS):
                mid = 0.5 * (lo + hi)
                above = sub.log_marginal(np.exp(mid)) > y
                lo, hi = np.where(above, mid, lo), np.where(above, hi, mid)
            t = t.copy()
            t[other] = np.exp(0.5 * (lo + hi))
        return np.clip(t, self.lo, self.hi)
