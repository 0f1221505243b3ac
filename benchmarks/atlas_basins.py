"""Where do the coupler-curve atlas's starts lead? Each placed start of a free-timing file,
taken alone through the stages a multistart round puts its picks through (batched
Levenberg-Marquardt with the linear part projected out, the refinement, the polish on every
variable, the settle of a pick left unconverged: types/path_generation/solve.py), and the feasible objective it ends at, against
the file's `[reference] objective` (its best known).

Usage (from the repository root, the atlas built: `linkcli atlas build`):

    python3 benchmarks/atlas_basins.py [--starts 96] [--hits 160] [FILE...]

Default: every free-timing file of problems/bench, the starts a search asks of the atlas
(solve.ATLAS_STARTS) from the lookup's usual hits (atlas_starts.HITS). Per file: how many
starts were placed, how many end within 1e-6 (relative) and within 1 % of the best known,
the lowest and median end, the rank (in the lookup's order, 1 first) of the first start that
ends within 1e-6, and the CPU seconds of the polishing. A start that ends far above the best
known fell into another basin: the lookup handed the search nothing there.
"""

from __future__ import annotations

import argparse
import glob
import os
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from atlas_bench import free_timing, reference  # noqa: E402


def ends(path: str, starts: int, hits: int) -> tuple[np.ndarray, float]:
    """The feasible objective each placed start ends at (inf: infeasible), in the lookup's
    order, and the CPU seconds taken."""
    from linkcli.io.safe_read import read_problem_bytes
    from linkcli.reading.load import load
    from linkcli.search.budget import Budget
    from linkcli.types.path_generation import atlas_starts
    from linkcli.types.path_generation import solve as search
    from linkcli.types.path_generation.model import build
    from linkcli.types.path_generation.search import Space, batch_lm

    design = build(load(path, read_problem_bytes(path)))
    atlas_starts.HITS = hits
    found = atlas_starts.starts_for(design, starts)
    if found is None:
        return np.zeros(0), 0.0
    x, sign, s, _, _ = found
    t0 = time.process_time()
    budget = Budget(10 ** 12)
    with np.errstate(all="ignore"):
        x = design.wrapped(np.clip(x, design.lo, design.hi))
        proj = Space(design, budget, project=True)
        z, _, _ = batch_lm(proj, proj.free(x), sign, s, search.LM_WEIGHT,
                           search.FIELD_ROUNDS * search.FIELD_ITERATIONS)
        space = Space(design, budget, project=True, closed_penalties=False)
        z, _, conv = batch_lm(space, z, sign, s, search.LM_WEIGHT, search.REFINE_ITERATIONS + search.REFINE_ALL)
        done = search.polish_all(design, budget, space.full(z, sign, s), sign, s, conv)
        done = [c if c.converged else search._settled_pick(design, budget, c) for c in done]
    ranks = [search._rank(design, c) for c in done]
    out = np.array([r[2] if not r[0] else np.inf for r in ranks])
    return out, time.process_time() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="*")
    ap.add_argument("--starts", type=int, default=None, help="placed starts asked of the atlas")
    ap.add_argument("--hits", type=int, default=None, help="nearest stretches placed back")
    args = ap.parse_args()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    from linkcli.types.path_generation import atlas_starts
    from linkcli.types.path_generation import solve as search
    starts = args.starts or search.ATLAS_STARTS
    hits = args.hits or atlas_starts.HITS
    files = args.files or [f for f in sorted(glob.glob("problems/bench/*.toml")) if free_timing(f)]
    print(f"starts asked: {starts}, hits: {hits}")
    print("| problem | best known | starts placed | within 1e-6 | within 1 % | first within 1e-6 (rank) "
          "| lowest end | median end | cpu s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for path in files:
        best, floor, _ = reference(path)  # a best known of 0 is met within floor
        end, cpu = ends(path, starts, hits)
        name = os.path.splitext(os.path.basename(path))[0]
        if not len(end):
            print(f"| {name} | {best} | 0 | - | - | - | - | - | - |")
            continue
        known = best if best is not None else -np.inf
        near = end <= max(known * (1 + 1e-6), floor)
        close = end <= max(known * 1.01, floor)
        first = int(np.flatnonzero(near)[0]) + 1 if near.any() else "-"
        finite = end[np.isfinite(end)]
        median = f"{statistics.median(finite):.8g}" if len(finite) else "-"
        print(f"| {name} | {best} | {len(end)} | {int(near.sum())} | {int(close.sum())} | {first} | "
              f"{end.min():.8g} | {median} | {cpu:.1f} |", flush=True)


if __name__ == "__main__":
    main()
