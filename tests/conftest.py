"""Shared test setup: the --update-goldens option and a CLI runner."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

# the tests live in folders that mirror the packages; some take an independent reference from
# another test module (test_batch from test_kinematics, test_motion_scoring from
# test_path_closure): every folder is importable, whichever is collected first
for _folder in sorted(p for p in Path(__file__).resolve().parent.iterdir()
                      if p.is_dir() and p.name not in ("golden", "bad", "data", "__pycache__")):
    if str(_folder) not in sys.path:
        sys.path.append(str(_folder))

from linkcli.pipeline import single_threaded_blas  # noqa: E402

single_threaded_blas()  # the BLAS threads of the command line (before numpy is imported)

try:  # property tests draw the same examples on every run and machine: CI's verdict is
    # the one a developer sees (a random draw found a subnormal input once, on one run)
    from hypothesis import settings as _hypothesis_settings

    _hypothesis_settings.register_profile("linkcli", derandomize=True, print_blob=True)
    _hypothesis_settings.load_profile("linkcli")
except ImportError:  # the test extra installs it; without it those tests are skipped
    pass


def pytest_addoption(parser):
    parser.addoption("--update-goldens", action="store_true", default=False,
                     help="rewrite tests/golden/ and tests/bad/*.txt from the current output")


@pytest.fixture
def update_goldens(request) -> bool:
    return request.config.getoption("--update-goldens")


@pytest.fixture(autouse=True)
def _run_from_root(monkeypatch):
    """Every test runs from the repository root, so file names in output are relative."""
    monkeypatch.chdir(ROOT)


def run_cli(*args: str):
    """Run the linkcli app in-process: (exit code, stdout, stderr)."""
    from typer.testing import CliRunner

    from linkcli.cli import app
    result = CliRunner().invoke(app, list(args), catch_exceptions=False)
    return result.exit_code, result.stdout, result.stderr


TEST_CACHE = ROOT / "build" / "test-cache"  # the atlas the tests' free-timing searches use (git-ignored)


def pytest_configure(config):
    """Every test's free-timing search (and every linkcli it starts) uses one atlas, built
    once into TEST_CACHE (kept between sessions; under xdist one worker builds it while the
    others wait on a lock), never the developer's own cache."""
    os.environ.setdefault("LINKCLI_CACHE_DIR", str(TEST_CACHE))
    os.environ.pop("LINKCLI_ATLAS", None)
    folder = Path(os.environ["LINKCLI_CACHE_DIR"])
    folder.mkdir(parents=True, exist_ok=True)
    import fcntl
    with open(folder / ".build-lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        from linkcli.atlas import cache, store
        path = cache.default_path()
        try:
            store.read(path)
        except (OSError, store.AtlasFileError):
            from linkcli.atlas.build import build
            tables = build(cache.DEFAULT_SIZE, cache.DEFAULT_SEED)
            store.write(path, store.encode(tables, cache.DEFAULT_SIZE, cache.DEFAULT_SEED))
