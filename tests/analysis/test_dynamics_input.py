"""[springs], [dampers] and [dynamics]: input that only solving shows impossible (exit 2, one
located line), runs that fall short of what was asked (exit 1 with the reason), hostile sizes
(bounded time, one line), and what a `check` or a closed-form problem must not import. The bad
files found by reading alone are goldens in tests/bad/dynamics_*.toml."""

from __future__ import annotations

import subprocess
import sys

import pytest
from conftest import ROOT, run_cli

DOOR = """type = "linkage"
[linkage]
ground = 50
input = 27.6293
coupler = 57.2363
output = 41.1104
[masses]
input = { mass = 30, center = [400, 0], inertia = 5 }
"""
ROCKER = """type = "linkage"
[linkage]
ground = 60
input = 40
coupler = 30
output = 45
[masses]
input = { mass = 1, center = [40, 0] }
"""


def _synth(tmp_path, text: str, *args: str):
    path = tmp_path / "p.toml"
    path.write_text(text, encoding="utf-8")
    return (path,) + run_cli("synth", str(path), *args)


@pytest.mark.parametrize("extra,line,message", [
    ('[dynamics]\nstart = { angle = 120 }\nduration = 1\n', 10,
     "dynamics.start.angle: expected an initial angle within the drive's range of motion [-95.0797, 95.0797] (deg), found 120"),
    ('[dynamics]\nstart = { angle = 30 }\nstop = { angle = 100 }\nduration = 1\n', 11,
     "dynamics.stop.angle: expected a stop angle within the drive's range of motion"),
    ('[dynamics]\nfluctuation = 0.02\nmean_speed = 100\n', 10,
     "dynamics.fluctuation: expected a drive that turns fully for a flywheel"),
])
def test_what_only_solving_shows_impossible_is_one_located_line(tmp_path, extra, line, message):
    path, code, out, err = _synth(tmp_path, ROCKER + extra)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"{path}:{line}: {message}"), err


def test_a_linkage_without_inertia_is_refused(tmp_path):
    path, code, out, err = _synth(tmp_path, DOOR.replace("mass = 30, center = [400, 0], inertia = 5",
                                                         "mass = 0") + "[dynamics]\nstart = { angle = 90 }\nduration = 1\n")
    assert code == 2 and "Traceback" not in err
    assert "expected masses that move with the drive" in err and err.count("\n") == 1


def test_a_door_that_cannot_close_in_its_duration_is_exit_1_with_the_reason(tmp_path):
    path, code, out, err = _synth(tmp_path, DOOR + """[springs]
closer = { link = "output", stiffness = 29, free_angle = -37 }
[dampers]
valve = { link = "output", coefficient = 500 }
[dynamics]
start = { angle = 135 }
stop = { angle = 45 }
duration = 0.5
steps = 5
""", "--format", "json")
    assert code == 1
    assert '"status": "infeasible"' in out
    assert "does not reach the stop angle 45 deg: the run ends at its duration at 0.5 s" in out


def test_an_integration_over_its_budget_ends_not_converged_in_bounded_time(tmp_path):
    path, code, out, err = _synth(tmp_path, DOOR + """[solver]
budget = 2000
[springs]
closer = { link = "output", stiffness = 29, free_angle = -37 }
[dynamics]
start = { angle = 90, speed = 0 }
duration = 1000000
""", "--format", "json")
    assert code == 1
    assert '"status": "not-converged"' in out and "more than 2000 evaluations" in out


def test_a_motor_too_weak_for_its_load_is_exit_1(tmp_path):
    path, code, out, err = _synth(tmp_path, DOOR.replace("[masses]", "[loads]\noutput_torque = -50\n[masses]") + """[dampers]
d = { link = "output", coefficient = 50 }
[dynamics]
drive = { torque_speed = [[0, 0.5], [100, 0.4], [200, 0]] }
fluctuation = 0.05
""", "--format", "json")
    assert code == 1 and "the motor cannot drive the linkage" in out


@pytest.mark.parametrize("extra,expected", [
    ("[dampers]\nv = { link = \"output\", table = [" + ", ".join(f"[{k}, {k}]" for k in range(10_001)) + "] }\n"
     "[dynamics]\nstart = { angle = 90 }\nduration = 1\n", "expected a table [[speed, force], ...] of 2 to 10000 rows"),
    ("[springs]\n" + "".join(f"s{k} = {{ link = \"output\", stiffness = 1, free_angle = 0 }}\n" for k in range(101))
     + "[dynamics]\nstart = { angle = 90 }\nduration = 1\n", "springs: expected at most 100 springs"),
    ("[dynamics]\nstart = { angle = 90 }\nduration = 1\nmarks = [" + ", ".join(["1"] * 101) + "]\n",
     "dynamics.marks: expected an array of 1 to 100 angles"),
    ("[dynamics]\nstart = { angle = 90 }\nduration = 1e300\n", "dynamics.duration: expected a time in s in (0, 1000000]"),
    ("[dynamics]\nstart = { angle = 90 }\nduration = 1\nsteps = 1000001\n", "dynamics.steps: expected an integer in [2, 100000]"),
    ("[dynamics]\nstart = { angle = 90, speed = inf }\nduration = 1\n", "dynamics.start.speed: expected the drive's speed"),
    ("[dynamics]\nstart = { angle = 90 }\nduration = 1\nfriction = -0.1\n", "dynamics.friction: expected a Coulomb friction coefficient"),
    ("[dynamics]\nstart = { angle = 90 }\nduration = 1\nfriction = 0.1\n", "dynamics.friction: expected a [joints] diameter for every pin"),
    ("[dynamics]\nstart = [90]\nduration = 1\n", "dynamics.start: expected a table"),
    ("[dynamics]\ncounterweights = { coupler = 3 }\n", "dynamics.counterweights.coupler: expected a link that takes a counterweight: input, output"),
    ("[dynamics]\nfluctuation = 1\nmean_speed = 3\n", "dynamics.fluctuation: expected a coefficient of speed fluctuation strictly between 0 and 1"),
    ("[dynamics]\nfluctuation = 0.1\nmean_speed = 0\n", "dynamics.mean_speed: expected a non-zero speed"),
    ("[dynamics]\n", "dynamics: expected start = { angle, speed } (a simulation), fluctuation (a flywheel), balance or counterweights"),
    ("[dynamics]\nstart = { angle = 90 }\nduration = 1\n[dampers]\nd = { link = \"output\", coefficient = 1, table = [[0, 0], [1, 1]] }\n",
     "dampers.d: expected one of coefficient or table, found both"),
    ("[springs]\ns = { between = [\"A0\", \"Q\"], stiffness = 1, free_length = 3 }\n[dynamics]\nstart = { angle = 90 }\nduration = 1\n",
     'springs.s.between: expected points of the linkage: A0, A, B, B0, or [x, y], found "Q"'),
    ("[springs]\ns = { link = \"output\", links = [\"input\", \"output\"], stiffness = 1, free_angle = 3 }\n"
     "[dynamics]\nstart = { angle = 90 }\nduration = 1\n", "springs.s: expected one of between"),
])
def test_hostile_and_wrong_values_are_one_located_line_each(tmp_path, extra, expected):
    path = tmp_path / "p.toml"
    path.write_text(DOOR + extra, encoding="utf-8")
    code, out, err = run_cli("check", str(path))
    assert code == 2 and out == "" and "Traceback" not in err
    assert all(line.startswith(f"{path}:") for line in err.splitlines())
    assert expected in err, err


def test_check_of_a_dynamics_problem_imports_neither_numpy_nor_scipy():
    program = ("import sys\nsys.argv = ['linkcli', 'check', 'problems/firedoor_closing.toml', "
               "'problems/crank_rocker_motor.toml', 'problems/balanced_four_bar.toml']\n"
               "from linkcli.cli import main\ntry:\n    main()\nfinally:\n"
               "    sys.stderr.write('\\nLOADED ' + ' '.join(sorted(sys.modules)) + '\\n')\n")
    res = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    loaded = set(res.stderr.rsplit("LOADED ", 1)[1].split())
    assert not {"numpy", "scipy"} & loaded


def test_a_closed_form_problem_with_loads_does_not_import_scipy_but_a_dynamics_one_does():
    program = ("import sys\nsys.argv = ['linkcli', 'synth', {file!r}]\nfrom linkcli.cli import main\n"
               "try:\n    main()\nfinally:\n    sys.stderr.write('\\nLOADED ' + ' '.join(sorted(sys.modules)) + '\\n')\n")
    loaded = {}
    for name in ("problems/firedoor_loads.toml", "problems/balanced_four_bar.toml"):
        res = subprocess.run([sys.executable, "-c", program.format(file=name)], capture_output=True, text=True, cwd=ROOT)
        assert res.returncode == 0, res.stderr
        loaded[name] = set(res.stderr.rsplit("LOADED ", 1)[1].split())
    assert "scipy" not in loaded["problems/firedoor_loads.toml"]
    assert not any(m.startswith("linkcli.analysis.dynamics.") for m in loaded["problems/firedoor_loads.toml"])
    assert "linkcli.analysis.dynamics.system" in loaded["problems/balanced_four_bar.toml"]
