"""The one printed field that may differ between machines, masked for golden comparisons.

docs/determinism.md: only `solver.evaluations` (and `solver.seconds`,
printed with `--timing` only) may differ from one CPU, BLAS kernel or SIMD setting to
another. The golden files keep every other byte; that value is written as MASK there, and
an output is masked the same way before it is compared. Masking checks what it masks:
each `solver` section of the report must hold a whole-number count, and nothing else is
touched, so a missing, extra or malformed field still makes the comparison fail.
"""

from __future__ import annotations

import json
import re

MASK = "(machine-dependent)"
_JSON_LINE = re.compile(r'^(\s*"evaluations": )(\d+)(,?)$', re.MULTILINE)
_TABLE_LINE = re.compile(r"^(evaluations +)(\d+) *$")


def masked(text: str, fmt: str) -> str:
    """`text` (an output of `linkcli synth --format fmt`, fmt json or table) with the
    solver's evaluation count replaced by MASK."""
    return _masked_json(text) if fmt == "json" else _masked_table(text)


def _solver_counts(report) -> int:
    """How many `solver` sections with an evaluation count the report (or batch) holds."""
    reports = report if isinstance(report, list) else [report]
    count = 0
    for rep in reports:
        solver = rep.get("solver") if isinstance(rep, dict) else None
        if isinstance(solver, dict) and "evaluations" in solver:
            assert isinstance(solver["evaluations"], int) and solver["evaluations"] >= 1, solver
            count += 1
    return count


def _masked_json(text: str) -> str:
    expected = _solver_counts(json.loads(text))
    out, replaced = _JSON_LINE.subn(lambda m: f'{m.group(1)}"{MASK}"{m.group(3)}', text)
    assert replaced == expected, f"{replaced} evaluation lines for {expected} solver sections"
    return out


def _masked_table(text: str) -> str:
    """The `evaluations` row of the Solver table masked; that table's lines lose their
    trailing padding, whose width follows the widest cell, perhaps the count itself."""
    lines = text.split("\n")
    for i, line in enumerate(lines):
        match = _TABLE_LINE.match(line)
        if not match:
            continue
        width = len(line)
        lo = i
        while lo > 0 and len(lines[lo - 1]) == width:
            lo -= 1
        hi = i
        while hi + 1 < len(lines) and len(lines[hi + 1]) == width:
            hi += 1
        for k in range(lo, hi + 1):
            lines[k] = lines[k].rstrip()
        lines[i] = match.group(1) + MASK
    return "\n".join(lines)
