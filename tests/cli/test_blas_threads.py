"""The BLAS threads the command line sets (linkcli.pipeline.single_threaded_blas): one
thread unless the environment names a count, set before numpy is imported. Each case runs
in a fresh interpreter (in this one numpy is loaded already) and asks the OpenBLAS that
numpy loaded for its thread count."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from linkcli.pipeline import BLAS_THREADS

QUERY = """
import ctypes, glob, os, sys
{before}
import numpy
libs = glob.glob(os.path.join(os.path.dirname(numpy.__file__) + '.libs', '*openblas*'))
if not libs:
    print('no-openblas')
    sys.exit(0)
lib = ctypes.CDLL(libs[0])
for name in ('scipy_openblas_get_num_threads64_', 'openblas_get_num_threads64_', 'openblas_get_num_threads'):
    if hasattr(lib, name):
        print(getattr(lib, name)())
        break
else:
    print('no-openblas')
"""


def threads(before: str, **env) -> str:
    clean = {k: v for k, v in os.environ.items() if k not in BLAS_THREADS}
    clean.update(env)
    out = subprocess.run([sys.executable, "-c", QUERY.format(before=before)], capture_output=True,
                         text=True, env=clean, check=True).stdout.strip()
    if out == "no-openblas":
        pytest.skip("numpy is not linked with a bundled OpenBLAS here")
    return out


def test_the_command_line_runs_one_blas_thread():
    """The executor of synth/analyze sets one thread before numpy loads."""
    assert threads("from linkcli.pipeline import executor\nexecutor(1, ['x.toml'], False)") == "1"


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="OpenBLAS caps its threads at the cores")
def test_a_count_in_the_environment_is_kept():
    assert threads("from linkcli.pipeline import single_threaded_blas\nsingle_threaded_blas()",
                   OPENBLAS_NUM_THREADS="2") == "2"


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="one core: one thread either way")
def test_without_the_call_openblas_takes_a_thread_per_core():
    """The reference the first test is measured against: numpy alone starts more than one."""
    assert int(threads("")) > 1
