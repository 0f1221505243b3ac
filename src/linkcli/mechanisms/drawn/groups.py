"""A group that is not a dyad (a class-III triad and the like), by Newton's method.

Unknowns: each group link's pose (origin x, y and angle: three per link). Equations, one
set per constraint of the group (structure.Group): a pin of a group link at a joint whose
place is known, p_b(J) - X_J = 0; a pin shared by two group links, p_b(J) - p_c(J) = 0;
a slider joint on a guide, u x (p_J - Q) = 0. The structure guarantees as many equations as
unknowns; the Jacobian has the columns dF/do = I and dF/dtheta = perp(R l) (pins) and the
matching ones for the guide (Haug, Computer-Aided Kinematics and Dynamics of Mechanical
Systems, ch. 3: the constraint Jacobian).

Continuation (the one loop over steps): from the drawing (an exact solution at offset 0)
along a grid of the leading drive's offset, each step predicted by the secant of the last
two and corrected by Newton; a step whose Jacobian determinant changes sign, or that does
not converge, is a dead point of the group: the track ends there, refined by bisection. The
track keeps the drawn branch. Rows (any number, any order) are then solved together: Newton
from the track interpolated at their offsets, batched over rows; a row that does not
converge, or lands on the other branch (the sign of the determinant), is invalid.
Velocities and accelerations: J z' = -F'(z' = 0), J z'' = -F''(z'' = 0) (the constraint
equations differentiated once and twice, linear in the unknown rates).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.drawn.structure import GROUND, Group, placed_by
from linkcli.mechanisms.drawn.vectors import cross, perp, rotate

TRACK_STEPS = 180  # largest steps over one turn of the leading drive (or over its slide bound)
NEWTON_ITERATIONS = 30
RESIDUAL_RTOL = 1e-13  # converged: every residual below this times the linkage's size
CORRECTION = 0.5  # largest Newton correction of a step, relative to the predicted move
MIN_STEP = 1e-12  # relative to the grid step: a smaller step means a dead point


@dataclass(frozen=True)
class Constraint:
    """One constraint: kind "pin" (body's point of `joint` at `ref`: "known" or another
    group body) or "slide" (`joint` on `guide`'s line, the joint's place from `carrier`,
    a group body, or known)."""

    kind: str
    joint: str
    body: str | None
    ref: str | None = None
    guide: str | None = None


@dataclass
class Track:
    """The continuation of one group: offsets q (sorted) and the unknowns z (rows of 3 k:
    origin x, y, angle per link, angles unwrapped along the track), the sign of the
    Jacobian's determinant, and where it ended (None: the bound was reached)."""

    q: np.ndarray
    z: np.ndarray
    sign: float
    ends: tuple[float | None, float | None]


def constraints(structure, op: Group, placed: set[str]) -> list[Constraint]:
    """The group's equations given the bodies placed before it."""
    inside = set(op.links)
    out = []
    joints = dict.fromkeys(j for b in op.links for j in structure.points[b])
    for joint in joints:
        bodies = structure.pins[joint]
        members = [b for b in bodies if b in inside]
        known = any(b in placed for b in bodies)
        if known:
            out += [Constraint("pin", joint, b, "known") for b in members]
        else:
            out += [Constraint("pin", joint, b, members[0]) for b in members[1:]]
    for joint, guide in structure.slides.items():
        carriers = structure.pins[joint]
        has_guide = guide in inside or guide in placed
        known = any(b in placed for b in carriers)
        inner = [b for b in carriers if b in inside]
        if has_guide and (known or inner) and (guide in inside or inner):
            out.append(Constraint("slide", joint, None if known else inner[0], guide=guide))
    return out


class GroupSolver:
    """The equations of one group over rows of a state (poses of the bodies placed before).

    `prepare` gathers, once per state, every pin's points in their bodies' frames and the
    known places they must meet, so that each Newton iteration is a few array operations
    over (rows, constraints)."""

    def __init__(self, kin, op: Group, index: int):
        self.kin = kin
        self.op = op
        self.index = index
        placed = {GROUND}
        for earlier in kin.structure.plan[:index]:
            placed |= placed_by(earlier)
        self.links = list(op.links)
        self.slot = {b: k for k, b in enumerate(self.links)}
        self.cons = constraints(kin.structure, op, placed)
        self.pins = [c for c in self.cons if c.kind == "pin"]
        self.slides = [c for c in self.cons if c.kind == "slide"]
        self.m = 3 * len(self.links)
        self.size = max(1.0, _extent(kin.drawing))
        self.slot_a = np.array([self.slot[c.body] for c in self.pins], dtype=int)
        self.paired = np.array([c.ref != "known" for c in self.pins], dtype=bool)
        self.slot_b = np.array([self.slot[c.ref] if c.ref != "known" else 0 for c in self.pins], dtype=int)
        rows = np.arange(len(self.pins))
        self.row_x, self.row_y = 2 * rows, 2 * rows + 1

    # ------------------------------------------------------------ what a state gives
    def prepare(self, st, rows=slice(None)) -> dict:
        """Per state rows: each pin's points in its bodies' frames (la, lb: (n, C, 2)) and the
        known places (x: (n, C, 2)); each slide's pieces."""
        q = st.q[rows]
        n = q.shape[0]
        geo, speeds = self.kin.geometry, self.kin.speeds
        la = np.empty((n, len(self.pins), 2))
        lb = np.zeros((n, len(self.pins), 2))
        x = np.zeros((n, len(self.pins), 2))
        for k, c in enumerate(self.pins):
            la[:, k] = geo.point(c.body, c.joint, q, speeds)[0]
            if c.ref == "known":
                x[:, k] = st.pos[c.joint][rows]
            else:
                lb[:, k] = geo.point(c.ref, c.joint, q, speeds)[0]
        return {"st": st, "rows": rows, "q": q, "la": la, "lb": lb, "x": x}

    def _origin_theta(self, body, z, prep):
        if body in self.slot:
            k = 3 * self.slot[body]
            return z[:, k:k + 2], z[:, k + 2]
        return prep["st"].origin[body][prep["rows"]], prep["st"].theta[body][prep["rows"]]

    def _point(self, st, body, joint, z, rows=slice(None)):
        """(p, R l, R l', R l'') of a body's point: a group body from z, else the state's."""
        l, dl, ddl = self.kin.geometry.point(body, joint, st.q[rows], self.kin.speeds)
        prep = {"st": st, "rows": rows}
        origin, theta = self._origin_theta(body, z, prep)
        c, s = np.cos(theta), np.sin(theta)
        rl = rotate(l, c, s)
        return origin + rl, rl, rotate(dl, c, s), rotate(ddl, c, s)

    def _guide(self, st, joint, z, rows=slice(None)):
        body, g, beta = self.kin.geometry.guides[joint]
        origin, theta = self._origin_theta(body, z, {"st": st, "rows": rows})
        c, s = np.cos(theta), np.sin(theta)
        rg = rotate(g, c, s)
        u = rotate(np.array([math.cos(beta), math.sin(beta)]), c, s)
        return origin + rg, rg, u, body

    # ------------------------------------------------------------ residual and Jacobian
    def residual(self, prep, z, jacobian: bool = True):
        n = z.shape[0]
        f = np.zeros((n, self.m))
        jac = np.zeros((n, self.m, self.m)) if jacobian else None
        npins = len(self.pins)
        if npins:
            ka = 3 * self.slot_a
            ta = z[:, ka + 2]
            rla = _rot(prep["la"], ta)
            pa = z[:, np.stack([ka, ka + 1], axis=-1)] + rla
            kb = 3 * self.slot_b
            tb = z[:, kb + 2]
            rlb = _rot(prep["lb"], tb)
            pb = np.where(self.paired[None, :, None], z[:, np.stack([kb, kb + 1], axis=-1)] + rlb, prep["x"])
            f[:, :2 * npins] = (pa - pb).reshape(n, 2 * npins)
            if jacobian:
                jac[:, self.row_x, ka] = 1.0
                jac[:, self.row_y, ka + 1] = 1.0
                jac[:, self.row_x, ka + 2] = -rla[..., 1]
                jac[:, self.row_y, ka + 2] = rla[..., 0]
                if self.paired.any():
                    sel = np.flatnonzero(self.paired)
                    kbs = kb[sel]
                    jac[:, self.row_x[sel], kbs] -= 1.0
                    jac[:, self.row_y[sel], kbs + 1] -= 1.0
                    jac[:, self.row_x[sel], kbs + 2] += rlb[:, sel, 1]
                    jac[:, self.row_y[sel], kbs + 2] -= rlb[:, sel, 0]
        r = 2 * npins
        st, rows = prep["st"], prep["rows"]
        for con in self.slides:
            q_point, rg, u, gbody = self._guide(st, con.joint, z, rows)
            if con.body is None:
                p, rl = st.pos[con.joint][rows], None
            else:
                p, rl, _, _ = self._point(st, con.body, con.joint, z, rows)
            e = p - q_point
            f[:, r] = cross(u, e)
            if jacobian:
                if gbody in self.slot:
                    k = 3 * self.slot[gbody]
                    jac[:, r, k], jac[:, r, k + 1] = u[:, 1], -u[:, 0]
                    jac[:, r, k + 2] = cross(perp(u), e) - cross(u, perp(rg))
                if con.body is not None:
                    k = 3 * self.slot[con.body]
                    jac[:, r, k] += -u[:, 1]
                    jac[:, r, k + 1] += u[:, 0]
                    jac[:, r, k + 2] += cross(u, perp(rl))
            r += 1
        return f, jac

    def rates_rhs(self, st, z, twist, order: int):
        """F' (order 1) with the group's unknown rates `twist` (n, m), or F'' (order 2) with
        the unknown accelerations 0 and the rates `twist`: the constant parts of the rate
        equations."""
        n = z.shape[0]
        out = np.zeros((n, self.m))

        def kin_of(body):
            if body in self.slot:
                k = 3 * self.slot[body]
                w = twist[:, k + 2]
                return twist[:, k:k + 2], w, np.zeros((n, 2)), np.zeros(n)
            return st.origin_v[body], st.omega[body], st.origin_a[body], st.alpha[body]

        def point_rates(body, joint):
            _, rl, rdl, rddl = self._point(st, body, joint, z)
            ov, w, oa, a = kin_of(body)
            w_, a_ = w[:, None], a[:, None]
            v = ov + w_ * perp(rl) + rdl
            acc = oa + a_ * perp(rl) - w_ * w_ * rl + 2.0 * w_ * perp(rdl) + rddl
            return v, acc

        r = 0
        for con in self.cons:
            if con.kind == "pin":
                v, a = point_rates(con.body, con.joint)
                if con.ref == "known":
                    vr, ar = st.vel[con.joint], st.acc[con.joint]
                else:
                    vr, ar = point_rates(con.ref, con.joint)
                out[:, r:r + 2] = (v - vr) if order == 1 else (a - ar)
                r += 2
                continue
            q_point, rg, u, gbody = self._guide(st, con.joint, z)
            if con.body is None:
                p, vp, ap = st.pos[con.joint], st.vel[con.joint], st.acc[con.joint]
            else:
                p = self._point(st, con.body, con.joint, z)[0]
                vp, ap = point_rates(con.body, con.joint)
            ov, w, oa, a = kin_of(gbody)
            w_, a_ = w[:, None], a[:, None]
            vq = ov + w_ * perp(rg)
            aq = oa + a_ * perp(rg) - w_ * w_ * rg
            e, de = p - q_point, vp - vq
            if order == 1:
                out[:, r] = w * cross(perp(u), e) + cross(u, de)
            else:
                ddu = a_ * perp(u) - w_ * w_ * u
                out[:, r] = cross(ddu, e) + 2.0 * w * cross(perp(u), de) + cross(u, ap - aq)
            r += 1
        return out

    # ------------------------------------------------------------ Newton
    def newton(self, st, z, rows=slice(None), iterations: int = NEWTON_ITERATIONS):
        """(z, converged (n,), sign of det J (n,)) from the guess z over the rows."""
        z = np.array(z, dtype=float)
        prep = self.prepare(st, rows)
        tol = RESIDUAL_RTOL * self.size
        for _ in range(iterations):
            f, jac = self.residual(prep, z)
            todo = ~np.all(np.abs(f) <= tol, axis=1) & np.all(np.isfinite(f), axis=1)
            if not todo.any():
                break
            z[todo] -= _solve(jac[todo], f[todo])
        f, jac = self.residual(prep, z)
        done = np.all(np.abs(f) <= tol, axis=1)
        with np.errstate(all="ignore"):
            sign = np.sign(np.linalg.det(np.nan_to_num(jac)))
        return z, done, sign


def _rot(local, theta):
    """R(theta) l for (n, C, 2) points and (n, C) angles."""
    c, s = np.cos(theta), np.sin(theta)
    out = np.empty(local.shape)
    out[..., 0] = local[..., 0] * c - local[..., 1] * s
    out[..., 1] = local[..., 0] * s + local[..., 1] * c
    return out


def _solve(jac, f):
    """jac^-1 f per row (LAPACK's batched solve: its rounding, which differs between CPUs,
    stays far below the printed digits -- positions are converged by Newton on elementwise
    residuals, and a rate is one well-conditioned solve; search.linalg's elementwise
    elimination is slower on 12 x 12 stacks); NaN where the Jacobian is singular."""
    try:
        with np.errstate(all="ignore"):
            out = np.linalg.solve(jac, f[..., None])[..., 0]
        return np.where(np.isfinite(out), out, np.nan)
    except np.linalg.LinAlgError:  # a singular row among them: solve the others
        out = np.full(f.shape, np.nan)
        with np.errstate(all="ignore"):
            det = np.linalg.det(np.nan_to_num(jac))
        ok = np.isfinite(det) & (det != 0)
        if ok.any():
            out[ok] = np.linalg.solve(jac[ok], f[ok][..., None])[..., 0]
        return out


def _extent(drawing) -> float:
    xs = [j.at[0] for j in drawing.joints]
    ys = [j.at[1] for j in drawing.joints]
    return max(max(xs) - min(xs), max(ys) - min(ys))


def drawn_unknowns(kin, op: Group) -> np.ndarray:
    """z at the drawing: each link's drawn frame."""
    z = []
    for b in op.links:
        z += [*kin.geometry.origin0[b], kin.geometry.angle0[b]]
    return np.array(z, dtype=float)


# ---------------------------------------------------------------- the track

def bound(kin) -> float:
    """How far the track follows the leading drive either way: two turns (a turning drive) or
    four times the drawing's extent (a sliding one)."""
    from linkcli.mechanisms.drawn.model import TURN
    return 2.0 * math.pi if kin.drawing.drives[0].kind == TURN else 4.0 * max(1.0, _extent(kin.drawing))


def build_track(kin, index: int, op: Group) -> Track:
    """Continuation from the drawing both ways (module docstring)."""
    solver = GroupSolver(kin, op, index)
    z0 = drawn_unknowns(kin, op)
    st0 = kin.run(np.zeros(1), rates=False, upto=index)
    z0, ok, sign0 = solver.newton(st0, z0[None, :])
    if not ok[0] or sign0[0] == 0:
        from linkcli.errors import SolveInputError
        raise SolveInputError(f"links {', '.join(op.links)} determined by the drawing (a group whose "
                              "equations are independent there)",
                              "a drawing where they can move without the drives (a singular group)",
                              key="links")
    halves = [_follow(kin, solver, index, z0[0], sign0[0], direction) for direction in (1.0, -1.0)]
    (qf, zf, ef), (qb, zb, eb) = halves
    q = np.concatenate([qb[::-1], qf[1:]])
    z = np.concatenate([zb[::-1], zf[1:]])
    return Track(q, z, float(sign0[0]), (eb, ef))


def _follow(kin, solver, index, z0, sign, direction):
    """(q, z, end) of the continuation one way: steps of at most the grid step, halved where
    Newton fails, lands on the other branch or corrects the secant prediction by more than
    CORRECTION of the step (a turn of the branch the step would cut), doubled again after a
    success; it ends where the step falls below MIN_STEP (a dead point) or at the bound."""
    reach = bound(kin)
    full = reach / TRACK_STEPS
    h = full / 8  # the first step has no secant to predict it: a short one
    qs, zs = [0.0], [z0]
    scale = np.tile([solver.size, solver.size, 1.0], len(solver.links))
    while abs(qs[-1]) < reach:
        q = direction * min(abs(qs[-1]) + h, reach)
        if len(zs) > 1:
            guess = zs[-1] + (zs[-1] - zs[-2]) * ((q - qs[-1]) / (qs[-1] - qs[-2]))
        else:
            guess = zs[-1]
        st = kin.run(np.array([q]), rates=False, upto=index)
        z, ok, s = solver.newton(st, guess[None, :], iterations=12)
        moved = np.max(np.abs(guess - zs[-1]) / scale)
        corrected = np.max(np.abs(z[0] - guess) / scale)
        if (st.valid[0] and ok[0] and s[0] == sign and np.all(np.abs(z[0] - zs[-1])[2::3] < math.pi / 4)
                and (len(zs) == 1 or corrected <= CORRECTION * moved + 1e-9)):
            qs.append(q)
            zs.append(z[0])
            h = min(2.0 * h, full)
            continue
        h *= 0.5
        if h < MIN_STEP * full:
            return np.array(qs), np.array(zs), qs[-1]
    return np.array(qs), np.array(zs), None


# ---------------------------------------------------------------- rows

def solve_group(kin, st, index: int, op: Group, guess=None) -> None:
    """Place the group's links over the state's rows (module docstring)."""
    solver = GroupSolver(kin, op, index)
    track = kin.tracks.get(index)
    if track is None:
        track = kin.tracks[index] = build_track(kin, index, op)
    q1 = st.q[:, 0]
    inside = (q1 >= track.q[0]) & (q1 <= track.q[-1]) & st.valid
    z = np.full((st.n, solver.m), np.nan)
    if guess is None:
        for k in range(solver.m):
            z[:, k] = np.interp(q1, track.q, track.z[:, k])
    else:
        z[:] = guess
    rows = np.flatnonzero(inside)
    if rows.size:
        sub = _subset(st, rows)
        zr, ok, sign = solver.newton(sub, z[rows])
        good = ok & (sign == track.sign) & np.all(np.abs(zr - z[rows])[:, 2::3] < math.pi / 2, axis=1)
        z[rows] = np.where(good[:, None], zr, np.nan)
        inside[rows] = good
    kin.invalidate(st, ~inside)
    z[~inside] = np.nan
    for b in op.links:
        k = 3 * solver.slot[b]
        st.theta[b] = z[:, k + 2]
        st.origin[b] = z[:, k:k + 2]
    if st.rates:
        _group_rates(kin, solver, st, z)
    for b in op.links:
        for joint in kin.structure.points[b]:
            if joint not in st.pos:
                kin._point_of(st, b, joint)


def _subset(st, rows):
    """The state's rows `rows` (what a group's equations read)."""
    from linkcli.mechanisms.drawn.state import State
    sub = State(len(rows), st.q[rows], st.rates)
    for name in ("theta", "omega", "alpha", "origin", "origin_v", "origin_a", "pos", "vel", "acc"):
        setattr(sub, name, {k: v[rows] for k, v in getattr(st, name).items()})
    return sub


def _group_rates(kin, solver: GroupSolver, st, z) -> None:
    """Velocities and accelerations of the group's links (module docstring)."""
    _, jac = solver.residual(solver.prepare(st), np.nan_to_num(z))
    ok = np.all(np.isfinite(z), axis=1)
    zero = np.zeros_like(z)
    rhs1 = solver.rates_rhs(st, np.nan_to_num(z), zero, 1)
    dz = np.full_like(z, np.nan)
    if ok.any():
        dz[ok] = -_solve(jac[ok], rhs1[ok])
    rhs2 = solver.rates_rhs(st, np.nan_to_num(z), np.nan_to_num(dz), 2)
    ddz = np.full_like(z, np.nan)
    if ok.any():
        ddz[ok] = -_solve(jac[ok], rhs2[ok])
    for b in solver.links:
        k = 3 * solver.slot[b]
        st.omega[b], st.alpha[b] = dz[:, k + 2], ddz[:, k + 2]
        st.origin_v[b], st.origin_a[b] = dz[:, k:k + 2], ddz[:, k:k + 2]
