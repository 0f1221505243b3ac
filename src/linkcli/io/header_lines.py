"""Lines for tables defined only implicitly by a deep header: `[a.b.c]` defines `a` and
`a.b` too, on no line of their own; they get the first line that names them in a header
or a dotted key, so that an error about `a` is located."""

from __future__ import annotations


def with_parent_lines(lines: dict[tuple[str, ...], int], ambiguous=()) -> dict[tuple[str, ...], int]:
    """`lines` plus every missing prefix of its paths, at the smallest line below it; a
    path in `ambiguous` (an array of tables: which element is not known) stays without."""
    parents: dict[tuple[str, ...], int] = {}
    for path, n in lines.items():
        for k in range(1, len(path)):
            prefix = path[:k]
            if prefix not in lines and prefix not in ambiguous and n < parents.get(prefix, n + 1):
                parents[prefix] = n
    return {**lines, **parents}
