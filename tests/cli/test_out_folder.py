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
