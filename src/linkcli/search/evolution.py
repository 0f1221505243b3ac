"""The one differential-evolution front door every search uses (scipy, imported lazily).

Differential evolution (Storn & Price 1997), strategy best1bin: each generation, every
member x_i meets a mutant b + F (x_r1 - x_r2) (b the best member, F drawn per generation
from `mutation`), takes each coordinate of it with probability `recombination`, and keeps
the trial if it costs no more. scipy's implementation, always vectorized (one call scores
the whole population: the cost gets rows (S, dims) and returns (S,)), with deferred
updating (the population is replaced once per generation) and no polish (each type
polishes with its own local solver). Converged: the population's spread of costs fell
below tol * |mean| + atol (scipy's criterion).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from linkcli.search.budget import BudgetSpent


class Evolved(NamedTuple):
    """Where differential evolution ended: the best member, its cost, and whether the
    population converged."""

    x: np.ndarray
    cost: float
    converged: bool


def evolve(cost: Callable[[np.ndarray], np.ndarray], bounds, generations: int, *, init,
           rng=None, seed: int | None = None, popsize: int = 15, tol: float = 0.01,
           atol: float = 0.0, mutation=(0.5, 1), recombination: float = 0.7) -> Evolved | None:
    """scipy's differential evolution of `cost` over the box `bounds` [(lo, hi)] for at
    most `generations` generations after the first, from `init` (an array of members,
    or "latinhypercube" with `popsize` members per variable). The random source is `rng`
    (a numpy Generator or seed) or, for a search whose seeds were drawn that way, `seed`
    (scipy's legacy RandomState stream). None when the cost raised BudgetSpent."""

    from scipy.optimize import differential_evolution

    def rows_cost(x):  # scipy sends (dims, S); the cost reads rows (S, dims)
        return cost(np.atleast_2d(np.asarray(x).T))

    random = {"rng": rng} if seed is None else {"seed": seed}
    try:
        res = differential_evolution(rows_cost, bounds, maxiter=generations, popsize=popsize, init=init,
                                     tol=tol, atol=atol, mutation=mutation, recombination=recombination,
                                     polish=False, vectorized=True, updating="deferred", **random)
    except BudgetSpent:
        return None
    return Evolved(np.asarray(res.x, dtype=float), float(res.fun), bool(res.success))
