"""Loads on a drawn linkage: the Newton-Euler equations of every body, one (n, m, m) linear
system over the rows, solved at once (mechanisms.newton_euler; Norton, Design of Machinery,
ch. 11, written for any number of links).

Bodies and equations: each link, sum F = m a_G and sum (P - G) x F + sum T = I_G alpha (three);
each slider block, a point mass at its joint, sum F = m a_J (two: it carries no moment).

Unknowns, and the convention of every reported pin force (which body it acts on):
- A joint J joins the bodies B_0, B_1, ... in this order: the ground (a ground joint), the
  links listing J in [links] order (not the link whose guide a slider runs on), the slider
  block (a slider joint). The pin belongs to B_0; the unknown F_{J,i} is the force B_0
  exerts on B_i at J (i >= 1), and B_0 carries -sum_i F_{J,i}. Reported: a joint of two
  bodies as "J" (the force on B_1: on the later link, the link on a ground pivot, the block
  on its rod); a joint of k > 2 bodies as "J/B_i" for each i >= 1 (the block: "J/slider").
  The force on B_0 is minus their sum (`link_forces` gives every (joint, link) force).
- A slider block on its guide: the guide's normal force N perp(u) on the block, reported as
  "J/guide" (N, global x and y); the guide's body carries -N perp(u) at J (frictionless).
- Each drive: its torque on the driven link (N m, counter-clockwise positive; the ground
  takes the reaction), or its force along the guide on a driven slider's block (N; the
  guide's body takes the reaction). The leading drive's effort is `input_torque`, every
  drive's is in `efforts` (DrawnLoadRows).
External loads: gravity on every mass; [loads] torques (N m on a link) and forces (N at a
joint: on the slider block at a slider joint, else on the first link of [links] carrying it).
Lengths enter in metres. Singular rows: where a closure locks (|sin mu| <= SINGULAR_TOLERANCE:
the system has no unique solution, forces NaN). Mechanical advantage: the leading drive's
rate over the output's (the [motion] output, else the last link), velocity-ratio form
(Norton ch. 6): rad/rad for a link, rad/m for a slider; infinite (NaN) where the output
stands still (|rate| <= SINGULAR_TOLERANCE times its largest over the rows).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from linkcli.mechanisms.drawn.structure import GROUND
from linkcli.mechanisms.drawn.vectors import cross, perp, rotate
from linkcli.mechanisms.newton_euler import SINGULAR_TOLERANCE, finite_max, max_norm, scales
from linkcli.mechanisms.protocol import LoadRows
from linkcli.model import LinkMass

SLIDER = "slider"


@dataclass
class DrawnLoadRows(LoadRows):
    """LoadRows with every drive's effort: drive name -> (n,) its torque on its link (N m) or
    its force along the guide on its slider's block (N); the first is `input_torque`."""

    efforts: dict[str, np.ndarray] = field(default_factory=dict)


def pin_bodies(drawing) -> dict[str, list[str]]:
    """Joint -> the bodies it joins, in the order of the convention (module docstring); the
    block of a slider joint is named SLIDER."""
    out = {}
    for joint in drawing.joints:
        bodies = [GROUND] if joint.ground else []
        bodies += [k.name for k in drawing.links if joint.name in k.joints and k.name != joint.guide]
        if joint.slider is not None:
            bodies.append(SLIDER)
        out[joint.name] = bodies
    return out


def pin_names(drawing) -> list[tuple[str, str, str]]:
    """(report name, joint, body acted on) of every pin force, in report order."""
    out = []
    for joint, bodies in pin_bodies(drawing).items():
        if len(bodies) == 2:
            out.append((joint, joint, bodies[1]))
        else:
            out += [(f"{joint}/{b}", joint, b) for b in bodies[1:]]
    out += [(f"{j.name}/guide", j.name, "guide") for j in drawing.joints if j.slider is not None]
    return out


def link_forces(drawing, rows: LoadRows) -> dict[tuple[str, str], np.ndarray]:
    """(joint, body) -> (n, 2) N: the force each pin exerts on each body it joins (the pin's
    owner B_0 included, as minus the others'), from the reported pins."""
    out = {}
    names = {(joint, body): name for name, joint, body in pin_names(drawing) if body != "guide"}
    for joint, bodies in pin_bodies(drawing).items():
        if len(bodies) < 2:
            continue
        total = 0.0
        for body in bodies[1:]:
            force = rows.pins[names[(joint, body)]]
            out[(joint, body)] = force
            total = total + force
        out[(joint, bodies[0])] = -total
    return out


def drawn_loads(home, st, case, metres: float) -> LoadRows:
    """Input effort, pin forces and guide forces at every row of the state (one solve)."""
    d = home.linkage
    kin = home.solved.kin
    n = st.n
    loads, masses = case.loads, case.masses
    gravity = np.asarray(loads.gravity, dtype=float)
    links = [k.name for k in d.links]
    sliders = [j.name for j in d.joints if j.slider is not None]
    row_of = {}
    m = 0
    for name in links:
        row_of[name] = m
        m += 3
    for j in sliders:
        row_of[(SLIDER, j)] = m
        m += 2
    matrix = np.zeros((n, m, m))
    rhs = np.zeros((n, m))
    pos = {j: st.pos[j] * metres for j in st.pos}
    centre, force_terms, inertia_terms = {}, [], []
    ext_torque = dict(loads.torques)
    with np.errstate(all="ignore"):
        for name in links:
            mass = masses.of(name) or LinkMass(0.0)
            c, s = np.cos(st.theta[name]), np.sin(st.theta[name])
            rc = rotate(np.asarray(mass.center, dtype=float) * metres, c, s)
            g = st.origin[name] * metres + rc
            w, a = st.omega[name][:, None], st.alpha[name][:, None]
            acc = st.origin_a[name] * metres + a * perp(rc) - w * w * rc
            r = row_of[name]
            rhs[:, r:r + 2] = mass.mass * (acc - gravity)
            rhs[:, r + 2] = mass.inertia * st.alpha[name] - ext_torque.get(name, 0.0)
            centre[name] = g
            force_terms += [mass.mass * np.abs(gravity).sum(), mass.mass * max_norm(acc)]
            inertia_terms.append(mass.inertia * finite_max(st.alpha[name]))
        for j in sliders:
            mass = masses.of(j) or LinkMass(0.0)
            r = row_of[(SLIDER, j)]
            acc = st.acc[j] * metres
            rhs[:, r:r + 2] = mass.mass * (acc - gravity)
            force_terms += [mass.mass * np.abs(gravity).sum(), mass.mass * max_norm(acc)]
        bodies = pin_bodies(d)
        for joint, force in loads.forces:
            target = (SLIDER, joint) if d.joint(joint).slider is not None else next(
                b for b in bodies[joint] if b != GROUND)
            _apply_known(rhs, row_of, centre, target, pos[joint], np.asarray(force, dtype=float))
            force_terms.append(float(np.abs(force).sum()))

        def put(body, column, point, sign, direction=None):
            """The unknown in `column` (a 2-vector, or a scalar along `direction`) acting on body."""
            if body == GROUND:
                return
            key = (SLIDER, point[1]) if body == SLIDER else body
            r = row_of[key]
            if direction is None:
                matrix[:, r, column] += sign
                matrix[:, r + 1, column + 1] += sign
            else:
                matrix[:, r, column] += sign * direction[:, 0]
                matrix[:, r + 1, column] += sign * direction[:, 1]
            if body == SLIDER:
                return
            lever = pos[point[1]] - centre[body]
            if direction is None:
                matrix[:, r + 2, column] += -sign * lever[:, 1]
                matrix[:, r + 2, column + 1] += sign * lever[:, 0]
            else:
                matrix[:, r + 2, column] += sign * cross(lever, direction)

        column = 0
        pin_columns = {}
        for joint, bs in bodies.items():
            for b in bs[1:]:
                put(b, column, (None, joint), 1.0)
                put(bs[0], column, (None, joint), -1.0)
                pin_columns[(joint, b)] = column
                column += 2
        guide_columns = {}
        for j in sliders:
            _, u, gbody = kin.guide_line(st, j)
            normal = perp(u)
            put(SLIDER, column, (None, j), 1.0, normal)
            put(gbody, column, (None, j), -1.0, normal)
            guide_columns[j] = (column, normal)
            column += 1
        drive_columns = []
        for k, drive in enumerate(d.drives):
            if drive.kind == "turn":
                matrix[:, row_of[drive.name] + 2, column] += 1.0
            else:
                _, u, gbody = kin.guide_line(st, drive.name)
                put(SLIDER, column, (None, drive.name), 1.0, u)
                put(gbody, column, (None, drive.name), -1.0, u)
            drive_columns.append(column)
            column += 1
        singular = _singular(home, st)
        matrix[singular] = np.eye(m)
        solution = np.linalg.solve(matrix, rhs[..., None])[..., 0]
        solution[singular] = np.nan
        pins = {}
        for name, joint, body in pin_names(d):
            if body == "guide":
                col, normal = guide_columns[joint]
                pins[name] = solution[:, col, None] * normal
            else:
                col = pin_columns[(joint, body)]
                pins[name] = solution[:, col:col + 2]
        length = max(max_norm(pos[b] - pos[a]) for k in d.links for a, b in zip(k.joints, k.joints[1:]))
        force_scale, torque_scale = scales(force_terms, inertia_terms,
                                           sum(abs(t) for _, t in loads.torques), length)
        return DrawnLoadRows(solution[:, drive_columns[0]], pins, singular, _advantage(home, st, metres),
                             force_scale, torque_scale, tuple(name for name, _, _ in pin_names(d)),
                             efforts={drive.name: solution[:, col] for drive, col in zip(d.drives, drive_columns)})


def _apply_known(rhs, row_of, centre, target, point, force) -> None:
    """A known external force at `point` on `target`: moved to the right-hand side."""
    r = row_of[target]
    rhs[:, r:r + 2] -= force
    if isinstance(target, tuple):
        return
    rhs[:, r + 2] -= cross(point - centre[target], np.broadcast_to(force, point.shape))


def _singular(home, st) -> np.ndarray:
    """Rows where a closure locks (|sin mu| <= SINGULAR_TOLERANCE) or that do not close."""
    from linkcli.mechanisms.drawn.motion import closure_vectors, transmission
    bad = ~st.valid
    for c in home.solved.structure.closures():
        a, _, _, b, _, _ = closure_vectors(home.solved.kin, st, c)
        mu, _, _ = transmission(c.kind, a, None, None, b, None, None)
        bad |= ~(np.abs(np.sin(mu)) > SINGULAR_TOLERANCE)
    return bad


def _advantage(home, st, metres: float) -> np.ndarray:
    """The leading drive's rate over the output's (module docstring)."""
    from linkcli.mechanisms.drawn.sections import slides
    d = home.linkage
    output = d.output or d.links[-1].name
    if output in {k.name for k in d.links}:
        rate = st.omega[output]
    else:
        rate = slides(home, st, output)[1] * metres
    lead = d.drives[0].speed * (1.0 if home.solved.turning else metres)
    top = finite_max(rate)
    toggle = ~(np.abs(rate) > SINGULAR_TOLERANCE * top)
    with np.errstate(all="ignore"):
        return np.where(toggle, np.nan, lead / np.where(toggle, 1.0, rate))
