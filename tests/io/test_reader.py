"""The problem-file reader: line numbers of keys (never inside a string or a comment),
a UTF-8 byte-order mark, one line per error, and the checks that need the whole file
([tolerance] and [report], batch result files).

The expected lines are counted here by hand from the text of each case, or found by
searching the raw text for a unique marker; never taken from the reader itself.
"""

from __future__ import annotations

import json
import string
import tomllib

import pytest
import tomli_w
from conftest import ROOT, run_cli
from hypothesis import given, settings
from hypothesis import strategies as st

from linkcli.errors import InputError, InputErrors
from linkcli.io.reader import Reader, _line_map
from linkcli.reading.load import load, load_for_analysis

LINKAGE = """[linkage]
ground = 50
input = 27.6293
coupler = 57.2363
output = 41.1104
"""


def errors_of(text: str, name: str = "f.toml") -> list[InputError]:
    with pytest.raises(InputErrors) as info:
        load(name, text)
    return info.value.errors


def line_of_marker(text: str, marker: str) -> int:
    """1-based line of the only line of `text` that holds `marker`."""
    hits = [n for n, line in enumerate(text.split("\n"), start=1) if marker in line]
    assert len(hits) == 1, hits
    return hits[0]


# ---------------------------------------------------------------- strings and comments

STRING_CASES = {
    "bracket and hash in a basic string": 'title = "a # [b"\n',
    "bracket and hash in a literal string": "title = 'a # [b'\n",
    "escaped quote in a basic string": 'title = "say \\"[x\\" # [y"\n',
    "backslash at the end of a basic string": 'title = "ends in \\\\"  # [ comment\n',
    "multi-line basic string holding a table": 'title = """\n[linkage]\nground = 5\n"""\n',
    "multi-line literal string holding a table": "title = '''\n[linkage]\nground = 5\n'''\n",
    "multi-line basic string with escapes": 'title = """a \\""" [\n[linkage] \\\n  ground = 5 \\"""\n"""\n',
    "quotes next to the closing delimiter": 'title = """[linkage]\nground = 5 ""\"""\n',
    "literal quotes next to the closing delimiter": "title = '''[linkage]\nground = 5 '''''\n",
    "comment holding quotes and brackets": "# it's [a \"comment\n",
    "string holding a key": 'title = "x = [1, 2"\n',
}


@pytest.mark.parametrize("head", STRING_CASES.values(), ids=STRING_CASES.keys())
def test_brackets_keys_and_comments_inside_strings_are_not_structure(head):
    text = 'type = "linkage"\n' + head + LINKAGE.replace("ground = 50", "ground = -1  # GROUND")
    assert tomllib.loads(text)["linkage"]["ground"] == -1  # the case is valid TOML
    (err,) = errors_of(text)
    assert err.key == "linkage.ground"
    assert err.line == line_of_marker(text, "# GROUND")


def test_dotted_key_after_a_string_with_a_bracket():
    # the probe's case: the key sits at the root as a dotted key
    text = ('type = "linkage"\ntitle = "a # [b"\nlinkage.ground = -1\nlinkage.input = 27.6293\n'
            "linkage.coupler = 57.2363\nlinkage.output = 41.1104\n")
    (err,) = errors_of(text)
    assert (err.key, err.line) == ("linkage.ground", 3)


def test_table_written_inside_a_multi_line_string_is_not_the_real_table():
    # the probe's case: a real [bounds] after a title that quotes one
    text = open(ROOT / "problems" / "crank_rocker.toml", encoding="utf-8").read()
    text = text.replace("[bounds]", '[bounds]\nground = -5  # REAL', 1)
    text = 'title = """\n[bounds]\nground = 5\n"""\n' + text.replace("title =", "subtitle =", 1)
    data = tomllib.loads(text)
    assert data["bounds"]["ground"] == -5
    lines = _line_map(text)
    real = line_of_marker(text, "# REAL")
    assert lines[("bounds",)] == real - 1 and lines[("bounds", "ground")] == real
    assert lines[("title",)] == 1


def test_line_map_details():
    text = "\n".join([
        'a = [  # [',                # 1: a multi-line array
        '  "]",',                    # 2
        '  { x = 1 },',              # 3: inside the array: belongs to a
        ']',                         # 4
        'b = 1',                     # 5
        '"quoted.key" = 2',          # 6
        "'lit' = 3",                 # 7
        'c = { d = 1, "e f" = 2, g.h = 3 }',  # 8
        '"esc\\"aped" = 4',          # 9
        '[[arr]]',                   # 10
        'k = 1',                     # 11
        '[[arr]]',                   # 12
        'k = 2',                     # 13
        '[t]',                       # 14
        's = """',                   # 15
        'x = 1',                     # 16: inside the string
        '"""',                       # 17
        'y = 2',                     # 18
    ])
    data = tomllib.loads(text)
    assert data["a"] == ["]", {"x": 1}] and data['esc"aped'] == 4
    lines = _line_map(text)
    assert lines[("a",)] == 1 and ("a", "x") not in lines and ("x",) not in lines
    assert lines[("b",)] == 5
    assert lines[("quoted.key",)] == 6
    assert lines[("lit",)] == 7
    assert lines[("c",)] == 8 and lines[("c", "d")] == 8 and lines[("c", "e f")] == 8
    assert lines[("c", "g", "h")] == 8
    assert lines[('esc"aped',)] == 9
    # an array of tables: which element a key belongs to is not known: no line
    assert ("arr",) not in lines and ("arr", "k") not in lines
    assert lines[("t",)] == 14 and lines[("t", "s")] == 15 and lines[("t", "y")] == 18
    assert ("t", "x") not in lines


ALPHABET = string.ascii_letters + string.digits + " #[]{}=,.'\"\\\n\t"


@settings(max_examples=200, deadline=None)
@given(title=st.text(alphabet=ALPHABET, max_size=40), multiline=st.booleans())
def test_any_title_leaves_the_lines_of_the_keys_after_it(title, multiline):
    text = tomli_w.dumps({"type": "linkage", "title": title}, multiline_strings=multiline)
    text += LINKAGE.replace("ground = 50", "ground = -1")
    assert tomllib.loads(text)["title"] == title
    want = text.split("\n").index("ground = -1") + 1
    lines = _line_map(text)
    assert lines[("linkage",)] == want - 1
    assert lines[("linkage", "ground")] == want
    assert lines[("linkage", "output")] == want + 3
    assert set(lines) == {("type",), ("title",), ("linkage",)} | {("linkage", k) for k in
                                                                   ("ground", "input", "coupler", "output")}


def _keys(node, prefix=()):
    for k, v in node.items():
        yield prefix + (k,)
        if isinstance(v, dict):
            yield from _keys(v, prefix + (k,))


@pytest.mark.parametrize("path", sorted(p.relative_to(ROOT).as_posix() for p in
                                        list((ROOT / "problems").rglob("*.toml"))
                                        + list((ROOT / "tests" / "bad").glob("*.toml"))))
def test_every_key_of_the_examples_is_found_on_a_line_that_names_it(path):
    raw = (ROOT / path).read_bytes()
    try:
        text = raw.decode("utf-8")
        data = tomllib.loads(text)
    except (UnicodeDecodeError, tomllib.TOMLDecodeError):
        pytest.skip("not valid TOML: the reader stops before mapping lines")
    lines = _line_map(text)
    rows = text.split("\n")
    for key in _keys(data):
        n = lines.get(key)
        if n is None:  # allowed only inside an inline table or array: the parent has a line
            assert any(key[:k] in lines for k in range(len(key) - 1, 0, -1)), key
            continue
        assert key[-1] in rows[n - 1], (key, n, rows[n - 1])


# ---------------------------------------------------------------- one line per error

def test_a_multi_line_string_in_an_error_stays_on_one_line():
    text = 'type = "linkage"\n' + LINKAGE.replace("coupler = 57.2363", 'coupler = """a\n[b]\nc"""')
    (err,) = errors_of(text)
    assert err.line == 5 and "\n" not in str(err)
    assert str(err).endswith('found "a\\n[b]\\nc" (string)')


def test_a_quoted_key_with_a_newline_stays_on_one_line():
    text = 'type = "linkage"\n"a\\nb" = 1\n' + LINKAGE
    (err,) = errors_of(text)
    assert err.line == 2 and "\n" not in str(err) and 'unknown key "a\\nb"' in str(err)


# ---------------------------------------------------------------- byte-order mark

BOM = b"\xef\xbb\xbf"


@pytest.mark.parametrize("example", ["firedoor.toml", "firedoor_motion.toml"])
def test_a_byte_order_mark_is_accepted_and_changes_nothing(tmp_path, example):
    plain = (ROOT / "problems" / example).read_bytes()
    (tmp_path / "plain").mkdir()
    (tmp_path / "bom").mkdir()
    (tmp_path / "plain" / example).write_bytes(plain)
    (tmp_path / "bom" / example).write_bytes(BOM + plain)
    runs = [run_cli("synth", str(tmp_path / d / example), "--format", "json") for d in ("plain", "bom")]
    assert runs[0][0] == runs[1][0] == 0, runs[1][2]
    assert runs[1][2] == ""
    assert runs[0][1].replace("/plain/", "/bom/") == runs[1][1]


def test_a_byte_order_mark_keeps_the_line_numbers(tmp_path):
    text = 'type = "linkage"\n' + LINKAGE.replace("input = 27.6293", "input = -2")
    (tmp_path / "a.toml").write_bytes(BOM + text.encode())
    with pytest.raises(InputErrors) as info:
        load(str(tmp_path / "a.toml"))
    (err,) = info.value.errors
    assert (err.key, err.line) == ("linkage.input", 4)
    (tmp_path / "b.toml").write_bytes(BOM + b"type = = 1\n")
    code, out, errtext = run_cli("check", str(tmp_path / "b.toml"))
    assert code == 2 and errtext.startswith(f"{tmp_path / 'b.toml'}:1: expected valid TOML")


def test_only_a_leading_byte_order_mark_is_dropped():
    reader = Reader("x.toml", '\ufefftitle = "\ufeff"\n')
    assert reader.data == {"title": "\ufeff"}


# ---------------------------------------------------------------- whole-file checks

def test_tolerance_section_asked_without_a_tolerance_table_is_an_input_error():
    text = 'type = "linkage"\n' + LINKAGE + '[report]\nsections = ["lengths", "tolerance"]\n'
    (err,) = errors_of(text)
    assert (err.key, err.line) == ("report.sections", 8)
    assert err.expected.startswith('a [tolerance] table for the "tolerance" section')
    assert err.got == "no [tolerance] table"


def test_tolerance_section_with_its_table_is_accepted():
    text = ('type = "linkage"\n' + LINKAGE + '[report]\nsections = ["tolerance"]\n'
            "[tolerance]\nlengths = 0.05\nsamples = 10\n")
    assert load("f.toml", text).meta.sections == ("tolerance",)


@pytest.mark.parametrize("count, refused", [(10_000, False), (10_001, True)])
def test_report_sections_hold_at_most_the_array_cap(count, refused):
    # a string array, so not capped by number_list: 10,001 names were accepted
    text = 'type = "linkage"\n' + LINKAGE + f'[report]\nsections = {["lengths"] * count}\n'
    if not refused:
        assert load("f.toml", text).meta.sections == ("lengths",)
        return
    (err,) = errors_of(text)
    assert (err.key, err.line) == ("report.sections", 8)
    assert err.expected.startswith("an array of 1 to 10000 section names from: lengths, ")
    assert err.got == "an array of 10001"


def test_a_bad_tolerance_table_is_reported_once():
    text = 'type = "linkage"\ntolerance = 3\n' + LINKAGE + '[report]\nsections = ["tolerance"]\n'
    (err,) = errors_of(text)
    assert (err.key, err.line) == ("tolerance", 2)


def test_a_batch_result_file_is_refused_with_what_to_do(tmp_path):
    a, b = "problems/firedoor_motion.toml", "problems/firedoor.toml"
    code, out, _ = run_cli("synth", a, b, "--format", "toml")
    assert code == 0
    batch = tmp_path / "batch.toml"
    batch.write_text(out, encoding="utf-8")
    assert len(tomllib.loads(out)["result"]) == 2
    code, out, err = run_cli("analyze", str(batch))
    assert code == 2 and out == ""
    assert err == (f"{batch}: result: expected a single result (analyze reads one result per "
                   "file: write them one per file with synth --out DIR --format toml), found a "
                   "batch result file holding 2 results\n")
    # what the message says to do works
    code, _, _ = run_cli("synth", a, b, "--format", "toml", "--out", str(tmp_path / "one"))
    assert code == 0
    for stem in ("firedoor_motion", "firedoor"):
        code, out, err = run_cli("analyze", str(tmp_path / "one" / f"{stem}.toml"), "--format", "json")
        assert code == 0, err
        assert json.loads(out)["linkage"]["ground"] == 50


def test_a_problem_file_named_result_is_not_a_batch():
    text = 'type = "linkage"\n' + LINKAGE + "[[result]]\nstatus = 1\n"
    with pytest.raises(InputErrors) as info:
        load_for_analysis("f.toml", text)
    (err,) = info.value.errors
    assert err.key == "result" and "unknown key" in err.got


# ---------------------------------------------------------------- located: end of file, missing keys

@pytest.mark.parametrize("text, line", [
    ('type = "linkage"\n[linkage]\nground = 50\nx = ', 4),  # a value never written
    ('type = "linkage"\n[linkage]\nground = 50\n[sect', 4),  # a header never closed
    ('type = "linkage"\n[linkage]\nground = 50\ninput = [1,\n  2,\n', 5),  # an array never closed
    ('type = "linkage"\ntitle = """never closed\n\n', 3),  # a multi-line string never closed
])
def test_a_syntax_error_at_the_end_of_the_file_names_its_last_line(text, line):
    # tomllib says "at end of document" instead of a line and column: the end is the last line
    with pytest.raises(InputError) as info:
        Reader("f.toml", text)
    assert info.value.line == line
    assert str(info.value).startswith(f"f.toml:{line}: expected valid TOML, found a syntax error: ")
    assert str(info.value).endswith("(at end of document)")


@pytest.mark.parametrize("text, key, line", [
    ("", "type", 1),  # an empty file: its first line
    ("[linkage]\nground = 50\n", "type", 1),  # a top-level key: line 1
    ('type = "precision-position"\n' + LINKAGE, "positions", 1),  # a top-level table
    ('type = "linkage"\n\n\n' + LINKAGE.replace("coupler = 57.2363\n", ""), "linkage.coupler", 4),  # its header
    ('type = "linkage"\n' + LINKAGE + "[motion]\nsteps = 10\n[tolerance]\nlengths = 0.05\n"
     "max_failure_probability = 0.01\n", "tolerance.allowed_error", 9),  # its header, below another table
])
def test_a_missing_key_names_the_line_of_its_table_or_line_1(text, key, line):
    errors = errors_of(text)
    (err,) = [e for e in errors if e.key == key]
    assert err.got == "nothing (the key is missing)"
    assert err.line == line
