"""JSON and TOML writers with deterministic rounding to N significant digits.

`rounded(report, digits)` is the single place numbers are rounded: floats to `digits`
significant digits, numbers inside messages and notes likewise (linkcli.textnum), -0.0 to 0.0, non-finite to None (JSON null; left out of TOML, which
has no null). Same report, same bytes. `result_stems` names the files written per
result (--out and --plot).
"""

from __future__ import annotations

import json
import math
from pathlib import PurePath

from linkcli.textnum import render


def round_sig(x: float, digits: int) -> float | None:
    if not math.isfinite(x):
        return None
    if x == 0.0:
        return 0.0
    return float(f"{x:.{digits}g}") + 0.0


def rounded(obj, digits: int):
    """A deep copy of a report with every float rounded (numpy scalars become Python)."""
    if isinstance(obj, dict):
        return {str(k): rounded(v, digits) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [rounded(v, digits) for v in obj]
    if isinstance(obj, str):
        return render(obj, digits)  # numbers inside messages and notes follow the precision
    if isinstance(obj, bool) or obj is None:
        return obj
    if isinstance(obj, int):
        return obj
    if hasattr(obj, "item"):  # numpy scalar
        return rounded(obj.item(), digits)
    return round_sig(float(obj), digits)


def to_json(reports, digits: int) -> str:
    return json.dumps(rounded(reports, digits), indent=2, ensure_ascii=False) + "\n"


def _drop_none(obj):
    if isinstance(obj, dict):
        return {k: _drop_none(v) for k, v in obj.items() if v is not None}
    if isinstance(obj, list):
        return [_drop_none(v) for v in obj if v is not None]
    return obj


def to_toml(report: dict, digits: int) -> str:
    import tomli_w
    return tomli_w.dumps(_drop_none(rounded(report, digits)))


def to_toml_many(reports: list[dict], digits: int) -> str:
    """Several reports in one TOML document: an array of tables `[[result]]`."""
    import tomli_w
    if len(reports) == 1:
        return to_toml(reports[0], digits)
    return tomli_w.dumps({"result": [_drop_none(rounded(r, digits)) for r in reports]})


def result_stems(files: list[str]) -> list[str]:
    """One output name per result, in argument order: the file's stem, with _2, _3, ...
    added to a stem already taken (a/firedoor.toml and b/firedoor.toml -> firedoor,
    firedoor_2), so no result overwrites another: the names of --out files and --plot pictures."""
    taken: set[str] = set()
    stems = []
    for f in files:
        stem, k = PurePath(f).stem, 1
        name = stem
        while name in taken:
            k += 1
            name = f"{stem}_{k}"
        taken.add(name)
        stems.append(name)
    return stems
