"""Drawn designs: each problem's default search from seeds 0..N-1, timed (the solve alone, in
this process, one BLAS thread), with its status, printed objective and evaluations.

Usage (from the repository root):

    python3 benchmarks/drawn_synthesis.py [FILE ...] [--seeds 5]

Default: problems/bench/drawn_six_bar_path.toml (a six-bar path: 16 points, 13 free
coordinates) and the examples problems/drawn_*.toml that design. Prints one row per run (wall
and process seconds: on a shared machine the process time is the one that does not follow the
other users' load), then per problem the median seconds and the statuses.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from dataclasses import replace

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from linkcli.pipeline import single_threaded_blas  # noqa: E402

single_threaded_blas()
import numpy  # noqa: E402,F401  (imported before any timing)

DEFAULT = ("problems/bench/drawn_six_bar_path.toml", "problems/drawn_dwell.toml",
           "problems/drawn_six_bar_path.toml", "problems/drawn_seven_poses.toml",
           "problems/drawn_jansen_stride.toml")


def main() -> int:
    from linkcli.bench import printed_objective
    from linkcli.reading.load import load
    from linkcli.pipeline import solve
    p = argparse.ArgumentParser()
    p.add_argument("files", nargs="*", default=list(DEFAULT))
    p.add_argument("--seeds", type=int, default=5)
    args = p.parse_args()
    for path in args.files:
        base = load(path)
        walls, cpus, statuses = [], [], []
        for seed in range(args.seeds):
            problem = replace(base, meta=replace(base.meta, solver=replace(base.meta.solver, seed=seed)))
            t0, c0 = time.perf_counter(), time.process_time()
            sol = solve(problem)
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
            walls.append(wall)
            cpus.append(cpu)
            statuses.append(sol.status.value)
            print(f"{path} seed {seed}: {sol.status.value} objective {printed_objective(problem, sol)} "
                  f"evaluations {sol.solver.evaluations} {wall:.2f} s ({cpu:.2f} s process)", flush=True)
        ok = statuses.count("ok")
        print(f"{path}: median {statistics.median(walls):.2f} s wall, {statistics.median(cpus):.2f} s process; "
              f"ok on {ok} of {len(statuses)} seeds\n", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
