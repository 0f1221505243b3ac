"""Pareto fronts (issue 51): the speed of a front and the choice of its method, measured.

    python3 benchmarks/pareto_fronts.py [--nsga]

1. Speed: a 2-objective front (error against size) of 20 designs for a 10-point path
   (prescribed timing, an offset free; benchmarks/pareto/path10.toml), `linkcli synth` whole:
   wall and CPU seconds, the front's evaluations per design (the type's own search apart).
2. With --nsga (needs `pip install pymoo`, not a linkcli dependency): NSGA-II (pymoo) on the
   same design space and objectives (linkcli.pareto's measure, the type's constraints as
   g >= 0), with as many design evaluations as the sweep spent and with five times as many:
   its non-dominated feasible designs' hypervolume against the sweep's reference point, and
   how far its points lie from the sweep's front (the error above the sweep's error at the
   same size, relative to the front's error range, interpolated between the sweep's rows).

Prints one line per measurement (the figures quoted in benchmarks/RESULTS.md).
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
PROBLEM = ROOT / "benchmarks" / "pareto" / "path10.toml"


def cpu_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def speed() -> dict:
    before, start = cpu_children(), time.perf_counter()
    out = subprocess.run([sys.executable, "-m", "linkcli", "synth", str(PROBLEM), "--format", "json", "--timing"],
                         capture_output=True, text=True, check=False)
    wall, cpu = time.perf_counter() - start, cpu_children() - before
    report = json.loads(out.stdout)
    front = report["front"]
    return {"exit": out.returncode, "wall_s": round(wall, 1), "cpu_s": round(cpu, 1),
            "designs": len(front["rows"]), "certified": sum(r["certified"] for r in front["rows"]),
            "evaluations": report["solver"]["evaluations"], "hypervolume": front["hypervolume"],
            "reference_point": front["reference_point"], "rows": front["rows"]}


def type_evaluations() -> int:
    """The type's own search alone (the same file without its front)."""
    import tomllib
    spec = tomllib.loads(PROBLEM.read_text())
    text = PROBLEM.read_text().split("[objective]")[0]
    alone = ROOT / "benchmarks" / "pareto" / "_alone.toml"
    alone.write_text(text)
    try:
        out = subprocess.run([sys.executable, "-m", "linkcli", "synth", str(alone), "--format", "json"],
                             capture_output=True, text=True, check=False)
        return int(json.loads(out.stdout)["solver"]["evaluations"])
    finally:
        alone.unlink()
        del spec


def nsga(evaluations: int, sweep: dict) -> dict:
    """NSGA-II on the sweep's space (module docstring, 2.)."""
    from pymoo.algorithms.moo.nsga2 import NSGA2
    from pymoo.core.problem import Problem
    from pymoo.optimize import minimize

    import linkcli.pareto.run as run
    from linkcli.pareto.hypervolume import hypervolume
    from linkcli.pareto.objectives import Measure
    from linkcli.reading.load import load
    from linkcli.types.path_generation import solve as path_solve

    problem = load(str(PROBLEM))
    captured = {}

    def keep(p, space, found):
        captured["space"] = space
        return found

    run.solve_front, original = keep, run.solve_front
    try:
        path_solve.solve(problem)
    finally:
        run.solve_front = original
    space = captured["space"]
    measure = Measure(problem, space, problem.meta.front.objectives)
    free = np.flatnonzero(space.hi > space.lo)

    class Designs(Problem):
        def __init__(self):
            super().__init__(n_var=len(free), n_obj=2, n_ieq_constr=space.inequalities(space.x0[None]).shape[1],
                             xl=space.lo[free], xu=space.hi[free])

        def _evaluate(self, z, out, *args, **kwargs):
            x = np.repeat(space.x0[None], len(z), axis=0)
            x[:, free] = z
            with np.errstate(all="ignore"):
                f = np.array([measure.values(row) for row in x])
                g = -space.inequalities(x)
            out["F"] = np.where(np.isfinite(f), f, 1e12)
            out["G"] = np.where(np.isfinite(g), g, 1e12)

    population = 40
    start = time.perf_counter()
    res = minimize(Designs(), NSGA2(pop_size=population), ("n_eval", evaluations), seed=1, verbose=False)
    seconds = time.perf_counter() - start
    feasible = res.F if res.F is not None else np.zeros((0, 2))
    ref = np.array(sweep["reference_point"])
    sweep_pts = np.array([[r["objectives"]["error"], r["objectives"]["size"]] for r in sweep["rows"]])
    order = np.argsort(sweep_pts[:, 1])
    span = float(np.ptp(sweep_pts[:, 0]))
    gaps = [float(f[0] - np.interp(f[1], sweep_pts[order, 1], sweep_pts[order, 0])) / span
            for f in feasible if sweep_pts[:, 1].min() <= f[1] <= sweep_pts[:, 1].max()]
    return {"evaluations": evaluations, "seconds": round(seconds, 1), "designs": len(feasible),
            "hypervolume": hypervolume(feasible, ref) if len(feasible) else 0.0,
            "sweep_hypervolume": sweep["hypervolume"],
            "median_gap": float(np.median(gaps)) if gaps else None, "best_gap": float(min(gaps)) if gaps else None}


def main() -> None:
    sweep = speed()
    own = type_evaluations()
    per_design = (sweep["evaluations"] - own) / max(sweep["designs"], 1)
    print(json.dumps({k: v for k, v in sweep.items() if k != "rows"} | {"type_evaluations": own,
                     "front_evaluations_per_design": round(per_design)}))
    if "--nsga" in sys.argv:
        front_evals = sweep["evaluations"] - own
        for k in (1, 5):
            print(json.dumps(nsga(k * front_evals, sweep)))


if __name__ == "__main__":
    main()
