"""Time whole commands side by side: interleaved runs, CPU and wall time, peak memory, ratios.

Usage (from the repository root):

    python3 benchmarks/compare_commands.py [--runs 7] [--warmup 1] -- COMMAND [COMMAND ...]

Each COMMAND is one argument, split as a shell would split it (shlex) and run without a
shell, its output discarded. Round r runs every command once, in the order given (A B A B
...), so that a shared machine's drift weighs on each alike; `--warmup` rounds run first and
are not counted. Per command: the median wall seconds, the median CPU seconds (user + system
of the process and of the children it waited for, from os.wait4), the largest peak resident
memory, and the exit codes seen; and against the first command, the median of the
round-by-round ratios of CPU time, with their range (min-max). CPU time is the steadier
figure on a machine that other jobs share.

Two versions of linkcli: make a worktree of the older commit and run its source through
PYTHONPATH (env is the POSIX command):

    git worktree add /tmp/previous 7379980
    python3 benchmarks/compare_commands.py --runs 5 -- \\
        'env PYTHONPATH=/tmp/previous/src python3 -m linkcli synth problems/bench/kunjur5.toml' \\
        'env PYTHONPATH=src python3 -m linkcli synth problems/bench/kunjur5.toml'
"""

from __future__ import annotations

import argparse
import os
import shlex
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass, field


@dataclass
class Runs:
    """The measured runs of one command."""
    command: str
    wall: list[float] = field(default_factory=list)
    cpu: list[float] = field(default_factory=list)
    peak_mib: float = 0.0
    codes: set[int] = field(default_factory=set)


def run_once(argv: list[str]) -> tuple[float, float, float, int]:
    """(wall s, CPU s, peak MiB, exit code) of one run of argv, output discarded."""
    start = time.perf_counter()
    child = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    child.returncode = os.waitstatus_to_exitcode(status)  # reaped here, not by Popen
    return wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0, child.returncode


def ratio_summary(values: list[float], reference: list[float]) -> tuple[float, float, float]:
    """Median, min and max of the round-by-round ratios values[r] / reference[r]."""
    ratios = [v / r for v, r in zip(values, reference, strict=True) if r > 0]
    return statistics.median(ratios), min(ratios), max(ratios)


def measure(commands: list[str], runs: int, warmup: int) -> list[Runs]:
    argvs = [shlex.split(c) for c in commands]
    for _ in range(warmup):
        for argv in argvs:
            run_once(argv)
    table = [Runs(c) for c in commands]
    for _ in range(runs):
        for argv, row in zip(argvs, table):
            wall, cpu, peak, code = run_once(argv)
            row.wall.append(wall)
            row.cpu.append(cpu)
            row.peak_mib = max(row.peak_mib, peak)
            row.codes.add(code)
    return table


def markdown(table: list[Runs]) -> str:
    head = ("| command | runs | median wall s | median CPU s | peak MiB | exit | CPU / first: median (min-max) |\n"
            "|---|---|---|---|---|---|---|\n")
    lines = []
    first = table[0]
    for row in table:
        if row is first:
            ratio = "1"
        else:
            mid, low, high = ratio_summary(row.cpu, first.cpu)
            ratio = f"{mid:.3g} ({low:.3g}-{high:.3g})"
        codes = ", ".join(str(c) for c in sorted(row.codes))
        lines.append(f"| `{row.command}` | {len(row.cpu)} | {statistics.median(row.wall):.3g} | "
                     f"{statistics.median(row.cpu):.3g} | {row.peak_mib:.0f} | {codes} | {ratio} |\n")
    return head + "".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=7, help="counted rounds (default 7)")
    ap.add_argument("--warmup", type=int, default=1, help="rounds run first and not counted (default 1)")
    ap.add_argument("commands", nargs="+", help="the commands, each one quoted argument")
    args = ap.parse_args(argv)
    if args.runs < 1 or args.warmup < 0:
        ap.error("--runs must be at least 1 and --warmup at least 0")
    sys.stdout.write(markdown(measure(args.commands, args.runs, args.warmup)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
