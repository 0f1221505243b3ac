"""Commented template problem files, one per problem type (`linkcli new TYPE [FILE]`).

Each template is package data, `<type>.toml` beside this module, read with
importlib.resources so that it works from a source tree, an installed wheel or a zip.
Every template is a small realistic problem that passes `linkcli check` and solves
with `linkcli synth` (tests/reading/test_templates.py). No numerics here.
"""

from __future__ import annotations

from importlib import resources

SUFFIX = ".toml"


def template_names() -> tuple[str, ...]:
    """The problem types that have a template, sorted (e.g. "linkage", "path-generation")."""
    folder = resources.files(__name__)
    return tuple(sorted(entry.name[:-len(SUFFIX)] for entry in folder.iterdir()
                        if entry.name.endswith(SUFFIX) and entry.is_file()))


def template_text(type_name: str) -> str:
    """The template of one problem type as text; KeyError naming the known types when
    there is none."""
    if type_name not in template_names():
        raise KeyError(f"no template for type {type_name!r} (known: {', '.join(template_names())})")
    return resources.files(__name__).joinpath(type_name + SUFFIX).read_text(encoding="utf-8")
