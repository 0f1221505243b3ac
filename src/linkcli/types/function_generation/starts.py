"""Where the searches of function generation start: Freudenstein designs on a grid of
start angles, seeded Latin hypercube samples, the best distinct rows; and the check that
the law can be evaluated at all (`check_law`).

Freudenstein designs: unless the start is the extended dead-centre, the start angles
(given, or a grid over their bounds) fix the target angles at the points, and
Freudenstein's equation, linear in its three ratios, gives a design per start pair by
least squares (Model.freudenstein).
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.errors import SolveInputError
from linkcli.search import sampling
from linkcli.types.function_generation.model import BRANCH_SIGN, STARTS, Model
from linkcli.types.function_generation.search import Search

SEED_PAIRS = 256  # start-angle pairs fitted by Freudenstein's equation (free starts)
DISTINCT = 0.15  # slsqp: starts differ by this much in some variable (unit box)


def check_law(model: Model, u: np.ndarray) -> None:
    """SolveInputError when the law is undefined at every point for every sampled candidate
    on every branch (the law, not the linkage, is then at fault). A law undefined at some
    points only (a domain that holds part of the sweeps) is left to the search, which
    penalizes those points (check_law_finite judges the linkage it ends with). Not an
    evaluation of the objective: the linkage is not assembled."""
    p = model.problem
    if p.form == "function":
        return
    values = model.values(u)
    a, b, c, d = model.lengths(values)
    for sign in sorted({BRANCH_SIGN[b_] for b_ in (("open", "crossed") if p.branch == "either" else (p.branch,))}):
        with np.errstate(all="ignore"):
            phi0, psi0, no_start = model.start(values, a, b, c, d, sign)
            phi = phi0 + model.t * p.input_sweep
            target = model.target(phi, phi0, psi0)
        # start angles defined: finite (else the lengths overflowed), and for the extended
        # start a linkage that has one (else phi0 is a clipped 0, and the law's value there
        # says nothing about the law)
        sane = np.isfinite(phi0[:, 0]) & np.isfinite(psi0[:, 0]) & (no_start[:, 0] <= 0.0)
        if not sane.any() or np.isfinite(target[sane]).any():
            return
    i = int(np.argmax(sane))
    k = int(np.argmin(np.isfinite(target[i])))
    phi = phi[i:i + 1]
    value = float(target[i, k])
    shown = "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    u_ = p.meta.units
    raise SolveInputError("a law finite at every evaluation point of some linkage within the bounds",
                     f"{shown} at phi = {u_.from_rad(float(phi[0, k])):.6g} {u_.angle} "
                     f"(and at every point for every sampled linkage)", path=p.meta.path,
                     line=p.lines.get("law"), key=p.lines.get("law_key"))


def start_pairs(model: Model, count: int) -> np.ndarray | None:
    """Start-angle pairs (phi_s, psi_s) to fit Freudenstein's equation at: the given
    pair, or a grid of cell centres over the free start bounds (about `count` pairs);
    None for the extended start (it depends on the lengths)."""
    p = model.problem
    if p.start == "extended" or count < 1:
        return None
    free = [k for k in STARTS if k in p.start_bounds]
    given = {"input_start": p.input_start, "output_start": p.output_start}
    side = max(1, int(count ** (1.0 / len(free)))) if free else 1
    axes = []
    for k in STARTS:
        if k in p.start_bounds:
            lo, hi = p.start_bounds[k]
            axes.append(lo + (np.arange(side) + 0.5) / side * (hi - lo))
        else:
            axes.append(np.array([float(given[k] or 0.0)]))
    grid = np.meshgrid(*axes, indexing="ij")
    return np.column_stack([g.ravel() for g in grid])


def freudenstein_designs(model: Model, count: int = SEED_PAIRS) -> np.ndarray:
    """Freudenstein designs (global unit box, (k, n)) at about `count` start pairs
    (start_pairs); none for the extended start."""
    pairs = start_pairs(model, count)
    return np.zeros((0, model.n_variables)) if pairs is None else model.freudenstein(pairs)


def freudenstein_seeds(search: Search, branch: str, count: int):
    """Freudenstein designs at start pairs (start_pairs), evaluated on the branch
    (counted): (rows best first and distinct (unit box, (k, n)), their penalized
    objectives); empty when there are none or the budget cannot pay for them."""
    model = search.model
    none = np.zeros((0, model.n_variables)), np.zeros(0)
    u = freudenstein_designs(model, count)
    if len(u) == 0 or search.evaluations.used + len(u) > search.evaluations.total:
        return none
    return distinct(u, search.run(u, branch).penalized, len(u))


def distinct(u: np.ndarray, scores: np.ndarray, most: int):
    """(rows, scores) of u, best score first, each row more than DISTINCT (unit box, in
    some variable) from those kept before it; at most `most` rows."""
    kept = sampling.distinct(u, np.argsort(scores, kind="stable"), DISTINCT, most)
    return u[kept].reshape(len(kept), u.shape[1]), scores[kept]
