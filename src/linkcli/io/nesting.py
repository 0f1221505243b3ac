"""Keys nested too deep, refused before they cost anything.

A problem or result file nests a few levels (`forces.rows[i].pins.A0.x` is the deepest a
result holds: 6). A dotted key or a header of thousands of parts (`a.a.a...a = 1`) makes
tomllib's parse quadratic in time and memory (100,000 parts: gigabytes) and any recursive
walk of the data overflow Python's stack, so:

- `deep_key_line(masked)` finds, in the text with strings and comments masked (reader's
  `_mask`), a dotted key of more than MAX_DEPTH parts before tomllib sees it (only a key
  can be a dot-joined run of that many bare or quoted parts: a number has one dot);
- `too_deep(data)` walks the parsed data without recursion and gives the first path deeper
  than MAX_DEPTH (tables and arrays nested inline, a header's parts plus a key's); plain
  values are only looked at, their paths made only where they are too deep (an array of a
  million numbers is walked in a tenth of a second).
"""

from __future__ import annotations

import re

MAX_DEPTH = 32  # levels of tables and arrays a file may nest
# MAX_DEPTH + 1 dot-joined parts (masked strings are "xxx" or 'xxx'). Linear time: every
# quantifier is possessive (a part or a run of blanks, once read, is never given back), and
# a match begins only at the start of a run of bare-key characters (the lookbehind), so a
# run of n such characters (a long key, number, or string masked to "xxx...") is read O(1)
# times, not once per start and length (the backtracking regex took minutes on 4 MiB).
_KEY_CHARS = r"A-Za-z0-9_\-"
_PART = rf"""(?:[{_KEY_CHARS}]++|"x*+"|'x*+')"""
_FIRST = rf"""(?:(?<![{_KEY_CHARS}])[{_KEY_CHARS}]++|"x*+"|'x*+')"""
_DEEP_KEY = re.compile(rf"{_FIRST}(?:[ \t]*+\.[ \t]*+{_PART}){{{MAX_DEPTH}}}")
_BRACKET = re.compile(r"[\[\]{}]")


def deep_key_line(masked: str) -> int | None:
    """The 1-based line of the first dotted key of more than MAX_DEPTH parts, or None."""
    m = _DEEP_KEY.search(masked)
    return None if m is None else masked.count("\n", 0, m.start()) + 1


def deep_bracket_line(masked: str) -> int | None:
    """The 1-based line where arrays and inline tables (brackets and braces outside strings
    and comments) first nest more than MAX_DEPTH deep, or None: where tomllib's recursion
    gave up."""
    depth = 0
    for m in _BRACKET.finditer(masked):
        depth += 1 if m.group() in "[{" else -1
        if depth > MAX_DEPTH + 2:  # a header's own [[ ]] may add two
            return masked.count("\n", 0, m.start()) + 1
    return None


def too_deep(data) -> tuple[str, ...] | None:
    """The path (array items as `key[i]`) of the first value nested deeper than MAX_DEPTH
    tables and arrays in parsed TOML data, or None; no recursion, so any depth is safe."""
    stack = [((), data, 0)]
    while stack:
        path, node, depth = stack.pop()
        if depth > MAX_DEPTH:
            return path
        every = depth + 1 > MAX_DEPTH  # a plain value one level down is too deep as well
        if isinstance(node, dict):
            stack.extend(reversed([(path + (str(key),), value, depth + 1) for key, value in node.items()
                                   if every or isinstance(value, (dict, list))]))
        elif isinstance(node, list):  # reversed: popped in the order of the file
            head = path[-1] if path else ""
            stack.extend(reversed([(path[:-1] + (f"{head}[{i}]",), value, depth + 1)
                                   for i, value in enumerate(node) if every or isinstance(value, (dict, list))]))
    return None
