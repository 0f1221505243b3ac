"""[sections], [material] and [strength] (docs/strength.md), read in one place; the pins'
sizes come from [joints] (linkcli.io.joints). Pure Python (`check` reads them without numpy).

    [sections]  <link> = { width = 12, thickness = 4 }   rectangle: width in the plane of motion
                <link> = { diameter = 10 }               round bar
                <link> = { diameter = 12, wall = 1.5 }   tube
    [material]  name = "AISI 1045 CD"                    one of linkcli.materials.MATERIALS, or
                ultimate, yield, endurance, modulus      MPa (each overrides the named value)
    [strength]  required = 1.5                           the factor every part must reach
                criterion = "goodman"                    | gerber | soderberg | asme-elliptic

[sections] alone is a drawing's data (link widths); [material] turns the `strength` section on,
and needs the load cycle ([loads] or [masses]) and at least one sized part.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from linkcli.io.bounds import bounded_length
from linkcli.io.reader import MISSING, Table

if TYPE_CHECKING:  # names of annotations only (imported where they are used)
    from linkcli.model.strength import LinkSection, StrengthSpec

CRITERIA = ("goodman", "gerber", "soderberg", "asme-elliptic")
MATERIAL_KEYS = ("ultimate", "yield", "endurance", "modulus")
MATERIAL_WORDS = {"ultimate": "an ultimate tensile strength > 0 (MPa)",
                  "yield": "a tensile yield strength > 0 (MPa)",
                  "endurance": "a fully reversed endurance strength > 0 (MPa), corrected for the part",
                  "modulus": "a Young's modulus > 0 (MPa)"}
MAX_STRESS = 1e7  # MPa: beyond any material
MAX_FACTOR = 1e3
STRENGTH_TABLES = ("sections", "material", "strength")


def read_parts(root: Table, kind: str, allowed: tuple[str, ...], asked: tuple[str, ...],
               has_loads: bool, mechanism: str, joints) -> tuple[dict, StrengthSpec | None]:
    """(link sections, strength spec) of a file; refused, located, on a type whose result is
    no linkage (`allowed`, its report sections, lack `strength`). The spec is None without
    [material] (or when in error: errors recorded)."""
    if "strength" not in allowed:
        _refuse(root, kind)
        return {}, None
    sections = read_link_sections(root, mechanism)
    material = root.table("material")
    if material is None:
        for name in ("strength",):
            if name in root:
                root.raw(name)
                root.error(name, f"a [material] table with [{name}] (the strengths it checks "
                           "against)", raw_got="no [material] table")
        if "strength" in asked:
            root.reader.error(("report", "sections"), 'a [material] table for the "strength" '
                              "section (the strengths to check against)", raw_got="none")
        return sections, None
    errors = len(root.reader.errors)
    spec = read_material(material)
    options = root.table("strength")
    required, criterion = 1.0, "goodman"
    if options is not None:
        required = options.number("required", 1.0, lo=1.0, hi=MAX_FACTOR,
                                  what="a required safety factor")
        criterion = options.string("criterion", "goodman", choices=CRITERIA)
    if not has_loads:
        root.reader.error(("material",), "a [loads] or [masses] table with [material] (the "
                          "strength section checks the parts over their load cycle)",
                          raw_got="neither")
    _check_sizes(root, joints or (), sections)
    if spec is None or required is None or criterion is None or len(root.reader.errors) > errors:
        return sections, None
    line_of = root.reader.line_of
    lines = {name: line_of((name,)) for name in ("material", "strength", "sections", "joints")}
    from dataclasses import replace
    return sections, replace(spec, required=required, criterion=criterion, lines=lines)


def _refuse(root: Table, kind: str) -> None:
    from linkcli.registry import NAMES, problem_type
    with_linkage = ", ".join(n for n in NAMES if "strength" in problem_type(n).sections)
    for name in STRENGTH_TABLES:
        if name in root:
            root.raw(name)
            root.error(name, f"a problem whose result is a linkage ({with_linkage}) for [{name}]",
                       raw_got=f'type = "{kind}", which has no linkage')


def read_material(t: Table) -> StrengthSpec | None:
    """[material]: a listed `name` (each value given overrides the listed one) or all four
    values; yield and endurance at most the ultimate. None when in error (errors recorded)."""
    from linkcli import materials
    from linkcli.model import StrengthSpec
    errors = len(t.reader.errors)
    named = "name" in t
    name = t.string("name", None, max_len=100)
    base = None
    if name is not None:
        found = materials.lookup(name)
        if found is None:
            hint = materials.suggestion(name)
            extra = f' (did you mean "{hint}"?)' if hint else ""
            t.error("name", f"a material of the list ({', '.join(materials.MATERIALS)}), or the "
                    f"values {', '.join(MATERIAL_KEYS)}{extra}", name)
        else:
            name, base = found
    values = {key: _bounded(t, key, None if named else MISSING, MAX_STRESS, MATERIAL_WORDS[key])
              for key in MATERIAL_KEYS}
    if len(t.reader.errors) > errors:
        return None
    listed = {"ultimate": base.ultimate, "yield": base.yield_, "endurance": base.endurance,
              "modulus": base.modulus} if base else {}
    pick = {k: values[k] if values[k] is not None else listed[k] for k in MATERIAL_KEYS}
    for key in ("yield", "endurance"):
        if pick[key] > pick["ultimate"]:
            t.error(key if key in t else "ultimate", f"a {key} strength at most the ultimate strength",
                    raw_got=f"{key} {pick[key]:g} MPa and ultimate {pick['ultimate']:g} MPa")
            return None
    return StrengthSpec(ultimate=pick["ultimate"], yield_=pick["yield"], endurance=pick["endurance"],
                        modulus=pick["modulus"], name=name if base else None,
                        source=base.source if base else None,
                        endurance_listed=base is not None and values["endurance"] is None)


def read_link_sections(root: Table, mechanism: str) -> dict[str, LinkSection]:
    """[sections]: one cross-section per link the mechanism has (`links` of its schema; a
    drawing's own [links], or a design's result's kept [linkage.links]: `check` names a link
    the drawing has not, as `analyze` does)."""
    t = root.table("sections")
    if t is None:
        return {}
    from linkcli.io.joints import named_tables
    from linkcli.mechanisms import schema_of
    schema = schema_of(mechanism)
    names, label = (None, mechanism) if schema.draws else (schema.links, mechanism)
    if schema.draws:
        kept = root.data.get("linkage") if "status" in root.data else None
        raw = kept.get("links") if isinstance(kept, dict) else root.data.get("links")
        if isinstance(raw, dict) and raw and all(isinstance(k, str) and k for k in raw):
            names, label = list(raw), "drawing"  # a drawing in error names nothing: its own lines say why
    entries = named_tables(t, names, "link", label, "{ width = 12, thickness = 4 } or { diameter = 10 }")
    out = {}
    for link, section in entries or ():
        shape = _section(section, root.reader.line_of(("sections", link)))
        if shape is not None:
            out[link] = shape
    return out


SHAPES = "width and thickness (a rectangle), or diameter (a round bar; with wall, a tube)"


def _section(t: Table, line) -> LinkSection | None:
    """One cross-section from its keys; None when in error (recorded)."""
    from linkcli.model import LinkSection
    rectangle = "width" in t or "thickness" in t
    if rectangle and ("diameter" in t or "wall" in t):
        t.allow("width", "thickness", "diameter", "wall")
        t.error(None, f"either {SHAPES}", raw_got=f"keys {', '.join(k for k in t.keys())}")
        return None
    if rectangle:
        width = _length(t, "width", "a width > 0 in the plane of motion (length unit)")
        thickness = _length(t, "thickness", "a thickness > 0 normal to the plane of motion (length unit)")
        if width is None or thickness is None:
            return None
        return LinkSection("rectangle", width=width, thickness=thickness, line=line)
    if "diameter" not in t:
        t.allow("wall")
        t.error(None, SHAPES, raw_got=f"keys {', '.join(t.keys())}" if t.keys() else "an empty table")
        return None
    diameter = _length(t, "diameter", "a diameter > 0 (length unit)")
    wall = _length(t, "wall", "a tube wall > 0 (length unit)", required=False)
    if diameter is None or (wall is None and "wall" in t):
        return None
    if wall is None:
        return LinkSection("round", diameter=diameter, line=line)
    if wall >= diameter / 2:
        t.error("wall", "a tube wall thinner than half the diameter (a solid bar: leave wall out)",
                raw_got=f"wall {wall:g} with diameter {diameter:g}")
        return None
    return LinkSection("tube", diameter=diameter, wall=wall, line=line)


def _length(t: Table, key: str, what: str, required: bool = True):
    """A section's length within [MIN_LENGTH, MAX_LENGTH] (`io.bounds.bounded_length`); None when
    bad (recorded) or absent and optional."""
    return bounded_length(t, key, MISSING if required else None, what)


def _bounded(t: Table, key: str, default, most: float, what: str):
    """A positive number at most `most`; None when bad (recorded) or absent with default None."""
    value = t.number(key, default, positive=True, what=what)
    if value is not None and value > most:
        t.error(key, f"{what}, at most {most:g}", value)
        return None
    return value


def _check_sizes(root: Table, joints, sections: dict) -> None:
    """With the strength section on: a pin sized for it has both diameter and width, and at
    least one part is sized."""
    sized = 0
    for joint in joints:
        has = {"diameter": joint.diameter is not None, "width": joint.width is not None}
        if has["diameter"] and has["width"]:
            sized += 1
        elif has["diameter"] or has["width"]:
            need = "width" if has["diameter"] else "diameter"
            what = ("a bearing width with the pin diameter (the strength section checks bearing "
                    "F / (d w))" if need == "width" else
                    "a pin diameter with the bearing width (the strength section checks shear "
                    "and bearing)")
            root.reader.error(("joints", joint.name, need), what,
                              raw_got=f"{'diameter' if need == 'width' else 'width'} only")
    if not sized and not sections and "joints" not in root and "sections" not in root:
        kept = root.data.get("linkage") if "status" in root.data else None  # a design's result: its drawing
        pins = "[linkage.joints]" if isinstance(kept, dict) and isinstance(kept.get("joints"), dict) else "[joints]"
        root.reader.error(("material",), f"part sizes with [material]: {pins} pin diameters and "
                          "widths, or [sections] link cross-sections", raw_got="neither")


def describe_section(section: LinkSection) -> str:
    """The cross-section in words, length unit: "rectangle 12 x 4", "round 10", "tube 12 x 1.5"."""
    if section.shape == "rectangle":
        return f"rectangle {section.width:g} x {section.thickness:g}"
    if section.shape == "tube":
        return f"tube {section.diameter:g} x {section.wall:g}"
    return f"round {section.diameter:g}"


