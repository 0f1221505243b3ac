"""Motion generation on few poses nobody tuned on: random four-bars, 6 or 7 noisy poses each.

    python3 benchmarks/random_motion.py [--problems 30] [--seeds 2] [--out rows.json]

Problem k is drawn with numpy.random.default_rng(777) in turn (benchmarks/RESULTS.md's
figures): lengths uniform in [0.5, 4], the ground pivot, coupler point and angles at random, 6 or 7 input
angles over a travel of at most 2.5 rad on one branch (the linkage must assemble along all
of it), and N(0, 0.01) noise on the pose origins, so that the optimum is a least-squares
fit, not an exact one; default bounds, no constraint. Each problem is solved with seeds
0..seeds-1 and a row printed (status, objective, evaluations, seconds); with no long-run
best known, compare two versions' rows by the better of their objectives per problem (the
motion change in benchmarks/RESULTS.md did so).
"""

from __future__ import annotations

import argparse
import json
import time
from dataclasses import replace

import numpy as np

from linkcli.pipeline import solve
from linkcli.reading.load import load
from linkcli.types.motion_generation import assemble


def problems(count: int) -> list[str]:
    """The TOML texts of the first `count` problems (module docstring)."""
    rng = np.random.default_rng(777)
    texts = []
    while len(texts) < count:
        a, b, c, d = rng.uniform(0.5, 4.0, 4)
        p = np.array([rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-np.pi, np.pi), d, a, b, c,
                      rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-np.pi, np.pi)])
        n = int(rng.integers(6, 8))
        sign = -1.0 if rng.random() < 0.5 else 1.0
        phi = rng.uniform(-np.pi, np.pi) + np.sort(rng.uniform(0, 2.5, n))
        poses, valid = assemble.body_poses(p, phi, sign)
        if not np.all(valid):
            continue
        _, along = assemble.body_poses(p, np.linspace(phi[0], phi[-1], 200), sign)
        if not np.all(along):
            continue
        poses[:, :2] += rng.normal(0, 0.01, (n, 2))
        rows = ", ".join("[%r, %r, %r]" % (float(q[0]), float(q[1]), float(q[2])) for q in poses)
        texts.append(f'type = "motion-generation"\ntitle = "random {n} noisy poses"\n\n[units]\n'
                     f'length = "m"\nangle = "rad"\n\n[target]\nposes = [{rows}]\n')
    return texts


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--problems", type=int, default=30)
    ap.add_argument("--seeds", type=int, default=2)
    ap.add_argument("--out", help="write the rows as JSON here")
    args = ap.parse_args()
    rows = []
    for k, text in enumerate(problems(args.problems)):
        for seed in range(args.seeds):
            problem = load(f"random{k:02d}.toml", text)
            problem = replace(problem, meta=replace(problem.meta, solver=replace(problem.meta.solver, seed=seed)))
            t0 = time.perf_counter()
            sol = solve(problem)
            row = dict(problem=k, seed=seed, status=sol.status.value, objective=sol.objective,
                       evaluations=sol.solver.evaluations, seconds=time.perf_counter() - t0)
            rows.append(row)
            print(f"problem {k:2d} seed {seed}: {row['status']} {row['objective']!r} "
                  f"{row['evaluations']} evaluations {row['seconds']:.2f} s", flush=True)
    if args.out:
        with open(args.out, "w") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
