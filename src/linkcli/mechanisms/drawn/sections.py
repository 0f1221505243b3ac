"""A drawn linkage's report sections (docs/drawn.md): linkage (every distance between two
joints of a link), its structure (class section), transmission (every closure), motion
(the drive's reach, dead points, each link's and slider's range) and the kinematics rows.

Angles leave in the file's angle unit (positions wrapped to (-180, 180] deg), lengths in its
length unit; round-off is 0 under the noise floor of the drawing's size (`size`), of 1 rad
(angles) and of each column's scale. Extremes are exact (motion.extremes); ties between
closures go to the first in plan order.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.angles import wrap
from linkcli.mechanisms.columns import TRANSMISSION_BAND
from linkcli.mechanisms.columns import angle_out as _ang
from linkcli.mechanisms.columns import turn_out as _dang
from linkcli.mechanisms.drawn.structure import describe_plan
from linkcli.noise import snap, snap_series
from linkcli.textnum import num

CLASS_NAMES = {4: "four-bar", 5: "five-bar", 6: "six-bar", 7: "seven-bar", 8: "eight-bar", 10: "ten-bar"}


def size(drawing) -> float:
    """The drawing's scale: its longest distance between two joints of one link (or of the
    ground); round-off below NOISE_FLOOR times it is 0."""
    return max(drawing.distances().values(), default=1.0) or 1.0


def linkage_section(drawing, u) -> dict:
    """mechanism, (a designed drawing: its `drawing_section`), then every distance."""
    kept = drawing_section(drawing, u) if drawing.designed else {}
    return {"mechanism": "drawn", **kept, **drawing.distances()}


def drawing_section(drawing, u) -> dict:
    """The drawing as a file gives it (mechanisms.drawn.kept reads it back): joints (name ->
    at, and ground, slider (angle unit) and guide where they apply), links (name -> joints),
    drive (name -> speed, angle unit/s or length unit/s)."""
    from linkcli.mechanisms.drawn.model import TURN
    joints = {}
    for j in drawing.joints:
        entry = {"at": [float(j.at[0]), float(j.at[1])]}
        if j.ground:
            entry["ground"] = True
        if j.slider is not None:
            entry["slider"] = float(u.from_rad(j.slider))
        if j.guide is not None:
            entry["guide"] = j.guide
        joints[j.name] = entry
    return {"joints": joints, "links": {k.name: list(k.joints) for k in drawing.links},
            "drive": {d.name: {"speed": float(u.from_rad(d.speed)) if d.kind == TURN else float(d.speed)}
                      for d in drawing.drives}}


def class_section(structure) -> dict:
    """The structure: the class by count of bodies (ground, links, slider blocks), Watt or
    Stephenson for a six-bar of pins with two ternary bodies, the others binary (Watt: the
    two ternary bodies share a joint; Stephenson: they do not). The ground is a body like
    the links: with three pivots it is ternary (the Watt II and Stephenson III drawings,
    whose one ternary link is pinned to the ground, are Watt and Stephenson six-bars too).
    A body's joints are counted as pins only when another body shares them: a traced point
    carried by one link alone (a coupler point) does not make it ternary.
    Also the mobility and the plan (the Assur groups in solve order)."""
    bodies = structure.bodies
    name = CLASS_NAMES.get(bodies, f"{bodies}-bar")
    drawing = structure.drawing
    ground = {j.name for j in drawing.joints if j.ground}
    carried = [ground] + [set(k.joints) for k in drawing.links]
    shared = {j for j in ground | {n for k in drawing.links for n in k.joints}
              if sum(j in body for body in carried) >= 2}
    joints = [body & shared for body in carried]
    ternary = [j for j in joints if len(j) == 3]
    if bodies == 6 and not structure.prismatic_pairs and len(ternary) == 2 and all(len(j) <= 3 for j in joints):
        name = f"{name} ({'Watt' if ternary[0] & ternary[1] else 'Stephenson'})"
    return {"class": name, "mobility": structure.mobility, "drives": len(structure.drawing.drives),
            "links": len(structure.drawing.links), "sliders": structure.prismatic_pairs,
            "groups": describe_plan(structure)}


# ---------------------------------------------------------------- quantities over rows

def _evaluate_closures(home, closures, sine: bool = False):
    """Per offset: the signed angle psi of each closure (b against a: motion.closure_vectors)
    with its rates, or (`sine`) sin psi with its rates. mu = |psi| at a pin, 90 deg - |psi|
    folded to [-90, 90] deg at a guide: mu is smooth except where sin psi = 0, so its
    extremes lie at psi's extremes, at the zeros of sin psi or at the range's ends."""
    from linkcli.mechanisms.drawn.motion import closure_vectors
    from linkcli.mechanisms.drawn.vectors import cross, direction_rates, dot
    speed = home.linkage.drives[0].speed
    kin = home.solved.kin

    def evaluate(q):
        st = kin.run(q, rates=True)
        v, d1, d2 = [], [], []
        for c in closures:
            a, da, dda, b, db, ddb = closure_vectors(kin, st, c)
            _, wa, aa = direction_rates(a, da, dda)
            _, wb, ab = direction_rates(b, db, ddb)
            psi = np.arctan2(cross(a, b), dot(a, b))
            dpsi, ddpsi = (wb - wa) / speed, (ab - aa) / speed ** 2
            if sine:
                v.append(np.sin(psi))
                d1.append(np.cos(psi) * dpsi)
                d2.append(np.cos(psi) * ddpsi - np.sin(psi) * dpsi * dpsi)
            else:
                v.append(psi)
                d1.append(dpsi)
                d2.append(ddpsi)
        return np.stack(v, axis=1), np.stack(d1, axis=1), np.stack(d2, axis=1)
    return evaluate


def _evaluate_links(home, links):
    speed = home.linkage.drives[0].speed

    def evaluate(q):
        st = home.solved.kin.run(q, rates=True)
        v = np.stack([st.theta[k] for k in links], axis=1)
        d1 = np.stack([st.omega[k] / speed for k in links], axis=1)
        d2 = np.stack([st.alpha[k] / speed ** 2 for k in links], axis=1)
        return v, d1, d2
    return evaluate


def slides(home, st, joint):
    """(s, s', s'') of a slider joint along its guide: s = (J - O) . u, O the guide body's
    frame origin, u its guide's direction (u' = omega perp(u))."""
    kin = home.solved.kin
    body = kin.geometry.guides[joint][0]
    _, u, _ = kin.guide_line(st, joint)
    r = st.pos[joint] - st.origin[body]
    s = r[:, 0] * u[:, 0] + r[:, 1] * u[:, 1]
    if not st.rates:
        return s, None, None
    w, a = st.omega[body][:, None], st.alpha[body][:, None]
    pu = np.stack([-u[:, 1], u[:, 0]], axis=-1)
    dr = st.vel[joint] - st.origin_v[body]
    ddr = st.acc[joint] - st.origin_a[body]
    du, ddu = w * pu, a * pu - w * w * u
    ds = np.sum(dr * u + r * du, axis=1)
    dds = np.sum(ddr * u + 2.0 * dr * du + r * ddu, axis=1)
    return s, ds, dds


def _evaluate_sliders(home, joints):
    speed = home.linkage.drives[0].speed

    def evaluate(q):
        st = home.solved.kin.run(q, rates=True)
        values = [slides(home, st, j) for j in joints]
        return (np.stack([v for v, _, _ in values], axis=1), np.stack([d / speed for _, d, _ in values], axis=1),
                np.stack([dd / speed ** 2 for _, _, dd in values], axis=1))
    return evaluate


def _span(home, study):
    """(lo, hi) offsets of the study's range and whether it is a full turn."""
    sv = home.solved
    lo, hi = study.arc
    if study.full_turn:
        return 0.0, TWO_PI, True
    return lo - sv.start, hi - sv.start, False


def _extremes(home, study, evaluate, count, periodic=False):
    from linkcli.mechanisms.drawn.motion import extremes, grid_step
    lo, hi, full = _span(home, study)
    if hi <= lo:
        v, _, _ = evaluate(np.array([lo]))
        return [[float(v[0, k]), lo, float(v[0, k]), lo] for k in range(count)]
    return extremes(evaluate, lo, hi, full, grid_step(home.solved.kin), count, periodic, _sweep_key(home, study))


def _sweep_key(home, study):
    """Ties go to the first the linkage reaches: a full turn from drive value 0 in the
    direction the drive turns (counter-clockwise for a positive speed, clockwise for a
    negative one: a time ratio taken between tied extremes follows the motion, not the
    rows' order); a rocking drive (which runs both ways) from its range's start."""
    lo, _, full = _span(home, study)
    start = home.solved.start
    if not full:
        return lambda q: q - lo
    if home.linkage.drives[0].speed < 0:
        return lambda q: (-(start + q)) % TWO_PI
    return lambda q: (start + q) % TWO_PI


TWO_PI = 2.0 * math.pi


# ---------------------------------------------------------------- transmission

def transmission_section(home, study, u, notes) -> dict:
    """min, max (and the drive's value there) over every closure, the closure where each
    lies, and per closure its links, min, max, worst (farther from 90 deg) and where."""
    from linkcli.mechanisms.drawn.motion import closure_vectors, crossings, grid_step, grid_values, transmission
    sv = home.solved
    closures = sv.structure.closures()
    if not closures:
        return {}
    lo, hi, full = _span(home, study)
    count = len(closures)
    found = _extremes(home, study, _evaluate_closures(home, closures), count, periodic=True)
    cands = [[e[1], e[3]] if e else [] for e in found]
    if hi > lo:
        sine = _evaluate_closures(home, closures, sine=True)
        q, value = grid_values(sine, lo, hi, grid_step(sv.kin))
        for k, roots in crossings(sine, q, value, range(count)).items():
            cands[k] += roots
        if not full:
            for k in range(count):
                cands[k] += [lo, hi]
    flat = np.array([x for c in cands for x in c])
    st = sv.kin.run(flat, rates=False)
    key = _sweep_key(home, study)
    per, mins, maxs = {}, [], []
    start = 0
    for k, c in enumerate(closures):
        xs = flat[start:start + len(cands[k])]
        if not len(xs):
            continue
        a, _, _, b, _, _ = closure_vectors(sv.kin, st, c)
        mu = transmission(c.kind, a[start:start + len(xs)], None, None, b[start:start + len(xs)], None, None)[0]
        start += len(xs)
        mu = _locked(sv, c, xs, mu, full)
        if not np.isfinite(mu).any():
            continue
        mn, at_mn = _pick(mu, xs, key, -1.0)
        mx, at_mx = _pick(mu, xs, key, 1.0)
        worst, at_worst = (mn, at_mn) if (math.pi / 2 - mn) >= (mx - math.pi / 2) else (mx, at_mx)
        per[c.joint] = {"links": [b_ or "ground" for b_ in c.links], "min": _dang(u, snap(mn, 1.0)),
                        "input_at_min": _shown(home, at_mn, u), "max": _dang(u, mx),
                        "input_at_max": _shown(home, at_mx, u), "worst": _dang(u, snap(worst, 1.0)),
                        "input_at_worst": _shown(home, at_worst, u)}
        mins.append((mn, at_mn, c.joint))
        maxs.append((mx, at_mx, c.joint))
    if not per:
        return {}
    mn, at_mn, j_mn = min(mins, key=lambda t: t[0])  # ties: the first closure in plan order
    mx, at_mx, j_mx = max(maxs, key=lambda t: t[0])
    band = TRANSMISSION_BAND
    if math.degrees(mn) < band[0] * (1 - 1e-9) or math.degrees(mx) > band[1] * (1 + 1e-9):
        notes.append(f"transmission angle leaves the recommended {band[0]:g}..{band[1]:g} deg band "
                     f"({num(math.degrees(mn))}..{num(math.degrees(mx))} deg over the drive's range)")
    return {"min": _dang(u, snap(mn, 1.0)), "max": _dang(u, mx), "input_at_min": _shown(home, at_mn, u),
            "input_at_max": _shown(home, at_mx, u), "closure_at_min": j_mn, "closure_at_max": j_mx,
            "closures": per}


def _locked(sv, closure, xs, mu, full: bool):
    """At a dead point of the reach the locking closure's angle is exactly 0 or 180 deg (a
    guide's 0): the value the refined end only approaches to round-off."""
    if full:
        return mu
    r = sv.reach
    mu = np.array(mu, dtype=float)
    for end, op in ((r.lo, r.locks[0]), (r.hi, r.locks[1])):
        if op is None or getattr(sv.structure.plan[op], "joint", None) != closure.joint:
            continue
        at = np.abs(xs - end) <= 1e-9 * max(1.0, abs(end))  # the study's ends, to round-off
        mu[at] = np.where(mu[at] < np.pi / 2, 0.0, np.pi) if closure.kind == "pin" else 0.0
    return mu


def _pick(values, xs, key, sense: float):
    """(value, x) of the extreme of `values` (sense -1: min, +1: max); ties within noise.TIE
    go to the smallest key(x)."""
    from linkcli.noise import TIE
    finite = np.isfinite(values)
    best = float(np.max(sense * values[finite]))
    tied = [i for i in np.flatnonzero(finite) if sense * values[i] >= best - TIE * abs(best)]
    i = min(tied, key=lambda i: key(xs[i]))
    return float(values[i]), float(xs[i])


def _shown(home, q, u) -> float:
    """A leading-drive offset as its printed value (angle wrapped, or length)."""
    sv = home.solved
    x = sv.value(q)
    return _ang(u, x) if sv.turning else snap(float(x), size(home.linkage))


# ---------------------------------------------------------------- motion

def motion_section(home, study, u) -> dict:
    """The drive's range (full turn, or its reach with the dead points), each link's and
    slider's range over it, and the drives."""
    sv = home.solved
    d = home.linkage
    out: dict = {"input_full_turn": bool(study.full_turn)}
    if not study.full_turn:
        lo, hi = study.arc
        out["input_range"] = [_shown(home, lo - sv.start, u), _shown(home, hi - sv.start, u)]
    if not sv.reach.full_turn:
        dead = _dead_points(home, u)
        if d.span is None:
            out["dead_points"] = dead
        else:  # the dead points the asked span runs into (where its study stops)
            lo, hi = d.span
            slack = 1e-9 * max(1.0, abs(lo), abs(hi))
            ends = (sv.reach.lo, sv.reach.hi)
            inside = [p for p, q, lock in zip(dead, ends, sv.reach.locks)
                      if lock is not None and lo - slack <= q <= hi + slack]
            if inside:
                out["dead_points"] = inside
    links = [k.name for k in d.links if k.name not in {dr.name for dr in d.drives}]
    out["links"] = _link_ranges(home, study, links, u)
    sliders = [j.name for j in d.joints if j.slider is not None]
    if sliders:
        found = _extremes(home, study, _evaluate_sliders(home, sliders), len(sliders))
        scale = size(d)
        full = bool(study.full_turn)
        out["sliders"] = {}
        for j, e in zip(sliders, found):
            if e is None:
                continue
            entry = {"range": [snap(e[0], scale), snap(e[2], scale)], "stroke": snap(e[2] - e[0], scale)}
            if full:
                entry.update(_time_ratio(e[1], e[3]))
            out["sliders"][j] = entry
    out["drives"] = {dr.name: {"kind": dr.kind, "speed": _dang(u, dr.speed) if dr.kind == "turn" else dr.speed}
                     for dr in d.drives}
    if d.span is not None:  # the study as the file set it: a design's result keeps it (drawn.kept)
        out["span"] = [float(u.from_rad(v)) if sv.turning else float(v) for v in d.span]
    if d.points:
        out["points"] = list(d.points)
    if d.output is not None:
        out["output"] = d.output
    return out


def _dead_points(home, u) -> list[dict]:
    sv = home.solved
    r = sv.reach
    out = []
    for q, op in ((r.lo, r.locks[0]), (r.hi, r.locks[1])):
        if op is None:
            out.append({"input": _shown(home, q, u), "joint": None, "links": [],
                        "why": "the search bound (no dead point within it)"})
            continue
        closure = _closure_of(sv.structure, op)
        out.append({"input": _shown(home, q, u), "joint": closure[0], "links": list(closure[1])})
    return out


def _closure_of(structure, index: int):
    """(joint, links) of the closure of plan op `index`."""
    from linkcli.mechanisms.drawn.structure import Group
    op = structure.plan[index]
    if isinstance(op, Group):  # the joints inside the group
        inside = [j for j, bodies in structure.pins.items() if bodies and all(b in op.links for b in bodies)]
        return ", ".join(inside), op.links
    joint = op.joint
    for c in structure.closures():
        if c.joint == joint:
            return joint, c.links
    return joint, ()


def _link_ranges(home, study, links, u) -> dict:
    """Per link: full_turn, else its range (wrapped angles) and swing; with a full-turn drive
    and a rocking link, the time ratio of its two swings (>= 1)."""
    if not links:
        return {}
    from linkcli.mechanisms.drawn.motion import grid_step
    sv = home.solved
    lo, hi, full = _span(home, study)
    step = grid_step(sv.kin)
    q = np.linspace(lo, hi, max(8, int(math.ceil((hi - lo) / step))) + 1)
    st = sv.kin.run(q, rates=False)
    turns = {}
    for k in links:
        theta = np.unwrap(st.theta[k][np.isfinite(st.theta[k])])
        turns[k] = bool(full and theta.size and abs(theta[-1] - theta[0]) > math.pi)
    rocking = [k for k in links if not turns[k]]
    out = {k: {"full_turn": True} for k in links if turns[k]}
    if rocking:
        found = _extremes(home, study, _evaluate_links(home, rocking), len(rocking), periodic=True)
        for k, e in zip(rocking, found):
            if e is None:
                continue
            mn, at_mn, mx, at_mx = e
            entry = {"full_turn": False, "range": [_ang(u, mn), _ang(u, mx)], "swing": _dang(u, mx - mn)}
            if full:
                entry.update(_time_ratio(at_mn, at_mx))
            out[k] = entry
    return {k: out[k] for k in links if k in out}


def _time_ratio(at_min: float, at_max: float) -> dict:
    """With a drive turning fully at constant speed: the time ratio of the two strokes between
    a link's (or slider's) extremes, slow over fast (>= 1; Norton ch. 3)."""
    forward = (at_max - at_min) % TWO_PI
    slow, fast = max(forward, TWO_PI - forward), min(forward, TWO_PI - forward)
    return {"time_ratio": slow / fast} if fast > 0 else {}


def shortfall_message(home, lo: float, hi: float) -> str:
    sv = home.solved
    r = sv.reach
    ends = []
    for q, op, asked in ((r.lo, r.locks[0], lo), (r.hi, r.locks[1], hi)):
        if (asked < q) if q == r.lo else (asked > q):
            where = "the search bound" if op is None else f"a dead point at {_closure_of(sv.structure, op)[0]}"
            ends.append(f"{where} (offset {num(q if not sv.turning else math.degrees(q))}"
                        f"{' deg' if sv.turning else ''} from the drawing)")
    return ("the drawing cannot move over the asked span: it stops at " + " and at ".join(ends)
            + "; the rows reached are reported")


# ---------------------------------------------------------------- kinematics rows

def kinematics_rows(home, study, steps: int, u) -> list[dict]:
    """One row per study row: input (the leading drive), each other drive, each link's angle,
    angular velocity and acceleration, each slider's place, velocity and acceleration along
    its guide, each closure's transmission angle, each asked point's x, y and rates."""
    from linkcli.mechanisms.drawn.motion import closure_vectors, transmission
    sv = home.solved
    d = home.linkage
    x, shown = study.rows(steps)
    st = sv.kin.run(sv.q_of(x, study.full_turn), rates=True)
    valid = st.valid
    scale = size(d)
    lead = abs(d.drives[0].speed)
    rate = lead if sv.turning else lead / scale
    cols: dict = {}
    inputs = study.printed(shown, u)

    def col(values, natural):
        return snap_series(np.where(valid, values, np.nan), natural)

    for k, dr in enumerate(d.drives[1:], start=1):
        value = st.q[:, k] + sv.starts[k]
        cols[("drives", dr.name)] = u.from_rad(snap_series(value, 1.0)) if dr.kind == "turn" else snap_series(value, scale)
    for link in d.links:
        k = link.name
        cols[("links", k, "angle")] = u.from_rad(snap(wrap(st.theta[k]), 1.0))
        cols[("links", k, "velocity")] = u.from_rad(col(st.omega[k], rate))
        cols[("links", k, "acceleration")] = u.from_rad(col(st.alpha[k], rate * rate))
    for j in (j.name for j in d.joints if j.slider is not None):
        s, ds, dds = slides(home, st, j)
        cols[("sliders", j, "position")] = snap_series(s, scale)
        cols[("sliders", j, "velocity")] = col(ds, scale * rate)
        cols[("sliders", j, "acceleration")] = col(dds, scale * rate * rate)
    for c in sv.structure.closures():
        mu, _, _ = transmission(c.kind, *closure_vectors(sv.kin, st, c))
        cols[("transmission", c.joint)] = u.from_rad(mu)
    for p in d.points:
        for axis, name in ((0, "x"), (1, "y")):
            cols[("points", p, name)] = snap_series(st.pos[p][:, axis], scale)
        for axis, name in ((0, "vx"), (1, "vy")):
            cols[("points", p, name)] = col(st.vel[p][:, axis], scale * rate)
        for axis, name in ((0, "ax"), (1, "ay")):
            cols[("points", p, name)] = col(st.acc[p][:, axis], scale * rate * rate)
    lists = {key: [float(v) if math.isfinite(v) and ok else None for v, ok in zip(np.asarray(val, dtype=float).tolist(), valid.tolist())]
             for key, val in cols.items()}
    rows = []
    for i, x_i in enumerate(np.asarray(inputs, dtype=float).tolist()):
        row: dict = {"input": x_i}
        for key, values in lists.items():
            node = row
            for part in key[:-1]:
                node = node.setdefault(part, {})
            node[key[-1]] = values[i]
        rows.append(row)
    return rows
