"""The benchmark problem set of `linkcli bench` without FILE, shipped as package data so
that it runs from any folder (and from an installed wheel).

`problems/bench/` in the repository is the user-visible copy of these files; a test keeps
the two identical (tests/cli/test_newcomer.py). Read with importlib.resources. No numerics.
"""

from __future__ import annotations

from importlib import resources

SUFFIX = ".toml"
SHOWN_FOLDER = "bench"  # problems are named bench/<name>.toml in bench output, on any machine


def bench_files() -> tuple[tuple[str, str], ...]:
    """(shown name, TOML text) of every packaged bench problem, sorted by name."""
    folder = resources.files(__name__)
    names = sorted(e.name for e in folder.iterdir() if e.name.endswith(SUFFIX) and e.is_file())
    return tuple((f"{SHOWN_FOLDER}/{n}", folder.joinpath(n).read_text(encoding="utf-8")) for n in names)
