"""The drawn home's population kinematics: N designs x S drive values at once
(mechanisms/drawn/population.py), the kernel of every drawn design's search.

Usage (from the repository root):

    python3 benchmarks/drawn_population.py [--designs 1000] [--steps 72] [--repeat 7]

For Jansen's leg (problems/drawn_jansen.toml: a crank and three dyads, eight joints), the
Stephenson III six-bar of problems/drawn_six_bar_path.toml and the Stephenson six-bar driven
into a class-III triad of problems/drawn_stephenson.toml (continuation over the population,
mechanisms/drawn/population_groups.py): every moving joint free in a box
of +-10 (length unit), `--designs` designs drawn in the boxes, each at `--steps` drive
values over a turn; one call gives the traced point (the foot F, the coupler point P), every
closure's margin and transmission angle. Prints the median and the best of `--repeat` calls
(seconds, wall clock, one thread) and the time per design-step.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from linkcli.pipeline import single_threaded_blas  # noqa: E402

single_threaded_blas()
import numpy as np  # noqa: E402

CASES = (("problems/drawn_jansen.toml", "F"), ("problems/drawn_six_bar_path.toml", "P"),
         ("problems/drawn_stephenson.toml", "D"))


def population(path: str, traced: str):
    from linkcli.mechanisms.drawn.population import DrawnPopulation
    from linkcli.mechanisms.drawn.structure import analyse
    from linkcli.reading.load import load
    problem = load(path)
    drawing = getattr(problem, "linkage", None) or problem.drawing
    moving = tuple(j.name for j in drawing.joints if not j.ground)
    boxes = {j: ((drawing.joint(j).at[0] - 10, drawing.joint(j).at[0] + 10),
                 (drawing.joint(j).at[1] - 10, drawing.joint(j).at[1] + 10)) for j in moving}
    return DrawnPopulation(drawing, analyse(drawing), moving, boxes, traced=(traced,))


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("--designs", type=int, default=1000)
    p.add_argument("--steps", type=int, default=72)
    p.add_argument("--repeat", type=int, default=7)
    args = p.parse_args()
    for path, traced in CASES:
        pop = population(path, traced)
        x = pop.starts(np.random.default_rng(0), args.designs)
        q = np.repeat((np.arange(args.steps) * (2 * np.pi / args.steps))[None, :], args.designs, axis=0)
        pop.kinematics(x, q)  # warm
        times = []
        for _ in range(args.repeat):
            pop.__dict__.pop("_tracks", None)  # a triad's tracks followed again, not taken from the last call
            t0 = time.perf_counter()
            motion = pop.kinematics(x, q)
            times.append(time.perf_counter() - t0)
        med = statistics.median(times)
        print(f"{path}: {args.designs} designs x {args.steps} steps, {len(pop.free)} free joints, "
              f"{len(pop.closures)} closures: median {1e3 * med:.1f} ms, best {1e3 * min(times):.1f} ms "
              f"({1e9 * med / (args.designs * args.steps):.0f} ns a design-step; "
              f"{100 * motion.valid.mean():.0f} % of the rows assemble)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
