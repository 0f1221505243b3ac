"""[[tolerance.schemes]] compared (docs/tolerance.md): each scheme's fits and length tolerances
studied on the same draws (common random numbers: the differences between schemes are the
schemes', not the sampling's), costed by [tolerance.cost], and ranked.

Cost of a scheme: the sum of the cost-tolerance models (analysis.cost_models) over its
toleranced dimensions: each link at its +- tolerance and, for each fitted joint with a cost
model, its hole and its shaft at their half zone widths (ISO 286). A link made exact
(tolerance 0) costs infinitely much under every model: the cost is then infinite.
Ranking: the schemes that meet `max_failure_probability` (Wilson 95 % upper bound at most
the limit) by cost, lowest first, then the others by failure probability; ties by failure
probability, then by name. Without [tolerance.cost] by failure probability, then p95 error.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.analysis.cost_models import Costs
from linkcli.analysis.made_parts import FitZones, column_key
from linkcli.analysis.made_parts import parts as made_parts
from linkcli.analysis.tolerance import chunks, plan_of, run, wilson


def scheme_cost(cost, model, parts) -> float:
    """The total cost of the toleranced dimensions of `parts` (module docstring)."""
    models, sizes = [], []
    for column, t in zip(model.columns, parts.scale):
        if column in model.inverse and cost.of(column_key(model, column)) is not None:
            models.append(cost.of(column_key(model, column)))
            sizes.append(float(t))
    for zones in (parts.clearance, parts.play):
        if isinstance(zones, FitZones):
            for name, (hole, shaft) in zip(zones.names, zones.zones()):
                if cost.of(name) is not None:
                    models += [cost.of(name)] * 2
                    sizes += [hole, shaft]
    if not models:
        return 0.0
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        values = Costs(models).cost(np.array(sizes))
    total = float(np.sum(values))
    return total if math.isfinite(total) else math.inf


def schemes_section(problem, model, level: float | None, opt) -> list[dict]:
    """One row per scheme, ranked (module docstring): cost, failure probability with its
    Wilson interval, p95 error, whether it meets the limit, rank."""
    meta = problem.meta
    tol = meta.tolerance
    seed, n = int(meta.solver.seed), tol.samples
    rows = []
    for i, scheme in enumerate(tol.schemes):
        key = f"tolerance.schemes[{i}]"
        line = problem.meta.tolerance.lines.get(f"schemes[{i}]")
        parts = made_parts(model, problem, lengths=scheme.lengths, general=scheme.general,
                           fits=scheme.fits, where=(key, line))
        err, ok = run(model, chunks(seed, plan_of(model, parts, n, tol.distribution)), parts)
        bad = ~ok if tol.allowed_error is None else ~ok | (err > tol.allowed_error)
        k = int(np.count_nonzero(bad))
        lo, hi = wilson(k, n)
        good = err[ok]
        row = {"scheme": scheme.name}
        if tol.cost is not None:
            row["cost"] = scheme_cost(tol.cost, model, parts)
        row.update({"failure_probability": k / n, "failure_probability_ci95": [lo, hi],
                    "error_p95": opt(float(np.percentile(good, 95))) if good.size else None})
        if level is not None:
            row["meets"] = bool(hi <= level)
        rows.append(row)
    order = sorted(range(len(rows)), key=lambda j: _rank_key(rows[j]))
    ranked = [rows[j] for j in order]
    for rank, row in enumerate(ranked, start=1):
        row["rank"] = rank
    return ranked


def _rank_key(row: dict):
    p95 = row["error_p95"] if row["error_p95"] is not None else math.inf
    if "cost" in row:
        meets = row.get("meets", True)
        first = row["cost"] if meets else row["failure_probability"]
        return (not meets, first, row["failure_probability"], row["scheme"])
    return (not row.get("meets", True), row["failure_probability"], p95, row["scheme"])
