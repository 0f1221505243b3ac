"""The templates of `linkcli new TYPE [FILE]` (package data, linkcli.templates): one per
problem type, each valid TOML that passes `check` and solves with exit 0, and every key
a template shows, its commented-out optional keys included, is a key the schema accepts."""

from __future__ import annotations

import json
import re
import tomllib

import pytest

from conftest import run_cli
from linkcli.errors import InputErrors
from linkcli.reading.load import load
from linkcli.registry import NAMES as TYPES
from linkcli.templates import template_names, template_text

EXISTING = ("precision-position", "function-generation", "path-generation", "flipper-cylinder", "linkage",
            "quick-return")
COMMENTED_KEY = re.compile(r"^# ([A-Za-z_][A-Za-z0-9_]*) = ")
COMMENTED_HEADER = re.compile(r"^# (\[[A-Za-z_][A-Za-z0-9_]*\])")
HEADER = re.compile(r"^\[[A-Za-z_][A-Za-z0-9_]*\]")


MECHANISM_TEMPLATES = ("five-bar", "drawn")  # `new five-bar`, `new drawn`: type = "linkage" of that mechanism


def test_every_existing_type_has_a_template_and_every_template_a_type():
    from linkcli.mechanisms import NAMES as MECHANISMS
    names = template_names()
    assert set(EXISTING) <= set(names) and set(MECHANISM_TEMPLATES) <= set(names)
    assert set(names) <= set(TYPES) | set(MECHANISMS)
    assert list(names) == sorted(names)


@pytest.mark.parametrize("name", MECHANISM_TEMPLATES)
def test_a_mechanism_template_is_a_linkage_of_it_that_check_synth_and_analyze_accept(name, tmp_path):
    """`linkcli new five-bar` and `linkcli new drawn` (issue 47: `new` had only the commented
    drawn block of the linkage template, and no five-bar): real problem files."""
    text = template_text(name)
    data = tomllib.loads(text)
    assert data["type"] == "linkage" and data["linkage"]["mechanism"] == name
    path = tmp_path / f"{name}.toml"
    path.write_text(text, encoding="utf-8")
    assert run_cli("check", str(path)) == (0, f"{path}: ok\n", "")
    for command in ("synth", "analyze"):
        code, out, err = run_cli(command, str(path), "--format", "json")
        assert code == 0, err
        report = json.loads(out)
        assert report["status"] == "ok" and report["linkage"]["mechanism"] == name
    if name == "drawn":
        assert report["grashof"]["class"] == "six-bar (Watt)"
    else:
        assert len(report["kinematics"]) == len(data["motion"]["path"])


@pytest.mark.parametrize("name", MECHANISM_TEMPLATES)
def test_every_commented_out_key_of_a_mechanism_template_is_accepted(name, tmp_path):
    variants = list(uncommented_variants(template_text(name)))
    assert len(variants) >= 3
    for key, text in variants:
        tomllib.loads(text)
        path = tmp_path / f"{name}.toml"
        path.write_text(text, encoding="utf-8")
        try:
            load(str(path))
        except InputErrors as exc:
            unknown = [str(e) for e in exc.errors if "unknown key" in str(e)]
            assert not unknown, (key, unknown)


def test_an_unknown_type_names_the_known_ones():
    with pytest.raises(KeyError, match="known: .*linkage"):
        template_text("four-bar")


@pytest.mark.parametrize("name", EXISTING)
def test_template_is_toml_of_its_type_and_passes_check(name, tmp_path):
    text = template_text(name)
    assert tomllib.loads(text)["type"] == name
    path = tmp_path / f"{name}.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = run_cli("check", str(path))
    assert code == 0, err
    assert out == f"{path}: ok\n" and err == ""


@pytest.mark.parametrize("name", EXISTING)
def test_template_solves_within_every_constraint(name, tmp_path):
    path = tmp_path / f"{name}.toml"
    path.write_text(template_text(name), encoding="utf-8")
    code, out, err = run_cli("synth", str(path), "--format", "json")
    assert code == 0, err
    report = json.loads(out)
    assert report["status"] == "ok", report["message"]
    assert report["type"] == name


def uncommented_variants(text: str):
    """(key, text) for each commented-out key line `# key = value`: that line uncommented,
    and its table header too when the header is commented out as well."""
    lines = text.split("\n")
    header_at = None  # index of the last header line seen, real or commented out
    for i, line in enumerate(lines):
        if HEADER.match(line) or COMMENTED_HEADER.match(line):
            header_at = i
            continue
        m = COMMENTED_KEY.match(line)
        if not m:
            continue
        new = list(lines)
        new[i] = line[2:]
        if header_at is not None and COMMENTED_HEADER.match(lines[header_at]):
            new[header_at] = lines[header_at][2:]
        table = (COMMENTED_HEADER.match(lines[header_at]) or HEADER.match(lines[header_at])).group(
            1 if COMMENTED_HEADER.match(lines[header_at]) else 0) if header_at is not None else ""
        yield f"{table}.{m.group(1)}", "\n".join(new)


@pytest.mark.parametrize("name", EXISTING)
def test_every_commented_out_key_is_a_key_the_schema_accepts(name, tmp_path):
    variants = list(uncommented_variants(template_text(name)))
    assert len(variants) >= 3  # every template shows optional keys ([solver] seed at least)
    for key, text in variants:
        tomllib.loads(text)  # uncommented, the file is still TOML (no key given twice)
        path = tmp_path / f"{name}.toml"
        path.write_text(text, encoding="utf-8")
        try:
            load(str(path))
        except InputErrors as exc:
            unknown = [str(e) for e in exc.errors if "unknown key" in str(e)]
            assert not unknown, (key, unknown)
