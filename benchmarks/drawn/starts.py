"""Speed of the six-bar catalogue (docs/six_bars.md, "Speed"): the enumeration of the chains
and their inversions, and the starting drawings of every choice.

    python benchmarks/drawn/starts.py            # count = 3 drawings a choice, seeds 0 to 4

Times are medians over the seeds (time.perf_counter), on whatever the machine is doing:
state the machine's load with the figures.
"""

from __future__ import annotations

import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))

SEEDS = range(5)
COUNT = 3
BOX = (0.0, 0.0, 100.0, 60.0)


def main() -> None:
    from linkcli.mechanisms.drawn import catalogue, chains

    start = time.perf_counter()
    chains.chains(6)
    chains.inversions(6)
    print(f"enumeration (2 chains, 5 inversions, first call): {1e3 * (time.perf_counter() - start):.0f} ms")
    catalogue.starting_drawings(catalogue.choices("four-bar", "path")[0], BOX)  # numpy and the caches
    print(f"{'choice':78s} {'median ms':>9s} ({COUNT} drawings)")
    totals = {}
    for task in catalogue.TASKS:
        for choice in catalogue.choices("any six-bar", task) + catalogue.choices("four-bar", task):
            times = []
            for seed in SEEDS:
                start = time.perf_counter()
                catalogue.starting_drawings(choice, BOX, seed=seed, count=COUNT)
                times.append(time.perf_counter() - start)
            median = statistics.median(times)
            totals[task] = totals.get(task, 0.0) + median
            print(f"{task + ': ' + choice.label:78s} {1e3 * median:9.1f}")
    for task, total in totals.items():
        print(f"every {task} choice, {COUNT} drawings each: {1e3 * total:.0f} ms")


if __name__ == "__main__":
    main()
