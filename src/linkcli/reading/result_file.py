"""Result files written by `linkcli synth --format toml`, read back as a linkage to analyse.

Only `title`, `[units]`, `[linkage]`, `[motion]`'s study, `[loads]`/`[masses]` and the studies
added by hand (a `[tolerance]` without the report's `measure`; `[material]` with `[sections]`,
`[strength]` and a four-bar's `[joints]`) are read; the rest of a result file is linkcli's
own output (status, tables): it is checked, not read (reading.result_check: known top-level
keys, `type` and `status` of their vocabularies, finite numbers, bounded arrays, the keys
the report writer writes in each output section), and unknown keys of the tables read are
errors, as in a problem file. A batch
written by `synth A B --format toml` (`[[result]]` tables) is refused with a clear line:
`analyze` makes one report per file, so each result must be in a file of its own.
"""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING

from linkcli.errors import SchemaError
from linkcli.io.reader import Reader

if TYPE_CHECKING:  # names of annotations only (imported where they are used)
    from linkcli.model.linkage import LinkageProblem

# what parse() reads with is imported there: synth and check import this module for
# refuse_result_file() alone


def refuse_result_file(reader) -> None:
    """synth/check of a result file of `synth --format toml`: one line, not one per key."""
    if is_result(reader.data):
        data = reader.data
        linkage = data.get("linkage")
        drawn = isinstance(linkage, dict) and linkage.get("mechanism") == "drawn" and "joints" not in linkage
        found = ("a result file of a drawn linkage's analysis (its problem file holds the drawing: synth, "
                 "check and analyze read that)" if drawn else
                 "a result file of linkcli synth (analyse it with linkcli analyze)")
        raise SchemaError("a problem file", found, path=reader.path, line=reader.line_of(("status",)))


def is_result(data: dict) -> bool:
    """A result file carries `status` (linkcli's own output key); a problem file never does.
    A batch (`synth A B --format toml`: an array of tables `[[result]]`, one per problem)
    is recognised too, so that `parse` can say what to do with it."""
    return isinstance(data, dict) and ("status" in data or batch_size(data) > 0)


def batch_size(data: dict) -> int:
    """Results in a batch result file (0 when the file is not one)."""
    results = data.get("result") if "type" not in data and "status" not in data else None
    if isinstance(results, list) and results and all(isinstance(r, dict) and "status" in r
                                                     for r in results):
        return len(results)
    return 0


def has_linkage(data: dict) -> bool:
    return isinstance(data.get("linkage"), dict)


def parse(reader: Reader) -> LinkageProblem | None:
    from linkcli.io.bounds import MAX_LENGTH
    from linkcli.model import LinkageProblem, Meta
    from linkcli.reading.linkage import read_linkage
    from linkcli.reading.loads import read_loads
    from linkcli.reading.meta import read_tolerance, read_units
    from linkcli.reading.result_check import check_header, check_sections, check_values
    from linkcli.reading.result_motion import motion_study
    from linkcli.registry import problem_type
    root = reader.root()
    count = batch_size(reader.data)
    if count:
        # one file, one report: `analyze` reads a single result (the CLI's unit is a file)
        root.error("result", "a single result (analyze reads one result per file: write them "
                   "one per file with synth --out DIR --format toml)",
                   raw_got=f"a batch result file holding {count} results")
        return None
    if not check_header(root):  # a wrong type: nothing else can be judged
        return None
    check_values(root)
    check_sections(root)
    if not has_linkage(reader.data):
        kind = reader.data.get("type")
        what = f'a {kind} result without one' if isinstance(kind, str) else "a result without one"
        root.error("linkage", "a result with a [linkage] table (only linkages can be analysed)",
                   raw_got=what)
        reader.finish()
        return None
    title = root.data.get("title")  # checked by check_header
    units = read_units(root)
    link = root.table("linkage", required=True)
    fourbar = read_linkage(link, units) if link else None
    if link is not None:
        link.allow("ground_pivot", "ground_angle", "coupler_point", "coupler_angle")
        angle = link.number("coupler_angle", None, lo=-MAX_LENGTH, hi=MAX_LENGTH)
        if (fourbar is not None and angle is not None and fourbar.coupler_point is not None
                and hasattr(fourbar, "coupler_angle")):
            fourbar = replace(fourbar, coupler_angle=units.to_rad(angle))  # a motion-generation result
    loads = read_loads(root, "linkage")  # [loads] / [masses]: echoed by synth, or added by hand
    drawn_pins_apart(root)
    if reader.errors or fourbar is None:
        _given_up(root)
        return None
    tolerance = None
    asked = root.data.get("tolerance")
    if isinstance(asked, dict) and "measure" not in asked:  # a study added by hand (the report's own names its measure)
        tolerance = read_tolerance(root, units, kind="linkage")
        if tolerance is None or reader.errors:
            _given_up(root)
            return None
    joints, link_sections, strength = strength_study(root, link, units, loads is not None)
    if reader.errors:
        _given_up(root)
        return None
    sections = problem_type("linkage").default_sections + (("forces",) if loads is not None else ()) \
        + (("tolerance",) if tolerance is not None else ()) + (("strength",) if strength is not None else ())
    meta = Meta(path=reader.path, type="linkage", title=title,  # a string or None: check_header judged it
                units=units, sections=sections, loads=loads, tolerance=tolerance, joints=joints,
                link_sections=link_sections, strength=strength)
    problem = motion_study(root, LinkageProblem(meta=meta, linkage=fourbar, input_speed=units.to_rad(1.0), steps=360))
    reader.finish()  # unknown keys of the tables read (and of the top level): errors
    return problem


STUDIES = ("tolerance", "material", "sections", "strength", "joints")  # tables a study added by hand may hold


def _given_up(root) -> None:
    """The errors found, without more: the result's [motion] keys (the report's own, judged
    against a linkage in error, or not reached) and the studies added by hand not read yet are
    not blamed as unknown keys (a bad criterion gave three lines calling the report's motion
    keys unknown)."""
    motion = root.data.get("motion")
    if isinstance(motion, dict):
        root.table("motion").allow(*motion.keys())
    root.allow(*(name for name in STUDIES if name in root.data))
    root.reader.finish()  # raises them


def drawn_pins_apart(root) -> None:
    """A top-level [joints] in a drawn design's result: one line (its pins are sized in the kept
    [linkage.joints]; the result was read as a problem file, 16 lines)."""
    from linkcli.mechanisms import schema_of
    from linkcli.mechanisms.schema import mechanism_of
    if "joints" in root.data and schema_of(mechanism_of(root)).draws:
        root.raw("joints")
        root.error("joints", "a drawing's pin sizes in its [linkage.joints.<J>] (diameter, width, shear), not in a "
                   "top-level [joints] (a design's result keeps its drawing in [linkage])", raw_got="a [joints] table")


def strength_study(root, link, units, has_loads: bool):
    """(pin sizes, link sections, strength spec or None) of a strength study added to a result
    by hand: [material] (with [sections] and [strength]), as a linkage file reads them
    (reading.strength.read_parts); the report never writes [material] or [sections] (its own
    [strength] section echoes `required` and `criterion`, read as the study's then). The pins'
    sizes: a drawing's in its kept [linkage.joints] (`diameter`, `width`, `shear`), a
    four-bar's in a [joints] table added beside the [material] one; a [strength] of the study's
    own keys alone asks for [material]. ((), {}, None) when the file adds none of them."""
    given = root.data.get("strength")
    report_own = isinstance(given, dict) and bool(set(given) - {"required", "criterion"})
    if "material" not in root.data and "sections" not in root.data and (given is None or report_own):
        return (), {}, None  # no study added (the report's own [strength] is output: result_check)
    from linkcli.mechanisms import schema_of
    from linkcli.mechanisms.schema import mechanism_of
    from linkcli.reading.meta import read_joint_table
    from linkcli.reading.strength import read_parts
    from linkcli.registry import problem_type
    spec = problem_type("linkage")
    mechanism = mechanism_of(root)
    if schema_of(mechanism).draws:
        from linkcli.io.joints import read_joints
        joints = read_joints(link, schema_of(mechanism), units)  # the kept drawing's (read with it)
    else:
        joints = read_joint_table(root, "linkage", spec, units)
    own = root.table("strength")
    if own is not None and (report_own or "material" not in root.data):
        own.allow(*own.keys())  # the report's own section (output: result_check; its echo of the two read),
        # or one without [material], which is then the one line
    asked = spec.default_sections + (("strength",) if "material" in root.data else ())
    link_sections, strength = read_parts(root, "linkage", spec.sections, asked, has_loads, mechanism, joints)
    return joints or (), link_sections, strength
