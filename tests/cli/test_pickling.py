"""What crosses a process boundary (--jobs) or the network (--cluster) pickles: every
LinkcliError subclass with its fields, InputErrors with every error it collects, and an
Outcome with its Result."""

from __future__ import annotations

import importlib
import pickle
import pkgutil

import pytest

import linkcli
from linkcli.errors import (
    InputError,
    InputErrors,
    LinkcliError,
    PlotError,
    SchemaError,
    SolveInputError,
    TomlSyntaxError,
)
from linkcli.expr import ExpressionError


def every_subclass(cls: type) -> set[type]:
    found = set()
    for sub in cls.__subclasses__():
        found |= {sub} | every_subclass(sub)
    return found


ONE_ERROR = SchemaError("a positive length", '"fifty" (string)', path="a.toml", line=3,
                        key="linkage.ground")
EXAMPLES = [
    LinkcliError("--cluster: the Dask scheduler at tcp://h:1 was lost mid-run"),
    InputError("a readable problem file", "No such file or directory", path="nosuch.toml"),
    InputError("either --cluster or --jobs N", "both (--jobs 2)", path="--cluster"),
    TomlSyntaxError("valid TOML", "a syntax error: expected '=' (column 5)", path="a.toml",
                    line=2),
    ONE_ERROR,
    SolveInputError("positions 1 and 2 distinct once wrapped", "both at 45 deg", path="b.toml",
                    line=7, key="positions.input"),
    ExpressionError("an expression in phi", "import (a name)", path="c.toml", line=9,
                    key="target.output"),
    InputErrors([ONE_ERROR, SchemaError("a positive length", "nothing (the key is missing)",
                                        path="a.toml", line=2, key="linkage.input")]),
    PlotError("out.gif: expected a .png or .svg file, found .gif"),
    PlotError("out.png: expected a writable file, found Permission denied", exit_code=1),
]


def fields(error: LinkcliError) -> tuple:
    return (type(error), str(error), error.lines(), error.exit_code,
            *(getattr(error, name, None) for name in ("expected", "got", "path", "line", "key")))


def test_the_examples_cover_every_error_class():
    for info in pkgutil.walk_packages(linkcli.__path__, "linkcli."):
        importlib.import_module(info.name)  # every module that may define an error
    classes = every_subclass(LinkcliError) | {LinkcliError}
    assert classes == {type(error) for error in EXAMPLES}


@pytest.mark.parametrize("error", EXAMPLES, ids=lambda error: type(error).__name__)
def test_every_error_round_trips_through_pickle(error):
    again = pickle.loads(pickle.dumps(error))
    assert fields(again) == fields(error)
    if isinstance(error, InputErrors):
        assert [fields(one) for one in again.errors] == [fields(one) for one in error.errors]
        assert len(again.lines()) == 2


def test_an_outcome_with_its_result_round_trips_through_pickle():
    from linkcli.pipeline import Request, run
    outcome = run("problems/firedoor.toml", Request())
    again = pickle.loads(pickle.dumps(outcome))
    assert again.exit_code == outcome.exit_code == 0
    assert repr(again.result.report) == repr(outcome.result.report)
    assert again.result.problem == outcome.result.problem
    bad = run("tests/no_such_file.toml", Request())
    assert pickle.loads(pickle.dumps(bad)) == bad and bad.exit_code == 2
