"""Integers beyond the range of a double, found once in a parsed TOML document.

TOML integers are unbounded in tomllib, but every number linkcli uses becomes a float,
and `float(10**400)` raises OverflowError. `huge_integers(data)` walks the parsed data
once and yields (key path, digits) for every integer with |n| > sys.float_info.max, so
the reader can refuse them as located input errors before any parser converts them.
"""

from __future__ import annotations

import sys
from collections.abc import Iterator

_LIMIT = int(sys.float_info.max)


def _digits(n: int) -> int:
    return len(str(abs(n))) if abs(n).bit_length() < 14_000 else int(abs(n).bit_length() * 0.30103) + 1


def _huge(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and abs(value) > _LIMIT


def huge_integers(node, path: tuple[str, ...] = ()) -> Iterator[tuple[tuple[str, ...], int]]:
    """(key path, number of decimal digits) of each integer too large for a float; an
    array element's path ends in `key[i]`. A plain value is only looked at (its path made
    where it is huge): a million numbers take a tenth of a second."""
    if isinstance(node, dict):
        for key, value in node.items():
            if isinstance(value, (dict, list)):
                yield from huge_integers(value, path + (key,))
            elif _huge(value):
                yield path + (key,), _digits(value)
    elif isinstance(node, list):
        head = path[-1] if path else ""
        for i, value in enumerate(node):
            if isinstance(value, (dict, list)):
                yield from huge_integers(value, path[:-1] + (f"{head}[{i}]",))
            elif _huge(value):
                yield path[:-1] + (f"{head}[{i}]",), _digits(value)
    elif _huge(node):
        yield path, _digits(node)


def refuse_huge_integers(reader) -> None:
    """Raise InputErrors (exit 2) with one located line per huge integer of the reader's
    data: `FILE:LINE: key: expected a finite number, found an integer of N digits`."""
    for path, digits in huge_integers(reader.data):
        reader.error(path, "a finite number", raw_got=f"an integer of {digits} digits")
    if reader.errors:
        from linkcli.errors import InputErrors
        raise InputErrors(reader.errors)


def too_many_digits(path: str, text: str):
    """The error for an integer that tomllib cannot even convert (more digits than Python's
    int-string limit, 4300 by default: it raises ValueError), located at its first line."""
    from linkcli.errors import TomlSyntaxError
    limit = sys.get_int_max_str_digits() if hasattr(sys, "get_int_max_str_digits") else 4300
    import re
    m = re.search(r"[0-9_]{%d,}" % (limit + 1), text)
    line = text.count("\n", 0, m.start()) + 1 if m else None
    return TomlSyntaxError("a finite number", f"an integer of more than {limit} digits", path=path, line=line)
