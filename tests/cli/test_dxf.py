"""--dxf: the file is read back with ezdxf and the reported lengths are found in it to
1e-9 (links as LINE entities, the ground as the distance between the ground pivots'
circles, a slider-crank's offset as the distance from its crank pivot to the guide); the
position drawn, the coupler curve and the targets are checked against the independent
closure of tests/cli/test_plot.py; layers, $INSUNITS, outlines from widths, pin diameters
from [joints], the flipper, repeatable bytes and bad input.
"""

from __future__ import annotations

import math
import sys

import numpy as np
import pytest
from conftest import run_cli
from test_plot import FIREDOOR, closure, solved

ezdxf = pytest.importorskip("ezdxf")

LAYERS = {"GROUND", "PINS", "LINKS", "OUTLINES", "GUIDES", "SLIDERS", "PATHS", "TARGETS", "POSITIONS", "LABELS"}


def written(tmp_path, *args, name="design.dxf"):
    """Run linkcli with --dxf and read the file back."""
    target = tmp_path / name
    code, out, err = run_cli(*args, "--format", "json", "--dxf", str(target))
    assert code in (0, 1), err
    return ezdxf.readfile(target), target


def entities(doc, kind: str, layer: str) -> list:
    return list(doc.modelspace().query(f'{kind}[layer=="{layer}"]'))


def line_lengths(doc, layer: str = "LINKS") -> list[float]:
    return [math.dist(e.dxf.start, e.dxf.end) for e in entities(doc, "LINE", layer)]


def found(lengths: list[float], value: float, tol: float = 1e-9) -> bool:
    return any(abs(v - value) <= tol for v in lengths)


def xy(v) -> np.ndarray:
    return np.array([v.x, v.y])


def cross(u, v) -> float:
    return float(u[0] * v[1] - u[1] * v[0])


def centres(doc, layer: str) -> list[np.ndarray]:
    return [xy(e.dxf.center) for e in entities(doc, "CIRCLE", layer)]


def test_a_four_bar_reads_back_with_its_reported_lengths(tmp_path):
    """Fire-door closer: every layer, millimetres, the three links as lines and the ground
    between the pivots' circles to 1e-9; drawn at the first target (input 45 deg): A and
    B where the closure puts them; the three precision positions on their own layer."""
    a, b, c, d = FIREDOOR
    doc, _ = written(tmp_path, "synth", "problems/firedoor.toml")
    report = solved("problems/firedoor.toml").report["linkage"]
    assert {layer.dxf.name for layer in doc.layers} >= LAYERS
    assert doc.header["$INSUNITS"] == 4 and doc.header["$MEASUREMENT"] == 1  # mm, metric
    links = line_lengths(doc)
    for key in ("input", "coupler", "output"):
        assert found(links, report[key]), (key, links)
    ground = centres(doc, "GROUND")
    assert len(ground) == 2 and abs(math.dist(*ground) - report["ground"]) <= 1e-9
    pins = centres(doc, "PINS")
    (ax, ay), (bx, by), _, _, _ = closure(a, b, c, d, math.radians(45.0))
    for point in ((ax, ay), (bx, by)):
        assert min(math.dist(p, point) for p in pins) < 1e-3  # the seed's lengths to 5 digits
    assert len(line_lengths(doc, "POSITIONS")) == 3 * 3  # three positions, three bars each
    texts = {e.dxf.text for e in doc.modelspace().query('TEXT[layer=="LABELS"]')}
    assert {"A0", "B0", "A", "B"} <= texts and any(t.startswith("input 27.6293") for t in texts)


def test_a_path_generation_result_has_its_curve_and_targets(tmp_path):
    """Straight-line path: the placed linkage's lengths; the target points as POINTs; the
    coupler curve polyline passes through each achieved point (independent closure and
    placement: the distance to the polyline is below its chord error)."""
    doc, _ = written(tmp_path, "synth", "problems/straight_line.toml")
    report = solved("problems/straight_line.toml").report
    lk = report["linkage"]
    links = line_lengths(doc)
    for key in ("input", "coupler", "output"):
        assert found(links, lk[key]), key
    assert abs(math.dist(*centres(doc, "GROUND")) - lk["ground"]) <= 1e-9
    px, py = lk["coupler_point"]
    assert found(links, math.hypot(px, py))  # A-P on the coupler plate
    targets = [xy(e.dxf.location) for e in entities(doc, "POINT", "TARGETS")]
    assert len(targets) == len(report["positions"])
    for row, got in zip(report["positions"], targets):
        np.testing.assert_allclose(got, row["target"], atol=1e-9)
    (curve,) = entities(doc, "LWPOLYLINE", "PATHS")
    pts = np.array([(p[0], p[1]) for p in curve.get_points()])
    a, b, c, d = (lk[k] for k in ("input", "coupler", "output", "ground"))
    g = math.radians(lk["ground_angle"])
    for row in report["positions"]:  # P = A + (px + i py) e^{i theta}, then X = G + R(g) x
        (ax, ay), _, theta, _, _ = closure(a, b, c, d, math.radians(row["input"]), lk["branch"])
        x = ax + px * math.cos(theta) - py * math.sin(theta)
        y = ay + px * math.sin(theta) + py * math.cos(theta)
        q = np.array(lk["ground_pivot"]) + [math.cos(g) * x - math.sin(g) * y, math.sin(g) * x + math.cos(g) * y]
        np.testing.assert_allclose(q, row["achieved"], atol=1e-6)
        assert _to_polyline(pts, q) < 0.05


def _to_polyline(pts: np.ndarray, q: np.ndarray) -> float:
    """The distance from q to the polyline through pts (to its segments, not its vertices:
    a vertex can lie half a segment away where the curve moves fast)."""
    a, b = pts[:-1], pts[1:]
    ab = b - a
    t = np.clip(np.sum((q - a) * ab, axis=1) / np.maximum(np.sum(ab * ab, axis=1), 1e-300), 0.0, 1.0)
    return float(np.min(np.hypot(*(a + t[:, None] * ab - q).T)))


def test_a_slider_crank_has_its_guide_at_the_offset(tmp_path):
    doc, _ = written(tmp_path, "analyze", "problems/slider_crank.toml")
    lk = solved("problems/slider_crank.toml", "analyze").report["linkage"]
    links = line_lengths(doc)
    assert found(links, lk["input"]) and found(links, lk["coupler"])
    (pivot,) = centres(doc, "GROUND")
    (guide,) = entities(doc, "LINE", "GUIDES")
    p, q = xy(guide.dxf.start), xy(guide.dxf.end)
    u = (q - p) / np.linalg.norm(q - p)
    offset = abs(cross(u, pivot - p))
    assert abs(offset - abs(lk["offset"])) <= 1e-9
    assert len(entities(doc, "LWPOLYLINE", "SLIDERS")) == 1


@pytest.mark.parametrize("unit, code, measurement", [("in", 1, 0), ("m", 6, 1), ("cm", 5, 1)])
def test_insunits_follows_the_length_unit(tmp_path, unit, code, measurement):
    src = tmp_path / "rocker.toml"
    src.write_text(f'type = "linkage"\n[units]\nlength = "{unit}"\n[linkage]\nground = 1.0\ninput = 0.8\n'
                   'coupler = 0.5\noutput = 0.9\nbranch = "crossed"\ncoupler_point = [0.3, -0.2]\n')
    doc, _ = written(tmp_path, "analyze", str(src))
    assert doc.header["$INSUNITS"] == code and doc.header["$MEASUREMENT"] == measurement
    links = line_lengths(doc)
    assert found(links, 0.8) and found(links, 0.5) and found(links, 0.9)


def test_joint_diameters_size_the_pin_circles(tmp_path):
    src = tmp_path / "door.toml"
    src.write_text('type = "linkage"\n[linkage]\nground = 50\ninput = 27.6293\ncoupler = 57.2363\noutput = 41.1104\n'
                   '[joints]\nA = { diameter = 8 }\nB0 = { diameter = 10 }\n')
    doc, _ = written(tmp_path, "analyze", str(src))
    radii = {e.dxf.layer + str(round(e.dxf.center[0], 3)): e.dxf.radius for e in doc.modelspace().query("CIRCLE")}
    assert radii["GROUND50.0"] == 5.0
    assert 4.0 in [e.dxf.radius for e in entities(doc, "CIRCLE", "PINS")]


def test_link_widths_draw_outlines(tmp_path):
    """cad.dxf.render with widths: a bar's outline is two lines parallel to it at half
    the width and two half circles of that radius round its pins."""
    from linkcli.animate.scene import scene_of
    from linkcli.cad.dxf import render
    target = tmp_path / "wide.dxf"
    target.write_bytes(render(scene_of(solved("problems/firedoor.toml")), widths={"input": 8.0}))
    doc = ezdxf.readfile(target)
    lines = entities(doc, "LINE", "OUTLINES")
    arcs = entities(doc, "ARC", "OUTLINES")
    assert len(lines) == 2 and len(arcs) == 2
    a = solved("problems/firedoor.toml").report["linkage"]["input"]
    for line in lines:
        start, end = xy(line.dxf.start), xy(line.dxf.end)
        assert abs(np.linalg.norm(end - start) - a) < 1e-9
        assert abs(abs(cross(end - start, start)) / a - 4.0) < 1e-9  # 4 from the line through A0 = (0, 0)
    for arc in arcs:
        assert arc.dxf.radius == 4.0
        assert abs((arc.dxf.end_angle - arc.dxf.start_angle) % 360.0 - 180.0) < 1e-9


def test_the_flipper_draws_platform_and_cylinder_at_the_start(tmp_path):
    """No linkage: the hinge B and base pivot C as ground circles, the rod pivot A (the
    reported one, at the start position) as a pin, the cylinder C-A as long as the force
    table's first row says, G as a point, the end position on POSITIONS."""
    doc, _ = written(tmp_path, "synth", "problems/flipper.toml")
    cyl = solved("problems/flipper.toml").report["cylinder"]
    ground = sorted(tuple(p) for p in centres(doc, "GROUND"))
    np.testing.assert_allclose(ground, sorted([(0.0, 0.0), tuple(cyl["base_pivot"])]), atol=1e-9)
    (pin,) = centres(doc, "PINS")
    np.testing.assert_allclose(pin, cyl["rod_pivot"], atol=1e-9)
    assert found(line_lengths(doc), cyl["forces"][0]["length"], 1e-9)
    (g,) = entities(doc, "POINT", "PATHS")
    np.testing.assert_allclose(xy(g.dxf.location), [830.0, 500.0], atol=1e-9)
    assert len(line_lengths(doc, "POSITIONS")) == 3 + 1  # the platform B-A-G closed, the cylinder


def test_dxf_bytes_repeat(tmp_path):
    first = written(tmp_path, "synth", "problems/motion3.toml", name="a.dxf")[1].read_bytes()
    second = written(tmp_path, "synth", "problems/motion3.toml", name="b.dxf")[1].read_bytes()
    assert first == second


def test_bad_dxf_paths_and_missing_ezdxf_are_refused_before_solving(monkeypatch, tmp_path):
    target = tmp_path / "door.dwg"
    code, out, err = run_cli("synth", "problems/firedoor.toml", "--dxf", str(target))
    assert (code, out) == (2, "") and err == f'{target}: expected a .dxf file name, found ".dwg"\n'
    monkeypatch.setitem(sys.modules, "ezdxf", None)
    target = tmp_path / "door.dxf"
    code, out, err = run_cli("synth", "problems/firedoor.toml", "--dxf", str(target))
    assert (code, out) == (2, "")
    assert err == f'{target}: expected ezdxf for --dxf DXF (pip install "linkcli[cad]"), found it not installed\n'


def test_sections_of_the_file_give_the_outlines(tmp_path):
    """--dxf of a file with [sections]: each sized link's outline on OUTLINES, two lines at
    half its in-plane width from its axis (rectangle width; round bar diameter)."""
    import math

    from conftest import run_cli
    src = tmp_path / "door.toml"
    src.write_text('type = "linkage"\n[linkage]\nground = 50\ninput = 27.6293\ncoupler = 57.2363\n'
                   'output = 41.1104\n[motion]\nsteps = 12\n[loads]\noutput_torque = -20\n'
                   '[sections]\ncoupler = { width = 6, thickness = 3 }\noutput = { diameter = 8 }\n'
                   '[material]\nname = "AISI 1020 HR"\n', encoding="utf-8")
    out = tmp_path / "door.dxf"
    code, _, err = run_cli("synth", str(src), "--dxf", str(out))
    assert code in (0, 1), err
    doc = ezdxf.readfile(out)
    offsets = []
    for line in doc.modelspace().query('LINE[layer=="OUTLINES"]'):
        (x1, y1), (x2, y2) = (line.dxf.start[0], line.dxf.start[1]), (line.dxf.end[0], line.dxf.end[1])
        offsets.append(round(math.hypot(x2 - x1, y2 - y1), 6))
    # two sized links, two straight edges each, as long as the links
    assert sorted(offsets) == sorted([57.2363, 57.2363, 41.1104, 41.1104])


def test_a_drawn_design_is_drawn_where_it_reaches_its_first_target():
    """A drawn design's positions count the drive from its drawn position (timing's
    drawn_drive_angle): the DXF's and the animation's reference is the designed linkage at the
    first target -- the path's tracer on the first achieved point, the dwell's drawing itself
    (its first target at 0) -- and a function's ghosts at its targets show the output at the
    achieved angles. (They were drawn at the offsets read as the drive's own angles: 14 to 50
    mm off.)"""
    from linkcli.animate.scene import evenly, scene_of

    path = solved("problems/drawn_six_bar_path.toml")
    first = path.report["positions"][0]
    scene = scene_of(path)
    np.testing.assert_allclose(scene.reference.joints["P"][0], first["achieved"], atol=1e-9)

    dwell = solved("problems/drawn_dwell.toml")
    rows = dwell.report["positions"]
    assert rows[0]["input"] == 0.0
    scene = scene_of(dwell)
    for joint in dwell.solution.linkage.joints:
        np.testing.assert_allclose(scene.reference.joints[joint.name][0], joint.at, atol=1e-9)
    o6, d = (dwell.solution.linkage.joint(j).at for j in ("O6", "D"))
    drawn = math.atan2(d[1] - o6[1], d[0] - o6[0])
    shown = evenly([r["input"] for r in rows])
    assert len(shown) == len(scene.ghosts.joints["D"]) > 2
    for k, value in enumerate(shown):
        row = next(r for r in rows if r["input"] == value)
        at_o6, at_d = scene.ghosts.joints["O6"][k], scene.ghosts.joints["D"][k]
        turned = math.degrees(math.atan2(at_d[1] - at_o6[1], at_d[0] - at_o6[0]) - drawn)
        assert abs((turned - row["achieved"] + 180.0) % 360.0 - 180.0) < 1e-6
