"""Run the whole problems/bench set and write benchmarks/RESULTS.md: run time against error.

Usage (from the repository root): python3 benchmarks/run.py [--seeds N]
"""

from __future__ import annotations

import argparse
import glob
import os
import platform
import sys

import numpy
import scipy

from linkcli import __version__
from linkcli.bench import SUMMARY_COLUMNS, markdown, run_problem, summary


def machine() -> str:
    return (f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
            f"numpy {numpy.__version__}, scipy {scipy.__version__}, linkcli {__version__}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--out", default="benchmarks/RESULTS.md")
    args = ap.parse_args()
    rows = []
    for path in sorted(glob.glob("problems/bench/*.toml")):
        rows.extend(run_problem(path, args.seeds))
        print(f"{path}: done", file=sys.stderr)
    text = (f"# linkcli bench\n\nMachine: {machine()}.\n"
            f"Reproduce: `python3 benchmarks/run.py --seeds {args.seeds}`.\n"
            "`seconds` is the solve alone (no start-up); `gap` = (objective - best_known) / best_known;\n"
            "`auto` is the default; a `-` budget is the file's own (or the method's default).\n\n"
            "## Summary over seeds\n\n" + markdown(summary(rows), 5, SUMMARY_COLUMNS)
            + "\n## Every run\n\n" + markdown(rows))
    with open(args.out, "w", encoding="utf-8") as fh:
        fh.write(text)
    print(text)


if __name__ == "__main__":
    main()
