"""Schema of `type = "function-generation"`: optimize lengths so that psi follows a law.

    [linkage]      lengths held fixed (at least one: it sets the scale)
    [target]       output = "<law in phi, phi0, psi0>"   with start = "extended" or
                                                         input_start / output_start
                   or function = "<f(x)>", x = [x0, x1], output_sweep
                   input_sweep, points, spacing = "uniform" | "chebyshev"
    [bounds]       a range [lo, hi] for every length not fixed; input_start / output_start
                   ranges make the start angles free
    [constraints]  transmission = [lo, hi], grashof, branch; defect_free (robust design)
    [objective]    minimize = "error" | "failure-probability" (reading.robust_keys)

Choices where the format leaves a choice: a length (or start angle) is either fixed or bounded, never
both (an error names both keys); a bound given as one number, or as [v, v], fixes the
value; a length neither fixed nor bounded is an error, and so is a file with no fixed
length. Expressions are checked here (expr.py, no numpy); a law whose value at the
evaluation points is already known (the function form, or given start angles) must be
finite there. No numerics beyond that.
"""

from __future__ import annotations

import math
from dataclasses import replace

from linkcli.expr import ExpressionError, compile_expression
from linkcli.io.bounds import MAX_LENGTH, MAX_RATIO, MIN_LENGTH, over_ratio
from linkcli.io.reader import Table
from linkcli.mechanisms.four_bar.model import LINKS
from linkcli.model import FunctionGenerationProblem, Meta
from linkcli.noise import NOISE_FLOOR
from linkcli.reading.pareto_keys import read_front
from linkcli.reading.robust_keys import read_objective

GRASHOF = ("any", "crank-rocker", "double-crank", "rocker-crank", "double-rocker", "triple-rocker")
BRANCHES = ("either", "open", "crossed")
SPACINGS = ("uniform", "chebyshev")
STARTS = ("input_start", "output_start")
DEFAULT_POINTS = 31
SPAN_RTOL = 8 * 2.0 ** -52  # f(x1) - f(x0) within a few ulps of the largest |f| is round-off
MAX_SHAPE = 1e6  # |f(x_k) - f(x0)| / |f(x1) - f(x0)|: beyond, the output would turn 1e6 sweeps
LAW_LIMIT = 1e6  # rad: a target angle beyond this magnitude has no digits left below a degree
START_SAMPLES = 24  # start angles tried per free start when the starts are not known yet
MAX_POINTS = 2000
TARGET_KEYS = ("output", "function", "start", "input_start", "output_start", "input_sweep",
               "output_sweep", "x", "points", "spacing")
OUTPUT_VARIABLES = ("phi", "phi0", "psi0")
FUNCTION_VARIABLES = ("x",)


def fractions(points: int, spacing: str) -> tuple[float, ...]:
    """Where the evaluation points sit along the sweep, in [0, 1], increasing.

    uniform: k / (n - 1), ends included. chebyshev: (1 - cos((2k - 1) pi / (2n))) / 2,
    k = 1..n, the Chebyshev nodes of the interval (ends excluded; Freudenstein & Sandor).
    """
    if spacing == "chebyshev":
        return tuple((1.0 - math.cos((2 * k - 1) * math.pi / (2 * points))) / 2.0
                     for k in range(1, points + 1))
    return tuple(k / (points - 1) for k in range(points))


def parse(root: Table, meta: Meta):
    """The problem of the mechanism [linkage] names, read by its home's synthesis face
    (mechanisms.synthesis): the four-bar's below (`parse_four_bar`), another home's keys."""
    from linkcli.mechanisms import synthesis
    return synthesis.read("function-generation", root, meta)


def parse_four_bar(root: Table, meta: Meta) -> FunctionGenerationProblem | None:
    """A four-bar's output angle following a law (the module docstring's keys)."""
    u = meta.units
    ok = True
    link = root.table("linkage")
    bnd = root.table("bounds")
    tgt = root.table("target", required=True)
    if link is not None:
        link.allow(*LINKS)
    if bnd is not None:
        bnd.allow(*LINKS, *STARTS)
    if tgt is None:
        return None
    tgt.allow(*TARGET_KEYS)
    lengths = read_lengths(root, link, bnd)
    form_law = read_law(tgt)
    sweep = read_sweep(tgt, "input_sweep", u)
    points = tgt.number("points", DEFAULT_POINTS, integer=True, lo=2, hi=MAX_POINTS)
    spacing = tgt.string("spacing", "uniform", choices=SPACINGS)
    needs_psi0 = form_law is None or form_law[0] == "function" or form_law[1].uses("psi0")
    starts = read_starts(tgt, bnd, u, needs_psi0)
    function = read_function_keys(tgt, form_law[0] if form_law else None, u)
    constraints = read_constraints(root, u)
    robust = read_objective(root, meta)  # [objective] minimize, [constraints] defect_free
    front_ok, front = read_front(root, meta)  # [objective] minimize = [...]: a Pareto front
    meta = replace(meta, front=front) if front is not None else meta
    if None in (lengths, form_law, sweep, points, spacing, starts, function, constraints, robust) or not front_ok:
        return None
    fixed, bounds = lengths
    form, law = form_law
    start, given, start_bounds = starts
    output_sweep, x_range = function
    transmission, grashof, branch = constraints
    t = fractions(points, spacing)
    law_key = ("target", "output" if form == "output" else "function")
    lines = {"law": root.reader.line_of(law_key), "law_key": ".".join(law_key)}
    shape: tuple[float, ...] = ()
    if form == "function":
        shape = function_shape(tgt, law, x_range, t)
        ok = shape is not None
    elif start == "given" and not start_bounds:
        ok = check_law_at_points(tgt, law, given, sweep, t, u)
    else:
        ok = check_law_for_some_start(tgt, law, given, start_bounds, sweep, t, u)
    if not ok:
        return None
    return FunctionGenerationProblem(
        meta=meta, fixed=fixed, bounds=bounds, law=law, form=form, input_sweep=sweep,
        fractions=t, start=start, input_start=given.get("input_start"),
        output_start=given.get("output_start"), start_bounds=start_bounds,
        output_sweep=output_sweep, x_range=x_range, shape=shape, spacing=spacing,
        transmission=transmission, grashof=grashof, branch=branch, lines=lines,
        objective=robust[0], defect_free=robust[1])


# ---------------------------------------------------------------- lengths

def read_lengths(root: Table, link: Table | None, bnd: Table | None):
    """(fixed, bounds): every link fixed in [linkage] or bounded in [bounds], never both,
    at least one fixed. A bound that is one number (or [v, v]) fixes the link. A `linkage`
    that is not a table (its one error already recorded) may have fixed any link: a length
    missing from [bounds] is then not judged (no second line for the same mistake)."""
    unjudged = link is None and "linkage" in root
    fixed: dict[str, float] = {}
    bounds: dict[str, tuple[float, float]] = {}
    ok = True
    for k in LINKS:
        in_link = link is not None and k in link
        in_bnd = bnd is not None and k in bnd
        value = link.number(k, positive=True, what="a positive length") if in_link else None
        rng = bnd.range(k, positive=True) if in_bnd else None
        if value is not None and not MIN_LENGTH <= value <= MAX_LENGTH:
            link.error(k, f"a length within [{MIN_LENGTH:g}, {MAX_LENGTH:g}]", link.raw(k))
            value, ok = None, False
        if rng is not None and not (MIN_LENGTH <= rng[0] and rng[1] <= MAX_LENGTH):
            bnd.error(k, f"a range within [{MIN_LENGTH:g}, {MAX_LENGTH:g}]", raw_got=_show(bnd.raw(k)))
            rng, ok = None, False
        if in_link and in_bnd:
            bnd.error(k, "a length either fixed in [linkage] or bounded in [bounds], not both",
                      raw_got=f"linkage.{k} = {_show(link.raw(k))} and bounds.{k} = {_show(bnd.raw(k))}")
            ok = False
        elif not in_link and not in_bnd and unjudged:
            ok = False
        elif not in_link and not in_bnd:
            where = ("bounds", k) if bnd is not None else ("linkage", k)
            root.reader.error(where, f"a length for {k}: fixed in [linkage] or a range [lo, hi] in [bounds]")
            ok = False
        elif (in_link and value is None) or (in_bnd and rng is None):
            ok = False
        elif in_link:
            fixed[k] = value
        elif rng[0] == rng[1]:
            fixed[k] = rng[0]
        else:
            bounds[k] = rng
    extremes = over_ratio(fixed) if ok and fixed else None
    if extremes:
        longest, shortest = extremes
        where = link if link is not None and longest in link else bnd
        where.error(longest, f"fixed lengths whose longest is at most {MAX_RATIO:g} times the shortest "
                             "(beyond, double precision cannot resolve the angles)",
                    raw_got=f"{longest} {_fmt(fixed[longest])} and {shortest} {_fmt(fixed[shortest])}")
        ok = False
    if ok and not fixed:
        where = ("linkage",) if link is not None else ("bounds",)
        root.reader.error(where, "at least one length fixed in [linkage] (it sets the scale)",
                          raw_got="every length free")
        ok = False
    return (fixed, bounds) if ok else None


def _show(value) -> str:
    if isinstance(value, list):
        return "[" + ", ".join(_show(v) for v in value) + "]"
    if isinstance(value, float) and value.is_integer() and abs(value) < 1e15:
        return repr(int(value))
    return repr(value) if not isinstance(value, str) else f'"{value}"'


# ---------------------------------------------------------------- target law

def read_law(tgt: Table):
    """(form, Expression): `output = "..."` (psi of phi, phi0, psi0) or `function = "..."`."""
    has_out, has_fn = "output" in tgt, "function" in tgt
    if has_out and has_fn:
        tgt.raw("output")
        tgt.error("function", 'either output = "<law in phi>" or function = "<f(x)>", not both',
                  raw_got="both")
        return None
    if not has_out and not has_fn:
        tgt.error(None, 'output = "<law in phi, phi0, psi0>" or function = "<f(x)>" in [target]',
                  raw_got="neither")
        return None
    key, form, variables = (("output", "output", OUTPUT_VARIABLES) if has_out
                            else ("function", "function", FUNCTION_VARIABLES))
    text = tgt.string(key, max_len=10**6)
    if text is None:
        return None
    try:
        return form, compile_expression(text, variables)
    except ExpressionError as exc:
        tgt.error(key, exc.expected, raw_got=exc.got)
        return None


def read_sweep(tgt: Table, key: str, u):
    """A non-zero signed angle of at most one turn, in radians."""
    full = u.from_rad(2 * math.pi)
    least = u.from_rad(NOISE_FLOOR)  # below it the points' drive angles are round-off of one another
    value = tgt.number(key, what=f"a non-zero angle within one turn ({u.angle})")
    if value is None:
        return None
    if abs(value) < least or abs(value) > full:
        tgt.error(key, f"a non-zero angle of at most one turn ({_fmt(full)} {u.angle} in magnitude) and at "
                  f"least {least:g} {u.angle} (1e-9 rad)", tgt.raw(key))
        return None
    return u.to_rad(value)


def read_starts(tgt: Table, bnd: Table | None, u, needs_psi0: bool = True):
    """(start, given, bounds): `start = "extended"`, or each start angle given in [target]
    (angle) or free in [bounds] (range), never both. A law in phi alone needs no
    output_start (psi0 is then 0 and unused)."""
    start = tgt.string("start", None, choices=("extended",))
    if "start" in tgt and start is None:
        return None
    given: dict[str, float] = {}
    bounds: dict[str, tuple[float, float]] = {}
    ok = True
    for k in STARTS:
        in_tgt, in_bnd = k in tgt, bnd is not None and k in bnd
        if start == "extended" and (in_tgt or in_bnd):
            table = tgt if in_tgt else bnd
            table.raw(k)
            table.error(k, f'no {k} with start = "extended" (the extended dead-centre sets it)',
                        table.raw(k))
            ok = False
            continue
        if start == "extended":
            continue
        value = tgt.number(k, lo=-MAX_LENGTH, hi=MAX_LENGTH, what=f"an angle ({u.angle})") if in_tgt else None
        rng = bnd.range(k) if in_bnd else None
        if in_tgt and in_bnd:
            bnd.error(k, "a start angle either given in [target] or bounded in [bounds], not both",
                      raw_got=f"target.{k} = {_show(tgt.raw(k))} and bounds.{k} = {_show(bnd.raw(k))}")
            ok = False
        elif not in_tgt and not in_bnd:
            if k == "output_start" and not needs_psi0:
                given[k] = 0.0
                continue
            tgt.error(k, f'an angle ({u.angle}), a range in [bounds].{k}, or start = "extended"')
            ok = False
        elif (in_tgt and value is None) or (in_bnd and rng is None):
            ok = False
        elif in_tgt:
            given[k] = u.to_rad(value)
        elif rng[0] == rng[1]:
            given[k] = u.to_rad(rng[0])
        else:
            bounds[k] = (u.to_rad(rng[0]), u.to_rad(rng[1]))
    if not ok:
        return None
    return (start or "given"), given, bounds


def read_function_keys(tgt: Table, form: str | None, u):
    """(output_sweep, (x0, x1)) of the function form; (None, None) for the output form,
    where those keys are an error."""
    if form is None:
        return None
    if form == "output":
        bad = [k for k in ("x", "output_sweep") if k in tgt]
        for k in bad:
            tgt.error(k, f'no {k} with output = "<law>" (it belongs to the function = "<f(x)>" form)',
                      tgt.raw(k))
        return None if bad else (None, None)
    sweep = read_sweep(tgt, "output_sweep", u)
    x = tgt.number_list("x", length=2, what="numbers [x0, x1]")
    if x is not None and x[0] == x[1]:
        tgt.error("x", "a range [x0, x1] with x0 != x1", raw_got=f"[{_fmt(x[0])}, {_fmt(x[1])}]")
        x = None
    if sweep is None or x is None:
        return None
    return sweep, (x[0], x[1])


def function_shape(tgt: Table, law, x_range, t):
    """(f(x_k) - f(x0)) / (f(x1) - f(x0)) at each point; f must be finite at x0, x1 and
    every evaluation point, and f(x1) != f(x0)."""
    x0, x1 = x_range
    xs = [x0, x1] + [x0 + tk * (x1 - x0) for tk in t]
    values = [law.scalar(x=x) for x in xs]
    for x, v in zip(xs, values):
        if not math.isfinite(v):
            tgt.error("function", "a function finite at x0, x1 and every evaluation point",
                      raw_got=f"{_fmt(v)} at x = {_fmt(x)}")
            return None
    f0, f1 = values[0], values[1]
    if abs(f1 - f0) <= SPAN_RTOL * max(abs(v) for v in values):
        got = (f"f({_fmt(x0)}) = f({_fmt(x1)}) = {_fmt(f0)}" if f1 == f0 else
               f"f({_fmt(x0)}) = {_fmt(f0)} and f({_fmt(x1)}) = {_fmt(f1)}, equal within round-off")
        tgt.error("function", "a function with f(x1) != f(x0) (the output sweep maps f(x0)..f(x1))",
                  raw_got=got)
        return None
    span = f1 - f0
    shape = tuple((v - f0) / span for v in values[2:])
    if not all(math.isfinite(s) and abs(s) <= MAX_SHAPE for s in shape):
        finite = [abs(v) for v in shape if math.isfinite(v)]
        worst = max(finite) if len(finite) == len(shape) else math.inf
        tgt.error("function", f"a function whose values at the points lie within {MAX_SHAPE:g} times "
                  "f(x1) - f(x0) of f(x0) (the output sweep maps f(x0)..f(x1))",
                  raw_got=f"f({_fmt(x1)}) - f({_fmt(x0)}) = {_fmt(span)} and a point {_fmt(worst)} times that away")
        return None
    return shape


def usable(v: float) -> bool:
    """A law value (rad) that is finite and small enough to keep its fraction of a turn."""
    return math.isfinite(v) and abs(v) <= LAW_LIMIT


def check_law_at_points(tgt: Table, law, given, sweep, t, u) -> bool:
    """With given start angles the law's values are known now: finite at every point."""
    phi0, psi0 = given["input_start"], given["output_start"]
    for tk in t:
        phi = phi0 + tk * sweep
        v = law.scalar(phi=phi, phi0=phi0, psi0=psi0)
        if not usable(v):
            tgt.error("output", f"a law finite at every evaluation point (and within {LAW_LIMIT:g} rad)",
                      raw_got=f"{_fmt(v)} at phi = {_fmt(u.from_rad(phi))} {u.angle}")
            return False
    return True


def _start_samples(key: str, given: dict, start_bounds: dict) -> list[float]:
    if key in given:
        return [given[key]]
    lo, hi = start_bounds.get(key, (-math.pi, math.pi))
    return [lo + (hi - lo) * (i + 0.5) / START_SAMPLES for i in range(START_SAMPLES)]


def check_law_for_some_start(tgt: Table, law, given, start_bounds, sweep, t, u) -> bool:
    """With start angles found by the solver (extended dead-centre, or free within bounds)
    the law's values depend on the design; still, a point where it is not finite for any
    of START_SAMPLES start angles (each free one) is a law no design can follow: 1/(phi -
    phi0), an overflow, log of a negative constant."""
    phi0s = _start_samples("input_start", given, start_bounds)
    psi0s = _start_samples("output_start", given, start_bounds) if law.uses("psi0") else [0.0]
    for k, tk in enumerate(t):
        values = (law.scalar(phi=phi0 + tk * sweep, phi0=phi0, psi0=psi0)
                  for phi0 in phi0s for psi0 in psi0s)
        if not any(usable(v) for v in values):  # stops at the first usable value
            first = law.scalar(phi=phi0s[0] + tk * sweep, phi0=phi0s[0], psi0=psi0s[0])
            tgt.error("output", "a law finite at every evaluation point for some start angles "
                      f"(and within {LAW_LIMIT:g} rad)",
                      raw_got=f"{_fmt(first)} at point {k + 1} of {len(t)} "
                              f"(phi = phi0 + {_fmt(u.from_rad(tk * sweep))} {u.angle}) for every "
                              "start angle tried")
            return False
    return True


# ---------------------------------------------------------------- constraints

def read_constraints(root: Table, u):
    """(transmission window in rad or None, grashof class, branch)."""
    con = root.table("constraints")
    if con is None:
        return None, "any", "either"
    con.allow("transmission", "grashof", "branch", "defect_free")  # defect_free: reading.robust_keys
    window, ok = None, True
    if "transmission" in con:
        top = u.from_rad(math.pi)
        w = con.number_list("transmission", length=2, what="angles [lo, hi]")
        if w is not None and not 0 <= w[0] < w[1] <= top:
            con.error("transmission", f"a window [lo, hi] with 0 <= lo < hi <= {_fmt(top)} ({u.angle})",
                      raw_got=f"[{_fmt(w[0])}, {_fmt(w[1])}]")
            w = None
        ok = w is not None
        window = (u.to_rad(w[0]), u.to_rad(w[1])) if ok else None
    grashof = con.string("grashof", "any", choices=GRASHOF)
    branch = con.string("branch", "either", choices=BRANCHES)
    if grashof is None or branch is None or not ok:
        return None
    return window, grashof, branch


def _fmt(x: float) -> str:
    if not math.isfinite(x):
        return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")
    return repr(int(x)) if float(x).is_integer() and abs(x) < 1e15 else f"{x:.6g}"
