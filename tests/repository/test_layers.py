"""The house map stays true (issue 48): docs/architecture.md's floor table names every package
and top-level module of src/linkcli/, and nothing that does not exist; every import -- at module
level or inside a function, read from the source by ast -- goes to the importer's own floor or
below; and no import cycle spans two packages; inside a package, only the cycles named in
KNOWN_CYCLES (and docs/architecture.md) remain.

A dynamic import by name (importlib, as the registries load a type's or a home's modules on
demand) is not an edge: that is how a lower floor reaches what stands above it without
depending on it.
"""

from __future__ import annotations

import ast
import re
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "src" / "linkcli"
MAP = ROOT / "docs" / "architecture.md"
FLOOR_ROW = re.compile(r"^\|\s*(\d+)\s*\|([^|]*)\|")


def floors() -> dict[str, int]:
    """Place (a package, or a top-level module without .py) -> its floor, from the first
    column of the floor table of docs/architecture.md (rows `| N | `place`, `place` | ... |`)."""
    out: dict[str, int] = {}
    for line in MAP.read_text(encoding="utf-8").splitlines():
        m = FLOOR_ROW.match(line)
        if m:
            for place in re.findall(r"`([a-z_]+)(?:/|\.py)?`", m.group(2)):
                out[place] = int(m.group(1))
    return out


def places() -> set[str]:
    """Every package and top-level module of src/linkcli (the package's own __init__ is
    `linkcli`, its face)."""
    out = {p.name for p in SRC.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    out |= {p.stem for p in SRC.glob("*.py") if p.stem != "__init__"}
    return out


def module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in SRC.rglob("*.py")}


def imports() -> dict[str, set[str]]:
    """Module -> the linkcli modules it imports (a `from pkg import name` of a submodule
    counts as that submodule)."""
    mods = modules()
    out: dict[str, set[str]] = {}
    for name, path in mods.items():
        edges: set[str] = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.split(".")[0] == "linkcli":
                for alias in node.names:
                    sub = f"{node.module}.{alias.name}"
                    edges.add(sub if sub in mods else node.module)
            elif isinstance(node, ast.Import):
                edges |= {a.name for a in node.names if a.name.split(".")[0] == "linkcli"}
        out[name] = edges
    return out


def place_of(module: str) -> str:
    """linkcli.io.reader -> io; linkcli.cli -> cli; linkcli -> linkcli."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "linkcli"


def test_the_map_names_every_place_and_only_places_that_exist():
    mapped, real = floors(), places() | {"linkcli"}
    assert not real - set(mapped), f"docs/architecture.md's floor table lacks {sorted(real - set(mapped))}"
    assert not set(mapped) - real, f"docs/architecture.md names what does not exist: {sorted(set(mapped) - real)}"


def test_no_module_imports_a_floor_above_its_own():
    floor = floors()
    upward = sorted(f"{a} (floor {floor[place_of(a)]}) -> {b} (floor {floor[place_of(b)]})"
                    for a, targets in imports().items() for b in targets
                    if floor[place_of(b)] > floor[place_of(a)])
    assert not upward, "imports that run up a floor:\n" + "\n".join(upward)


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Every strongly connected component of more than one module (Tarjan), each sorted."""
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 10 * len(graph)))
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in graph:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return sorted(found)


def test_no_import_cycle_spans_two_packages():
    spanning = [c for c in cycles(imports()) if len({place_of(m) for m in c}) > 1]
    assert not spanning, f"import cycles across packages: {spanning}"


# The cycles left inside one package, named in docs/architecture.md (none today): a new one
# fails here, and so does one undone without its line struck from this list.
KNOWN_CYCLES: list[list[str]] = []


def test_the_cycles_inside_a_package_are_the_known_ones():
    assert cycles(imports()) == sorted(KNOWN_CYCLES)


@pytest.mark.parametrize("case", ["upward", "cycle"])
def test_the_guards_see_what_they_guard(case, monkeypatch):
    """The checks above fail on a house that breaks them (an import from io up to the
    mechanisms; a cycle between two packages), so a pass means something."""
    real = imports()
    fake = {k: set(v) for k, v in real.items()}
    fake["linkcli.io.reader"].add("linkcli.mechanisms.four_bar.schema")
    if case == "cycle":
        fake["linkcli.mechanisms.four_bar.schema"].add("linkcli.io.reader")
    monkeypatch.setattr(sys.modules[__name__], "imports", lambda: fake)
    check = test_no_module_imports_a_floor_above_its_own if case == "upward" else test_no_import_cycle_spans_two_packages
    with pytest.raises(AssertionError):
        check()


def test_a_new_cycle_inside_a_package_is_seen(monkeypatch):
    """A cycle between two modules of one package (types/path_generation's solve and result)
    fails the known-cycles check."""
    fake = {k: set(v) for k, v in imports().items()}
    fake["linkcli.types.path_generation.result"].add("linkcli.types.path_generation.solve")
    monkeypatch.setattr(sys.modules[__name__], "imports", lambda: fake)
    with pytest.raises(AssertionError):
        test_the_cycles_inside_a_package_are_the_known_ones()
