"""--animate: every problem type that yields a linkage (and the flipper) animates; the
frames are counted from the decoded GIF (Pillow) and MP4 (imageio-ffmpeg); the SVG's SMIL
values and the GIF's pixels are checked against an independent closure (tests/cli/test_plot.py's
`closure`, math module only); the SVG is opened in headless Chromium and screenshotted at
two times, the crank found in the pixels where the closure puts it; bytes repeat from run
to run and across processes; bad input is exit 2 before solving where it can be known.

Chromium: Debian's package (`apt-get install chromium`); .ci/run installs it and sets
LINKCLI_NEED_CHROMIUM=1, which turns the skip into a failure.
"""

from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, run_cli
from test_plot import FIREDOOR, closure, handed, solved

pytestmark = pytest.mark.slow  # animations and the browser: the full suite runs them, the fast lane does not

SVG = "{http://www.w3.org/2000/svg}"
INPUT, COUPLER, OUTPUT = "#1f77b4", "#d62728", "#2ca02c"  # plots.common.LINK_COLORS


@pytest.fixture
def mpl():
    return pytest.importorskip("matplotlib")


def gif_frames(data: bytes) -> list[np.ndarray]:
    """Every frame of a GIF as an (h, w, 3) array, with its duration checked."""
    import io

    from PIL import Image
    im = Image.open(io.BytesIO(data))
    frames = []
    for k in range(im.n_frames):
        im.seek(k)
        assert im.info["duration"] == 50
        frames.append(np.asarray(im.convert("RGB")).astype(int))
    return frames


def pixels(frame: np.ndarray, color: str, tol: int = 10) -> np.ndarray:
    """(x, y_up) of the pixels of one flat colour."""
    rgb = [int(color[i:i + 2], 16) for i in (1, 3, 5)]
    ys, xs = np.nonzero(np.all(np.abs(frame - rgb) <= tol, axis=2))
    return np.column_stack([xs, -ys]).astype(float)


def direction_mod_180(pts: np.ndarray) -> float:
    """The direction (deg, [0, 180)) of a thin bar of pixels: its principal axis."""
    c = pts - pts.mean(axis=0)
    w, v = np.linalg.eigh(c.T @ c)
    x, y = v[:, -1]
    return math.degrees(math.atan2(y, x)) % 180.0


def mod_distance(a: float, b: float, period: float) -> float:
    return abs((a - b + period / 2) % period - period / 2)


# ---------------------------------------------------------------- every type animates

EXAMPLES = {  # file, command, frames (120 for a full turn; a rocking drive 2 m - 2, m = min(steps, 61))
    "precision-position four-bar": ("problems/firedoor.toml", "synth", 120),
    "precision-position slider-crank": ("problems/slider_positions.toml", "synth", None),
    "function-generation": ("problems/log_generator.toml", "synth", None),
    "path-generation": ("problems/straight_line.toml", "synth", None),
    "motion-generation": ("problems/motion3.toml", "synth", None),
    "quick-return crank-rocker": ("problems/quick_return.toml", "synth", 120),
    "quick-return slider-crank": ("problems/quick_return_slider.toml", "synth", 120),
    "linkage four-bar": ("problems/firedoor_motion.toml", "analyze", 36),
    "linkage slider-crank": ("problems/slider_crank.toml", "analyze", 36),
    "flipper-cylinder": ("problems/flipper.toml", "synth", 120),
}


@pytest.mark.parametrize("name", list(EXAMPLES))
def test_every_example_animates_as_svg_with_one_frame_a_step(name, mpl):
    """Every type's example: the scene's frames follow the kinematics steps (a full turn
    min(steps, 120), a rocking drive out and back), the still SVG carries the moving group
    with one animation per moving part, and no script."""
    from linkcli.animate.render import render
    from linkcli.animate.scene import scene_of
    path, command, frames = EXAMPLES[name]
    result = solved(path, command)
    scene = scene_of(result)
    n = len(scene.values)
    if frames is not None:
        assert n == frames
    if scene.full_turn:
        np.testing.assert_allclose(np.diff(scene.values), 2 * math.pi / n, atol=1e-12)
    else:  # out over m cell centres and back without repeating the ends
        m = n // 2 + 1
        np.testing.assert_array_equal(scene.values[m:], scene.values[m - 2:0:-1])
        assert n == 2 * min(getattr(result.problem, "steps", 360), 61) - 2
    data = render(scene, ".svg")
    root = ET.fromstring(data)
    assert not list(root.iter(f"{SVG}script")) and b"<script" not in data
    group = next(g for g in root.iter(f"{SVG}g") if g.get("id") == "linkcli-motion")
    moving = [e for e in group if e.tag in (f"{SVG}polyline", f"{SVG}polygon", f"{SVG}circle", f"{SVG}rect", f"{SVG}text")]
    assert len(moving) >= 4
    for element in moving:
        anim = [a for a in element if a.tag in (f"{SVG}animate", f"{SVG}animateTransform")]
        assert len(anim) == 1 and anim[0].get("repeatCount") == "indefinite"
        assert len(anim[0].get("values").split(";")) == n + 1  # the first repeated: a loop
    labels = [g for g in root.iter(f"{SVG}g") if (g.get("id") or "").startswith("linkcli-motion-frame-")]
    assert len(labels) == n  # the frame's drive value, one text a frame


def test_the_flipper_animates_its_platform_and_cylinder(mpl):
    """The flipper has no linkage: its platform (B, A, G) turns about B from start to end
    and the cylinder runs from C to A; its reported pivots are where the frames put them."""
    from linkcli.animate.scene import scene_of
    result = solved("problems/flipper.toml")
    cyl = result.report["cylinder"]
    scene = scene_of(result)
    assert scene.drive.name == "platform angle"
    assert set(scene.frames.links) == {"platform", "cylinder"}
    sk = scene.reference  # the start position (0 deg)
    np.testing.assert_allclose(sk.joints["A"][0], cyl["rod_pivot"], atol=1e-9)
    np.testing.assert_allclose(sk.joints["C"][0], cyl["base_pivot"], atol=1e-9)
    np.testing.assert_allclose(sk.joints["G"][0], [830.0, 500.0], atol=1e-9)
    # the cylinder's length over the frames stays within the reported closed and open lengths
    length = np.hypot(*(scene.frames.joints["A"] - scene.frames.joints["C"]).T)
    assert cyl["min_length"] - 1e-9 <= length.min() and length.max() <= cyl["max_length"] + 1e-9
    # at 90 deg (the end, ghosted) A has turned a quarter turn: (x, y) -> (-y, x)
    np.testing.assert_allclose(scene.ghosts.joints["A"][0], [-cyl["rod_pivot"][1], cyl["rod_pivot"][0]], atol=1e-9)


# ---------------------------------------------------------------- what the frames show

def _svg_values(root, color: str) -> list[np.ndarray]:
    """The per-frame points of the moving polyline drawn in `color`."""
    line = next(e for e in root.iter(f"{SVG}polyline") if e.get("stroke") == color)
    values = next(iter(line)).get("values").split(";")
    return [np.array([[float(v) for v in p.split(",")] for p in frame.split()]) for frame in values]


def test_svg_frames_follow_the_closure(mpl):
    """Frame k of the fire-door closer is input phi = 3k deg: in the SVG's own coordinates
    (y down) the crank has that direction and the rocker end B sits where the loop closure
    puts it, at the scale the ground pivots A0, B0 give (d = 50 mm)."""
    from linkcli.animate.render import render
    from linkcli.animate.scene import scene_of
    a, b, c, d = FIREDOOR
    root = ET.fromstring(render(scene_of(solved("problems/firedoor.toml")), ".svg"))
    crank, rocker = _svg_values(root, INPUT), _svg_values(root, OUTPUT)
    assert len(crank) == 121
    a0, b0 = crank[0][0], rocker[0][0]
    scale = math.hypot(*(b0 - a0)) / d  # points per mm
    assert abs(b0[1] - a0[1]) < 0.01  # the ground line is level
    for k in range(120):
        phi = math.radians(3 * k)
        _, (bx, by), _, _, _ = closure(a, b, c, d, phi)
        np.testing.assert_allclose(crank[k][0], a0, atol=0.006)
        np.testing.assert_allclose(crank[k][1], a0 + scale * np.array([a * math.cos(phi), -a * math.sin(phi)]),
                                   atol=0.02)
        np.testing.assert_allclose(rocker[k][1], a0 + scale * np.array([bx, -by]), atol=0.02)


def test_gif_frames_show_the_crank_and_coupler_at_their_angles(mpl):
    """Decoded GIF: 120 frames of 960 x 640; in frames 0, 17, 45 and 100 the crank's
    pixels (its exact colour, inside the drawing) lie along phi = 3k deg and the coupler's
    along theta of the closure (both modulo 180 deg, the bars' principal axes)."""
    from linkcli.animate.render import render
    from linkcli.animate.scene import scene_of
    a, b, c, d = FIREDOOR
    frames = gif_frames(render(scene_of(solved("problems/firedoor.toml")), ".gif"))
    assert len(frames) == 120 and frames[0].shape == (640, 960, 3)
    for k in (0, 17, 45, 100):
        drawing = frames[k][:, :700]  # left of the legend
        phi = 3.0 * k
        theta = math.degrees(closure(a, b, c, d, math.radians(phi))[2])
        assert mod_distance(direction_mod_180(pixels(drawing, INPUT)), phi, 180.0) < 2.0
        assert mod_distance(direction_mod_180(pixels(drawing, COUPLER)), theta, 180.0) < 2.0
    assert not np.array_equal(frames[0], frames[30])


def test_mp4_decodes_to_one_frame_a_step_and_repeats(tmp_path):
    pytest.importorskip("matplotlib")
    ffmpeg = pytest.importorskip("imageio_ffmpeg")
    first, second = tmp_path / "a.mp4", tmp_path / "b.mp4"
    for target in (first, second):
        code, out, err = run_cli("analyze", "problems/slider_crank.toml", "--animate", str(target))
        assert code == 0, err
    assert first.read_bytes() == second.read_bytes()
    reader = ffmpeg.read_frames(str(first))
    meta = next(reader)
    assert meta["size"] == (960, 640) and meta["fps"] == 20.0
    assert sum(1 for _ in reader) == 36  # [motion] steps = 36


def test_gif_svg_and_dxf_bytes_repeat_across_processes(mpl, tmp_path):
    outputs = []
    for run in ("1", "2"):
        gif, svg = tmp_path / f"{run}.gif", tmp_path / f"{run}.svg"
        for target in (gif, svg):
            res = subprocess.run([sys.executable, "-m", "linkcli", "analyze", "problems/slider_crank.toml",
                                  "--animate", str(target)], capture_output=True, text=True, cwd=ROOT)
            assert res.returncode == 0, res.stderr
        outputs.append((gif.read_bytes(), svg.read_bytes()))
    assert outputs[0] == outputs[1]
    assert len(gif_frames(outputs[0][0])) == 36


# ---------------------------------------------------------------- a browser plays the SVG

CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync",
                  "--hide-scrollbars", "--window-size=960,640"]


def chromium() -> str:
    """Debian's chromium, or a skip (a failure where LINKCLI_NEED_CHROMIUM=1: CI installs it)."""
    exe = shutil.which("chromium") or shutil.which("chromium-browser")
    if exe is None:
        if os.environ.get("LINKCLI_NEED_CHROMIUM") == "1":
            pytest.fail("chromium not found, and LINKCLI_NEED_CHROMIUM=1 (CI installs it: .ci/run)")
        pytest.skip("chromium not installed (apt-get install chromium)")
    return exe


def screenshot(exe: str, url: str, target: Path, profile: Path, *extra: str) -> np.ndarray:
    from PIL import Image
    res = subprocess.run([exe, *CHROMIUM_FLAGS, *extra, f"--user-data-dir={profile}", f"--screenshot={target}", url],
                         capture_output=True, text=True, timeout=120)
    assert target.exists(), res.stderr[-2000:]
    return np.asarray(Image.open(target).convert("RGB")).astype(int)


def test_chromium_plays_the_svg_and_shows_the_crank_where_the_time_puts_it(mpl, tmp_path):
    """The SVG opened by itself renders the linkage; then, paused at t = 0.525 s and
    2.025 s (through the SVG DOM from a page around it: the file itself has no script),
    the crank's pixels point at phi = 360 t / 6 s = 31.5 and 121.5 deg."""
    exe = chromium()
    svg = tmp_path / "door.svg"
    code, _, err = run_cli("synth", "problems/firedoor.toml", "--animate", str(svg))
    assert code == 0, err
    text = svg.read_text()
    m = re.search(r'<polyline points="([\d.]+),([\d.]+) [\d.,]+" fill="none" stroke="#1f77b4"', text)
    a0 = np.array([float(m.group(1)), -float(m.group(2))]) * 96 / 72  # the crank's pivot, CSS px, y up
    direct = screenshot(exe, svg.as_uri(), tmp_path / "direct.png", tmp_path / "p0")
    assert len(pixels(direct[:, :700], INPUT)) > 100
    shots = []
    for k, t in enumerate((0.525, 2.025)):
        page = tmp_path / f"page{k}.html"
        page.write_text(f'<!DOCTYPE html><html><body style="margin:0"><object id="svg" type="image/svg+xml" '
                        f'data="{svg.as_uri()}"></object><script>document.getElementById("svg").addEventListener('
                        f'"load", function () {{ var root = this.contentDocument.documentElement; '
                        f"root.pauseAnimations(); root.setCurrentTime({t}); }});</script></body></html>")
        shot = screenshot(exe, page.as_uri(), tmp_path / f"shot{k}.png", tmp_path / f"p{k + 1}",
                          "--allow-file-access-from-files", "--virtual-time-budget=2000")
        crank = pixels(shot[:, :700], INPUT)
        crank = crank[np.hypot(*(crank - a0).T) < 200]  # the moving crank, not the legend's swatch
        v = (crank - a0).mean(axis=0)
        angle = math.degrees(math.atan2(v[1], v[0])) % 360.0
        assert mod_distance(angle, 360.0 * t / 6.0, 360.0) < 1.5, (t, angle)
        shots.append(shot)
    assert np.abs(shots[0] - shots[1]).sum() > 0


# ---------------------------------------------------------------- bad input

@pytest.mark.parametrize("name, found", [("door.png", '".png"'), ("door", "no extension")])
def test_an_unknown_extension_is_refused_before_solving(tmp_path, name, found):
    target = tmp_path / name
    code, out, err = run_cli("synth", "problems/firedoor.toml", "--animate", str(target))
    assert code == 2 and out == ""  # nothing solved
    assert err == f"{target}: expected a .gif, .mp4 or .svg file name, found {found}\n"


def test_an_unwritable_path_is_refused_before_solving(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    target = blocker / "door.gif"
    code, out, err = run_cli("synth", "problems/firedoor.toml", "--animate", str(target))
    assert code == 2 and out == ""
    assert err == f"{target}: expected an animation path inside a folder, found {blocker} is a file\n"


def test_several_files_need_a_folder_and_fill_it(mpl, tmp_path):
    target = tmp_path / "all.gif"
    code, out, err = run_cli("analyze", "problems/slider_crank.toml", "problems/firedoor_motion.toml",
                             "--animate", str(target))
    assert code == 2 and out == ""
    assert (f"{target}: expected a folder for the animations of 2 files (each written as <problem>.gif), "
            'found a ".gif" file name') in err
    folder = tmp_path / "movies"
    code, _, err = run_cli("analyze", "problems/slider_crank.toml", "problems/firedoor_motion.toml",
                           "--animate", str(folder))
    assert code == 0, err
    assert sorted(p.name for p in folder.iterdir()) == ["firedoor_motion.gif", "slider_crank.gif"]
    assert [len(gif_frames(p.read_bytes())) for p in sorted(folder.iterdir())] == [36, 36]


@pytest.mark.parametrize("module, name, extra, target", [
    ("matplotlib", "matplotlib", "plot", "door.gif"),
    ("imageio_ffmpeg", "imageio-ffmpeg", "video", "door.mp4"),
])
def test_a_missing_library_is_refused_before_solving(monkeypatch, tmp_path, module, name, extra, target):
    monkeypatch.setitem(sys.modules, module, None)  # `import module` now fails
    path = tmp_path / target
    code, out, err = run_cli("synth", "problems/firedoor.toml", "--animate", str(path))
    assert code == 2 and out == ""
    fmt = target.split(".")[1].upper()
    assert err == (f'{path}: expected {name} for --animate {fmt} (pip install "linkcli[{extra}]"), '
                   "found it not installed\n")


def test_a_result_with_nothing_to_move_is_bad_input_naming_the_file(mpl, tmp_path, capsys):
    """A linkage that never assembles (a + b + c < d), and a result without a linkage:
    exit 2, one line each; the other results are still written."""
    from linkcli import exports
    report = {"file": "problems/apart.toml", "title": "Apart", "type": "linkage", "status": "ok", "message": "",
              "units": {"length": "mm", "angle": "deg"},
              "linkage": {"ground": 100.0, "input": 10.0, "coupler": 10.0, "output": 10.0, "branch": "open"}}
    apart = handed(report)
    lost = handed({"file": "problems/lost.toml", "type": "path-generation", "status": "not-converged",
                   "message": "the solver did not converge", "units": {"length": "mm", "angle": "deg"}})
    good = solved("problems/slider_crank.toml", "analyze")
    folder = tmp_path / "movies"
    assert exports.write([apart, lost, good], 3, folder, None, False) == 2
    err = capsys.readouterr().err.splitlines()
    assert err == [f"{folder / 'apart.gif'}: expected a result with a linkage to animate, found problems/apart.toml: "
                   "the linkage cannot assemble at any input angle",
                   f"{folder / 'lost.gif'}: expected a result with a linkage to animate, found problems/lost.toml: "
                   "no linkage in the result (the solver did not converge)",
                   f"problems/slider_crank.toml: animation written to {folder / 'slider_crank.gif'}"]
    assert sorted(p.name for p in folder.iterdir()) == ["slider_crank.gif"]
