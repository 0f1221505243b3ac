"""What linkcli's report writer writes in each output section of a result file, found by
running it: the source of src/linkcli/reading/result_keys.py (tests/reading/test_result_keys.py holds
that module equal to `module_text()`; `pytest tests/reading/test_result_keys.py --update-goldens`
rewrites it after a deliberate change of the writer, to be reviewed as a golden is).

Every problem of the corpus -- the examples in problems/, the template of every type
(`linkcli new`) and the variants in tests/data/result_keys/ that reach the writer's optional
keys (a dead point under load, general tolerances, an allocation that misses its limit,
candidates counted by defect, a free timing offset, a five-bar's mode pairs, `--timing`) --
is solved and analysed by the pipeline, its report written as `synth --format toml` writes
it and read back; the keys of every table in it, by section, are the section's keys. Maps
keyed by the linkage's own names (its pins, links, joints, sliders, drives and toleranced
distances: `forces.pins.A0`, `kinematics[].links.rocker`) hold any name: folded into OPEN by
rule (NAMED). The sections `analyze` reads back (result_check.READ) are checked where they
are read, and left out. A new key of the writer that no problem here reaches is not known:
add a variant that reaches it.
"""

from __future__ import annotations

import textwrap
import tomllib

from conftest import ROOT

OPEN = "*"  # a map keyed by the linkage's own names: any key
ROWS = "[]"  # the rows of an array of tables

# key paths (ROWS for the rows of an array) whose keys are names the problem chose or its
# mechanism gives its parts; the rule: a pin, link, joint, slider, drive or toleranced
# distance by name
NAMED = (
    ("forces", "pins"), ("forces", "rows", ROWS, "pins"),
    ("strength", "rows", ROWS, "pins"), ("strength", "rows", ROWS, "links"),
    ("kinematics", ROWS, "links"), ("kinematics", ROWS, "points"), ("kinematics", ROWS, "sliders"),
    ("kinematics", ROWS, "drives"), ("kinematics", ROWS, "transmission"),
    ("transmission", "closures"),
    ("tolerance", "lengths"), ("tolerance", "sensitivity"), ("tolerance", "general_tolerances"),
    ("history", ROWS, "pins"), ("history", ROWS, "elements"), ("history", ROWS, "friction"),
    ("history", ROWS, "drives"), ("events", ROWS, "drives"), ("simulation", "drives"),
    ("balance", "unbalanced", "pins"), ("balance", "balanced", "pins"), ("balance", "counterweights"),
    ("front", "units"), ("front", "rows", ROWS, "objectives"),  # a Pareto front's objectives by name
    ("front", "rows", ROWS, "linkage"),  # each row's design: its mechanism's linkage section
)

VARIANTS = ROOT / "tests" / "data" / "result_keys"


def corpus() -> list[tuple[str, str, bool]]:
    """(name, TOML text, timing) of every problem the keys are found from."""
    from linkcli.templates import template_names, template_text
    files = sorted((ROOT / "problems").glob("*.toml")) + sorted(VARIANTS.glob("*.toml"))
    items = [(p.relative_to(ROOT).as_posix(), p.read_text(encoding="utf-8"), False) for p in files]
    items += [(f"template {name}", template_text(name), False) for name in template_names()]
    items.append(("problems/firedoor.toml --timing", (ROOT / "problems" / "firedoor.toml").read_text(), True))
    return items


def written(name: str, text: str, timing: bool) -> dict:
    """The result file `synth --format toml` writes for one problem, read back."""
    from linkcli.io.export import to_toml
    from linkcli.pipeline import Request, run
    outcome = run(name, Request(mode="synth", timing=timing), text.encode())
    assert outcome.result is not None, (name, outcome.errors)
    return tomllib.loads(to_toml(outcome.result.report, 6))


def _merge(tree: dict, value, path: tuple[str, ...]) -> None:
    """Add the keys of `value` (found at `path`) to `tree`."""
    if isinstance(value, list):
        for item in value:
            if isinstance(item, dict):
                _merge(tree.setdefault(ROWS, {}), item, path + (ROWS,))
        return
    if not isinstance(value, dict):
        return
    if path in NAMED:
        tree = tree.setdefault(OPEN, {})
        for item in value.values():
            _merge(tree, item, path + (OPEN,))
        return
    for key, item in value.items():
        _merge(tree.setdefault(key, {}), item, path + (key,))


def keys_written() -> dict[str, tuple[str, ...]]:
    """section -> the dotted paths of every key the writer writes in it (ROWS for the rows
    of an array of tables, OPEN for a map of names), sorted."""
    from linkcli.reading.result_check import READ
    tree: dict = {}
    for name, text, timing in corpus():
        for section, value in written(name, text, timing).items():
            if isinstance(value, (dict, list)) and section not in READ:
                _merge(tree.setdefault(section, {}), value, (section,))
    return {section: tuple(sorted(_paths(tree[section]))) for section in sorted(tree) if tree[section]}


def _paths(tree: dict, head: str = "") -> list[str]:
    out = []
    for key, sub in tree.items():
        assert "." not in key, key  # a dotted path names it: no key the writer writes has a dot
        path = f"{head}.{key}" if head else key
        out.extend(_paths(sub, path) if sub else [path])
    return out


HEAD = '''"""The keys linkcli's report writer writes in each output section of a result file.

GENERATED by tests/result_keys_corpus.py, which runs the writer on every example, template
and variant problem (tests/reading/test_result_keys.py holds this module equal to what it finds;
`pytest tests/reading/test_result_keys.py --update-goldens` rewrites it): do not edit by hand.
reading.result_check judges the output sections of a result file by it. Per section, the dotted
path of every key: "[]" stands for the rows of an array of tables, "*" for a map keyed by
the linkage's own names (pins, links, joints, sliders, drives, toleranced distances), which
takes any name.
"""

OPEN = "*"
ROWS = "[]"

'''


def module_text() -> str:
    body = ",\n".join(f"    {section!r}: (\n" + textwrap.fill(
        " ".join(f"{p!r}," for p in paths), width=96, initial_indent=" " * 8, subsequent_indent=" " * 8,
        break_long_words=False, break_on_hyphens=False) + "\n    )" for section, paths in keys_written().items())
    return HEAD + "KEYS = {\n" + body + ",\n}\n"
