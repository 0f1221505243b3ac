"""The output sections of a result file (`analyze RESULT.toml`): every key in them is one the
report writer writes there (reading.result_keys, found by running the writer:
tests/result_keys_corpus.py), else one located line, as an unknown key of a problem file.

`pytest tests/reading/test_result_keys.py --update-goldens` rewrites src/linkcli/reading/result_keys.py
from the writer after a deliberate change of it; review the diff as a golden's."""

from __future__ import annotations

import tomllib

import pytest
from conftest import ROOT, run_cli
from result_keys_corpus import module_text

MODULE = ROOT / "src" / "linkcli" / "reading" / "result_keys.py"


@pytest.mark.slow
def test_the_known_keys_are_those_the_writer_writes(update_goldens):
    text = module_text()
    if update_goldens:
        MODULE.write_text(text, encoding="utf-8")
    assert MODULE.read_text(encoding="utf-8") == text, (
        "the report writer writes other keys than reading/result_keys.py knows: run pytest "
        "tests/reading/test_result_keys.py --update-goldens and review the diff")


def _result(tmp_path, example: str, edit) -> tuple[str, str, int, str]:
    """`analyze` of an example's result file after `edit`: (path, text, exit code, stderr)."""
    code, out, err = run_cli("synth", example, "--format", "toml")
    assert code in (0, 1), err
    text = edit(out)
    assert text != out and tomllib.loads(text)  # the edit made a change, and valid TOML
    path = tmp_path / "result.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = run_cli("analyze", str(path))
    return str(path), text, code, err


def _line_of(text: str, marker: str) -> int:
    (line,) = [n for n, row in enumerate(text.split("\n"), start=1) if marker in row]
    return line


UNKNOWN = {  # example, edit, the key path reported, a marker on the line reported
    "[transmission]": ("problems/firedoor.toml", lambda t: t.replace("[transmission]\n", "[transmission]\nmin_limit = 40\n", 1),
                       "transmission.min_limit", "min_limit"),
    "[error]": ("problems/firedoor.toml", lambda t: t.replace("[error]\n", "[error]\nmaxx = 1\n", 1),
                "error.maxx", "maxx"),
    "[solver]": ("problems/firedoor.toml", lambda t: t.replace("[solver]\n", "[solver]\nbudget = 100\n", 1),
                 "solver.budget", "budget"),
    "[grashof]": ("problems/firedoor.toml", lambda t: t.replace("[grashof]\n", "[grashof]\nkind = 1\n", 1),
                  "grashof.kind", "kind"),
    "a row of positions (an inline table: the array's line)": (
        "problems/firedoor.toml", lambda t: t.replace("{ input = 90.0,", "{ row_weight = 2, input = 90.0,", 1),
        "positions[1].row_weight", "positions = ["),
    "the 20th row of [[kinematics]]": (
        "problems/firedoor_motion.toml",
        lambda t: t.replace("[[kinematics]]\ninput = 190.0\n", "[[kinematics]]\ninput = 190.0\nspin_rate = 1\n", 1),
        "kinematics[19].spin_rate", "spin_rate"),
    "a pin's load cycle in [forces]": (
        "problems/firedoor_loads.toml", lambda t: t.replace("[forces.pins.A]\n", "[forces.pins.A]\nmedian = 1\n", 1),
        "forces.pins.A.median", "median"),
    "[tolerance]": ("problems/firedoor_tolerance.toml",
                    lambda t: t.replace("[tolerance]\n", "[tolerance]\nconfidence = 0.9\n", 1),
                    "tolerance.confidence", "confidence"),
    "a type's own section": ("problems/crank_rocker.toml",
                             lambda t: t.replace("[structural_error]\n", "[structural_error]\nmean = 1\n", 1),
                             "structural_error.mean", "mean"),
    "[strength.critical]": ("problems/firedoor_strength.toml",
                            lambda t: t.replace("[strength.critical]\n", "[strength.critical]\nmargin = 1\n", 1),
                            "strength.critical.margin", "margin"),
}


@pytest.mark.parametrize("case", UNKNOWN)
def test_an_unknown_key_in_an_output_section_is_one_located_line(tmp_path, case):
    example, edit, key, marker = UNKNOWN[case]
    path, text, code, err = _result(tmp_path, example, edit)
    assert code == 2, err
    assert err.count("\n") == 1, err
    assert err.startswith(f"{path}:{_line_of(text, marker)}: {key}: expected a known key (")
    assert err.rstrip().endswith(f'found unknown key "{key.rsplit(".", 1)[1]}"')


def test_a_misspelled_output_key_gets_a_did_you_mean(tmp_path):
    path, text, code, err = _result(tmp_path, "problems/firedoor.toml",
                                    lambda t: t.replace("[transmission]\nmin = ", "[transmission]\nmni = ", 1))
    assert code == 2
    assert err == (f'{path}:{_line_of(text, "mni = ")}: transmission.mni: expected a known key (did you '
                   'mean "min"?), found unknown key "mni"\n')


def test_names_of_the_linkage_are_any_names(tmp_path):
    # forces.pins, strength.rows[].pins and tolerance.lengths are keyed by the linkage's
    # pins and links: a pin renamed by hand is no unknown key (what analyze recomputes is
    # the forces, from [linkage] and [loads])
    path, text, code, err = _result(tmp_path, "problems/firedoor_loads.toml",
                                    lambda t: t.replace("[forces.pins.B0]", "[forces.pins.Q7]").replace(
                                        "[forces.pins.B0.", "[forces.pins.Q7."))
    assert code == 0 and err == "", err


def test_a_result_written_with_timing_is_accepted(tmp_path):
    code, _, err = run_cli("synth", "problems/firedoor.toml", "--format", "toml", "--timing",
                           "--out", str(tmp_path))
    assert code == 0, err
    assert "seconds = " in (tmp_path / "firedoor.toml").read_text()
    code, _, err = run_cli("analyze", str(tmp_path / "firedoor.toml"))
    assert code == 0 and err == "", err
