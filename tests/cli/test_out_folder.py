"""--out DIR never replaces an input file with its result (a hostile-input probe: --out the
problem's own folder with --format toml overwrote the problem file, exit 0; a drawing was then
lost, analyze refusing a drawn linkage's result)."""

from __future__ import annotations

import shutil

from conftest import ROOT, run_cli


def test_a_result_never_overwrites_its_problem_file(tmp_path):
    for name in ("firedoor.toml", "drawn_watt.toml"):
        shutil.copy(ROOT / "problems" / name, tmp_path / name)
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    for command, name in (("synth", "firedoor.toml"), ("analyze", "drawn_watt.toml")):
        code, out, err = run_cli(command, str(tmp_path / name), "--format", "toml", "--out", str(tmp_path))
        assert code == 2 and out == "", err
        assert err.splitlines() == [f"{tmp_path / name}: expected a result file name that is not one of the input "
                                    f"files, found the problem file {tmp_path / name} (--out names its folder: write "
                                    "the results to another folder, or use another --format)"]
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before
    code, _, err = run_cli("synth", str(tmp_path / "firedoor.toml"), "--format", "json", "--out", str(tmp_path))
    assert code == 0, err
    assert (tmp_path / "firedoor.json").exists() and (tmp_path / "firedoor.toml").read_bytes() == before["firedoor.toml"]
    other = tmp_path / "results"
    code, _, err = run_cli("synth", str(tmp_path / "firedoor.toml"), "--format", "toml", "--out", str(other))
    assert code == 0 and (other / "firedoor.toml").exists(), err


def test_csv_tables_never_overwrite_an_input_and_stems_follow_the_arguments(tmp_path):
    """--format csv writes DIR/<stem>.<table>.csv: one that would replace an input (here a file
    named like a table) is refused, nothing written (the guard skipped CSV: exit 0, the input
    replaced). A bad file keeps its stem: the next file of that stem is <stem>_2 whether the
    first solved or not (it became <stem> when the first was bad)."""
    shutil.copy(ROOT / "problems" / "straight_line.toml", tmp_path / "x.toml")
    decoy = tmp_path / "x.positions.csv"
    decoy.write_text("not a table\n")
    code, out, err = run_cli("synth", str(tmp_path / "x.toml"), str(decoy), "--format", "csv", "--out", str(tmp_path))
    assert code == 2 and decoy.read_text() == "not a table\n"
    assert f"{decoy}: expected a result file name that is not one of the input files" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.positions.csv", "x.toml"]
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    (tmp_path / "a" / "x.toml").write_text('type = "linkage"\n[linkage]\nground = -1\n')
    shutil.copy(ROOT / "problems" / "firedoor.toml", tmp_path / "b" / "x.toml")
    out_dir = tmp_path / "out"
    code, _, err = run_cli("synth", str(tmp_path / "a" / "x.toml"), str(tmp_path / "b" / "x.toml"), "--format", "json",
                           "--out", str(out_dir))
    assert code == 2 and sorted(p.name for p in out_dir.iterdir()) == ["x_2.json"], err
