"""Plot titles (issue 28): the numbers of a message rounded as in the report (--precision),
never the private markers of linkcli.textnum, wrapped inside the figure, no warning from
matplotlib on stderr, whatever the title holds."""

from __future__ import annotations

import subprocess
import sys
import warnings

import pytest
from conftest import ROOT

pytest.importorskip("matplotlib")

from linkcli.plots.common import TITLE_CHARACTERS, header_text  # noqa: E402
from linkcli.textnum import CLOSE, OPEN, num  # noqa: E402

INFEASIBLE = {"title": "Quick return, K 1.7, stroke 300", "file": "qr.toml", "type": "quick-return",
              "status": "infeasible",
              "message": f"no member keeps the transmission angle within [{num(29.999999999999996)}, "
                         f"{num(150.0)}] deg over the full turn: the closest, reported, misses it by "
                         f"{num(6.862112345678)} deg"}


def test_the_message_numbers_are_rounded_like_the_report():
    text = header_text(INFEASIBLE, 6)
    assert OPEN not in text and CLOSE not in text
    words = " ".join(text.split())
    assert "[30, 150] deg" in words and "misses it by 6.86211 deg" in words
    assert "29.999999999999996" not in text
    assert "6.862112346 deg" in " ".join(header_text(INFEASIBLE, 10).split())  # --precision 10


@pytest.mark.parametrize("title", [
    "x" * 500,  # one long word
    "A fire-door closer " * 30,
    "cost $5 and $6 per unit",  # mathtext would read this
    "tab\tnewline\nescape\x1b[2J",
    "门 closer ダンパー",  # glyphs DejaVu Sans lacks
])
def test_every_line_fits_the_figure_and_is_plain_text(title):
    report = dict(INFEASIBLE, title=title, message=INFEASIBLE["message"] * 3)
    lines = header_text(report, 6).split("\n")
    assert all(len(line) <= TITLE_CHARACTERS for line in lines)
    assert len(lines) <= 2 + 1 + 3  # title, type and status, message
    assert "\n" not in "".join(lines) and "\x1b" not in "".join(lines)
    assert all("$" not in line.replace(r"\$", "") for line in lines)


@pytest.mark.slow
def test_the_drawn_title_lies_inside_the_figure_without_warnings(tmp_path):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from linkcli.pipeline import Request, run
    from linkcli.plot import figure, render
    problem = tmp_path / "qr.toml"
    problem.write_text('title = "' + "Quick return slider " * 9 + '门"\ntype = "quick-return"\n'
                       'mechanism = "slider-crank"\ntime_ratio = 1.6\nstroke = 250\n'
                       '[constraints]\ntransmission = [30, 150]\n')
    outcome = run(str(problem), Request(plot=True))
    assert outcome.result.report["status"] == "infeasible"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any warning fails the test
        render(outcome.result, "png")
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="Glyph .* missing")  # drawn here, outside render
        fig = figure(outcome.result)
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
    box = fig._suptitle.get_window_extent(canvas.get_renderer())
    assert box.x0 >= 0 and box.x1 <= fig.bbox.width and box.y1 <= fig.bbox.height


@pytest.mark.slow
def test_synth_with_plot_prints_nothing_of_matplotlib(tmp_path):
    problem = tmp_path / "qr.toml"
    problem.write_text('type = "quick-return"\nmechanism = "slider-crank"\ntime_ratio = 1.6\nstroke = 250\n'
                       '[constraints]\ntransmission = [30, 150]\n')
    done = subprocess.run([sys.executable, "-m", "linkcli", "synth", str(problem), "--plot",
                           str(tmp_path / "qr.png"), "--format", "json"], capture_output=True, text=True,
                          cwd=ROOT, env={"PYTHONPATH": str(ROOT / "src"), "PATH": "/usr/bin:/bin"}, timeout=120)
    assert done.returncode == 1  # infeasible, drawn
    assert done.stderr == f"{problem}: plot written to {tmp_path / 'qr.png'}\n"  # where it went, nothing of matplotlib
    assert (tmp_path / "qr.png").stat().st_size > 0
