"""Run the bench set and write its section of benchmarks/RESULTS.md: run time against error,
and how reliably each method's seeds reach the best known.

Usage (from the repository root):

    python3 benchmarks/run.py [--seeds N] [--cluster local:2] [--methods auto] [--merge] [FILE...]

Default: every file of problems/bench, 10 seeds (0..9) per solver setting. RESULTS.md gets
the reliability summary (per problem and method: seeds within 1e-6 of the best known, seeds
ending `ok` outside it, not converged, infeasible, median and worst gap, median seconds),
then every run, between two marker lines (BEGIN, END): the rest of the file (the history of
the measurements) is kept as it is. The script also prints the default method's (`auto`) row
per problem, the bench rows of docs/performance.md. With --merge, only the rows run (FILEs,
--methods) are replaced between the markers (a change that touches a few problems or one
method need not rerun them all). `seconds` is the solve alone (scipy
imported before timing); with --cluster the runs share the workers' cores, so keep it for
the counts, not the times.
"""

from __future__ import annotations

import argparse
import contextlib
import glob
import os
import platform
import sys

from linkcli.pipeline import single_threaded_blas

single_threaded_blas()  # the command line's BLAS threads, before numpy is imported
import numpy  # noqa: E402
import scipy  # noqa: E402

from linkcli import __version__
from linkcli.bench import SUMMARY_COLUMNS, markdown, outcomes, runs_of, summary
from linkcli.report import fmt

BEGIN = "<!-- benchmarks/run.py writes from here -->\n"
END = "<!-- benchmarks/run.py writes up to here -->\n"
RELIABILITY = "### Reliability over the seeds\n\n"
EVERY_RUN = "### Every run\n\n"
DEFAULT_COLUMNS = ("problem", "type", "median s", "median evaluations", "best objective",
                  "best known", "within 1e-6", "worst gap")


def machine() -> str:
    return (f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
            f"numpy {numpy.__version__}, scipy {scipy.__version__}, linkcli {__version__}")


def problem_type(path: str) -> str:
    from linkcli.io.safe_read import read_problem_bytes
    from linkcli.reading.load import load
    return load(path, read_problem_bytes(path)).meta.type


def default_method_table(table: list[dict], types: dict[str, str]) -> str:
    """The default method's summary row of each problem, as docs/performance.md quotes it."""
    rows = [{"problem": f"`{t['problem']}`", "type": types[t["problem"]],
             "median s": t["median seconds"], "median evaluations": t["median evaluations"],
             "best objective": t["best objective"], "best known": t["best_known"],
             "within 1e-6": t["within 1e-6"], "worst gap": t["worst gap"]}
            for t in table if t["method"] == "auto" and t["budget"] is None]
    digits = {"median s": 3, "median evaluations": 9, "best objective": 8, "best known": 8, "worst gap": 2}
    head = "| " + " | ".join(DEFAULT_COLUMNS) + " |\n|" + "---|" * len(DEFAULT_COLUMNS) + "\n"
    return head + "".join("| " + " | ".join("-" if r[c] is None else r[c] if isinstance(r[c], str)
                                            else fmt(r[c], digits[c]) for c in DEFAULT_COLUMNS) + " |\n"
                          for r in rows)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="*", help="problem files (default: problems/bench/*.toml)")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--cluster", default=None, help="a Dask scheduler address or local:N")
    ap.add_argument("--out", default="benchmarks/RESULTS.md")
    ap.add_argument("--methods", default=None, help="comma-separated: only these settings' rows (e.g. auto)")
    ap.add_argument("--merge", action="store_true",
                    help="replace only these files' rows in --out (the others kept from an earlier run)")
    args = ap.parse_args()
    files = args.files or sorted(glob.glob("problems/bench/*.toml"))
    runs = [run for path in files for run in runs_of(path, args.seeds)
            if args.methods is None or run.method in args.methods.split(",")]
    rows = []
    with contextlib.closing(outcomes(runs, args.cluster)) as done:
        for outcome in done:
            for line in outcome.errors:
                print(line, file=sys.stderr)
            if outcome.row is not None:
                rows.append(outcome.row)
                if len(rows) % args.seeds == 0:
                    print(f"{outcome.path} {outcome.row['method']}: done", file=sys.stderr)
    table = summary(rows)
    types = {os.path.splitext(os.path.basename(p))[0]: problem_type(p) for p in files}
    text = ("## The bench set: every method, every run\n\n"
            f"Machine: {machine()}.\n"
            f"Reproduce: `python3 benchmarks/run.py --seeds {args.seeds}`"
            + (f" --cluster {args.cluster}" if args.cluster else "") + ".\n"
            "`seconds` is the solve alone (no start-up); `gap` = (objective - best_known) / |best_known|"
            " (the difference itself for a best known of 0); \"within 1e-6\" counts the seeds whose gap"
            " is at most 1e-6, \"ok but off\" those that ended `ok` outside it; `auto` is the default"
            " method; a `-` budget is the file's own (or the method's default).\n\n"
            + RELIABILITY + markdown(table, 4, SUMMARY_COLUMNS)
            + "\n" + EVERY_RUN + markdown(rows))
    write_section(args.out, text, files if args.merge else None)
    print(default_method_table(table, types))


def write_section(path: str, fresh: str, merge_files: list[str] | None) -> None:
    """Write `fresh` between the BEGIN and END lines of the file at `path`, the text around
    them kept (a file without them gets them at its end; a missing file is made). With
    `merge_files`, the rows of `fresh` replace only their own rows of the section there."""
    try:
        with open(path, encoding="utf-8") as fh:
            old = fh.read()
    except FileNotFoundError:
        old = ""
    if BEGIN in old and END in old.split(BEGIN, 1)[1]:
        before, rest = old.split(BEGIN, 1)
        section, after = rest.split(END, 1)
    else:
        before, section, after = (old.rstrip("\n") + "\n\n" if old else ""), "", ""
    if merge_files is not None and section:
        fresh = merged(section, fresh, merge_files)
    with open(path, "w", encoding="utf-8") as fh:
        fh.write(before + BEGIN + fresh.rstrip("\n") + "\n" + END + after)


def merged(section: str, fresh: str, files: list[str]) -> str:
    """The bench section `section` with the rows of `fresh` (a run of some files or methods
    alone) in place of the rows they replace (same problem, method, budget; and seed in the
    table of every run), the others and the header kept."""
    stems = {os.path.splitext(os.path.basename(f))[0] for f in files}

    def split(text: str):
        head, rest = text.split(RELIABILITY, 1)
        summary_part, runs_part = rest.split(EVERY_RUN, 1)
        return head, summary_part.strip().splitlines(), runs_part.strip().splitlines()

    head, old_summary, old_runs = split(section)
    _, new_summary, new_runs = split(fresh)
    tables = []
    for old, new, cells in ((old_summary, new_summary, 3), (old_runs, new_runs, 4)):
        def key(line: str) -> tuple:  # problem, method, budget (, seed)
            return tuple(cell.strip() for cell in line.split("|")[1:1 + cells])
        fresh_rows = {key(ln): ln for ln in new[2:]}
        body = [fresh_rows.pop(key(ln), ln) for ln in old[2:]]
        tables.append("\n".join(old[:2] + body + list(fresh_rows.values())) + "\n")
    note = f"\nRows of {', '.join(sorted(stems))} run apart (`python3 benchmarks/run.py --merge`).\n"
    return head + RELIABILITY + tables[0] + "\n" + EVERY_RUN + tables[1] + note


if __name__ == "__main__":
    main()
