"""Is each motion case's best known (benchmarks/constrained_variants.json) a local optimum?

An independent local optimizer on linkcli's own residuals and constraints: each case is
solved (seed 0), and at each of the first two designs the search settles
(linkcli.search.kkt.settle, the final Newton polish on the unit box of the design's free
variables), scipy's SLSQP also runs from the settle's start on the same objective f = |r|^2,
gradient and constraints c >= 0; the lowest feasible SLSQP end (c >= -1e-9) is compared
with the best known. SLSQP's quasi-Newton model walks long curved valleys that a Newton
step on a fixed active set overshoots.

Usage: PYTHONPATH=src python3 benchmarks/check_best_known_motion.py [case ids...]

Run on 2026-11-27 (before the motion settle's walk): case 103's best known, 0.020466, was
not a local optimum: SLSQP from the search's end point reached 0.0120500 (the reduced
gradient there was 0.084, the valley 0.63 of the unit box long), which linkcli's screen
accepts; the search now gets there itself (docs/motion_generation.md). Every other motion
case's SLSQP end equals its best known (case 67: 1e-8 lower at a 3.6e-10 violation); case
99, not kept, ended below its best known.
"""

from __future__ import annotations

import os
import sys
import time

BENCH = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, BENCH)
import constrained_variants as cv  # noqa: E402
import numpy as np  # noqa: E402
from scipy.optimize import Bounds, NonlinearConstraint, minimize  # noqa: E402

from linkcli.search import kkt  # noqa: E402

SETTLES = 2  # the first designs settled in a run (the best of its first rounds)
FEASIBLE = -1e-9  # order-one constraints: an SLSQP end this far outside counts as feasible


def slsqp_from(evaluate, u0):
    """(f, worst c) where SLSQP ends from u0 on the Points `evaluate` gives (f, g, c, a)."""
    memo = {}

    def point(u):
        key = u.tobytes()
        if key not in memo:
            if len(memo) > 4:
                memo.clear()
            memo[key] = evaluate(np.clip(u, 0.0, 1.0))
        return memo[key]

    u0 = np.asarray(u0, float)
    p0 = point(u0)
    cons = [NonlinearConstraint(lambda u: point(u).c, 0.0, np.inf, jac=lambda u: point(u).a)] if len(p0.c) else []
    res = minimize(lambda u: point(u).f, u0, jac=lambda u: point(u).g, bounds=Bounds(0.0, 1.0),
                   constraints=cons, method="SLSQP", options={"ftol": 1e-15, "maxiter": 600})
    q = point(np.clip(res.x, 0.0, 1.0))
    return q.f, float(q.c.min()) if len(q.c) else 0.0


def check(case: str, entry: dict) -> str:
    ends = []
    calls = [0]
    original = kkt.settle

    def settle(evaluate, u0, **kwargs):
        calls[0] += 1
        if calls[0] <= SETTLES:
            try:
                ends.append(slsqp_from(evaluate, u0))
            except Exception as exc:  # noqa: BLE001 -- a failed SLSQP is reported, not fatal
                ends.append((np.inf, repr(exc)[:60]))
        return original(evaluate, u0, **kwargs)

    kkt.settle = settle
    started = time.time()
    try:
        run = cv.solve_text(entry["text"], "auto", None, 0)
    finally:
        kkt.settle = original
    best = entry["best_known"]
    feasible = [f for f, worst in ends if isinstance(worst, float) and worst >= FEASIBLE]
    low = min(feasible, default=np.inf)
    flag = "LOWER" if low < best * (1.0 - 1e-6) else ""
    return (f"{case} {run['status']} run={run['objective']:.10g} best={best:.10g} slsqp={low:.10g} {flag} "
            f"{time.time() - started:.1f}s")


def main() -> None:
    cache = cv.load_cache(os.path.join(BENCH, "constrained_variants.json"))
    ids = sys.argv[1:] or [k for k, e in sorted(cache["cases"].items(), key=lambda kv: int(kv[0]))
                           if e["family"] == "motion" and e.get("best_known") is not None]
    for case in ids:
        print(check(case, cache["cases"][case]), flush=True)


if __name__ == "__main__":
    main()
