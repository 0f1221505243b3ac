"""One home per mechanism (issue 29): shared code calls the protocol and never asks which
mechanism it holds. Read from the source itself (imports and names, by ast), so a shortcut
through a home's private module, a class check or a mechanism's name in shared code fails here.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from linkcli import mechanisms

SRC = Path(mechanisms.__file__).resolve().parent.parent
SHARED = sorted([*(SRC / "analysis").glob("*.py"), *(SRC / "io").glob("*.py"), SRC / "plots" / "common.py",
                 SRC / "plots" / "forces.py", SRC / "plot.py", SRC / "pipeline.py", SRC / "cli.py",
                 SRC / "bench.py", *(SRC / "mechanisms").glob("*.py")])
HOMES = tuple(mechanisms.PACKAGES.values())
LINKAGE_CLASSES = ("FourBar", "SliderCrank")


def _modules_imported(tree) -> set[str]:
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            out.add(node.module)
            out.update(f"{node.module}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
    return out


@pytest.mark.parametrize("path", SHARED, ids=lambda p: str(p.relative_to(SRC)))
def test_shared_code_never_reaches_into_a_home(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    reached = {m for m in _modules_imported(tree) for home in HOMES
               if m.startswith(f"linkcli.mechanisms.{home}")}
    assert not reached, f"{path.name} imports a mechanism's home directly: {sorted(reached)}"
    names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    names |= {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
    asked = names & {*LINKAGE_CLASSES, "is_slider_crank", "abe", "abcd"}
    assert not asked, f"{path.name} asks which mechanism it holds: {sorted(asked)}"
    literals = {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, str)}
    named = literals & set(mechanisms.NAMES)
    if path.name != "__init__.py" or path.parent.name != "mechanisms":  # the registry names them
        assert not named, f"{path.name} names a mechanism: {sorted(named)}"


@pytest.mark.parametrize("name", mechanisms.NAMES)
def test_every_home_implements_the_protocol_and_the_light_modules(name):
    from linkcli.mechanisms.protocol import Mechanism
    home = mechanisms.module(name, "home").HOME
    assert issubclass(home, Mechanism) and not getattr(home, "__abstractmethods__", None)
    assert home.name == name
    from linkcli.mechanisms.schema import Schema
    schema = mechanisms.schema_of(name)
    assert isinstance(schema, Schema) and schema.name == name
    assert type(schema).read is not Schema.read, f"{name}'s schema reads no [linkage]"
    assert type(schema).class_block is not Schema.class_block, f"{name}'s schema lays out no class table"
    assert schema.output in ("angle", "length") and schema.class_keys
    assert set(schema.masses) >= set(schema.point_masses)
