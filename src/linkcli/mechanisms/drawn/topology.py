"""`[linkage] topology`: a six-bar that linkcli draws itself (docs/six_bars.md). Synthesis on a
drawn linkage starts from the file's drawing ([joints], [links], [drive]) or, with `topology`
and no drawing, from the starting drawings of the catalogue (drawn.catalogue). Pure Python
(`check` reads it without numpy).

    [linkage]
    mechanism = "drawn"
    topology = "stephenson-iii"     # watt-i | watt-ii | stephenson-i | stephenson-ii |
                                    # stephenson-iii | any six-bar
"""

from __future__ import annotations

import difflib
import re

from linkcli.io.reader import MISSING, Table

SIX_BARS = ("watt-i", "watt-ii", "stephenson-i", "stephenson-ii", "stephenson-iii")
ANY_SIX_BAR = "any six-bar"
TOPOLOGIES = SIX_BARS + (ANY_SIX_BAR,)
DRAWING = ("joints", "links", "drive")  # the tables of a drawing: none with a topology
ROMAN = {"1": "i", "2": "ii", "3": "iii"}


def read_topology(linkage: Table) -> str | None:
    """The `topology` of a [linkage] table: one of TOPOLOGIES, or None when absent or in
    error (every error recorded, one located line each: not a topology, with a "did you
    mean"; a drawing's tables given too)."""
    value = linkage.raw("topology")
    if value is MISSING:
        return None
    expected = f"one of: {', '.join(TOPOLOGIES)}"
    if not isinstance(value, str):
        linkage.error("topology", expected, value)
        return None
    if value not in TOPOLOGIES:
        linkage.error("topology", expected + _hint(value), value)
        return None
    root = linkage.reader.root()
    given = [name for name in DRAWING if name in root.data]
    if given:
        for name in given:
            root.raw(name)  # read: refused here, not also an unknown key
        first = min(given, key=lambda name: linkage.reader.line_of((name,)) or 0)
        tables = " and ".join(f"[{name}]" for name in given)
        root.error(first, f'no drawing with [linkage] topology = "{value}" (linkcli draws the starting '
                   "designs of the topology itself; to start from a drawing of your own, give "
                   "[joints], [links] and [drive] without topology)",
                   raw_got=f"{tables} as well")
        return None
    return value


def topologies(value: str) -> tuple[str, ...]:
    """The inversions a topology stands for ("any six-bar": all five, in catalogue order)."""
    return SIX_BARS if value == ANY_SIX_BAR else (value,)


def _hint(value: str) -> str:
    """' (did you mean "..."?)' for a near miss: written with digits, capitals, spaces or
    underscores ("Watt 2", "stephenson_III"), or close in spelling; a four-bar is its own
    mechanism."""
    word = value.strip().lower()
    if word.replace("_", "-").replace(" ", "-") in ("four-bar", "fourbar", "4-bar"):
        return ' (a four-bar is mechanism = "four-bar"; it is the baseline of every topology table)'
    word = re.sub(r"[\s_]+", "-", word)
    word = re.sub(r"(?<=[a-z])-?([123])$", lambda m: "-" + ROMAN[m.group(1)], word)
    word = re.sub(r"(?<=[a-z])(i{1,3})$", r"-\1", word) if "-" not in word else word
    word = word.replace("stevenson", "stephenson")
    if word in TOPOLOGIES:
        return f' (did you mean "{word}"?)'
    if word.replace("-", "") in ("anysixbar", "any", "all", "sixbar", "anysix-bar"):
        return f' (did you mean "{ANY_SIX_BAR}"?)'
    close = difflib.get_close_matches(word, TOPOLOGIES, n=1, cutoff=0.75)
    return f' (did you mean "{close[0]}"?)' if close else ""
