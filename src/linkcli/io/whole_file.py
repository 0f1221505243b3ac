"""A file written whole or not at all: the text goes to a temporary file beside the target,
renamed over it once complete (os.replace is atomic on one file system). A write that fails
midway -- a full disk, a quota, a file-size limit -- leaves no partial file behind, and an
existing file is replaced whole or kept. Used for `--out` result files; plot.write_bytes
does the same for pictures, animations and drawings."""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Iterator
from typing import IO


def _umask() -> int:
    """The process's umask (set and set back): the file gets the mode a plain open gives."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def whole_text_file(target, newline: str | None = None) -> Iterator[IO[str]]:
    """A UTF-8 text handle whose content becomes `target` when the block ends without an
    error; on any error the temporary file is removed and the error goes on (an OSError
    is the caller's to word)."""
    target = os.fspath(target)
    folder, name = os.path.split(target)
    handle, temporary = tempfile.mkstemp(prefix=f".{name}.", suffix=".part", dir=folder or ".")
    try:
        with os.fdopen(handle, "w", encoding="utf-8", newline=newline) as stream:
            yield stream
        os.chmod(temporary, 0o666 & ~_umask())
        os.replace(temporary, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        raise
