"""quick-return: the member of the time-ratio family that transmits force best (SPEC section 2).

Closed form plus a one-dimensional search (family.py; numpy only, no scipy):
- crank-rocker: the member with the best worst transmission angle over the full turn;
- slider-crank: with a given offset the unique design (closed form), else the best member
  of the free-offset family.
With `[constraints] transmission = [lo, hi]`: when the best member leaves the window but
other members keep the whole turn inside it, the best of those is reported (a note says
what the unconstrained best would give); when no member does, the status is `infeasible`
and the report holds the member that comes closest, with the amount it misses by.
A member on a limit (K = 1: the best lies at infinity; [bounds]; the documented link ratio
family.MAX_LINK_RATIO) is reported with a note naming the limit. Core errors that only the
family shows (no member within [bounds] or the link ratio) are exit 2 with the file's line.
"""

from __future__ import annotations

from linkcli.errors import SchemaError, SolveInputError
from linkcli.mechanisms.four_bar.model import FourBar
from linkcli.mechanisms.slider_crank.model import SliderCrank
from linkcli.search.budget import Budget
from linkcli.solution import Solution, SolverRecord, Status
from linkcli.textnum import num

from . import family, sections

COUNT_ONLY = 2**62  # the budget counts members evaluated; a closed form has no cap


def solve(problem) -> Solution:
    counter = Budget(COUNT_ONLY)
    try:
        return _solve(problem, counter)
    except SchemaError as exc:  # what only the family shows: located at its key
        raise located(problem, exc) from None


def located(problem, exc: SchemaError) -> SolveInputError:
    key = exc.key or "time_ratio"
    expected, got = exc.expected, exc.got
    if key == "bounds" and problem.bounds:
        got = ", ".join(f"{k} [{num_text(lo)}, {num_text(hi)}]" for k, (lo, hi) in problem.bounds.items())
    if key == "linkage":  # the chosen member did not recompute as a crank-rocker: degenerate
        key, expected = "time_ratio", ("a time ratio and swing that leave room for a crank-rocker "
                                       "(the members of this family are degenerate to round-off: "
                                       "crank as long as the coupler)")
    if key == "swing" and problem.mechanism == "slider-crank":
        key = "stroke"
    if key == "bounds" and not problem.bounds:
        key = "swing" if problem.mechanism == "crank-rocker" else "stroke"
    return SolveInputError(expected, got, path=problem.meta.path,
                           line=problem.lines.get(key), key=key)


def num_text(x: float) -> str:
    return f"{x:.6g}"


def _solve(problem, counter: Budget) -> Solution:
    u = problem.meta.units
    window = problem.transmission
    slider = problem.mechanism == "slider-crank"
    notes: list[str] = []
    status, message = Status.OK, ""
    if slider and problem.offset is not None and not (problem.offset == 0.0 and problem.time_ratio == 1.0):
        design = family.slider_crank_with_offset(problem.time_ratio, problem.stroke, problem.offset)
        counter.add(1)
        message = "the unique slider-crank of the given stroke, time ratio and offset (closed form)"
        if window is not None:
            miss = sections.window_miss("slider-crank", design.lengths, window)
            if miss > 0.0:
                status = Status.INFEASIBLE
                message = (f"the slider-crank of the given offset leaves the transmission window "
                           f"{window_text(u, window)} by {num(u.from_rad(miss))} {u.angle}")
    else:
        best = _best(problem, counter)
        design, message = best, "the member with the best worst transmission angle over the full turn"
        if window is not None and sections.window_miss(problem.mechanism, best.lengths, window) > 0.0:
            inside = _best(problem, counter, window)
            if inside is not None:
                design = inside
                message = ("the member with the best worst transmission angle among those within the "
                           f"transmission window {window_text(u, window)}")
                notes.append(f"the best member overall (worst transmission angle "
                             f"{num(u.from_rad(best.worst_transmission))} {u.angle}) leaves the window")
            else:
                design, miss = _closest(problem, counter)
                status = Status.INFEASIBLE
                message = (f"no member keeps the transmission angle within {window_text(u, window)} over "
                           f"the full turn: the closest, reported, misses it by {num(u.from_rad(miss))} "
                           f"{u.angle}")
        notes += limit_notes(problem, design)
    return Solution(status=status, linkage=slider_crank(design) if slider else four_bar(design),
                    message=message,
                    solver=SolverRecord("closed-form", problem.meta.solver.seed, counter.used, True),
                    sections=report_sections(problem, design), notes=notes)


def _args(problem):
    if problem.mechanism == "crank-rocker":
        return (problem.time_ratio, problem.swing, problem.scale)
    return (problem.time_ratio, problem.stroke)


def _best(problem, counter, window=None):
    fn = family.best_crank_rocker if problem.mechanism == "crank-rocker" else family.best_slider_crank
    return fn(*_args(problem), bounds=problem.bounds, window=window, counter=counter)


def _closest(problem, counter):
    fn = family.closest_crank_rocker if problem.mechanism == "crank-rocker" else family.closest_slider_crank
    return fn(*_args(problem), problem.transmission, bounds=problem.bounds, counter=counter)


def slider_crank(design) -> SliderCrank:
    """The chosen slider-crank (open branch): the shared slider sections report it."""
    L = design.lengths
    return SliderCrank(input=L["input"], coupler=L["coupler"], offset=L["offset"])


def four_bar(design) -> FourBar:
    L = design.lengths
    return FourBar(ground=L["ground"], input=L["input"], coupler=L["coupler"], output=L["output"])


def window_text(u, window) -> str:
    lo, hi = (u.from_rad(w) for w in window)
    return f"[{num(lo)}, {num(hi)}] {u.angle}"


def limit_notes(problem, design) -> list[str]:
    """What limits a member found on the edge of the searched family."""
    if not design.limited:
        return []
    links = [v for k, v in design.lengths.items() if k != "offset"]
    ratio = max(links) / min(links)
    if ratio >= family.MAX_LINK_RATIO * (1 - 1e-9):
        why = ("time ratio 1: the best member lies at infinity (the worst transmission angle rises "
               "without reaching its limit as the links grow); " if problem.time_ratio == 1.0 else "")
        return [f"{why}the reported member sits on the documented limit of the family, longest link "
                f"{num(family.MAX_LINK_RATIO)} times the shortest ([bounds] chooses another)"]
    active = []
    for key, (lo, hi) in problem.bounds.items():
        value = design.parameter if key == "parameter" else design.lengths[key]
        scale = max(abs(lo), abs(hi), 1e-300)
        if min(abs(value - lo), abs(value - hi)) <= 1e-9 * scale:
            active.append(key)
    if active:
        return [f"the reported member sits on its [bounds] ({', '.join(active)}): the family's best "
                "lies beyond"]
    return []


def report_sections(problem, design) -> dict:
    """The type's own sections: `design` always, `family` when asked for (the linkage,
    class, transmission, motion and kinematics sections are the shared ones of the linkage
    returned, four-bar or slider-crank)."""
    want = set(problem.meta.sections)
    out: dict = {}
    out["design"] = sections.design_section(problem, design)
    if "family" in want:
        table_of = (family.crank_rocker_family if problem.mechanism == "crank-rocker"
                    else family.slider_crank_family)
        bounds = problem.bounds if problem.offset is None else {}
        table = table_of(*_args(problem), bounds=bounds)
        out["family"] = sections.family_rows(problem, design, table, problem.transmission)
    return out

