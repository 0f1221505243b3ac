"""The atlas file and its cache: round trip, damaged, truncated and foreign files, a cache
that cannot be written, `linkcli atlas build` and its exit codes, the same bytes on every
CPU, and the [solver] atlas key."""

from __future__ import annotations

import errno
import hashlib
import os
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT, run_cli

from linkcli.atlas import cache, store
from linkcli.atlas.build import build

SMALL = 1000


@pytest.fixture(scope="module")
def small_bytes() -> bytes:
    return store.encode(build(SMALL, 0), SMALL, 0)


@pytest.fixture
def small_cache(tmp_path, monkeypatch):
    """A cache folder of its own whose default atlas is SMALL four-bars (built in a blink)."""
    monkeypatch.setenv("LINKCLI_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("LINKCLI_ATLAS", raising=False)
    monkeypatch.setattr(cache, "DEFAULT_SIZE", SMALL)
    cache.forget()
    yield tmp_path
    cache.forget()


def test_round_trip(tmp_path, small_bytes):
    path = tmp_path / "a.bin"
    store.write(str(path), small_bytes)
    header, arrays = store.read(str(path))
    tables = build(SMALL, 0)
    assert header["size"] == SMALL and header["version"] == store.VERSION
    assert np.array_equal(arrays["rings"], tables.rings) and np.array_equal(arrays["arcs"], tables.arcs)
    assert np.array_equal(arrays["lengths"], tables.linkages.lengths.astype(np.float32))
    assert not list(tmp_path.glob(".*.tmp"))  # the temporary file was renamed


@pytest.mark.parametrize("damage, reason", [
    (lambda b: b[:-5], "truncated"),
    (lambda b: b[:len(b) // 2], "truncated"),
    (lambda b: b[:40], "header"),
    (lambda b: b[:-200] + bytes([b[-200] ^ 1]) + b[-199:], "checksum"),
    (lambda b: b + b"x", "longer"),
    (lambda b: b"PK\x03\x04" + b[4:], "not an atlas"),
    (lambda b: b"", "not an atlas"),
    (lambda b: b.replace(b'"version":2', b'"version":1', 1), "version"),
    (lambda b: b.replace(b'"quant":1290', b'"quant":1291', 1), "another build"),
])
def test_damaged_truncated_and_foreign_files_are_refused(tmp_path, small_bytes, damage, reason):
    path = tmp_path / "a.bin"
    path.write_bytes(damage(small_bytes))
    with pytest.raises(store.AtlasFileError) as exc:
        store.read(str(path))
    assert reason in exc.value.reason


def _stderr_lines(capsys) -> list[str]:
    return [line for line in capsys.readouterr().err.splitlines() if line]


def test_first_use_builds_once_and_says_so(small_cache, capsys):
    atlas = cache.get()
    assert atlas is not None and atlas.size == SMALL
    assert cache.get() is atlas  # loaded once per process
    lines = _stderr_lines(capsys)
    assert len(lines) == 1 and "building the coupler-curve atlas" in lines[0] and "not built yet" in lines[0]
    assert os.path.exists(cache.default_path())


@pytest.mark.parametrize("how", ["flip", "truncate", "foreign"])
def test_a_damaged_cache_file_is_built_again(small_cache, small_bytes, capsys, how):
    path = cache.default_path()
    data = {"flip": small_bytes[:-100] + bytes([small_bytes[-100] ^ 255]) + small_bytes[-99:],
            "truncate": small_bytes[:-1000], "foreign": b"hello, not an atlas\n" * 10}[how]
    with open(path, "wb") as handle:
        handle.write(data)
    atlas = cache.get()
    assert atlas is not None
    with open(path, "rb") as handle:
        assert handle.read() == small_bytes  # rebuilt: the very bytes of a fresh build
    lines = _stderr_lines(capsys)
    assert len(lines) == 1 and "building the coupler-curve atlas" in lines[0], lines


def test_an_unwritable_cache_means_no_atlas_said_once(tmp_path, monkeypatch, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("a file where the cache folder would be")
    monkeypatch.setenv("LINKCLI_CACHE_DIR", str(blocker / "cache"))
    cache.forget()
    assert cache.get() is None and cache.get() is None
    lines = _stderr_lines(capsys)
    assert len(lines) == 1 and "cannot write the coupler-curve atlas" in lines[0] and "without the atlas" in lines[0]
    cache.forget()


def test_a_full_disk_means_no_atlas_said_once(small_cache, monkeypatch, capsys):
    def full(path, data):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(store, "write", full)
    assert cache.get() is None and cache.get() is None
    lines = _stderr_lines(capsys)
    assert lines[-1].endswith("searching without the atlas") and "No space left" in lines[-1]
    assert sum("cannot write" in line for line in lines) == 1


def test_a_search_without_a_writable_cache_still_solves(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    env = dict(os.environ, LINKCLI_CACHE_DIR=str(blocker / "cache"))
    res = subprocess.run([sys.executable, "-m", "linkcli", "synth", "problems/bench/closed_curve12.toml",
                          "-f", "json"], capture_output=True, text=True, env=env, cwd=ROOT)
    assert res.returncode == 0
    err = [line for line in res.stderr.splitlines() if line]
    assert len(err) == 1 and "searching without the atlas" in err[0]
    assert '"status": "ok"' in res.stdout


def test_atlas_build_writes_and_refuses_bad_paths(tmp_path):
    out = tmp_path / "atlas.bin"
    code, stdout, err = run_cli("atlas", "build", "--out", str(out), "--size", str(SMALL))
    assert code == 0 and err == "" and str(out) in stdout
    assert store.read(str(out))[0]["size"] == SMALL
    for path, why in ((tmp_path, "found a folder"), (tmp_path / "no" / "a.bin", "found no folder"),
                      ("/proc/linkcli-atlas.bin", "expected a writable folder")):
        code, stdout, err = run_cli("atlas", "build", "--out", str(path), "--size", str(SMALL))
        assert code == 2 and stdout == "", (path, err)
        assert err.count("\n") == 1 and why in err and "Traceback" not in err
    code, _, err = run_cli("atlas", "build", "--out", str(out), "--size", "10")
    assert code == 2 and "--size" in err


BYTES_PROGRAM = """\
import hashlib, sys
from linkcli.atlas.build import build
from linkcli.atlas import store
sys.stdout.write(hashlib.sha256(store.encode(build(3000, 5), 3000, 5)).hexdigest())
"""


def test_the_same_bytes_with_other_cpu_kernels():
    """numpy without its AVX-512 and AVX2 loops, OpenBLAS with another kernel: the same file."""
    here = hashlib.sha256(store.encode(build(3000, 5), 3000, 5)).hexdigest()
    for extra in ({"NPY_DISABLE_CPU_FEATURES": "X86_V3,X86_V4,AVX512_ICL,AVX512_SPR"},
                  {"OPENBLAS_CORETYPE": "Prescott"}, {"OPENBLAS_CORETYPE": "Haswell"}):
        env = dict(os.environ, **extra)
        res = subprocess.run([sys.executable, "-c", BYTES_PROGRAM], capture_output=True, text=True, env=env)
        assert res.returncode == 0, res.stderr
        assert res.stdout == here, extra


def test_solver_atlas_key(tmp_path):
    base = (ROOT / "problems" / "bench" / "closed_curve12.toml").read_text()
    bad = tmp_path / "bad.toml"
    bad.write_text(base + '\n[solver]\natlas = "yes"\n')
    code, _, err = run_cli("check", str(bad))
    assert code == 2 and "solver.atlas" in err and "true or false" in err
    other = tmp_path / "other.toml"
    other.write_text((ROOT / "problems" / "crank_rocker.toml").read_text() + "\n[solver]\natlas = false\n")
    code, _, err = run_cli("check", str(other))
    assert code == 2 and "atlas" in err  # function generation has no atlas: an unknown key
    good = tmp_path / "good.toml"
    good.write_text(base + "\n[solver]\natlas = false\n")
    assert run_cli("check", str(good))[0] == 0
