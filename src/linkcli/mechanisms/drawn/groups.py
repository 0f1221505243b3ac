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

from linkcli.mechanisms.drawn.solver import cross, dot, perp, rotate
from linkcli.mechanisms.drawn.structure import GROUND, Group

TRACK_STEPS = 360  # grid steps over one turn of the leading drive (or over its slide bound)
NEWTON_ITERATIONS = 30
RESIDUAL_RTOL = 1e-13  # converged: every residual below this times the linkage's size
BISECTIONS = 60


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
    """The equations of one group over rows of a state (poses of the bodies placed before)."""

    def __init__(self, kin, op: Group, index: int):
        self.kin = kin
        self.op = op
        self.index = index
        placed = {GROUND}
        for earlier in kin.structure.plan[:index]:
            placed |= _bodies_of(earlier)
        self.links = list(op.links)
        self.slot = {b: k for k, b in enumerate(self.links)}
        self.cons = constraints(kin.structure, op, placed)
        self.m = 3 * len(self.links)
        self.size = max(1.0, _extent(kin.drawing))

    # ------------------------------------------------------------ pieces
    def _point(self, st, body, joint, z, rows=slice(None)):
        """(p, R l, R l', R l'') of a body's point: a group body from z, else the state's."""
        l, dl, ddl = self.kin.geometry.point(body, joint, st.q[rows], self.kin.speeds)
        theta = z[:, 3 * self.slot[body] + 2] if body in self.slot else st.theta[body][rows]
        c, s = np.cos(theta), np.sin(theta)
        rl = rotate(l, c, s)
        origin = z[:, 3 * self.slot[body]:3 * self.slot[body] + 2] if body in self.slot else st.origin[body][rows]
        return origin + rl, rl, rotate(dl, c, s), rotate(ddl, c, s)

    def _guide(self, st, joint, z, rows=slice(None)):
        body, g, beta = self.kin.geometry.guides[joint]
        theta = z[:, 3 * self.slot[body] + 2] if body in self.slot else st.theta[body][rows]
        c, s = np.cos(theta), np.sin(theta)
        rg = rotate(g, c, s)
        origin = z[:, 3 * self.slot[body]:3 * self.slot[body] + 2] if body in self.slot else st.origin[body][rows]
        u = rotate(np.array([math.cos(beta), math.sin(beta)]), c, s)
        return origin + rg, rg, u, body

    def _joint_place(self, st, con, z, rows):
        if con.body is None:
            return st.pos[con.joint][rows], None, None
        p, rl, rdl, rddl = self._point(st, con.body, con.joint, z, rows)
        return p, rl, (rdl, rddl)

    # ------------------------------------------------------------ residual and Jacobian
    def residual(self, st, z, rows=slice(None), jacobian: bool = True):
        n = z.shape[0]
        f = np.zeros((n, self.m))
        jac = np.zeros((n, self.m, self.m)) if jacobian else None
        r = 0
        for con in self.cons:
            if con.kind == "pin":
                p, rl, _, _ = self._point(st, con.body, con.joint, z, rows)
                if con.ref == "known":
                    ref = st.pos[con.joint][rows]
                else:
                    ref, rl_ref, _, _ = self._point(st, con.ref, con.joint, z, rows)
                f[:, r:r + 2] = p - ref
                if jacobian:
                    k = 3 * self.slot[con.body]
                    jac[:, r, k], jac[:, r + 1, k + 1] = 1.0, 1.0
                    jac[:, r:r + 2, k + 2] = perp(rl)
                    if con.ref != "known":
                        k = 3 * self.slot[con.ref]
                        jac[:, r, k], jac[:, r + 1, k + 1] = -1.0, -1.0
                        jac[:, r:r + 2, k + 2] = -perp(rl_ref)
                r += 2
            else:
                q_point, rg, u, gbody = self._guide(st, con.joint, z, rows)
                p, rl, _ = self._joint_place(st, con, z, rows)
                e = p - q_point
                f[:, r] = cross(u, e)
                if jacobian:
                    if gbody in self.slot:
                        k = 3 * self.slot[gbody]
                        jac[:, r, k], jac[:, r, k + 1] = u[:, 1], -u[:, 0]
                        jac[:, r, k + 2] = cross(perp(u), e) - cross(u, perp(rg))
                    if con.body is not None:
                        k = 3 * self.slot[con.body]
                        jac[:, r, k], jac[:, r, k + 1] = -u[:, 1], u[:, 0]
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
        tol = RESIDUAL_RTOL * self.size
        done = np.zeros(z.shape[0], dtype=bool)
        for _ in range(iterations):
            f, jac = self.residual(st, z, rows)
            small = np.all(np.abs(f) <= tol, axis=1)
            done = small | done
            todo = ~small & np.all(np.isfinite(f), axis=1)
            if not todo.any():
                break
            step = _solve(jac[todo], f[todo])
            z[todo] -= step
        f, jac = self.residual(st, z, rows)
        done = np.all(np.abs(f) <= tol, axis=1)
        with np.errstate(all="ignore"):
            sign = np.sign(np.linalg.det(jac))
        return z, done, sign


def _solve(jac, f):
    """jac^-1 f per row; NaN where the Jacobian is singular or not finite."""
    with np.errstate(all="ignore"):
        det = np.linalg.det(np.nan_to_num(jac, nan=0.0, posinf=0.0, neginf=0.0))
    out = np.full(f.shape, np.nan)
    ok = np.isfinite(det) & (det != 0) & np.all(np.isfinite(f), axis=1) & np.all(np.isfinite(jac), axis=(1, 2))
    if ok.any():
        out[ok] = np.linalg.solve(jac[ok], f[ok][..., None])[..., 0]
    return out


def _bodies_of(op) -> set[str]:
    from linkcli.mechanisms.drawn.structure import Dyad, GuideThrough, OnGuide, Turn
    if isinstance(op, Dyad):
        return {op.first, op.second}
    if isinstance(op, (Turn, OnGuide, GuideThrough)):
        return {op.link}
    return set(op.links)


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
    reach = bound(kin)
    grid = np.linspace(0.0, reach, TRACK_STEPS + 1)
    z0 = drawn_unknowns(kin, op)
    st0 = kin.run(np.zeros(1), rates=False, upto=index)
    z0, ok, sign0 = solver.newton(st0, z0[None, :])
    if not ok[0] or sign0[0] == 0:
        from linkcli.errors import SolveInputError
        raise SolveInputError(f"links {', '.join(op.links)} determined by the drawing (a group whose "
                              "equations are independent there)",
                              "a drawing where they can move without the drives (a singular group)",
                              key="links")
    halves = []
    for direction in (1.0, -1.0):
        qs = direction * grid
        st = kin.run(qs, rates=False, upto=index)
        zs = [z0[0]]
        q_done = [0.0]
        end = None
        for k in range(1, len(qs)):
            guess = zs[-1] + (zs[-1] - zs[-2]) * ((qs[k] - q_done[-1]) / (q_done[-1] - q_done[-2])) \
                if len(zs) > 1 else zs[-1]
            z, ok, sign = solver.newton(st, guess[None, :], rows=slice(k, k + 1))
            if st.valid[k] and ok[0] and sign[0] == sign0[0] and _near(z[0], zs[-1], qs[k] - q_done[-1], zs, q_done):
                zs.append(z[0])
                q_done.append(qs[k])
                continue
            end, z_end = _refine(kin, solver, index, q_done[-1], qs[k], zs[-1], sign0[0])
            q_done.append(end)
            zs.append(z_end)
            break
        halves.append((np.array(q_done), np.array(zs), end))
    (qf, zf, ef), (qb, zb, eb) = halves
    q = np.concatenate([qb[::-1], qf[1:]])
    z = np.concatenate([zb[::-1], zf[1:]])
    return Track(q, z, float(sign0[0]), (eb, ef))


def _near(z, last, step, zs, qs) -> bool:
    """The step stays on the drawn branch: no angle jumps by more than a quarter turn, and the
    change is at most four times the previous step's (scaled to the step)."""
    change = np.abs(z - last)
    if np.any(change[2::3] > math.pi / 2):
        return False
    if len(zs) < 2:
        return True
    before = np.abs(zs[-1] - zs[-2]) * abs(step / (qs[-1] - qs[-2]))
    return bool(np.all(change <= 4.0 * before + 1e-6 * (1.0 + np.abs(last))))


def _refine(kin, solver, index, q_good, q_bad, z_good, sign):
    """The dead point between an offset that solves and one that does not: bisection."""
    for _ in range(BISECTIONS):
        mid = 0.5 * (q_good + q_bad)
        if mid == q_good or mid == q_bad:
            break
        st = kin.run(np.array([mid]), rates=False, upto=index)
        z, ok, s = solver.newton(st, z_good[None, :])
        if st.valid[0] and ok[0] and s[0] == sign and np.all(np.abs(z[0] - z_good)[2::3] < math.pi / 2):
            q_good, z_good = mid, z[0]
        else:
            q_bad = mid
    return q_good, z_good


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
    from linkcli.mechanisms.drawn.solver import State
    sub = State(len(rows), st.q[rows], st.rates)
    for name in ("theta", "omega", "alpha", "origin", "origin_v", "origin_a", "pos", "vel", "acc"):
        setattr(sub, name, {k: v[rows] for k, v in getattr(st, name).items()})
    return sub


def _group_rates(kin, solver: GroupSolver, st, z) -> None:
    """Velocities and accelerations of the group's links (module docstring)."""
    _, jac = solver.residual(st, np.nan_to_num(z))
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
