"""The keys every problem file shares: title, [units], [solver], [reference], [report],
[tolerance]. Returns a `Meta`."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from linkcli.io.bounds import MAX_LENGTH
from linkcli.io.reader import MAX_ARRAY, Table
from linkcli.model import Meta, Reference, SolverOptions
from linkcli.registry import ProblemType
from linkcli.units import ANGLE_UNITS, LENGTH_TO_MM, Units

if TYPE_CHECKING:  # names of annotations only (imported where they are used)
    from linkcli.model.tolerance import Tolerance

ALL_SECTIONS = ("lengths", "grashof", "transmission", "motion", "kinematics", "positions",
                "error", "cylinder", "family", "solver", "tolerance", "forces", "strength")
MAX_BUDGET = 10**9
MAX_SAMPLES = 1_000_000  # a tolerance study: more gains nothing but minutes
MIN_FAILURES = 10  # inverse mode: expected failures at the level, for a stable bisection

ANGLE_FIELDS = ("ground_angle", "coupler_angle")  # a linkage's fields that are not sizes


def refuse_oversized(problem, linkage) -> None:
    """SolveInputError (exit 2) when a solved linkage has a length or coordinate beyond
    MAX_LENGTH: no file could hold it (`analyze` of the result would refuse it), so the
    data are refused instead, with the way out (a larger length unit)."""
    from dataclasses import fields, is_dataclass

    from linkcli.errors import SolveInputError
    if linkage is None or not is_dataclass(linkage):
        return
    for f in fields(linkage):
        sizes = [] if f.name in ANGLE_FIELDS else _magnitudes(getattr(linkage, f.name))
        size = max(sizes, default=0.0)
        if size > MAX_LENGTH:
            unit = problem.meta.units.length
            raise SolveInputError(
                f"data whose linkage fits the sizes a file accepts (lengths and coordinates at most "
                f"{MAX_LENGTH:g} {unit}: give the problem in a larger length unit)",
                f"a linkage with {f.name.replace('_', ' ')} {size:.6g} {unit}", path=problem.meta.path,
                key="linkage")


def _magnitudes(value) -> list[float]:
    """|x| of a number or of a tuple of numbers; nothing for text, flags and nested records
    (a drawing, a motion: what they hold was bounded where the file was read)."""
    def number(x) -> bool:
        return isinstance(x, (int, float)) and not isinstance(x, bool)
    if number(value):
        return [abs(float(value))]
    if isinstance(value, tuple) and value and all(number(x) for x in value):
        return [abs(float(x)) for x in value]
    return []


def in_motion_order(angles: list[float]) -> list[float]:
    """Input angles (rad) of positions the input passes in the order given: kept as written
    when they already run one way; else, if taking each step the short way round makes
    them run one way, that form ([150, 180, -150] deg -> [150, 180, 210]), so that sweeps,
    working ranges and travel are measured along the motion, not across the +-180 seam."""
    steps = [b - a for a, b in zip(angles, angles[1:])]
    if all(s > 0 for s in steps) or all(s < 0 for s in steps):
        return list(angles)
    turn = 2 * math.pi
    short = [s - turn * math.floor((s + math.pi) / turn) for s in steps]  # in [-pi, pi)
    if all(s > 0 for s in short) or all(s < 0 for s in short):
        out = [angles[0]]
        for s in short:
            out.append(out[-1] + s)
        return out
    return list(angles)


def read_meta(root: Table, kind: str, spec: ProblemType) -> Meta:
    """What every file has ([units], [solver], [reference], [tolerance], [report]), checked
    against the vocabulary of its type."""
    title = root.string("title", None, max_len=200)
    units = read_units(root)
    solver = read_solver(root, spec.methods, spec.atlas)
    reference = read_reference(root)
    tolerance = read_tolerance(root, units) if spec.tolerance else None
    sections = read_sections(root, spec.default_sections, spec.sections)
    loads = read_load_case(root, kind, spec, sections)
    joints = read_joint_table(root, kind, spec, units)
    link_sections, strength = read_strength_tables(root, kind, spec, sections, loads, joints)
    from linkcli.reading.dynamics_keys import read_dynamics  # [springs], [dampers], [dynamics]
    dynamics = read_dynamics(root, kind, "forces" in spec.sections, units, joints)
    if tolerance is not None and joints is not None:  # fits of schemes and clearance = "fits"
        from linkcli.reading.tolerance_keys import check_fits
        check_fits(root, tolerance, joints, units)
    if loads is not None and "forces" not in sections:
        sections = sections + ("forces",)  # on when [loads] or [masses] is given (as tolerance)
    if strength is not None and "strength" not in sections:
        sections = sections + ("strength",)  # on when [material] is given
    report = root.data.get("report")
    asked = report.get("sections") if isinstance(report, dict) else None
    if (isinstance(asked, list) and "tolerance" in asked and "tolerance" in sections
            and tolerance is None and "tolerance" not in root):
        # asked for by name, and nothing to study: an empty report would pass for a result
        root.reader.error(("report", "sections"), 'a [tolerance] table for the "tolerance" section '
                          "(the tolerances to study)", raw_got="no [tolerance] table")
    if tolerance is not None and "tolerance" not in sections:
        sections = sections + ("tolerance",)
    return Meta(path=root.reader.path, type=kind, title=title, units=units, solver=solver,
                sections=sections, reference=reference, tolerance=tolerance, loads=loads,
                joints=joints or (), link_sections=link_sections, strength=strength, dynamics=dynamics)


def read_load_case(root: Table, kind: str, spec: ProblemType, sections: tuple[str, ...]):
    """[loads] / [masses] (linkcli.reading.loads) on a type that can report `forces`; refused,
    located, on one that cannot (no linkage); the `forces` section asked for by name
    without them is an error too (an empty section would pass for a result)."""
    from linkcli.reading.loads import read_loads, refuse_loads
    from linkcli.registry import NAMES, problem_type
    if "forces" not in spec.sections:
        refuse_loads(root, kind, tuple(n for n in NAMES if "forces" in problem_type(n).sections))
        return None
    loads = read_loads(root, kind)
    if "forces" in sections and "loads" not in root and "masses" not in root:
        root.reader.error(("report", "sections"), 'a [loads] or [masses] table for the "forces" '
                          "section (the loads to analyse)", raw_got="neither")
    return loads


def read_joint_table(root: Table, kind: str, spec: ProblemType, units: Units):
    """[joints] (linkcli.io.joints) on a type whose result is a linkage; refused, located, on
    one that has none."""
    from linkcli.mechanisms import schema_of
    from linkcli.mechanisms.schema import mechanism_of
    from linkcli.registry import NAMES, problem_type
    drawing = schema_of(mechanism_of(root)).draws  # [joints] is a drawing, read with it
    if "forces" not in spec.sections and not drawing:
        if "joints" in root:
            root.raw("joints")
            with_linkage = ", ".join(n for n in NAMES if "forces" in problem_type(n).sections)
            root.error("joints", f"a problem whose result is a linkage ({with_linkage}) for [joints]",
                       raw_got=f'type = "{kind}", which has no linkage')
        return ()
    if "joints" not in root:
        return ()  # what read_joints gives without the table, without importing io.joints
    from linkcli.io.joints import read_joints
    return read_joints(root, schema_of(mechanism_of(root)), units)


def read_strength_tables(root: Table, kind: str, spec: ProblemType, sections: tuple[str, ...],
                         loads, joints):
    """[sections], [material], [strength] (linkcli.reading.strength): (link sections, the strength
    spec or None)."""
    from linkcli.mechanisms import schema_of
    from linkcli.mechanisms.schema import mechanism_of
    from linkcli.reading.strength import read_parts
    mechanism = mechanism_of(root)
    if schema_of(mechanism).links_designed(root):  # a topology: its design type refuses them, one
        return {}, None  # line each (synthesis.schema); judged here they asked for loads the type refuses
    has_loads = loads is not None or "loads" in root or "masses" in root
    return read_parts(root, kind, spec.sections, sections, has_loads, mechanism, joints)


def read_units(root: Table) -> Units:
    t = root.table("units")
    if t is None:
        return Units()
    length = t.string("length", "mm", choices=tuple(LENGTH_TO_MM))
    angle = t.string("angle", "deg", choices=ANGLE_UNITS)
    return Units(length=length or "mm", angle=angle or "deg")


def read_solver(root: Table, methods: tuple[str, ...], atlas_key: bool = False) -> SolverOptions:
    t = root.table("solver")
    if t is None:
        return SolverOptions()
    method = t.string("method", "auto", choices=methods)
    seed = t.number("seed", 0, integer=True, lo=0, hi=2**32 - 1)
    budget = t.number("budget", None, integer=True, lo=1, hi=MAX_BUDGET)
    atlas = t.boolean("atlas", None) if atlas_key else None  # linkcli.atlas, docs/atlas.md
    return SolverOptions(method=method or "auto", seed=seed or 0, budget=budget, atlas=atlas)


def read_reference(root: Table) -> Reference | None:
    t = root.table("reference")
    if t is None:
        return None
    objective = t.number("objective", nonnegative=True)
    source = t.string("source", None, max_len=500)
    return None if objective is None else Reference(objective=objective, source=source)


def read_sections(root: Table, default: tuple[str, ...], allowed: tuple[str, ...]) -> tuple[str, ...]:
    """[report] sections: an array of 1 to MAX_ARRAY names from `allowed` (the cap of every
    array: this one, of strings, is not read by number_list, which holds it for numbers);
    `default` when absent or bad (error recorded)."""
    t = root.table("report")
    if t is None:
        return tuple(default)
    value = t.raw("sections", None)
    if value is None:
        return tuple(default)
    if (not isinstance(value, list) or not 1 <= len(value) <= MAX_ARRAY
            or not all(isinstance(v, str) for v in value)):
        t.error("sections", f"an array of 1 to {MAX_ARRAY} section names from: {', '.join(allowed)}", value)
        return tuple(default)
    bad = [v for v in value if v not in allowed]
    if bad:
        import difflib
        hint = difflib.get_close_matches(bad[0], allowed, n=1, cutoff=0.6)
        extra = f' (did you mean "{hint[0]}"?)' if hint else ""
        t.error("sections", f"section names from: {', '.join(allowed)}{extra}", bad[0])
        return tuple(default)
    return tuple(s for s in ALL_SECTIONS if s in value)


MIN_LEVEL = MIN_FAILURES / MAX_SAMPLES  # the least max_failure_probability: 1e-05


def read_level(t: Table) -> float | None:
    """The inverse mode's `max_failure_probability` p, None when missing or bad: a probability
    from MIN_LEVEL (1e-05) to below 1, since the study wants samples >= MIN_FAILURES / p and
    holds at most MAX_SAMPLES (a smaller p, down to a denormal, could never be met)."""
    level = t.number("max_failure_probability", None, what="a probability strictly between 0 and 1")
    if level is not None and not 0.0 < level < 1.0:
        t.error("max_failure_probability", "a probability strictly between 0 and 1", level)
        return None
    if level is not None and level < MIN_LEVEL:
        t.error("max_failure_probability", f"a probability of at least {MIN_LEVEL:g} (the study wants "
                f"samples >= {MIN_FAILURES} / max_failure_probability and holds at most {MAX_SAMPLES} samples)",
                level)
        return None
    return level


def read_tolerance(root: Table, units: Units, kind: str | None = None) -> Tolerance | None:
    """[tolerance]: `lengths` (one +- tolerance for every link, an ISO 2768 class, or a table
    per link of either; a path generator's table may add `coupler_point`, +- on each
    coordinate of P), `distribution`, `clearance` (a number or "fits"), `samples`,
    `allowed_error` (angle unit, or length unit for a path), the inverse mode's
    `max_failure_probability` (which then wants a single tolerance or none, unless
    [tolerance.cost] allocates them), [tolerance.cost] and [[tolerance.schemes]]
    (reading.tolerance_keys). `kind`: the problem type the study is of (default: the file's
    `type`; a design's result is analysed as a linkage)."""
    t = root.table("tolerance")
    kind = kind or root.raw("type")
    if t is None:
        return None
    from linkcli.mechanisms import NAMES, schema_of
    from linkcli.mechanisms.schema import mechanism_of
    from linkcli.model import InverseTolerance, Tolerance
    from linkcli.reading.tolerance_keys import check_cost_bounds, read_clearance, read_cost, read_lengths, read_schemes
    path_type = kind == "path-generation"
    mechanism = mechanism_of(root)
    own = schema_of(mechanism)
    links = own.toleranced_names(root)
    per_link = links + (("coupler_point",) if path_type and "coupler_point" in own.keys else ())
    raw = t.raw("lengths", None)
    every, designed = None, own.links_designed(root)
    if designed and isinstance(raw, dict):  # no link of the design has a name yet
        t.error("lengths", "one tolerance or an ISO 2768 class with [linkage] topology (every link of the "
                "design gets it: each choice names its links anew)", raw_got="a table")
        got = None
    elif designed and raw is not None:
        got = read_lengths(t, "lengths", ("every",), ("every",))
        if got is not None and got[0] is not None:
            every = got[1].get("every", got[0]["every"])
        got = None
    else:
        got = read_lengths(t, "lengths", links, per_link)
    lengths, general = got if got is not None and got[0] is not None else ({k: 0.0 for k in links}, {})
    distribution = t.string("distribution", "uniform", choices=("uniform", "normal"))
    clearance, clearance_fits = read_clearance(t)
    clearance_slider = 0.0
    if "clearance_slider" in own.plays:
        clearance_slider = t.number("clearance_slider", 0.0, nonnegative=True,
                                    what="a radial play of the slider in its guide >= 0 (length unit)")
    lock_play = 0.0
    if "lock_play" in own.plays:
        lock_play = t.number("lock_play", 0.0, lo=0.0, hi=units.from_rad(math.pi / 2),
                             what="an angular play of a held drive's lock (angle unit)")
    refused = set()
    for name in NAMES:
        for key, what in schema_of(name).plays.items():
            if key not in own.plays and key in t and key not in refused:  # once, naming the first home
                refused.add(key)
                t.allow(key)
                t.error(key, f'no {key} for a {mechanism} ({what}: only with [linkage] mechanism = "{name}")',
                        t.data[key])
    samples = t.number("samples", 20000, integer=True, lo=1, hi=MAX_SAMPLES)
    allowed = t.number("allowed_error", None, positive=True)
    if allowed is not None:
        angle = kind == "function-generation" or not (path_type or own.output == "length")
        allowed = units.to_rad(allowed) if angle else allowed  # a function's output is an angle
    level = read_level(t)
    if level is not None and allowed is None and "allowed_error" not in t:
        t.error("allowed_error", "a positive number (needed by max_failure_probability: a "
                "sample fails when its error exceeds allowed_error)")
    cost = read_cost(t, per_link, own.joint_names(root))
    schemes = read_schemes(t, links, per_link, None if own.draws else own.joints)
    if cost is not None and level is None and "max_failure_probability" not in t:
        t.error("max_failure_probability", "a probability strictly between 0 and 1 with [tolerance.cost] "
                "(the limit the least-cost tolerances must meet)")
    if cost is not None:
        check_cost_bounds(t, cost, links)
    if level is not None and isinstance(raw, dict) and cost is None:
        t.error("lengths", "a single tolerance (or none) with max_failure_probability: the search "
                "applies one tolerance to every link", raw_got="a table")
    if level is not None and samples is not None and samples * level < MIN_FAILURES:
        need = math.ceil(MIN_FAILURES / level)
        t.error("samples", f"at least {need} samples with max_failure_probability = {level:g} "
                f"({MIN_FAILURES} expected failures)", samples)
    line_of = root.reader.line_of
    lines = {".".join(k): line_of(("tolerance",) + k)
             for k in [("lengths",), ("clearance",), ("clearance_slider",), ("lock_play",), ("samples",)]
             + [("lengths", link) for link in per_link] + [(f"schemes[{i}]",) for i in range(len(schemes))]}
    base = dict(lengths=lengths, distribution=distribution or "uniform", clearance=clearance or 0.0,
                clearance_slider=clearance_slider or 0.0, lock_play=units.to_rad(lock_play or 0.0),
                samples=samples or 20000, allowed_error=allowed, lines=lines, general=general or {},
                clearance_fits=clearance_fits, cost=cost, schemes=schemes, every=every)
    if level is not None:
        return InverseTolerance(max_failure_probability=level, lengths_given=raw is not None, **base)
    return Tolerance(**base)
