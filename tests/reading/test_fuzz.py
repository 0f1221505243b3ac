"""Fuzzed problem files: random mutations of every example must give exit 0, 1 or 2 with a
message, never a traceback, an internal error or a hang.

Mutations (seeded, so the cases are the same every run): delete a key, replace a value by
another type, NaN, inf, a negative, zero, a huge number, a huge array, a deep table, add an
unknown key. Optimizing types get a small `[solver] budget` so that the valid mutants solve
quickly; the point here is robustness, not accuracy.
"""

from __future__ import annotations

import random
import tomllib
from pathlib import Path

import pytest
import tomli_w
from conftest import ROOT

from linkcli.io.export import to_json, to_toml
from linkcli.pipeline import Request, run
from linkcli.report import render_text

pytestmark = pytest.mark.slow  # the mutation fuzz: the full suite runs them, the fast lane does not

EXAMPLES = sorted((ROOT / "problems").glob("*.toml"))
REPLACEMENTS = [
    "text", True, float("nan"), float("inf"), float("-inf"), -1.0, 0, 1e308, -1e308, 1e-308,
    [], [1.0] * 20000, {"x": {"y": {"z": 1}}}, [[1, 2], [3]], "__import__('os')", 2**63 - 1,
]
CASES_PER_FILE = 30


def _paths(node, prefix=()):
    if isinstance(node, dict):
        for k, v in node.items():
            yield prefix + (k,)
            yield from _paths(v, prefix + (k,))


def _set(data, path, value):
    node = data
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value


def _delete(data, path):
    node = data
    for k in path[:-1]:
        node = node[k]
    del node[path[-1]]


def mutants(example: Path):
    rng = random.Random(f"{example.name}")
    base = tomllib.loads(example.read_text())
    paths = [p for p in _paths(base) if p != ("solver",) and p[:2] != ("solver", "budget")]
    for i in range(CASES_PER_FILE):
        data = tomllib.loads(example.read_text())
        path = rng.choice(paths)
        kind = rng.random()
        if kind < 0.2:
            _delete(data, path)
            what = f"delete {'.'.join(path)}"
        elif kind < 0.3:
            _set(data, path[:-1] + (path[-1] + "_typo",), 1.0)
            what = f"unknown key near {'.'.join(path)}"
        else:
            value = rng.choice(REPLACEMENTS)
            _set(data, path, value)
            what = f"{'.'.join(path)} = {str(value)[:30]}"
        if data.get("type") in ("function-generation", "path-generation", "flipper-cylinder"):
            data.setdefault("solver", {})
            if isinstance(data["solver"], dict):
                data["solver"]["budget"] = 300
        yield i, what, data


CASES = [(ex, i, what, data) for ex in EXAMPLES for i, what, data in mutants(ex)]


@pytest.mark.parametrize("example,i,what,data", CASES,
                         ids=[f"{c[0].stem}-{c[1]}" for c in CASES])
def test_mutated_file_fails_cleanly(tmp_path, example, i, what, data):
    path = tmp_path / example.name
    try:
        path.write_text(tomli_w.dumps(data))
    except (TypeError, ValueError):  # tomli-w cannot write it (e.g. mixed array): skip
        pytest.skip("mutant is not writable as TOML")
    for mode in ("check", "synth"):
        outcome = run(str(path), Request(mode=mode))
        code, errors = outcome.exit_code, outcome.errors
        report = outcome.result.report if outcome.result is not None else None
        assert code in (0, 1, 2), (what, errors)
        assert not any("internal error" in e for e in errors), (what, errors)
        if code == 2:
            assert errors and all(e.startswith(str(path)) for e in errors), (what, errors)
        if mode == "check" and code == 2:
            break
        if report is not None:  # every output format renders what was solved
            render_text([report], 6)
            to_json(report, 6)
            to_toml(report, 6)


def test_garbage_bytes_and_empty_file(tmp_path):
    for name, content in (("empty.toml", b""), ("garbage.toml", bytes(range(256))),
                          ("deep.toml", b"a = " + b"[" * 5000 + b"]" * 5000)):
        p = tmp_path / name
        p.write_bytes(content)
        outcome = run(str(p), Request())
        code, errors = outcome.exit_code, outcome.errors
        assert code == 2 and errors and not any("internal error" in e for e in errors), errors


def _number_leaves(node, prefix=()):
    """Key paths of every number in parsed TOML (array elements as (key, index))."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _number_leaves(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _number_leaves(v, prefix + (i,))
    elif isinstance(node, (int, float)) and not isinstance(node, bool):
        yield prefix


HUGE = [(ex, path) for ex in EXAMPLES for path in _number_leaves(tomllib.loads(ex.read_text()))]


@pytest.mark.parametrize("example,path", HUGE, ids=[f"{e.stem}-{'.'.join(map(str, p))}" for e, p in HUGE])
def test_every_number_set_to_an_integer_beyond_double_range_is_a_located_bad_input(tmp_path, example, path):
    data = tomllib.loads(example.read_text())
    _set(data, path, -(10 ** 400) if len(path) % 2 else 10 ** 400)
    p = tmp_path / example.name
    p.write_text(tomli_w.dumps(data))
    key = ""  # an index follows the array it indexes: points[2], schemes[0].lengths
    for k in path:
        key += f"[{k}]" if isinstance(k, int) else (f".{k}" if key else str(k))
    for mode in ("check", "synth", "analyze"):
        outcome = run(str(p), Request(mode=mode))
        code, report, errors = outcome.exit_code, outcome.result, list(outcome.errors)
        assert code == 2 and report is None, (mode, errors)
        assert len(errors) == 1 and errors[0].startswith(f"{p}:"), errors
        assert errors[0].endswith(f": {key}: expected a finite number, found an integer of 401 digits"), errors


def test_special_files_and_escapes_fail_cleanly(tmp_path):
    import os
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    escapes = tmp_path / "escapes.toml"
    escapes.write_text('type = "linkage\\u001b[2J"\n"\\u001b[31mkey" = 1\n')
    for p in (fifo, Path("/dev/zero"), escapes):
        for mode in ("check", "synth", "analyze"):
            outcome = run(str(p), Request(mode=mode))
            code, errors = outcome.exit_code, list(outcome.errors)
            assert code == 2 and errors, (p, mode)
            assert not any("\x1b" in e or "internal error" in e for e in errors), errors
