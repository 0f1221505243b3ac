"""Same bits before and after a refactoring: a sample of constrained-variant study runs
(benchmarks/constrained_variants.py's cases, the default search), each reduced to what must
not change -- status, printed objective, evaluations and a digest of the whole JSON report.
(problems/*.toml are the golden tests' own: tests/test_golden.py.)

Usage (from the repository root):

    python3 benchmarks/same_bits.py record OUT.json [--cases I ...] [--seeds 0 1]
    python3 benchmarks/same_bits.py compare BEFORE.json AFTER.json

`record` solves in this process (as `constrained_variants.py study` does); `compare` prints
every row, says which differ, and exits 1 if any does. To record the version before a change,
run `record` with PYTHONPATH pointing at an export of it (`git archive REV | tar -x -C DIR`,
PYTHONPATH=DIR/src).
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from linkcli.pipeline import single_threaded_blas  # noqa: E402

single_threaded_blas()
import constrained_variants as cv  # noqa: E402

SAMPLE = (0, 4, 8, 9, 13, 21, 2, 6, 10, 3, 7, 11)  # three cases of each family


def digest(report: dict) -> str:
    return hashlib.sha256(json.dumps(report, sort_keys=True, default=float).encode()).hexdigest()[:16]


def record(out: str, cases, seeds) -> None:
    cache = cv.load_cache()
    rows = []
    for i in cases:
        entry = cache["cases"][str(i)]
        for seed in seeds:
            run = cv.solve_text(entry["text"], "auto", None, seed)
            row = dict(case=i, family=entry["family"], seed=seed, status=run["status"],
                       objective=run["objective"], evaluations=run["evaluations"],
                       report=digest(run["report"]), seconds=round(run["seconds"], 2))
            rows.append(row)
            print(json.dumps(row), file=sys.stderr, flush=True)
    with open(out, "w") as f:
        json.dump(rows, f, indent=1)


def compare(before: str, after: str) -> int:
    a, b = json.load(open(before)), json.load(open(after))
    keys = ("status", "objective", "evaluations", "report")
    index = {(r["case"], r["seed"]): r for r in b}
    bad = 0
    for r in a:
        s = index.get((r["case"], r["seed"]))
        same = s is not None and all(r[k] == s[k] for k in keys)
        bad += not same
        print(f"case {r['case']:>3} ({r['family']:<15}) seed {r['seed']}: {r['status']:<13} "
              f"{r['objective']!s:<14} {r['evaluations']:>9} {'same' if same else 'DIFFERS: ' + str(s)}")
    print(f"{len(a) - bad} of {len(a)} runs repeat status, objective, evaluations and report digest")
    return 1 if bad else 0


def main() -> int:
    p = argparse.ArgumentParser()
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("record")
    r.add_argument("out")
    r.add_argument("--cases", type=int, nargs="*", default=list(SAMPLE))
    r.add_argument("--seeds", type=int, nargs="*", default=[0, 1])
    c = sub.add_parser("compare")
    c.add_argument("before")
    c.add_argument("after")
    args = p.parse_args()
    if args.cmd == "record":
        record(args.out, args.cases, args.seeds)
        return 0
    return compare(args.before, args.after)


if __name__ == "__main__":
    sys.exit(main())
