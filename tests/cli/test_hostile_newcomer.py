"""Hostile input, fourth round (issue 47), the newcomer's view: what linkcli says it is, the
templates `new` writes (tests/test_templates.py runs them), a "did you mean" for a near miss,
where a plot, an animation or a DXF went, progress on a terminal for long work (an animation,
a bench, a tolerance study), and command-line errors as one line."""

from __future__ import annotations

import os
import pty
import select
import subprocess
import sys
import tomllib

import pytest

from conftest import ROOT, run_cli

SRC = str(ROOT / "src")
ENV = dict(os.environ, PYTHONPATH=SRC, COLUMNS="120")


def test_help_package_and_docstring_say_planar_linkages():
    """Every linkage linkcli handles is planar, few are four-bars."""
    import linkcli
    code, out, err = run_cli("--help")
    assert code == 0 and "Design planar linkages from TOML problem files." in out
    assert "four-bar linkages" not in out
    assert linkcli.__doc__ == "linkcli: a command-line design tool for planar linkages."
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["description"] == "Command-line design tool for planar linkages"


@pytest.mark.parametrize("typed, meant", [("Linkage", "linkage"), ("PATH-GENERATION", "path-generation"),
                                          ("fivebar", "five-bar"), ("slider-crank", "linkage")])
def test_new_says_which_template_a_near_miss_means(typed, meant):
    code, out, err = run_cli("new", typed)
    assert code == 2 and out == ""
    assert len(err.splitlines()) == 1
    assert f'(did you mean "{meant}"?)' in err and err.rstrip().endswith(f'found "{typed}"')


def test_where_a_plot_an_animation_and_a_dxf_went_is_said_on_stderr(tmp_path):
    pytest.importorskip("matplotlib")
    pytest.importorskip("ezdxf")
    files = {"--plot": tmp_path / "fd.png", "--animate": tmp_path / "fd.svg", "--dxf": tmp_path / "fd.dxf"}
    args = [a for option, path in files.items() for a in (option, str(path))]
    code, out, err = run_cli("synth", "problems/firedoor_motion.toml", *args)
    assert code == 0, err
    assert err.splitlines() == [f"problems/firedoor_motion.toml: plot written to {files['--plot']}",
                                f"problems/firedoor_motion.toml: animation written to {files['--animate']}",
                                f"problems/firedoor_motion.toml: DXF drawing written to {files['--dxf']}"]
    assert all(path.stat().st_size > 1000 for path in files.values())


def on_a_terminal(*args: str, timeout: float = 300) -> tuple[int, str]:
    """(exit code, what reached the terminal) of linkcli with stderr on a pseudo-terminal."""
    main, child = pty.openpty()
    process = subprocess.Popen([sys.executable, "-m", "linkcli", *args], stdout=subprocess.DEVNULL,
                               stderr=child, env=ENV, cwd=ROOT)
    os.close(child)
    shown = b""
    try:
        while True:
            ready, _, _ = select.select([main], [], [], 0.5)
            if ready:
                try:
                    chunk = os.read(main, 65536)
                except OSError:
                    break
                if not chunk:
                    break
                shown += chunk
            elif process.poll() is not None:
                break
        process.wait(timeout=timeout)
    finally:
        os.close(main)
    return process.returncode, shown.decode("utf-8", "replace")


def test_an_animation_shows_its_frames_on_a_terminal(tmp_path):
    """A GIF of 360 frames took 5 to 8 s in silence after the report."""
    pytest.importorskip("matplotlib")
    target = tmp_path / "fd.gif"
    code, shown = on_a_terminal("synth", "problems/firedoor_motion.toml", "--animate", str(target))
    assert code == 0, shown
    assert "writing the animation" in shown and "frames drawn" in shown
    assert f"animation written to {target}" in shown


def test_bench_shows_its_runs_on_a_terminal():
    """`linkcli bench` with no files ran the bench set, 25 s and more, printing nothing until
    the end; every bench now shows its runs done and the one running (the same display with
    or without files)."""
    code, shown = on_a_terminal("bench", "problems/bench/firedoor.toml", "problems/bench/crank_rocker.toml",
                                "--seeds", "2")
    assert code == 0, shown
    assert "bench: firedoor" in shown and "bench: crank_rocker" in shown


def test_a_long_tolerance_study_shows_its_work_on_a_terminal(tmp_path):
    """The allocation of a drawn six-bar showed only a spinner for minutes; the display counts
    the sample-targets every tolerance pass assembles."""
    text = (ROOT / "problems" / "firedoor_cost.toml").read_text()
    path = tmp_path / "cost.toml"
    path.write_text(text)
    code, shown = on_a_terminal("synth", str(path))
    assert code == 0, shown
    assert "tolerance sample-targets" in shown


OPTION_ERRORS = {  # arguments -> the one line (issue 47: four-line usage blocks)
    ("synth", "problems/firedoor.toml", "--precision", "x"):
        'linkcli synth: --precision: expected a whole number from 1 to 17, found "x"',
    ("synth", "problems/firedoor.toml", "--format", "xml"):
        'linkcli synth: --format: expected one of: table, json, toml, csv, found "xml"',
    ("synth", "problems/firedoor.toml", "-fxml"):
        'linkcli synth: --format: expected one of: table, json, toml, csv, found "xml"',
    ("synth", "problems/firedoor.toml", "--jobs"):
        "linkcli synth: --jobs: expected a whole number >= 1 after it, found nothing",
    ("synth", "problems/firedoor.toml", "--jobs", "0"):
        'linkcli synth: --jobs: expected a whole number >= 1, found "0"',
    ("synth",): "linkcli synth: FILE...: expected one or more problem files, found nothing",
    ("synth", "problems/firedoor.toml", "--bogus"):
        "linkcli synth: --bogus: expected an option of linkcli synth (did you mean --out or --jobs?); "
        "linkcli synth --help lists them, found --bogus",
    ("bench", "--seeds", "1000000"): 'linkcli bench: --seeds: expected a whole number from 1 to 1000, found "1000000"',
    ("check", "--debug=3", "x.toml"): 'linkcli check: --debug: expected no value (a flag), found "3"',
    ("frobnicate",): 'linkcli: COMMAND: expected one of: synth, analyze, check, bench, new, atlas, found "frobnicate"',
    ("synt", "x.toml"): 'linkcli: COMMAND: expected one of: synth, analyze, check, bench, new, atlas (did you mean "synth"?), '
                        'found "synt"',
    ("new", "linkage", "a.toml", "b.toml"):
        "linkcli new: expected the arguments [OPTIONS] TYPE [FILE], found more: b.toml",
}


@pytest.mark.parametrize("args", OPTION_ERRORS)
def test_a_command_line_error_is_one_line_and_exit_2(args):
    code, out, err = run_cli(*args)
    assert (code, out) == (2, "")
    assert err == OPTION_ERRORS[args] + "\n"


def test_bench_seeds_beyond_the_cap_are_refused_at_once():
    """`bench --seeds 1000000` grew without output; the cap is documented in --help."""
    code, out, err = run_cli("bench", "--help")
    assert code == 0 and "(1 .. 1000" in out


def test_help_itself_and_no_arguments_still_print_the_usage():
    code, out, err = run_cli("synth", "--help")
    assert code == 0 and out.startswith("Usage: linkcli synth [OPTIONS] FILE...")
    code, out, err = run_cli()
    assert code == 2 and "Usage: linkcli [OPTIONS] COMMAND [ARGS]..." in out + err
