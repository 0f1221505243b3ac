"""Read a problem file safely: regular files only, at most MAX_FILE_BYTES.

A FIFO, a terminal or a device (`/dev/zero`) would block or never end, and a huge file
would fill memory; a problem file is a few kilobytes of TOML, so 4 MiB is a generous cap.
The file is stat-ed before it is opened, opened with O_NONBLOCK (so that a FIFO swapped
in after the stat cannot block the open) and stat-ed again through its descriptor; the
read asks for one byte more than the cap, so a file that grew after the stat is caught.
"""

from __future__ import annotations

import os
import stat

from linkcli.errors import InputError

MAX_FILE_BYTES = 4 * 1024 * 1024  # 4 MiB: far above any problem or result file


def _kind(mode: int) -> str:
    """The name of a non-regular file type, for the message."""
    for test, name in ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "a special file"


def _check(path: str, info: os.stat_result) -> None:
    if not stat.S_ISREG(info.st_mode):
        raise InputError("a regular problem file", _kind(info.st_mode), path=path)
    if info.st_size > MAX_FILE_BYTES:
        raise InputError(f"a problem file of at most {MAX_FILE_BYTES} bytes (4 MiB)",
                         f"{info.st_size} bytes", path=path)


def read_problem_bytes(path: str) -> bytes:
    """The bytes of a regular file of at most MAX_FILE_BYTES; InputError (exit 2) otherwise."""
    if not path:  # `linkcli synth ""`: not the current folder
        raise InputError("a problem file name", "an empty argument", path='""')
    try:
        _check(path, os.stat(path))
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    except OSError as exc:
        raise InputError("a readable problem file", exc.strerror or str(exc), path=path) from None
    try:
        _check(path, os.fstat(fd))
        chunks, size = [], 0
        while size <= MAX_FILE_BYTES:
            chunk = os.read(fd, MAX_FILE_BYTES + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    except OSError as exc:
        raise InputError("a readable problem file", exc.strerror or str(exc), path=path) from None
    finally:
        os.close(fd)
    if size > MAX_FILE_BYTES:
        raise InputError(f"a problem file of at most {MAX_FILE_BYTES} bytes (4 MiB)",
                         "a file that grew beyond it while read", path=path)
    return b"".join(chunks)
