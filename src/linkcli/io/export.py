"""JSON and TOML writers with deterministic rounding to N significant digits.

`rounded(report, digits)` is the single rule numbers are rounded by: floats to `digits`
significant digits, numbers inside messages and notes likewise (linkcli.textnum), -0.0 to
0.0, non-finite to None (JSON null; left out of TOML, which has no null). Same report, same
bytes. `result_stems` names the files written per result (--out and --plot).

JSON scales with the rows of a report (100,000 kinematics or load rows): `write_json`
rounds at the leaves as it writes (no rounded copy of the report) and hands every
container that holds only numbers, strings, booleans and nulls -- a row, a pin's force, a
point -- to the json module's C encoder, with the separators of its depth, so that the
bytes are exactly those of `json.dumps(rounded(report, digits), indent=2,
ensure_ascii=False)` (tests/io/test_export.py holds them against that reference); only the
few containers that hold containers are walked in Python. The text is written in pieces
as it is made.
"""

from __future__ import annotations

import math
from functools import cache
from pathlib import PurePath

from linkcli.textnum import render

_CONTAINERS = (dict, list, tuple)


def round_sig(x: float, digits: int) -> float | None:
    """x to `digits` significant digits; None when x is not finite, or when its rounding
    is not (1.5e308 to one digit is 2e308)."""
    if not math.isfinite(x):
        return None
    if x == 0.0:
        return 0.0
    value = float(f"{x:.{digits}g}") + 0.0
    return value if math.isfinite(value) else None


def rounded_leaf(obj, digits: int):
    """One value that is not a container, rounded: a float to `digits` significant
    digits (None if not finite), a string's wrapped numbers likewise, a numpy scalar as
    its Python value; booleans, integers and None unchanged."""
    kind = type(obj)
    if kind is float:
        return round_sig(obj, digits)
    if kind is str:
        return render(obj, digits)  # numbers inside messages and notes follow the precision
    if obj is None or kind is bool or kind is int:
        return obj
    if isinstance(obj, str):
        return render(str(obj), digits)
    if isinstance(obj, (bool, int)):
        return obj
    if hasattr(obj, "item"):  # numpy scalar
        return rounded(obj.item(), digits)
    return round_sig(float(obj), digits)


def rounded(obj, digits: int):
    """A deep copy of a report with every float rounded (numpy scalars become Python); a
    list subclass that says how it was cut (report.Elided) keeps its class."""
    if isinstance(obj, dict):
        return {str(k): rounded(v, digits) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        items = [rounded(v, digits) if isinstance(v, _CONTAINERS) else rounded_leaf(v, digits) for v in obj]
        return obj.like(items) if hasattr(obj, "like") else items
    return rounded_leaf(obj, digits)


@cache
def _flat_encoder(level: int):
    """The json module's encoder (C when available) for a container at indent `level`
    holding no container: its items separated as `indent=2` separates them at that depth."""
    import json  # here: the table view (linkcli.report) uses this module for `rounded` alone
    separator = ",\n" + "  " * (level + 1)
    encoder = json.JSONEncoder(ensure_ascii=False, check_circular=False, separators=(separator, ": "))
    make = getattr(json.encoder, "c_make_encoder", None)
    if make is None:  # no C accelerator (another Python implementation): the same bytes, slower
        return encoder.encode
    iterencode = make(None, encoder.default, json.encoder.encode_basestring, None, ": ", separator,
                      False, False, True)
    return lambda obj: "".join(iterencode(obj, 0))


def _json(obj, digits: int, level: int, out: list, flush=None) -> None:
    """Append the text of `json.dumps(rounded(obj, digits), indent=2, ensure_ascii=False)`
    (at indent `level`) to `out`, in pieces (module docstring); `flush()`, when given, is
    called between the items of a long array, so the caller can write what `out` holds."""
    if not isinstance(obj, _CONTAINERS):
        out.append(_flat_encoder(level)(rounded_leaf(obj, digits)))
        return
    is_dict = isinstance(obj, dict)
    if not obj:
        out.append("{}" if is_dict else "[]")
        return
    values = obj.values() if is_dict else obj
    inner, outer = "  " * (level + 1), "  " * level
    if not any(isinstance(v, _CONTAINERS) for v in values):
        # round_sig inlined for the common float (false for nan, inf and the few whose
        # rounding could overflow); "%g" of -0.0 is "-0", and + 0.0 makes it 0.0
        fmt = f".{digits}g"
        if is_dict:
            flat = {k if type(k) is str else str(k):
                    float(format(v, fmt)) + 0.0 if type(v) is float and -1e308 < v < 1e308
                    else rounded_leaf(v, digits) for k, v in obj.items()}
        else:
            flat = [float(format(v, fmt)) + 0.0 if type(v) is float and -1e308 < v < 1e308
                    else rounded_leaf(v, digits) for v in obj]
        text = _flat_encoder(level)(flat)
        out.append(("{\n" if is_dict else "[\n") + inner + text[1:-1] + "\n" + outer + ("}" if is_dict else "]"))
        return
    out.append("{" if is_dict else "[")
    first = True
    if is_dict:
        from json.encoder import encode_basestring
        for key, value in obj.items():
            out.append(("\n" if first else ",\n") + inner + encode_basestring(str(key)) + ": ")
            first = False
            _json(value, digits, level + 1, out, flush)
    else:
        for value in obj:
            out.append(("\n" if first else ",\n") + inner)
            first = False
            _json(value, digits, level + 1, out, flush)
            if flush is not None and len(out) >= FLUSH_PIECES:
                flush()
    out.append("\n" + outer + ("}" if is_dict else "]"))


FLUSH_PIECES = 4096  # write_json writes after about this many pieces


def to_json(reports, digits: int) -> str:
    out: list[str] = []
    _json(reports, digits, 0, out)
    out.append("\n")
    return "".join(out)


def write_json(reports, digits: int, file) -> None:
    """`to_json(reports, digits)` written to `file` as it is made, a few thousand pieces
    (some 100 KB) a write: the whole text is never held (100,000 rows are 50 MB of it)."""
    out: list[str] = []

    def flush() -> None:
        file.write("".join(out))
        out.clear()

    _json(reports, digits, 0, out, flush)
    out.append("\n")
    flush()


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
