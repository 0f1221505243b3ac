"""Hostile files, third round (issue 28): many keys checked in linear time, keys nested
without end, an unreadable file in a batch, an empty file name, and the wording of what
was found. Every case: exit 2, one located line per problem, bounded time and memory.

The inputs differ from the issue's reproductions on purpose: each test holds a kind
(every way of writing many keys, every way of nesting deep), not an example."""

from __future__ import annotations

import functools
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from conftest import ROOT, run_cli

SRC = str(ROOT / "src")
LINKAGE = ('type = "linkage"\n[linkage]\nground = 50\ninput = 20\ncoupler = 60\noutput = 45\n'
           'branch = "open"\n[motion]\ninput_speed = 10\nsteps = 36\n')


def _cli(*args: str, timeout: float = 120, prefix: tuple[str, ...] = (), cwd=ROOT):
    """linkcli in a subprocess: (exit code, stdout, stderr); a hang fails through the timeout."""
    env = dict(os.environ, PYTHONPATH=SRC)
    done = subprocess.run([*prefix, sys.executable, "-m", "linkcli", *args], capture_output=True,
                          text=True, timeout=timeout, env=env, cwd=cwd)
    return done.returncode, done.stdout, done.stderr


# -- many keys: linear in the file's size --------------------------------------------

def _fill(head: str, line, limit: int) -> tuple[str, int]:
    """`head` then line(0), line(1), ... while the text stays within `limit` bytes."""
    parts, size, n = [head], len(head), 0
    while True:
        text = line(n)
        if size + len(text) > limit:
            return "".join(parts), n
        parts.append(text)
        size += len(text)
        n += 1


MANY_KEYS = {  # every way of writing many keys or tables that the reader reports on
    "top-level keys": ('type = "linkage"\n', lambda n: f"k{n} = 1\n"),
    "quoted top-level keys": ('type = "linkage"\n', lambda n: f'"k {n}" = 1\n'),
    "empty tables": ('type = "linkage"\n', lambda n: f"[t{n}]\n"),
    "keys in a known table": (LINKAGE + "[units]\n", lambda n: f"k{n} = 1\n"),
    "tables in a known table": (LINKAGE, lambda n: f"[motion.t{n}]\n"),
    "dotted keys": ('type = "linkage"\n', lambda n: f"linkage.k{n} = 1\n"),
}


@pytest.mark.slow
@pytest.mark.parametrize("form", MANY_KEYS)
def test_a_mebibyte_of_keys_is_checked_in_linear_time(form):
    """A guard against quadratic checking, not a speed test: a mebibyte of keys (75,000 to
    120,000 of them) takes one to two seconds when the work per key is constant (ten on
    a loaded 2-core machine); the quadratic reader of issue 28 (the set of known keys
    rebuilt per unknown key: 20,000 keys 12 to 30 s) would need 5 to 20 minutes, and
    fails through the subprocess timeout of 2 minutes."""
    head, line = MANY_KEYS[form]
    text, n = _fill(head, line, 1024 * 1024)
    folder = Path(tempfile.mkdtemp())
    try:
        (folder / "many.toml").write_text(text)
        code, out, err = _cli("check", str(folder / "many.toml"), timeout=120)
    finally:
        shutil.rmtree(folder)
    from linkcli.errors import MAX_LISTED
    lines = err.splitlines()
    assert code == 2 and out == ""
    assert len(lines) == MAX_LISTED + 1, lines[-3:]  # the first 100, then one counting the rest
    assert lines[0].startswith(f"{folder / 'many.toml'}:") and "unknown key" in "".join(lines[:5])
    assert lines[-1].startswith(f"{folder / 'many.toml'}: expected at most {MAX_LISTED} errors "
                                "listed per file, found ")
    assert int(lines[-1].split("found ")[1].split()[0]) >= n - MAX_LISTED


def test_the_hint_of_an_unknown_key_is_worked_out_only_for_the_lines_listed(monkeypatch, tmp_path):
    # the "did you mean" (difflib) is the costly part of an unknown key's line: it is
    # computed for the lines shown, never for each of the 30,000 keys
    import difflib
    calls = []
    real = difflib.get_close_matches
    monkeypatch.setattr(difflib, "get_close_matches", lambda *a, **k: calls.append(a[0]) or real(*a, **k))
    target = tmp_path / "keys.toml"
    target.write_text(LINKAGE + "".join(f"[units.u{n}]\nk{n} = 1\n" for n in range(15_000)))
    code, out, err = run_cli("check", str(target))
    from linkcli.errors import MAX_LISTED
    assert code == 2
    assert len(err.splitlines()) == MAX_LISTED + 1
    assert len(calls) <= MAX_LISTED


def test_errors_are_listed_in_line_order_before_the_count(tmp_path):
    # a bad value above 150 unknown keys (read by the schema before the keys are known to
    # be unknown): the first 100 errors by line, then the count of the other 51
    target = tmp_path / "mixed.toml"
    target.write_text(LINKAGE.replace("ground = 50", "ground = -1") + "".join(f"x{n} = 1\n" for n in range(150)))
    code, out, err = run_cli("check", str(target))
    lines = err.splitlines()
    assert code == 2 and len(lines) == 101
    assert lines[0].startswith(f"{target}:3: linkage.ground: expected a positive length")
    assert lines[1].startswith(f"{target}:11: motion.x0: expected a known key")
    assert lines[99].startswith(f"{target}:109: motion.x98: expected a known key")
    assert lines[100] == f"{target}: expected at most 100 errors listed per file, found 51 more (fix these and run again)"


# -- keys nested without end ------------------------------------------------------------

def _dotted(parts: int, name: str = "a") -> str:
    return ".".join([name] * parts)


DEEP = {  # text after `type = ...`, the line of the error, the message's expected
    "a dotted key of 33 parts": (f"{_dotted(33)} = 1\n", 2, "dotted keys of at most 32 parts"),
    "a dotted key of 100,000 parts": (f"{_dotted(100_000, 'bb')} = 1\n", 2, "dotted keys of at most 32 parts"),
    "a table header of 500 parts": (f"\n[{_dotted(500)}]\n", 3, "dotted keys of at most 32 parts"),
    "an array-of-tables header of 5000 parts": (f"[[{_dotted(5000)}]]\nx = 1\n", 2,
                                                "dotted keys of at most 32 parts"),
    "quoted parts": ('x.' + '.'.join(['"q.r"'] * 40) + " = 1\n", 2, "dotted keys of at most 32 parts"),
    "a dotted key inside an inline table": ("x = { " + _dotted(40) + " = 1 }\n", 2,
                                            "dotted keys of at most 32 parts"),
    "a header of 20 parts and a key of 20": (f"[{_dotted(20)}]\n\n{_dotted(20)} = 1\n", 4,
                                             "tables and arrays nested at most 32 levels deep"),
    "inline tables 40 deep": ("x = " + "{a = " * 40 + "1" + "}" * 40 + "\n", 2,
                              "tables and arrays nested at most 32 levels deep"),
    # the line where the brackets pass 34 (a header's own [[ ]] may add two to the 32)
    "arrays 2000 deep over many lines": ("\nx = [\n" + "[\n" * 2000 + "1" + "]\n" * 2000 + "]\n", 37,
                                         "tables and arrays nested at most 32 levels deep"),
}


@pytest.mark.parametrize("case", DEEP)
def test_keys_and_values_nested_too_deep_are_one_located_line(case, tmp_path):
    body, line, expected = DEEP[case]
    target = tmp_path / "deep.toml"
    target.write_text('type = "linkage"\n' + body)
    code, out, err = _cli("check", str(target), timeout=60)
    assert code == 2 and out == ""
    assert len(err.splitlines()) == 1, err
    assert err.startswith(f"{target}:{line}: ") and f"expected {expected}, found " in err, err
    assert len(err) < 400


def test_a_key_32_deep_is_read():
    from linkcli.io.reader import Reader
    reader = Reader("deep.toml", _dotted(32) + " = 1\n" + "y = " + "[" * 31 + "1" + "]" * 31 + "\n")
    node = reader.data
    for _ in range(32):
        node = node["a"]
    assert node == 1


LONG_RUNS = {  # masked text with a 4 MiB run of bare-key characters, and where the deep key is
    "a string (masked to x)": ('title = "' + "x" * 4_000_000 + '"\n', None),
    "a bare key": ("k" * 4_000_000 + " = 1\n", None),
    "an integer": ("x = " + "1" * 4_000_000 + "\n", None),
    "a 32-part key with a long last part": ("a." * 31 + "b" * 4_000_000 + " = 1\n", None),
    "a 33-part key after a long string": ('t = "' + "x" * 4_000_000 + '"\n' + _dotted(33) + " = 1\n", 2),
    "a 33-part key whose first part is long": ("\n" + "k" * 4_000_000 + "." + _dotted(32) + " = 1\n", 2),
}


@pytest.mark.parametrize("case", LONG_RUNS)
def test_the_deep_key_scan_reads_a_long_run_of_key_characters_once(case):
    # the scan runs before tomllib on every file: the backtracking regex of the probe took
    # 16 s on a 40,000-character title and hours on the 4 MiB a file may hold (each start in
    # the run read the rest of it); the linear one reads these 4 MiB in a fraction of a second
    from linkcli.io.nesting import deep_key_line
    masked, line = LONG_RUNS[case]
    assert deep_key_line(masked) == line


# -- an integer beyond Python's digit limit keeps its key --------------------------------

@pytest.mark.parametrize("where, line, key", [
    ("[motion]\ninput_speed = 10\nsteps = {digits}\n", 4, "motion.steps"),
    ("[positions]\ninput = [\n  45,\n  {digits},\n]\n", 5, "positions.input"),
    ("[solver]\nseed = 1\n[bounds]\nlimits = {{ lo = 1, hi = {digits} }}\n", 5, "bounds.limits"),
])
def test_an_integer_of_thousands_of_digits_keeps_its_key_path(tmp_path, where, line, key):
    target = tmp_path / "digits.toml"
    target.write_text('type = "linkage"\n' + where.format(digits="7" * 6000))
    code, out, err = run_cli("check", str(target))
    assert code == 2
    assert err == (f"{target}:{line}: {key}: expected a finite number, found an integer of more "
                   f"than {sys.get_int_max_str_digits()} digits\n")


# -- file names: unreadable, empty -----------------------------------------------------

@functools.cache  # one probe of the other user per session, not one per test
def _as_another_user() -> tuple[str, ...] | None:
    """A command prefix that runs as a user without root's rights to read any file (None
    when there is none): the current user when not root, else `setpriv` to nobody."""
    if os.geteuid() != 0:
        return ()
    if shutil.which("setpriv") is None:
        return None
    prefix = ("setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups")
    # nobody must be able to run this Python with linkcli's dependencies (an interpreter or a
    # virtual environment under /root is not readable to nobody: then there is no such user)
    probe = subprocess.run([*prefix, sys.executable, "-c", "import typer, numpy, linkcli.cli"],
                           capture_output=True, cwd="/", env=dict(os.environ, PYTHONPATH=SRC), timeout=120)
    return prefix if probe.returncode == 0 else None


@pytest.mark.parametrize("command", ["synth", "check", "analyze"])
def test_an_unreadable_file_takes_its_slot_in_the_batch(command):
    prefix = _as_another_user()
    if prefix is None:
        pytest.skip("running as root without setpriv, or nobody cannot run this Python: every file is readable")
    folder = Path(tempfile.mkdtemp())  # not pytest's tmp_path: another user must enter it
    try:
        folder.chmod(0o755)
        source = ROOT / "problems" / ("firedoor_motion.toml" if command == "analyze" else "firedoor.toml")
        good, locked = folder / "good.toml", folder / "locked.toml"
        for target in (good, locked):
            shutil.copy(source, target)
        good.chmod(0o644)
        locked.chmod(0o000)
        code, out, err = _cli(command, str(locked), str(good), prefix=prefix, cwd=folder)
    finally:
        shutil.rmtree(folder)
    assert code == 2, err
    lines = err.splitlines()
    assert lines[0] == f"{locked}: expected a readable problem file, found Permission denied"
    assert "Usage" not in err
    if command == "check":
        assert out == f"{good}: ok\n"
    else:
        assert lines[-1] == "2 files: 1 solved, 0 infeasible or not converged, 1 bad input"
        assert "Fire-door closer" in out


def test_an_empty_file_name_is_named_as_such():
    code, out, err = run_cli("check", "", "problems/firedoor.toml")
    assert code == 2
    assert err == '"": expected a problem file name, found an empty argument\n'
    assert out == "problems/firedoor.toml: ok\n"


def test_a_file_name_is_kept_as_typed():
    code, out, err = run_cli("synth", "./problems//firedoor.toml", "--format", "json")
    assert code == 0
    assert '"file": "./problems//firedoor.toml"' in out


# -- what was found, in words -------------------------------------------------------------

def test_a_positive_number_with_an_upper_bound_has_an_open_range_at_zero():
    from linkcli.io.reader import NumberRule
    assert NumberRule(positive=True, hi=1e9, what="a positive length").expected == \
        "a positive length in (0, 1000000000]"
    assert NumberRule(nonnegative=True, hi=5).expected == "a number >= 0 in [0, 5]"
    assert NumberRule(positive=True, lo=2, hi=5).expected == "a positive number in [2, 5]"
    assert NumberRule(lo=-1, hi=1).expected == "a number in [-1, 1]"


@pytest.mark.parametrize("value, shown", [
    ("[5, -inf]", "an array of 2: [5, -inf]"),
    ("[nan, 0]", "an array of 2: [nan, 0]"),
    ("[1, 2, 3]", "an array of 3: [1, 2, 3]"),
    ("[]", "an array of 0"),
    ("[" + ", ".join(["1.5"] * 40) + "]", "an array of 40"),
])
def test_a_short_array_is_shown_in_what_was_found(tmp_path, value, shown):
    target = tmp_path / "force.toml"
    target.write_text(LINKAGE.replace("ground = 50", "ground = 50\ncoupler_point = [10, 5]")
                      + f"[loads]\ncoupler_force = {value}\n")
    code, out, err = run_cli("check", str(target))
    assert code == 2
    assert err == (f"{target}:13: loads.coupler_force: expected a force [Fx, Fy] of two finite "
                   f"numbers (N), found {shown}\n")


# -- sizes: a result any file can hold ------------------------------------------------------

def test_path_targets_near_the_size_limit_give_a_result_analyze_reads(tmp_path):
    # targets 1.9e9 apart: the default bounds (5 times the targets' extent) are kept within
    # the sizes a file accepts, so the linkage found is one `analyze` reads back (before:
    # lengths of 5.2e9, coordinates of 5.5e9, refused by analyze)
    problem = tmp_path / "far.toml"
    problem.write_text('type = "path-generation"\n[target]\n'
                       'points = [[-9.5e8, 2e8], [-3e8, 9.8e8], [5e8, 8e8], [9.7e8, -6e8]]\ntiming = "free"\n'
                       '[solver]\nbudget = 40000\n')
    code, out, err = run_cli("synth", str(problem), "--format", "toml")
    assert code in (0, 1), err
    result = tmp_path / "far_result.toml"
    result.write_text(out)
    import tomllib
    lk = tomllib.loads(out)["linkage"]
    assert max(lk[k] for k in ("ground", "input", "coupler", "output")) <= 1e9
    assert max(abs(v) for v in lk["coupler_point"] + lk["ground_pivot"]) <= 1e9
    code, out, err = run_cli("analyze", str(result))
    assert code in (0, 1) and err == "", err


def test_a_motion_search_near_the_size_limit_stays_within_it(tmp_path):
    problem = tmp_path / "far.toml"
    problem.write_text('type = "motion-generation"\n[target]\nposes = [[-6e8, -5e8, 20], [7e8, 6e8, 65]]\n')
    code, out, err = run_cli("synth", str(problem), "--format", "toml")
    assert code in (0, 1), err
    result = tmp_path / "result.toml"
    result.write_text(out)
    code, out, err = run_cli("analyze", str(result))
    assert code in (0, 1) and err == "", err


def test_a_solved_linkage_beyond_the_sizes_is_refused_as_input(tmp_path):
    problem = tmp_path / "huge.toml"  # the closed form gives a connecting rod of 1.76e9 mm
    problem.write_text('type = "quick-return"\nmechanism = "slider-crank"\ntime_ratio = 1.25\nstroke = 1e9\n'
                       '[linkage]\noffset = 1e9\n')
    code, out, err = run_cli("synth", str(problem))
    assert code == 2 and out == ""
    assert err.startswith(f"{problem}: linkage: expected data whose linkage fits the sizes a file accepts "
                          "(lengths and coordinates at most 1e+09 mm: give the problem in a larger length "
                          "unit), found a linkage with coupler 1.")
    assert len(err.splitlines()) == 1


# -- options refused before any solve -----------------------------------------------------

@pytest.mark.parametrize("option", ["--out", "--plot"])
def test_an_unwritable_folder_is_refused_before_solving(option):
    prefix = _as_another_user()
    if prefix is None:
        pytest.skip("running as root without setpriv, or nobody cannot run this Python: every folder is writable")
    folder = Path(tempfile.mkdtemp())
    try:
        folder.chmod(0o755)
        locked = folder / "locked"
        locked.mkdir()
        locked.chmod(0o555)
        shutil.copy(ROOT / "problems" / "firedoor.toml", folder / "a.toml")
        (folder / "a.toml").chmod(0o644)
        target = str(locked) if option == "--out" else str(locked / "a.png")
        code, out, err = _cli("synth", str(folder / "a.toml"), option, target, prefix=prefix, cwd=folder)
    finally:
        shutil.rmtree(folder)
    assert code == 2 and out == ""  # nothing solved, nothing printed
    assert err.count("\n") == 1 and "can be written, found" in err and "Permission denied" in err


@pytest.mark.parametrize("fmt", ["table", "json", "toml"])
def test_table_without_csv_is_refused(fmt):
    code, out, err = run_cli("synth", "problems/firedoor.toml", "--format", fmt, "--table", "positions")
    assert code == 2 and out == ""
    assert err == f"--table: expected --format csv with it (the row table to write), found --format {fmt}\n"


# -- round-off prints as 0 ----------------------------------------------------------------------

def test_a_pivot_on_a_zero_bound_prints_zero_in_the_trade_off(tmp_path):
    problem = tmp_path / "flip.toml"
    text = open(ROOT / "problems" / "flipper.toml").read().replace("[objective]", "[objective]\npareto = 5")
    import re
    text = re.sub(r"^base_pivot\s*=.*$", "base_pivot = { x = [400, 1400], y = [-50, 0] }", text, flags=re.M)
    problem.write_text(text)
    code, out, err = run_cli("synth", str(problem), "--format", "json")
    import json
    report = json.loads(out)
    values = [v for row in report["pareto"] for v in row["rod_pivot"] + row["base_pivot"]]
    values += [v for v in report["cylinder"]["rod_pivot"] + report["cylinder"]["base_pivot"]]
    size = max(abs(v) for v in values)
    assert all(v == 0 or abs(v) > 1e-9 * size for v in values), values  # no round-off of 0 printed
    assert any(row["base_pivot"][1] == 0 for row in report["pareto"])
