"""`linkcli atlas build`: write an atlas file, with a progress bar on a terminal.

Without --out, the default atlas of the user's cache (`cache.default_path`, the one every
free-timing search uses) at the size and seed given (other values are written beside it
under their own name, and used only through LINKCLI_ATLAS). Exit codes: 0 written; 2 a
path that is a folder, a folder that does not exist, or a file that cannot be written
(one line each, before any work).
"""

from __future__ import annotations

import os
import sys
import time

EXIT_OK, EXIT_BAD = 0, 2


def _err(text: str) -> None:
    from linkcli.io.terminal_text import write_error
    write_error(text)


def _writable(path: str) -> str | None:
    """Why `path` cannot take an atlas file, or None."""
    if os.path.isdir(path):
        return "expected a file name for the atlas, found a folder"
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        return f"expected a file in an existing folder, found no folder {folder}"
    probe = os.path.join(folder, f".linkcli-atlas-probe.{os.getpid()}")
    try:
        with open(probe, "wb"):
            pass
        os.unlink(probe)
    except OSError as exc:
        return f"expected a writable folder, found {exc.strerror or exc}"
    if os.path.exists(path) and not os.access(path, os.W_OK):
        return "expected a writable file, found a read-only one"
    return None


def build_command(out: str | None, size: int, seed: int) -> int:
    from linkcli.atlas import cache
    from linkcli.atlas.build import MAX_SIZE, MIN_SIZE
    if not MIN_SIZE <= size <= MAX_SIZE:
        _err(f"--size: expected a number of four-bars within [{MIN_SIZE:,}, {MAX_SIZE:,}], found {size}")
        return EXIT_BAD
    if out == "":  # a plain string (pathlib would read "" as ".", the current folder)
        _err("--out: expected a file name for the atlas, found an empty argument")
        return EXIT_BAD
    if out is None:
        folder = cache.cache_dir()
        try:
            os.makedirs(folder, exist_ok=True)
        except OSError as exc:
            _err(f"{folder}: expected a cache folder linkcli can make, found {exc.strerror or exc}")
            return EXIT_BAD
        out = cache.atlas_path(size, seed)
    why = _writable(out)
    if why is not None:
        _err(f"{out}: {why}")
        return EXIT_BAD
    from linkcli.atlas import store
    from linkcli.atlas.build import build
    start = time.perf_counter()
    with _progress(size) as tick:
        tables = build(size, seed, tick)
    data = store.encode(tables, size, seed)
    try:
        store.write(out, data)
    except OSError as exc:
        _err(f"{out}: expected a writable file, found {exc.strerror or exc}")
        return EXIT_BAD
    seconds = time.perf_counter() - start
    from linkcli.io.terminal_text import line
    sys.stdout.write(line(f"{out}: atlas of {size:,} four-bars (seed {seed}), {len(data) / 1e6:.1f} MB, "
                          f"built in {seconds:.1f} s"))
    return EXIT_OK


class _progress:
    """A rich progress bar on stderr while building (nothing when stderr is not a terminal):
    a context whose value is the build's progress callback (done, total)."""

    def __init__(self, total: int) -> None:
        self.total = total
        self.bar = None

    def __enter__(self):
        if not sys.stderr.isatty():
            return None
        from rich.console import Console
        from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn
        self.bar = Progress(TextColumn("building the atlas"), BarColumn(), MofNCompleteColumn(),
                            TimeRemainingColumn(), console=Console(file=sys.stderr), transient=True)
        self.bar.start()
        task = self.bar.add_task("atlas", total=self.total)
        return lambda done, total: self.bar.update(task, completed=done)

    def __exit__(self, *exc) -> None:
        if self.bar is not None:
            self.bar.stop()
