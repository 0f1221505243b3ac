"""--plot: one picture per problem type, checked structurally (PNG signature and IHDR
size, SVG parsed as XML holding its titles and labels), byte-identical from run to run,
and the curves it draws checked against an independent per-sample closure written here
(math module only), not against the code that drew them. No pixel goldens.

The drawing tests need matplotlib (in the `plot` and `test` extras) and skip without it; the tests of
the command line's checks (missing matplotlib, a bad PATH) run everywhere.
"""

from __future__ import annotations

import json
import math
import struct
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from conftest import ROOT, run_cli

SVG = "{http://www.w3.org/2000/svg}"
PNG_SIZE = (1300, 700)  # FIGSIZE 13 x 7 in at 100 dpi


@pytest.fixture
def mpl():
    return pytest.importorskip("matplotlib")


# ---------------------------------------------------------------- independent references

def closure(a, b, c, d, phi, branch="open"):
    """One sample of the loop (the conventions of docs/format.md): (A, B, theta, psi, mu) in the local frame."""
    ax, ay = a * math.cos(phi), a * math.sin(phi)
    rx, ry = ax - d, ay
    rho = math.hypot(rx, ry)
    alpha = math.acos((rho * rho + c * c - b * b) / (2 * rho * c))
    psi = math.atan2(ry, rx) + (-alpha if branch == "open" else alpha)
    bx, by = d + c * math.cos(psi), c * math.sin(psi)
    theta = math.atan2(by - ay, bx - ax)
    mu = math.acos((b * b + c * c - rho * rho) / (2 * b * c))
    return (ax, ay), (bx, by), theta, psi, mu


def coupler_point_global(a, b, c, d, phi, p, pivot, ground_angle):
    """P = A + (px + i py) e^{i theta}, then X = G + R(ground_angle) x."""
    (ax, ay), _, theta, _, _ = closure(a, b, c, d, phi)
    x = ax + p[0] * math.cos(theta) - p[1] * math.sin(theta)
    y = ay + p[0] * math.sin(theta) + p[1] * math.cos(theta)
    g = ground_angle
    return pivot[0] + math.cos(g) * x - math.sin(g) * y, pivot[1] + math.sin(g) * x + math.cos(g) * y


FIREDOOR = (27.6293, 57.2363, 41.1104, 50.0)  # a, b, c, d of problems/firedoor.toml


def function_report(n=31):
    """A function-generation report: the fire-door linkage over 30..150 deg against a law
    that differs from it by 0.3 sin(3 phi) deg."""
    a, b, c, d = FIREDOOR
    rows = []
    for deg in np.linspace(30.0, 150.0, n):
        psi = math.degrees(closure(a, b, c, d, math.radians(deg))[3])
        e = 0.3 * math.sin(3 * math.radians(deg))
        rows.append({"input": float(deg), "target": psi - e, "achieved": psi, "error": e})
    return {"file": "problems/law_demo.toml", "title": "Function generation demo", "type": "function-generation",
            "status": "ok", "message": "solved within every constraint", "units": {"length": "mm", "angle": "deg"},
            "linkage": {"ground": d, "input": a, "coupler": b, "output": c, "branch": "open"},
            "positions": rows}


PATH = {"a": 20.0, "b": 45.0, "c": 40.0, "d": 50.0, "p": (25.0, 18.0), "pivot": (10.0, 5.0), "angle": 30.0}


def path_report():
    """A path-generation report: targets 0.8 mm off the coupler curve of a placed linkage."""
    k = PATH
    rows = []
    for i, deg in enumerate((10, 50, 90, 130, 170, 210)):
        x, y = coupler_point_global(k["a"], k["b"], k["c"], k["d"], math.radians(deg), k["p"], k["pivot"],
                                    math.radians(k["angle"]))
        rows.append({"input": float(deg), "target": [x + 0.8 * math.cos(i), y + 0.8 * math.sin(i)],
                     "achieved": [x, y], "error": 0.8})
    return {"file": "problems/path_demo.toml", "title": "Path generation demo", "type": "path-generation",
            "status": "ok", "message": "solved within every constraint", "units": {"length": "mm", "angle": "deg"},
            "linkage": {"ground": k["d"], "input": k["a"], "coupler": k["b"], "output": k["c"], "branch": "open",
                        "coupler_point": list(k["p"]), "ground_pivot": list(k["pivot"]), "ground_angle": k["angle"]},
            "positions": rows, "error": {"objective": 6 * 0.64, "max": 0.8, "rms": 0.8}}


class FlipperLoad:
    """What the flipper plot reads from a problem: the load and the sweep (rad)."""

    center_of_mass = (830.0, 500.0)
    mass = 2000.0
    gravity = 9.8
    start = 0.0
    end = math.pi / 2


def flipper_report(n=46):
    """Static balance about the hinge B = (0, 0): F (A x e) = m g G_x, e = (A - C)/|A - C|,
    A and G turned by the platform angle; positive F pushes."""
    m, g = FlipperLoad.mass, FlipperLoad.gravity
    a0, c, g0 = (150.0, 800.0), (900.0, 50.0), FlipperLoad.center_of_mass
    rows = []
    for deg in np.linspace(0.0, 90.0, n):
        t = math.radians(deg)
        ax, ay = a0[0] * math.cos(t) - a0[1] * math.sin(t), a0[0] * math.sin(t) + a0[1] * math.cos(t)
        gx = g0[0] * math.cos(t) - g0[1] * math.sin(t)
        length = math.hypot(ax - c[0], ay - c[1])
        ex, ey = (ax - c[0]) / length, (ay - c[1]) / length
        cross = ax * ey - ay * ex
        rows.append({"angle": float(deg), "force": m * g * gx / cross, "arm": abs(cross), "length": length})
    forces = [r["force"] for r in rows]
    k = int(np.argmax(np.abs(forces)))
    lengths = [r["length"] for r in rows]
    cyl = {"rod_pivot": list(a0), "base_pivot": list(c), "peak_force": abs(forces[k]),
           "peak_angle": rows[k]["angle"], "peak_kind": "push" if forces[k] > 0 else "pull",
           "min_length": min(lengths), "max_length": max(lengths), "stroke": max(lengths) - min(lengths),
           "forces": rows}
    return {"file": "problems/flipper_demo.toml", "title": "Flipper demo", "type": "flipper-cylinder",
            "status": "ok", "message": "solved within every constraint", "units": {"length": "mm", "angle": "deg"},
            "cylinder": cyl}


# ---------------------------------------------------------------- structural checks

def png_size(data: bytes) -> tuple[int, int]:
    """Width and height from the IHDR chunk, after checking the PNG signature."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def svg_texts(data: bytes) -> list[str]:
    root = ET.fromstring(data)
    assert root.tag == f"{SVG}svg"
    return ["".join(t.itertext()) for t in root.iter(f"{SVG}text")]


def lines_by_label(fig) -> dict:
    return {ln.get_label(): ln for ax in fig.axes for ln in ax.get_lines()}


def solved(path: str, command: str = "synth"):
    """The pipeline Result of a problem file, as the CLI hands it to the plot."""
    from linkcli.pipeline import Request, run
    outcome = run(path, Request(mode="analyze" if command == "analyze" else "synth", plot=True))
    assert outcome.result is not None, outcome.errors
    return outcome.result


def solved_report(path: str, command: str = "synth") -> dict:
    """The unrounded report of a problem file."""
    return solved(path, command).report


def handed(report: dict, problem=None):
    """A Result holding a hand-made report, as the pipeline hands it to the plot: a problem
    with the report's units (`problem`'s own fields kept) and a Solution holding the
    linkage the report describes (the same hand-made numbers, angles in radians)."""
    from types import SimpleNamespace

    from linkcli.mechanisms.four_bar.model import FourBar
    from linkcli.pipeline import Result
    from linkcli.solution import Solution, Status
    from linkcli.units import Units
    units = Units(**report["units"])
    if getattr(problem, "meta", None) is None:
        fields = {k: getattr(problem, k) for k in dir(problem) if not k.startswith("_")} if problem else {}
        problem = SimpleNamespace(**fields, meta=SimpleNamespace(units=units))
    lk = report.get("linkage")
    linkage = None if lk is None else FourBar(
        ground=lk["ground"], input=lk["input"], coupler=lk["coupler"], output=lk["output"], branch=lk["branch"],
        coupler_point=tuple(lk["coupler_point"]) if "coupler_point" in lk else None,
        ground_pivot=tuple(lk.get("ground_pivot", (0.0, 0.0))),
        ground_angle=math.radians(lk.get("ground_angle", 0.0)))
    return Result(problem, Solution(Status(report["status"]), linkage=linkage), report)


CASES = {
    # type: (report builder, problem, texts the SVG must hold)
    "precision-position": (lambda: solved_report("problems/firedoor.toml"), None,
                           ["Fire-door closer", "output angle \u03c8 (deg)", "input angle \u03c6 (deg)",
                            "input a = 27.63 mm", "targets (3)", "Output angle over the whole motion (input turns fully)"]),
    "function-generation": (function_report, None,
                            ["Function generation demo", "target law (31 points)", "error, achieved \u2212 target (deg)",
                             "Output-angle error: max |error| 0.3 deg, rms "]),
    "path-generation": (path_report, None,
                        ["Path generation demo", "coupler curve", "target points (6)", "x (mm)", "y (mm)",
                         "distance to target (mm)", "coupler point P = (25, 18) mm", "Timing: input angle at each target"]),
    "flipper-cylinder": (flipper_report, FlipperLoad(),
                         ["Flipper demo", "force (kN)", "moment arm (mm)", "length (mm)", "platform angle (deg)",
                          "push (rod in compression)", "pull (rod in tension)", "A (start)", "G (end)"]),
    "linkage": (lambda: solved_report("problems/firedoor_motion.toml", "analyze"), "load",
                ["Fire-door closer: motion at 20 deg/s", "angular velocity (deg/s)",
                 "angular accel. (deg/s\u00b2)", "\u03bc (deg)", "recommended 40..140 deg",
                 "Motion study at a constant input speed of 20 deg/s"]),
}


def _problem(spec, report):
    if spec == "load":
        from linkcli.reading.load import load_for_analysis
        return load_for_analysis(report["file"])
    return spec


@pytest.mark.slow
@pytest.mark.parametrize("kind", list(CASES))
def test_each_type_writes_png_and_svg_identically_twice(kind, mpl, tmp_path):
    from linkcli.plot import render, write
    build, spec, texts = CASES[kind]
    report = build()
    assert report["type"] == kind
    result = handed(report, _problem(spec, report))
    write(result, tmp_path / "plot.png")
    write(result, tmp_path / "plot.svg")
    png = (tmp_path / "plot.png").read_bytes()
    svg = (tmp_path / "plot.svg").read_bytes()
    assert png_size(png) == PNG_SIZE
    found = svg_texts(svg)
    for text in texts:
        assert any(text in f for f in found), (text, found)
    assert render(result, "svg") == svg  # deterministic: identical bytes
    assert b"<dc:date>" not in svg and b"Matplotlib v" not in svg


EXAMPLES = {  # one solved example of each problem type, as the CLI hands it to the plot
    "precision-position": ("problems/firedoor.toml", "synth"),
    "function-generation": ("problems/log_generator.toml", "synth"),
    "path-generation": ("problems/straight_line.toml", "synth"),
    "flipper-cylinder": ("problems/flipper.toml", "synth"),
    "linkage": ("problems/firedoor_motion.toml", "analyze"),
}


@pytest.mark.slow
@pytest.mark.parametrize("kind", list(EXAMPLES))
def test_each_solved_example_plots_to_png_and_svg(kind, mpl):
    """The real reports of problems/ (not hand-made ones) draw without error, in the
    right size, with the problem's title and its type's axis labels in the SVG text."""
    from linkcli.plot import render
    path, command = EXAMPLES[kind]
    result = solved(path, command)
    report = result.report
    assert report["type"] == kind
    assert png_size(render(result, "png")) == PNG_SIZE
    found = svg_texts(render(result, "svg"))
    must = [report["title"]] + {"flipper-cylinder": ["force (kN)", "platform angle (deg)"],
                                "path-generation": ["x (mm)", "y (mm)", "coupler curve"]}.get(
        kind, ["input angle \u03c6 (deg)"])
    for text in must:
        assert any(text in f for f in found), (text, found)


@pytest.mark.slow
def test_svg_bytes_repeat_across_processes(mpl, tmp_path):
    first, second = tmp_path / "a.svg", tmp_path / "b.svg"
    code, _, err = run_cli("synth", "problems/firedoor.toml", "--plot", str(first))
    assert code == 0, err
    res = subprocess.run([sys.executable, "-m", "linkcli", "synth", "problems/firedoor.toml", "--plot", str(second)],
                         capture_output=True, text=True, cwd=ROOT)
    assert res.returncode == 0, res.stderr
    assert first.read_bytes() == second.read_bytes()


# ---------------------------------------------------------------- what the curves say

@pytest.mark.slow
def test_output_curve_meets_the_seed_positions(mpl):
    """The fire-door linkage gives psi = 52, 82, 112 deg at phi = 45, 90, 135 deg (seed)."""
    from linkcli.plot import figure
    fig = figure(solved("problems/firedoor.toml"))
    line = lines_by_label(fig)["achieved output angle"]
    x, y = (np.asarray(v, dtype=float) for v in line.get_data())
    got = np.interp([45.0, 90.0, 135.0], x, y)
    np.testing.assert_allclose(got, [52.0, 82.0, 112.0], atol=1e-2)
    # and anywhere else, the per-sample closure written above
    a, b, c, d = FIREDOOR
    for deg in (-60.0, 10.0, 200.0, 260.0):
        ref = math.degrees(closure(a, b, c, d, math.radians(deg))[3])
        val = float(np.interp(deg, x, y))
        assert abs((val - ref + 180.0) % 360.0 - 180.0) < 1e-2


def test_coupler_curve_is_placed_globally(mpl):
    """Every achieved point (independent closure + placement) lies on the drawn curve."""
    from linkcli.plot import figure
    report = path_report()
    fig = figure(handed(report))
    x, y = (np.asarray(v, dtype=float) for v in lines_by_label(fig)["coupler curve"].get_data())
    ok = np.isfinite(x)
    pts = np.column_stack([x[ok], y[ok]])
    seg0, seg1 = pts[:-1], pts[1:]
    for row in report["positions"]:
        q = np.asarray(row["achieved"])
        t = np.clip(np.einsum("ij,ij->i", q - seg0, seg1 - seg0) / np.einsum("ij,ij->i", seg1 - seg0, seg1 - seg0), 0, 1)
        dist = np.min(np.hypot(*(seg0 + t[:, None] * (seg1 - seg0) - q).T))
        assert dist < 1e-2
    # the drawing's joints follow the same placement
    from linkcli.mechanisms.four_bar.drawing import Geometry
    geo = Geometry.of(handed(report))
    k = PATH
    for deg in (0.0, 77.0, 301.0):
        px, py = (float(v) for v in geo.joints(math.radians(deg))["P"])
        rx, ry = coupler_point_global(k["a"], k["b"], k["c"], k["d"], math.radians(deg), k["p"], k["pivot"],
                                      math.radians(k["angle"]))
        assert math.hypot(px - rx, py - ry) < 1e-9


def test_motion_study_matches_finite_differences_of_the_closure(mpl):
    """omega_4 = (d psi / d phi) omega_2 at 20 deg/s; transmission minimum at phi = 0:
    cos(mu) = (b^2 + c^2 - (d - a)^2) / (2 b c)."""
    from linkcli.plot import figure
    fig = figure(solved("problems/firedoor_motion.toml", "analyze"))
    lines = lines_by_label(fig)
    x, w4 = (np.asarray(v, dtype=float) for v in lines["output \u03c9\u2084"].get_data())
    a, b, c, d = FIREDOOR
    h = 1e-6
    for deg in (30.0, 120.0, 250.0):
        phi = math.radians(deg)
        dpsi = (closure(a, b, c, d, phi + h)[3] - closure(a, b, c, d, phi - h)[3]) / (2 * h)
        assert float(np.interp(deg, x, w4)) == pytest.approx(dpsi * 20.0, rel=1e-3, abs=1e-3)
    _, mu = (np.asarray(v, dtype=float) for v in lines["transmission angle \u03bc"].get_data())
    mu_min = math.degrees(math.acos((b * b + c * c - (d - a) ** 2) / (2 * b * c)))
    assert float(mu.min()) == pytest.approx(mu_min, abs=1e-9)


def test_flipper_force_is_drawn_in_kilonewtons_with_its_peak(mpl):
    from linkcli.plot import figure
    report = flipper_report()
    fig = figure(handed(report, FlipperLoad()))
    x, f = (np.asarray(v, dtype=float) for v in lines_by_label(fig)["cylinder force"].get_data())
    rows = report["cylinder"]["forces"]
    np.testing.assert_allclose(x, [r["angle"] for r in rows])
    np.testing.assert_allclose(f, [r["force"] / 1000.0 for r in rows])
    # the geometry at 90 deg: A (150, 800) turned to (-800, 150), so the arm about B is
    # |A x e| with e along C -> A, C = (900, 50)
    ax, ay, cx, cy = -800.0, 150.0, 900.0, 50.0
    e = np.array([ax - cx, ay - cy]) / math.hypot(ax - cx, ay - cy)
    assert rows[-1]["arm"] == pytest.approx(abs(ax * e[1] - ay * e[0]))
    kx, ky = lines_by_label(fig)["moment arm about B"].get_data()
    assert float(ky[-1]) == pytest.approx(abs(ax * e[1] - ay * e[0]))


@pytest.mark.slow
def test_rocking_input_in_radians_and_metres(mpl, tmp_path):
    """A triple rocker (s + l > p + q): its input rocks between toggles, where the output
    speed grows without bound; the axes stay readable and every label has the file's units."""
    src = tmp_path / "rocker.toml"
    src.write_text('type = "linkage"\ntitle = "Triple rocker"\n[units]\nangle = "rad"\nlength = "m"\n'
                   '[linkage]\nground = 1.0\ninput = 0.8\ncoupler = 0.5\noutput = 0.9\nbranch = "crossed"\n'
                   'coupler_point = [0.3, -0.2]\n[motion]\ninput_speed = 2.0\n')
    target = tmp_path / "rocker.svg"
    code, _, err = run_cli("analyze", str(src), "--plot", str(target))
    assert code == 0, err
    texts = svg_texts(target.read_bytes())
    for text in ("angular velocity (rad/s)", "angular accel. (rad/s\u00b2)", "input angle \u03c6 (rad)", "x (m)",
                 "input a = 0.8 m", "clipped: values grow without bound near the toggles",
                 "Motion study at a constant input speed of 2 rad/s"):
        assert text in texts, text


# ---------------------------------------------------------------- the command line

def test_missing_matplotlib_is_bad_input_with_the_install_hint(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # `import matplotlib` now fails
    target = tmp_path / "door.png"
    code, out, err = run_cli("synth", "problems/firedoor.toml", "--plot", str(target))
    assert code == 2
    assert err == (f'{target}: expected matplotlib for --plot (pip install "linkcli[plot]"), '
                   "found it not installed\n")
    assert "Fire-door closer" in out  # the report itself still prints
    assert not target.exists()


def test_plot_module_and_check_do_not_import_matplotlib():
    """Nor the animation's and the CAD export's libraries (Pillow, imageio-ffmpeg, ezdxf),
    for check and for --help."""
    code = ("import sys; import linkcli.plot, linkcli.plots, linkcli.mechanisms.four_bar.angle_plot, linkcli.types.path_generation.plot, linkcli.types.precision_position.plot, "
            "linkcli.types.flipper_cylinder.plot, linkcli.types.linkage.plot, linkcli.exports, linkcli.animate, linkcli.cad\n"
            "from linkcli.cli import app\n"
            "for args in (['check', 'problems/firedoor.toml'], ['synth', '--help'], ['analyze', '--help']):\n"
            "    try:\n        app(args, prog_name='linkcli')\n    except SystemExit:\n        pass\n"
            "heavy = {'matplotlib', 'PIL', 'ezdxf', 'imageio_ffmpeg'} & set(sys.modules)\n"
            "assert not heavy, heavy")
    subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, cwd=ROOT)


@pytest.mark.parametrize("name, found", [("door.pdf", '".pdf"'), ("door", "no extension")])
def test_one_file_needs_a_png_or_svg_name(tmp_path, name, found):
    target = tmp_path / name
    code, _, err = run_cli("synth", "problems/firedoor.toml", "--plot", str(target))
    assert code == 2
    assert err == f"{target}: expected a .png or .svg file name, found {found}\n"
    assert not target.exists()


def test_several_files_need_a_folder(tmp_path):
    target = tmp_path / "all.png"
    code, _, err = run_cli("synth", "problems/firedoor.toml", "problems/firedoor_motion.toml", "--plot", str(target))
    assert code == 2
    assert (f"{target}: expected a folder for the plots of 2 files (each written as <problem>.png), "
            'found a ".png" file name') in err


@pytest.mark.slow
def test_several_files_write_one_png_each_into_the_folder(mpl, tmp_path):
    folder = tmp_path / "plots"
    code, _, err = run_cli("synth", "problems/firedoor.toml", "problems/firedoor_motion.toml",
                           "--format", "json", "--plot", str(folder))
    assert code == 0, err
    assert sorted(p.name for p in folder.iterdir()) == ["firedoor.png", "firedoor_motion.png"]
    for p in folder.iterdir():
        assert png_size(p.read_bytes()) == PNG_SIZE


@pytest.mark.slow
def test_sections_left_out_of_the_report_are_recomputed_for_the_plot(mpl, tmp_path):
    src = tmp_path / "door.toml"
    src.write_text((ROOT / "problems/firedoor.toml").read_text() + '[report]\nsections = ["grashof"]\n')
    target = tmp_path / "door.svg"
    code, out, err = run_cli("synth", str(src), "--format", "json", "--plot", str(target))
    assert code == 0, err
    assert "linkage" not in json.loads(out)  # the report keeps what the file asked for
    texts = svg_texts(target.read_bytes())
    assert "input a = 27.63 mm" in texts and "targets (3)" in texts


def test_an_unwritable_target_is_bad_input(mpl, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    target = blocker / "door.png"
    code, _, err = run_cli("synth", "problems/firedoor.toml", "--plot", str(target))
    assert code == 2
    assert err == f"{target}: expected a plot path inside a folder, found {blocker} is a file\n"  # before solving
    assert "Traceback" not in err
