"""The coupler-curve atlas's cost at two sizes: build time, file size, load time, memory and
lookup time.

Usage (from the repository root):

    python3 benchmarks/atlas_scaling.py [--sizes 25000 100000] [--repeats 5]

For each size: `linkcli.atlas.build` + `store.encode` timed (one process, CPU seconds too),
the file's bytes, `cache.load` timed, the loaded atlas's own arrays (`Atlas.nbytes`) and the
growth of this process's resident memory (VmRSS, Linux) across the load, then the lookup
(`lookup.starts`: similarity over every stretch, the best 160 placed back) on the free-timing
targets of problems/bench, and its first part alone (`lookup.hits`: the descriptor
match), the median over --repeats; BLAS single-threaded, as the command line runs it.
"""

from __future__ import annotations

import argparse
import glob
import os
import statistics
import tempfile
import time

from linkcli.pipeline import single_threaded_blas

single_threaded_blas()


def rss_mb() -> float:
    with open("/proc/self/status") as handle:
        for line in handle:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return float("nan")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[25_000, 100_000])
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    from linkcli.atlas import cache, store
    from linkcli.atlas.build import build
    from linkcli.io.safe_read import read_problem_bytes
    from linkcli.reading.load import load
    from linkcli.types.path_generation import atlas_starts as lookup
    from linkcli.types.path_generation.model import build as design_of
    designs = []
    for path in sorted(glob.glob("problems/bench/*.toml")):
        problem = load(path, read_problem_bytes(path))
        if problem.meta.type == "path-generation" and getattr(problem, "timing", "") == "free":
            designs.append((os.path.basename(path), design_of(problem)))
    print("| atlas size | build s (CPU s) | file MB | load s | arrays MB | RSS growth MB | lookup ms: match (median, max wall; median CPU) | lookup ms: with placing (same) |")
    print("|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as folder:
        for size in args.sizes:
            path = os.path.join(folder, f"atlas-{size}.bin")
            t0, c0 = time.perf_counter(), time.process_time()
            data = store.encode(build(size, 0), size, 0)
            built, cpu = time.perf_counter() - t0, time.process_time() - c0
            store.write(path, data)
            del data
            before = rss_mb()
            t0 = time.perf_counter()
            atlas = cache.load(path)
            loaded = time.perf_counter() - t0
            grown = rss_mb() - before
            match, full, match_cpu, full_cpu = [], [], [], []
            for _, design in designs:
                ok = lookup.allowed(design, atlas)
                for _ in range(args.repeats):
                    t0, c0 = time.perf_counter(), time.process_time()
                    lookup.hits(design, atlas, ok)
                    match.append(1e3 * (time.perf_counter() - t0))
                    match_cpu.append(1e3 * (time.process_time() - c0))
                    t0, c0 = time.perf_counter(), time.process_time()
                    lookup.starts(design, atlas, 96)
                    full.append(1e3 * (time.perf_counter() - t0))
                    full_cpu.append(1e3 * (time.process_time() - c0))
            print(f"| {size:,} | {built:.1f} ({cpu:.1f}) | {os.path.getsize(path) / 1e6:.1f} | {loaded:.2f} | "
                  f"{atlas.nbytes / 1e6:.0f} | {grown:.0f} | {statistics.median(match):.0f}, {max(match):.0f} "
                  f"({statistics.median(match_cpu):.0f}) | {statistics.median(full):.0f}, {max(full):.0f} "
                  f"({statistics.median(full_cpu):.0f}) |", flush=True)
            del atlas


if __name__ == "__main__":
    main()
