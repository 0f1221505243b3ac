"""The README is a front door (issue 48): short, its two commands first, its pictures made by
the commands written beside them; every relative link of the documentation leads to a file;
and no file of the repository names a tool that is not part of it or of its dependencies."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest
from conftest import ROOT

README = ROOT / "README.md"
INSTALL_AND_RUN = "python3 -m pip install . && linkcli synth problems/firedoor.toml"
TEST_COMMAND = 'python3 -m pip install -e ".[test]" && python3 -m ruff check && python3 -m mypy && python3 -m pytest -q -n auto'
# Tools a reader of this repository does not have (the names are split so that this file,
# which must hold them, does not name them itself).
OUTSIDE_TOOLS = re.compile("|".join(("farm" + "-", "duplicates" + " --", "hyper" + "fine")), re.IGNORECASE)


def _text(path: Path) -> str:
    return path.read_text(encoding="utf-8")


def _markdown_files() -> list[Path]:
    return [README, ROOT / "CHANGELOG.md", *sorted((ROOT / "docs").glob("*.md")),
            *sorted((ROOT / "benchmarks").glob("*.md"))]


def _links(text: str) -> list[str]:
    """Targets of markdown links and images, outside code blocks and code spans."""
    text = re.sub(r"^```.*?^```", "", text, flags=re.DOTALL | re.MULTILINE)
    text = re.sub(r"`[^`\n]*`", "", text)
    return re.findall(r"!?\[[^\]\n]*\]\(([^)\s]+)\)", text)


def test_readme_is_at_most_250_lines():
    assert len(_text(README).splitlines()) <= 250


def test_readme_first_code_block_holds_the_two_commands():
    block = re.search(r"^```[a-z]*\n(.*?)^```", _text(README), flags=re.DOTALL | re.MULTILINE)
    assert block is not None
    assert block.group(1).splitlines() == [INSTALL_AND_RUN, TEST_COMMAND]
    # and it comes before any section: the commands are the first thing a newcomer reads
    assert _text(README).index("```") < _text(README).index("\n## ")


def test_ci_runs_the_readme_test_command():
    """.ci/run runs the README's test command: its install, its linter, its type checker, then
    its pytest command, as written and in that order (pip may be told to be quiet)."""
    script = "\n".join(line for line in _text(ROOT / ".ci" / "run").splitlines()
                       if not line.lstrip().startswith("#")).replace("pip install -q ", "pip install ")
    *steps, run = TEST_COMMAND.split(" && ")
    assert all(step in script for step in steps) and re.search(rf"{re.escape(run)}\s*$", script, re.MULTILINE)
    assert [script.index(step) for step in steps] == sorted(script.index(step) for step in steps)
    assert script.index(steps[-1]) < script.index(run)


@pytest.mark.parametrize("path", _markdown_files(), ids=lambda p: str(p.relative_to(ROOT)))
def test_every_relative_link_resolves_to_a_file(path):
    missing = []
    for target in _links(_text(path)):
        if re.match(r"[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
            continue  # a web address, or an anchor in the same page
        file = target.split("#", 1)[0]
        if not (path.parent / file).exists():
            missing.append(target)
    assert missing == []


def test_the_link_check_sees_links_and_skips_code():
    text = "See [a](docs/a.md) and ![b](img/b.png#x).\n`[not](this.md)`\n```\n[nor](that.md)\n```\n"
    assert _links(text) == ["docs/a.md", "img/b.png#x"]


def test_readme_links_every_docs_page():
    linked = {Path(t.split("#", 1)[0]).name for t in _links(_text(README)) if t.startswith("docs/")}
    pages = {p.name for p in (ROOT / "docs").glob("*.md")}
    assert pages - linked == set()


def test_gallery_pictures_are_small_and_made_by_the_command_beside_them():
    text = _text(README)
    pictures = [t for t in _links(text) if t.startswith("docs/images/")]
    assert len(pictures) >= 2
    assert any(p.endswith(".png") for p in pictures)
    assert any(p.endswith((".svg", ".gif")) for p in pictures)  # an animation
    for picture in pictures:
        assert (ROOT / picture).stat().st_size < 200_000, picture
        # the command that made it, written beside it
        assert re.search(rf"`linkcli (synth|analyze) problems/\S+\.toml --(plot|animate) {re.escape(picture)}`", text), picture


def _repository_files() -> list[Path]:
    try:
        names = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, check=True).stdout
        return [ROOT / n for n in names.decode().split("\0") if n]
    except (OSError, subprocess.CalledProcessError):  # not a git checkout: every file but caches
        skip = {".git", ".venv", "__pycache__", ".pytest_cache", ".hypothesis"}
        return [p for p in ROOT.rglob("*") if p.is_file() and not skip & set(p.relative_to(ROOT).parts)]


def test_no_file_names_a_tool_outside_the_repository():
    named = []
    for path in _repository_files():
        try:
            text = path.read_text(encoding="utf-8")
        except (UnicodeDecodeError, FileNotFoundError):
            continue  # binary files (pictures, goldens of images); a file deleted but not yet staged
        for number, line in enumerate(text.splitlines(), 1):
            if OUTSIDE_TOOLS.search(line):
                named.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()[:80]}")
    assert named == []


def test_the_outside_tool_check_finds_what_it_looks_for():
    assert OUTSIDE_TOOLS.search("timed with " + "farm" + "-bench --vs")
    assert OUTSIDE_TOOLS.search("HYPER" + "FINE -w 3")
    assert not OUTSIDE_TOOLS.search("python3 benchmarks/compare_commands.py --runs 5")
