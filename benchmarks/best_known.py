"""Establish a bench problem's best known objective by long runs, apart from the bench's own.

Usage (from the repository root):

    python3 benchmarks/best_known.py FILE [--seeds 20] [--scale 10]

Runs every method of the file's type (not only the default), each with `--scale` times its
default budget (2,000,000 evaluations at least for the global methods), from seeds 100,
101, ... (outside the 0..9 the bench reports), and prints one line per run and the best
value with its design. A best known is the lowest value any of these runs reaches; it is
accepted when it is reached by more than one method or seed (printed as "found by"), and
then written to the file's `[reference]` by hand, with the way it was found. The runs use
the solvers' own exact kinematics: an independent check of the value is the test suite's
(tests/test_bench_references.py recomputes each stored design with its own closure).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import replace

from linkcli.io.safe_read import read_problem_bytes
from linkcli.pipeline import solve
from linkcli.reading.load import load
from linkcli.registry import problem_type

GLOBAL_MINIMUM = 2_000_000  # evaluations at least for a global method's long run
SEED_BASE = 100


def default_budget(problem, method: str) -> int | None:
    """The method's default budget, as the solver would choose it (None: the solver's own)."""
    module = problem_type(problem.meta.type).module("solve")
    table = getattr(module, "DEFAULT_BUDGET", None)
    if isinstance(table, dict) and method in table:
        return int(table[method])
    if isinstance(table, int):  # one default for the type's only method
        return table
    per = getattr(module, "DEFAULT_BUDGET_PER_VARIABLE", None)
    if per is not None:
        n = module.Model(problem).n_variables if hasattr(module, "Model") else 5
        return int(per * max(n, 1))
    return None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("file")
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--scale", type=float, default=10.0)
    ap.add_argument("--methods", default=None, help="comma-separated (default: every method of the type)")
    args = ap.parse_args()
    problem = load(args.file, read_problem_bytes(args.file))
    spec = problem_type(problem.meta.type)
    methods = (args.methods.split(",") if args.methods
               else [m for m in spec.methods if m != "auto"] or ["auto"])
    found = []
    for method in methods:
        base = default_budget(problem, method)
        budget = None if base is None else int(base * args.scale)
        if budget is not None and method in ("differential-evolution", "de-polish", "dual-annealing"):
            budget = max(budget, GLOBAL_MINIMUM)
        for seed in range(SEED_BASE, SEED_BASE + args.seeds):
            opts = replace(problem.meta.solver, method=method, seed=seed, budget=budget)
            p = replace(problem, meta=replace(problem.meta, solver=opts))
            t0 = time.perf_counter()
            sol = solve(p)
            seconds = time.perf_counter() - t0
            print(f"{method:24s} budget {budget} seed {seed}: {sol.objective!r} {sol.status.value} "
                  f"({seconds:.1f} s)", flush=True)
            if sol.objective is not None and sol.status.value != "infeasible":
                found.append((sol.objective, method, seed, sol.linkage))
    if not found:
        print("no feasible run", file=sys.stderr)
        sys.exit(1)
    best = min(found, key=lambda f: f[0])
    close = [(m, s) for f, m, s, _ in found if f <= best[0] * (1 + 1e-7) + 1e-20]
    print(json.dumps({"best": best[0], "method": best[1], "seed": best[2], "linkage": repr(best[3]),
                      "found by": [f"{m} seed {s}" for m, s in close]}, indent=1))


if __name__ == "__main__":
    main()
