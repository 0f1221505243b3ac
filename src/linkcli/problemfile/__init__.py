"""Problem files: read TOML, check it against the schema, build a frozen problem.

`load(path)` returns one of the problem dataclasses of `linkcli.model` or raises
`InputErrors` holding every error found in the file. Each problem type has its own
module here exposing `DEFAULT_SECTIONS`, `SECTIONS` (those it can report) and
`parse(root, meta)`; `TYPES` maps the `type` key to that module. No numerics here.
"""

from __future__ import annotations

import difflib
import importlib

from linkcli.errors import InputErrors
from linkcli.misplaced_keys import refuse_misplaced_type, refuse_result_file
from linkcli.problemfile.common import read_meta
from linkcli.problemfile.reader import MISSING, Reader

TYPES = {
    "precision-position": "precision_position",
    "function-generation": "function_generation",
    "path-generation": "path_generation",
    "flipper-cylinder": "flipper_cylinder",
    "linkage": "linkage",
}


def type_module(name: str):
    return importlib.import_module(f"linkcli.problemfile.{TYPES[name]}")


def load(path: str, text: str | None = None):
    """Read and validate one problem file; raise InputErrors with every problem found."""
    reader = Reader(path, text)
    refuse_result_file(reader)
    root = reader.root()
    kind = root.raw("type", None)
    if not isinstance(kind, str) or kind not in TYPES:
        refuse_misplaced_type(reader, kind)
        hint = difflib.get_close_matches(kind, list(TYPES), n=1) if isinstance(kind, str) else []
        extra = f' (did you mean "{hint[0]}"?)' if hint else ""
        root.error("type", f"one of: {', '.join(TYPES)}{extra}", MISSING if kind is None else kind)
        raise InputErrors(reader.errors)
    module = type_module(kind)
    meta = read_meta(root, kind, module)
    problem = module.parse(root, meta)
    reader.finish()
    if problem is None:  # a parser returns None only after recording errors
        raise AssertionError(f"{kind} parser returned no problem and no error")
    return problem


def load_for_analysis(path: str, text: str | None = None):
    """`linkcli analyze`: a `type = "linkage"` file or a result file of `synth --format toml`."""
    from linkcli.problemfile import result_file
    from linkcli.errors import SchemaError
    reader = Reader(path, text)
    if result_file.is_result(reader.data):
        problem = result_file.parse(reader)
        if reader.errors or problem is None:
            raise InputErrors(reader.errors)
        return problem
    problem = load(path, text)
    if problem.meta.type != "linkage":
        raise SchemaError('type = "linkage" or a result file of synth --format toml',
                          f'"{problem.meta.type}" (solve it with linkcli synth)', path=path,
                          line=reader.line_of(("type",)), key="type")
    return problem
