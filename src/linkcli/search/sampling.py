"""Where searches start: a Latin hypercube of the unit box, and the distinct best rows.

Latin hypercube (McKay, Beckman & Conover 1979): each of the `dims` axes is cut into
`points` equal cells and every cell of every axis holds exactly one point, placed
uniformly inside it; the cells are paired across axes by independent random
permutations (here the ranks of uniform draws, one column per axis).
"""

from __future__ import annotations

import numpy as np


def latin_hypercube(rng: np.random.Generator, points: int, dims: int) -> np.ndarray:
    """A seeded Latin hypercube sample of [0, 1]^dims, (points, dims)."""
    cells = np.argsort(rng.random((points, dims)), axis=0)
    return (cells + rng.random((points, dims))) / points


def distinct(rows: np.ndarray, order, radius: float, most: int, norm=np.inf) -> list[int]:
    """Indices taken from `order` (best first), each farther than `radius` from every row
    taken before it (`norm`: np.inf, the largest coordinate difference, or 2, Euclidean);
    at most `most`. Several starts often reach the same basin: restart from distinct ones."""
    taken: list[int] = []
    for i in order:  # a loop over the few candidates kept, not over a population
        if not taken or np.min(np.linalg.norm(rows[taken] - rows[i], ord=norm, axis=1)) > radius:
            taken.append(int(i))
            if len(taken) == most:
                break
    return taken
