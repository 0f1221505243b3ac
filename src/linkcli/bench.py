"""`linkcli bench`: run time against error for each problem, solver setting and seed.

Each row: problem, method, budget, seed, seconds (wall clock of the solve alone, scipy
already imported),
evaluations, objective, best_known (the file's `[reference] objective`), gap
((objective - best_known) / |best_known|), status. A problem type's schema module may list
`bench_settings` as (method, budget) pairs (linkcli.registry.ProblemType); otherwise every
method in its `methods` is run with the file's own budget.
"""

from __future__ import annotations

import os
import sys
import time
from dataclasses import replace

from linkcli.errors import LinkcliError
from linkcli.io.terminal_text import one_line

COLUMNS = ("problem", "method", "budget", "seed", "seconds", "evaluations", "objective",
           "best_known", "gap", "status")


def settings_for(problem) -> list[tuple[str, int | None]]:
    from linkcli.registry import problem_type
    spec = problem_type(problem.meta.type)
    if spec.bench_settings:
        return list(spec.bench_settings)
    return [(m, problem.meta.solver.budget) for m in spec.methods]


def run_problem(path: str, seeds: int, text: str | None = None) -> list[dict]:
    """Every setting and seed of one problem file (`text`: its content, when it is not
    read from `path`, as for the packaged bench set)."""
    from linkcli.analysis.sections import gap
    from linkcli.io.load import load
    from linkcli.pipeline import solve
    problem = load(path, text)
    import scipy.optimize  # noqa: F401  imported before any timing, so that no row pays for it
    best = problem.meta.reference.objective if problem.meta.reference else None
    rows = []
    for method, budget in settings_for(problem):
        for seed in range(seeds):
            opts = replace(problem.meta.solver, method=method, seed=seed, budget=budget)
            p = replace(problem, meta=replace(problem.meta, solver=opts))
            t0 = time.perf_counter()
            sol = solve(p)
            seconds = time.perf_counter() - t0
            obj = sol.objective
            rows.append({
                "problem": path, "method": method, "budget": budget, "seed": seed,
                "seconds": seconds, "evaluations": sol.solver.evaluations if sol.solver is not None else None,
                "objective": obj, "best_known": best,
                "gap": gap(obj, best) if (obj is not None and best is not None) else None,
                "status": sol.status.value,
            })
    return rows


def command(files: list[str], fmt: str, seeds: int, precision: int, debug: bool) -> int:
    """Without files, the packaged bench set (linkcli.bench_problems, named bench/<name>.toml)."""
    if files:
        problems = [(path, None) for path in files]
    else:
        from linkcli.bench_problems import bench_files
        problems = list(bench_files())
    rows, worst = [], 0
    for path, text in problems:
        try:
            rows.extend(run_problem(path, seeds, text))
        except LinkcliError as exc:
            if debug:
                raise
            for line in exc.lines() if hasattr(exc, "lines") else [str(exc)]:
                sys.stderr.write(one_line(line) + "\n")
            worst = max(worst, getattr(exc, "exit_code", 1))
    if fmt == "json":
        from linkcli.io.export import to_json
        sys.stdout.write(to_json(rows, precision))
    elif fmt == "csv":
        from linkcli.io.csv_tables import to_csv
        sys.stdout.write(to_csv(rows, precision) if rows else ",".join(COLUMNS) + "\n")
    elif fmt == "toml":
        from linkcli.io.export import to_toml
        sys.stdout.write(to_toml({"bench": rows}, precision))
    else:
        from rich import box
        from rich.table import Table

        from linkcli.io.report import console, fmt as fmt_value
        t = Table(title="linkcli bench: run time against error", title_justify="left",
                  box=box.SIMPLE_HEAD, pad_edge=False, show_edge=False)
        for c in COLUMNS:
            t.add_column(c, justify="left" if c in ("problem", "method", "status") else "right",
                         no_wrap=True)
        for r in rows:
            shown = dict(r, problem=one_line(os.path.splitext(os.path.basename(r["problem"]))[0]))
            t.add_row(*(fmt_value(shown[c], precision) if shown[c] is not None else "-" for c in COLUMNS))
        console(width=None if sys.stdout.isatty() else 140).print(t)
    return worst


SUMMARY_COLUMNS = ("problem", "method", "budget", "seeds ok", "median seconds",
                   "median evaluations", "best objective", "best_known", "worst gap")


def summary(rows: list[dict]) -> list[dict]:
    """One row per (problem, method, budget) over the seeds: how many ended `ok`, the
    median time and evaluations, the best objective and the worst gap."""
    from statistics import median
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault((r["problem"], r["method"], r["budget"]), []).append(r)
    out = []
    for (problem, method, budget), rs in groups.items():
        objs = [r["objective"] for r in rs if r["objective"] is not None]
        gaps = [r["gap"] for r in rs if r["gap"] is not None]
        evals = [r["evaluations"] for r in rs if r["evaluations"] is not None]
        out.append({
            "problem": os.path.splitext(os.path.basename(problem))[0], "method": method,
            "budget": budget,
            "seeds ok": f"{sum(r['status'] == 'ok' for r in rs)}/{len(rs)}",
            "median seconds": median(r["seconds"] for r in rs),
            "median evaluations": int(median(evals)) if evals else None,
            "best objective": min(objs) if objs else None,
            "best_known": rs[0]["best_known"],
            "worst gap": max(gaps) if gaps else None,
        })
    return out


def markdown(rows: list[dict], precision: int = 4, columns: tuple[str, ...] = COLUMNS) -> str:
    """A markdown table of bench rows (for the README)."""
    from linkcli.io.report import fmt as fmt_value
    head = "| " + " | ".join(columns) + " |\n|" + "---|" * len(columns) + "\n"
    body = "".join("| " + " | ".join(fmt_value(r[c], precision) if r[c] is not None else "-"
                                     for c in columns) + " |\n" for r in rows)
    return head + body
