"""Problem files: read TOML, check it against the schema, build a frozen problem.

`load(path)` returns the frozen problem of the file's type or raises `InputErrors`
holding every error found in the file. The type's vocabulary comes from
`linkcli.registry`, its checks from `linkcli.types.<type>.schema.parse(root, meta)`.
No numerics here.
"""

from __future__ import annotations

import difflib
from dataclasses import replace

from linkcli.errors import InputErrors
from linkcli.io.angle_units import angle_unit_note
from linkcli.io.misplaced_keys import refuse_misplaced_type
from linkcli.io.reader import MISSING, Reader
from linkcli.reading.meta import read_meta
from linkcli.reading.result_file import refuse_result_file
from linkcli.registry import NAMES, problem_type


def load(path: str, text: str | bytes | None = None):
    """Read and validate one problem file; raise InputErrors with every problem found."""
    reader = Reader(path, text)
    refuse_result_file(reader)
    root = reader.root()
    kind = root.raw("type", None)
    if not isinstance(kind, str) or kind not in NAMES:
        refuse_misplaced_type(reader, kind)
        hint = difflib.get_close_matches(kind, list(NAMES), n=1) if isinstance(kind, str) else []
        extra = f' (did you mean "{hint[0]}"?)' if hint else ""
        root.error("type", f"one of: {', '.join(NAMES)}{extra}", MISSING if kind is None else kind)
        raise InputErrors(reader.errors)
    refuse_unknown_mechanism(reader, root)
    kind_spec = problem_type(kind)
    meta = read_meta(root, kind, kind_spec)
    problem = kind_spec.module("schema").parse(root, meta)
    reader.finish()
    if problem is None:  # a parser returns None only after recording errors
        raise AssertionError(f"{kind} parser returned no problem and no error")
    if meta.tolerance is not None:  # what synth would refuse once solved, if the file fixes it
        from linkcli.reading.tolerance_lengths import check_lengths, known_lengths
        check_lengths(meta, *known_lengths(problem))
    note = angle_unit_note(reader.data, meta.units.angle)
    if note:
        problem = replace(problem, meta=replace(problem.meta, notes=problem.meta.notes + (note,)))
    return problem


def refuse_unknown_mechanism(reader: Reader, root) -> None:
    """A [linkage] `mechanism` that no mechanism is named: that one located line (with its
    did-you-mean), and nothing more. Every other table is read by the mechanism's vocabulary
    (joints, links, drives, [motion]): judged as another mechanism's, a misspelled "drawn"
    gave eleven more lines, each blaming a correct key. So is a topology without
    mechanism = "drawn": one line saying so."""
    from linkcli.mechanisms import NAMES as MECHANISMS
    from linkcli.reading.linkage import read_mechanism
    link = root.data.get("linkage")
    if isinstance(link, dict) and "mechanism" in link and link["mechanism"] not in MECHANISMS:
        read_mechanism(root.table("linkage"))  # records the line
        raise InputErrors(reader.errors)
    from linkcli.mechanisms import schema_of
    from linkcli.mechanisms.schema import mechanism_of
    if isinstance(link, dict) and "topology" in link and not schema_of(mechanism_of(root)).draws:
        # a topology is a drawing's: read as the four-bar's, it gave seven lines, none saying so
        found = f'mechanism = "{link["mechanism"]}"' if "mechanism" in link else 'no mechanism (the four-bar)'
        root.table("linkage").error("topology", 'mechanism = "drawn" with a topology (a topology is a drawn '
                                    "linkage's: docs/six_bars.md)", raw_got=found)
        raise InputErrors(reader.errors)


def load_for_analysis(path: str, text: str | bytes | None = None):
    """`linkcli analyze`: a `type = "linkage"` file or a result file of `synth --format toml`."""
    from linkcli.errors import SchemaError
    from linkcli.reading import result_file
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
