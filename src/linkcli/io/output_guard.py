"""Where output goes: standard output that can be lost mid-run, and what linkcli does then;
a folder that must take files (--out, --plot), probed before anything is solved.

Three ways the output goes: the reader closes the pipe (`linkcli synth ... | head -1`:
EPIPE), the device refuses it (`> /dev/full`: ENOSPC), or there is none (`>&-`: Python's
sys.stdout is None). `Guarded` wraps sys.stdout and turns any of them into `OutputLost`,
which no other handler catches (typer would turn an EPIPE into exit 1, and an ENOSPC into a
traceback). `exit_code(lost)` then decides, as docs/format.md documents (Exit codes; Choices,
"Where the output goes"):

- a closed pipe: the reader has what it wanted; nothing more is solved or written, nothing
  is said, and the exit code is 141 (128 + SIGPIPE, as for a command the signal ends, like
  130 for Ctrl-C);
- a device that refuses the output, or none: one line on stderr and exit 2, as for an
  --out folder that cannot be written.
"""

from __future__ import annotations

import errno
import os

BROKEN_PIPE_EXIT = 141  # 128 + SIGPIPE


class OutputLost(Exception):
    """Standard output failed: `error` is the OSError of the write or flush."""

    def __init__(self, error: OSError) -> None:
        super().__init__(str(error))
        self.error = error


class Guarded:
    """sys.stdout with every write and flush error raised as OutputLost (a closed stdout,
    None, fails at its first write); anything else is the stream's own."""

    def __init__(self, stream) -> None:
        self._stream = _retrying(stream)

    def _lost(self) -> OSError:
        return OSError(errno.EBADF, "no standard output (it is closed)")

    def write(self, text: str) -> int:
        if self._stream is None:
            raise OutputLost(self._lost())
        try:
            return self._stream.write(text)
        except OSError as exc:
            raise OutputLost(exc) from None

    def flush(self) -> None:
        if self._stream is None:
            return
        try:
            self._stream.flush()
        except OSError as exc:
            raise OutputLost(exc) from None

    def isatty(self) -> bool:
        return self._stream is not None and self._stream.isatty()

    @property
    def encoding(self) -> str:
        return getattr(self._stream, "encoding", None) or "utf-8"

    def __getattr__(self, name: str):
        if self._stream is None:
            raise AttributeError(name)
        return getattr(self._stream, name)


def _retrying(stream):
    """`stream`, or where its buffer is the raw file (PYTHONUNBUFFERED=1 or `python -u`, common
    in containers and CI) the same file through a BufferedWriter, flushed at each line. A raw
    file's write may take only part of the text (a disk that fills midway, a quota, a
    file-size limit: the next write is the one that fails) and TextIOWrapper neither retries
    nor reports the rest: the report was cut and the exit code 0. A BufferedWriter writes the
    rest and raises the error. Its own FileIO on the descriptor (not closing it) leaves the
    interpreter's stdout object untouched."""
    import io
    raw = getattr(stream, "buffer", None)
    if not isinstance(raw, io.RawIOBase):
        return stream
    try:
        fd = raw.fileno()
    except (OSError, ValueError):
        return stream
    return io.TextIOWrapper(io.BufferedWriter(io.FileIO(fd, "w", closefd=False)), encoding=stream.encoding,
                            errors=stream.errors, line_buffering=True)


def sink_for_closed_stderr() -> None:
    """A closed stderr (`2>&-`: Python's sys.stderr is None) made /dev/null: what linkcli writes
    there (error lines, the progress display, a library's warning) is dropped, as the README
    promises, instead of failing on None. File descriptor 2 is the lowest one free then, so
    opening /dev/null also gives the process (and its --jobs workers) a valid descriptor 2."""
    import sys
    if sys.stderr is not None:
        return
    try:
        sys.stderr = open(os.devnull, "w", encoding="utf-8")
    except OSError:  # nothing to open: the writers already tolerate None
        pass


def silence_stdout() -> None:
    """Point file descriptor 1 at /dev/null, so that what is still buffered for the lost
    output is dropped when Python flushes it at exit (not reported as an ignored error)."""
    try:
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 1)
        os.close(null)
    except OSError:
        pass


def exit_code(lost: OutputLost, report) -> int:
    """The exit code for a lost output (module docstring); `report(line)` writes the one
    line of a refused output to stderr."""
    silence_stdout()
    if lost.error.errno == errno.EPIPE:
        return BROKEN_PIPE_EXIT
    report(f"standard output: expected an output that takes the report, found "
           f"{lost.error.strerror or lost.error}")
    return 2


def refuses_files(folder) -> str | None:
    """Why `folder` (an existing folder) cannot take a new file, or None: a probe file is
    made and removed, which catches what permission bits do not show (a read-only file
    system, an ACL, root squash)."""
    import tempfile
    try:
        handle, probe = tempfile.mkstemp(prefix=".linkcli-probe-", dir=folder)
        os.close(handle)
        os.unlink(probe)
    except OSError as exc:
        return exc.strerror or str(exc)
    return None
