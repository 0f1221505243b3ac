"""Progress of long work beyond the searches' evaluations (search.budget counts those): the
passes of a tolerance study over its samples, the frames of an animation, the runs of a bench.

`watch`, when set, is told `(what, done, total)` after each piece of work: `what` names the
work ("tolerance", "frames", ...), `done` is how much of it is done so far (sample-targets
assembled, frames drawn, runs finished) and `total` how much there is, or None where it is
not known beforehand (an allocation's passes). The command line sets it, as it sets
budget.watch, only while stderr is a terminal (its rich progress display on stderr); else it
is None and counting costs one test. Work is counted where it is done, once per chunk of
samples or per frame: never per sample.
"""

from __future__ import annotations

from typing import Callable

watch: Callable[[str, int, int | None], None] | None = None
_done: dict[str, int] = {}


def start(what: str) -> None:
    """A new piece of work named `what`: its count starts at 0."""
    _done[what] = 0


def reset() -> None:
    """Every count back to 0 (the next file of a batch)."""
    _done.clear()


def count(what: str, n: int, total: int | None = None) -> None:
    """`n` more units of `what` done (out of `total`, when known): the watch is told."""
    if watch is None:
        return
    _done[what] = _done.get(what, 0) + int(n)
    watch(what, _done[what], total)


def display():
    """A rich progress display on stderr (a spinner, what is being done, a bar, done of total,
    a `work` field, the elapsed time), transient; None (nothing shown) when stderr is not a
    terminal. rich is imported here, only then."""
    import sys
    if sys.stderr is None or not sys.stderr.isatty():
        return None
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn
    return Progress(SpinnerColumn(), TextColumn("{task.description}"), BarColumn(),
                    MofNCompleteColumn(), TextColumn("{task.fields[work]}"), TimeElapsedColumn(),
                    console=Console(file=sys.stderr, soft_wrap=True), transient=True)  # a line printed meanwhile stays one line
