"""The hook a synthesis type gives the Pareto search: its design as a vector (docs/pareto.md).

A type that reports fronts writes one small module (`types/<type>/pareto.py`) whose
`space(problem, solution)` returns an object with these members, built from the type's own
least-squares answer (its branch, turning direction and orientation held); the front search
(linkcli.pareto.front) asks nothing else of the type. The object must pickle (the front's
points may be solved in other processes or on a cluster).

    x0, lo, hi      (n,) the type's optimum and the box of the design vector (lo == hi: fixed)
    full_turn       the motion the objectives measure: the full turn (the problem requires a
                    class whose input turns fully) or the targets' span
    error_kind      "angle" (residuals in rad) or "length"
    groups          (m,) the target each residual belongs to (max-error: a target's residuals
                    as one vector)
    residuals(X)    (N, m) the least-squares residuals of N designs (error = sum r^2)
    inequalities(X) (N, c) the type's constraints as g >= 0, each of order one
    solution(x)     a Solution of design x with its linkage, positions and working span (cheap)
    final(x)        the type's full Solution of x: its report sections and its status from its
                    own exact checks of every constraint of the file (infeasible: a violation)
"""

from __future__ import annotations

from typing import Protocol

import numpy as np


class Space(Protocol):
    x0: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    full_turn: bool
    error_kind: str
    groups: np.ndarray

    def residuals(self, x: np.ndarray) -> np.ndarray: ...

    def inequalities(self, x: np.ndarray) -> np.ndarray: ...

    def solution(self, x: np.ndarray): ...

    def final(self, x: np.ndarray): ...
