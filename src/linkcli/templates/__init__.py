"""Commented template problem files, one per problem type and one per mechanism that has a
file of its own (`linkcli new TYPE [FILE]`: `new five-bar`, `new drawn` write a `type =
"linkage"` file of that mechanism).

Each template is package data, `<name>.toml` beside this module, read with
importlib.resources so that it works from a source tree, an installed wheel or a zip.
Every template is a small realistic problem that passes `linkcli check` and solves
with `linkcli synth` (tests/reading/test_templates.py). No numerics here.
"""

from __future__ import annotations

from importlib import resources

SUFFIX = ".toml"
IN_LINKAGE = ("four-bar", "slider-crank")  # mechanisms the linkage template shows (no file of their own)


def template_names() -> tuple[str, ...]:
    """The names that have a template, sorted: problem types ("linkage", "path-generation")
    and mechanisms ("five-bar", "drawn")."""
    folder = resources.files(__name__)
    return tuple(sorted(entry.name[:-len(SUFFIX)] for entry in folder.iterdir()
                        if entry.name.endswith(SUFFIX) and entry.is_file()))


def template_text(type_name: str) -> str:
    """The template of one problem type as text; KeyError naming the known types when
    there is none."""
    if type_name not in template_names():
        raise KeyError(f"no template for type {type_name!r} (known: {', '.join(template_names())})")
    return resources.files(__name__).joinpath(type_name + SUFFIX).read_text(encoding="utf-8")


def nearest_name(name: str) -> str | None:
    """The template name a near miss means: the same name in another case (`Linkage`), or the
    closest by spelling (difflib, as the schema's "did you mean"); None when nothing is close."""
    import difflib
    names = template_names()
    lowered = {n.lower(): n for n in names}
    if name.lower() in lowered:
        return lowered[name.lower()]
    if name.lower() in IN_LINKAGE:
        return "linkage"
    close = difflib.get_close_matches(name.lower(), list(lowered), n=1, cutoff=0.6)
    return lowered[close[0]] if close else None
