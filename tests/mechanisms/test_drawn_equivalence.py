"""A four-bar and a slider-crank written as drawings (`mechanism = "drawn"`) print the same
numbers as the named mechanisms: every number both reports hold -- transmission extremes and
where, the ranges of motion, swing, stroke and time ratio, every kinematics row (angles,
rates, transmission, the coupler point), every forces row (the drive's torque, each pin's
force, the mechanical advantage) and the load cycle. The two outputs come from independent
code: the named mechanisms' closed forms (mechanisms/four_bar, slider_crank) and the drawn
linkage's plan of dyads.

The drawings are built here from the lengths: A0 at the origin, B0 on the x axis, the crank at
its drawn angle, B from the branch's closed form (SPEC section 1), P from the coupler frame.
"""

from __future__ import annotations

import json
import math

import pytest
from conftest import run_cli

REL = 1e-5  # both print 6 significant digits: the last may round either way


def close(a, b, scale) -> bool:
    if a is None or b is None:
        return a is b
    if isinstance(a, list):
        return len(a) == len(b) and all(close(x, y, scale) for x, y in zip(a, b))
    return math.isclose(a, b, rel_tol=REL, abs_tol=1e-7 * scale)


def same(a, b, what: str, scale: float = 100.0) -> None:
    assert close(a, b, scale), f"{what}: named {a!r}, drawn {b!r}"


def run(tmp_path, name: str, text: str) -> dict:
    path = tmp_path / f"{name}.toml"
    path.write_text(text, encoding="utf-8")
    code, out, err = run_cli("synth", str(path), "--format", "json")
    assert code == 0, err
    return json.loads(out)


LOADS = """
[loads]
gravity = [0, -9.81]
{force}
[masses]
{masses}
"""


def four_bar_texts(a, b, c, d, branch, phi0, point, steps):
    """(named, drawn) problem texts of one four-bar."""
    ax, ay = a * math.cos(phi0), a * math.sin(phi0)
    rho = math.hypot(ax - d, ay)
    theta_rho = math.atan2(ay, ax - d)
    alpha = math.acos((rho * rho + c * c - b * b) / (2 * rho * c))
    psi = theta_rho - alpha if branch == "open" else theta_rho + alpha
    bx, by = d + c * math.cos(psi), c * math.sin(psi)
    theta = math.atan2(by - ay, bx - ax)
    px = ax + point[0] * math.cos(theta) - point[1] * math.sin(theta)
    py = ay + point[0] * math.sin(theta) + point[1] * math.cos(theta)
    masses_named = ('input = { mass = 0.2, center = [13.8, 0], inertia = 1.0e-5 }\n'
                    'coupler = { mass = 0.5, center = [20, 5], inertia = 2.0e-4 }\n'
                    'output = { mass = 0.3, center = [20, 0], inertia = 1.0e-4 }')
    named = f"""type = "linkage"
[linkage]
ground = {d!r}
input = {a!r}
coupler = {b!r}
output = {c!r}
branch = "{branch}"
coupler_point = [{point[0]!r}, {point[1]!r}]
[motion]
input_speed = 20
steps = {steps}
""" + LOADS.format(force="coupler_force = [10, -100]\noutput_torque = 2.5", masses=masses_named)
    drawn = f"""type = "linkage"
[linkage]
mechanism = "drawn"
[joints]
A0 = {{ at = [0, 0], ground = true }}
B0 = {{ at = [{d!r}, 0], ground = true }}
A = {{ at = [{ax!r}, {ay!r}] }}
B = {{ at = [{bx!r}, {by!r}] }}
P = {{ at = [{px!r}, {py!r}] }}
[links]
input = ["A0", "A"]
coupler = ["A", "B", "P"]
output = ["B0", "B"]
[drive]
input = {{ speed = 20 }}
[motion]
steps = {steps}
points = ["P"]
""" + LOADS.format(force="forces = { P = [10, -100] }\ntorques = { output = 2.5 }", masses=masses_named)
    return named, drawn


FOUR_BARS = {  # a, b, c, d, branch, drawn crank angle (deg), coupler point
    "crank-rocker": (27.6293, 57.2363, 41.1104, 50.0, "open", 40.0, (20.0, 10.0)),
    "crank-rocker crossed": (20.0, 55.0, 40.0, 50.0, "crossed", 150.0, (15.0, -8.0)),
    "double-rocker": (40.0, 20.0, 45.0, 30.0, "open", 80.0, (10.0, 12.0)),
    "triple-rocker": (30.0, 40.0, 35.0, 50.0, "crossed", 60.0, (10.0, -5.0)),
    "double-crank": (60.0, 55.0, 50.0, 20.0, "open", 10.0, (30.0, 5.0)),
}


@pytest.mark.parametrize("case", list(FOUR_BARS))
def test_a_drawn_four_bar_prints_the_named_four_bars_numbers(case, tmp_path):
    a, b, c, d, branch, phi0, point = FOUR_BARS[case]
    named_text, drawn_text = four_bar_texts(a, b, c, d, branch, math.radians(phi0), point, 24)
    fb, dr = run(tmp_path, "named", named_text), run(tmp_path, "drawn", drawn_text)
    scale = max(a, b, c, d)
    t, closure = fb["transmission"], dr["transmission"]["closures"]["B"]
    for key in ("min", "max", "input_at_min", "input_at_max"):
        same(t[key], closure[key], f"transmission {key}")
        same(t[key], dr["transmission"][key], f"transmission {key} (overall)")
    m, links = fb["motion"], dr["motion"]["links"]
    assert m["input_full_turn"] == dr["motion"]["input_full_turn"]
    if not m["input_full_turn"]:
        same(m["input_range"], dr["motion"]["input_range"], "input_range")
    assert m["output_full_turn"] == links["output"]["full_turn"]
    if not m["output_full_turn"]:
        same(m["output_range"], links["output"]["range"], "output_range")
        same(m["output_swing"], links["output"]["swing"], "output_swing")
    if "time_ratio" in m:
        same(m["time_ratio"], links["output"]["time_ratio"], "time_ratio")
    assert len(fb["kinematics"]) == len(dr["kinematics"]) == 24
    for row, drow in zip(fb["kinematics"], dr["kinematics"]):
        where = f"row at input {row['input']}"
        same(row["input"], drow["input"], where)
        for name in ("coupler", "output"):
            same(row[name], drow["links"][name]["angle"], f"{where}: {name}")
            same(row[f"{name}_velocity"], drow["links"][name]["velocity"], f"{where}: {name}_velocity")
            same(row[f"{name}_acceleration"], drow["links"][name]["acceleration"], f"{where}: {name}_acceleration")
        same(row["transmission"], drow["transmission"]["B"], f"{where}: transmission")
        for key, sub in (("x", "x"), ("y", "y"), ("vx", "vx"), ("vy", "vy"), ("ax", "ax"), ("ay", "ay")):
            same(row[f"coupler_point_{key}"], drow["points"]["P"][sub], f"{where}: coupler point {key}", scale)
    _same_forces(fb["forces"], dr["forces"], {"A0": "A0", "A": "A", "B": "B", "B0": "B0"})


def _same_forces(named: dict, drawn: dict, pins: dict) -> None:
    for key in ("peak", "at_input", "rms"):
        same(named["input_torque"][key], drawn["input_torque"][key], f"input_torque {key}")
    for pin, other in pins.items():
        for key in ("max", "min", "mean", "amplitude"):
            same(named["pins"][pin][key], drawn["pins"][other][key], f"pin {pin} {key}")
    assert len(named["rows"]) == len(drawn["rows"])
    for row, drow in zip(named["rows"], drawn["rows"]):
        where = f"forces row at input {row['input']}"
        same(row["input"], drow["input"], where)
        same(row["input_torque"], drow["input_torque"], f"{where}: torque")
        same(row["mechanical_advantage"], drow["mechanical_advantage"], f"{where}: mechanical advantage")
        for pin, other in pins.items():
            for key in ("x", "y", "magnitude"):
                same(row["pins"][pin][key], drow["pins"][other][key], f"{where}: pin {pin} {key}")


SLIDER_CRANKS = {  # crank, rod, offset, branch, drawn crank angle (deg)
    "slider-crank": (47.2812, 104.9139, 30.0, "open", 40.0),
    "crossed": (30.0, 70.0, -10.0, "crossed", 200.0),
    "rocking slider": (50.0, 40.0, 20.0, "open", 60.0),
}


@pytest.mark.parametrize("case", list(SLIDER_CRANKS))
def test_a_drawn_slider_crank_prints_the_named_slider_cranks_numbers(case, tmp_path):
    a, b, e, branch, phi0 = SLIDER_CRANKS[case]
    phi = math.radians(phi0)
    ax, ay = a * math.cos(phi), a * math.sin(phi)
    root = math.sqrt(b * b - (e - ay) ** 2)
    s = ax + root if branch == "open" else ax - root
    masses = "{name} = {{ mass = 0.2, center = [13.8, 0], inertia = 1.0e-5 }}\n" \
             "{rod} = {{ mass = 0.5, center = [20, 5], inertia = 2.0e-4 }}\n{slider} = {{ mass = 0.3 }}"
    named = f"""type = "linkage"
[linkage]
mechanism = "slider-crank"
input = {a!r}
coupler = {b!r}
offset = {e!r}
branch = "{branch}"
[motion]
input_speed = 20
steps = 24
""" + LOADS.format(force="output_force = -50", masses=masses.format(name="input", rod="coupler", slider="slider"))
    drawn = f"""type = "linkage"
[linkage]
mechanism = "drawn"
[joints]
A0 = {{ at = [0, 0], ground = true }}
A = {{ at = [{ax!r}, {ay!r}] }}
B = {{ at = [{s!r}, {e!r}], slider = 0 }}
[links]
crank = ["A0", "A"]
rod = ["A", "B"]
[drive]
crank = {{ speed = 20 }}
[motion]
steps = 24
output = "B"
""" + LOADS.format(force="forces = { B = [-50, 0] }", masses=masses.format(name="crank", rod="rod", slider="B"))
    sc, dr = run(tmp_path, "named", named), run(tmp_path, "drawn", drawn)
    t, closure = sc["transmission"], dr["transmission"]["closures"]["B"]
    for key in ("min", "max", "input_at_min", "input_at_max"):
        same(t[key], closure[key], f"transmission {key}")
    m, slider = sc["motion"], dr["motion"]["sliders"]["B"]
    assert m["input_full_turn"] == dr["motion"]["input_full_turn"]
    if not m["input_full_turn"]:
        same(m["input_range"], dr["motion"]["input_range"], "input_range")
    same(m["slider_range"], slider["range"], "slider_range", a + b)
    same(m["stroke"], slider["stroke"], "stroke", a + b)
    if "time_ratio" in m:
        same(m["time_ratio"], slider["time_ratio"], "time_ratio")
    for row, drow in zip(sc["kinematics"], dr["kinematics"]):
        where = f"row at input {row['input']}"
        same(row["input"], drow["input"], where)
        same(row["coupler"], drow["links"]["rod"]["angle"], f"{where}: rod angle")
        same(row["coupler_velocity"], drow["links"]["rod"]["velocity"], f"{where}: rod velocity")
        same(row["coupler_acceleration"], drow["links"]["rod"]["acceleration"], f"{where}: rod acceleration")
        same(row["transmission"], drow["transmission"]["B"], f"{where}: transmission")
        for key, sub in (("slider", "position"), ("slider_velocity", "velocity"),
                         ("slider_acceleration", "acceleration")):
            same(row[key], drow["sliders"]["B"][sub], f"{where}: {key}", a + b)
    _same_forces(sc["forces"], dr["forces"], {"A0": "A0", "A": "A", "B": "B", "guide": "B/guide"})
