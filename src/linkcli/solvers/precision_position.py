"""Precision-position function generation by Freudenstein's equation (numpy only).

Freudenstein (1955), "Approximate synthesis of four-bar linkages", Trans. ASME 77:

    K1 cos(psi) - K2 cos(phi) + K3 = cos(phi - psi),
    K1 = d / a,  K2 = d / c,  K3 = (a^2 - b^2 + c^2 + d^2) / (2 a c)

is linear in K1, K2, K3: three (phi_i, psi_i) pairs give the exact linkage, four or more
a least-squares one, which is then refined by Levenberg-Marquardt on the true output-angle
error of the assembled linkage (the linear residual is not the angle error). A negative
ratio means that link points the other way (its angle is phi + 180 or psi + 180): the
lengths are reported positive and the note says so. This module must not import scipy.
"""

from __future__ import annotations

import numpy as np

from linkcli.errors import InputError
from linkcli.kinematics import TWO_PI, choose_arc, input_arcs, pose, wrap
from linkcli.model import FourBar
from linkcli.result import Positions, Solution, Status

COINCIDENT = 1e-9  # rad: two input (or output) angles closer than this are one position
ILL_CONDITIONED = 1e12


def freudenstein_ratios(phi: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """Least-squares (exact for three pairs) K1, K2, K3 of Freudenstein's equation."""
    m = np.column_stack([np.cos(psi), -np.cos(phi), np.ones_like(phi)])
    rhs = np.cos(phi - psi)
    k, *_ = np.linalg.lstsq(m, rhs, rcond=None)
    return k


def lengths_from_ratios(k: np.ndarray, d: float):
    """(a, b^2, c) signed: a = d/K1, c = d/K2, b^2 = a^2 + c^2 + d^2 - 2 a c K3."""
    a = d / k[0]
    c = d / k[1]
    b2 = a * a + c * c + d * d - 2 * a * c * k[2]
    return a, b2, c


def output_angles(a, b, c, d, phi, sign):
    """psi of the linkage with physical lengths at physical input angles on a branch."""
    return pose(a, b, c, d, phi, sign)


def _position_names(idx) -> str:
    return ", ".join(str(i + 1) for i in idx)


def _check_positions(problem) -> None:
    phi = np.array(problem.input_angles)
    psi = np.array(problem.output_angles)
    path = problem.meta.path
    for name, ang in (("positions.input", phi),):
        diff = np.abs(wrap(ang[:, None] - ang[None, :]))
        i, j = np.nonzero(np.triu(diff < COINCIDENT, 1))
        if len(i):
            raise InputError("distinct angles (each position a different angle)",
                             f"positions {i[0] + 1} and {j[0] + 1} at the same angle",
                             path=path, key=name, line=problem.lines[0] if problem.lines else None)


def _refine(phi, psi, a, b, c, d, sign, iters=100):
    """Levenberg-Marquardt on the true output-angle error, d fixed; lengths stay positive.

    Works on log-lengths so that a, b, c > 0; Jacobian by central differences (3 columns).
    Returns the lengths, whether every position assembles, and the residual evaluations.
    """
    x = np.log([a, b, c])
    calls = [0]

    def resid(v):
        calls[0] += 1
        aa, bb, cc = np.exp(v)
        p = pose(aa, bb, cc, d, phi, sign)
        r = wrap(p.psi - psi)
        # a position that cannot assemble is penalised by how far it is from assembling
        return np.where(p.valid, r, np.pi), bool(np.all(p.valid))

    r, ok = resid(x)
    lam = 1e-3
    for _ in range(iters):
        h = 1e-7
        jac = np.empty((len(phi), 3))
        for k in range(3):  # three columns: a loop over variables, not over points
            e = np.zeros(3)
            e[k] = h
            jac[:, k] = (resid(x + e)[0] - resid(x - e)[0]) / (2 * h)
        g = jac.T @ r
        hess = jac.T @ jac
        improved = False
        for _ in range(20):
            step = np.linalg.solve(hess + lam * np.diag(np.diag(hess) + 1e-12), -g)
            r_new, ok_new = resid(x + step)
            if r_new @ r_new < r @ r:
                x, r, ok = x + step, r_new, ok_new
                lam = max(lam / 10, 1e-12)
                improved = True
                break
            lam *= 10
        if not improved or np.linalg.norm(step) < 1e-14:
            break
    return tuple(np.exp(x)), ok, calls[0]


def solve(problem) -> Solution:
    _check_positions(problem)
    phi = np.array(problem.input_angles)
    psi = np.array(problem.output_angles)
    d = problem.ground
    n = len(phi)
    path = problem.meta.path
    m = np.column_stack([np.cos(psi), -np.cos(phi), np.ones_like(phi)])
    if np.linalg.cond(m) > ILL_CONDITIONED:
        raise InputError("positions that determine a linkage (Freudenstein's system is singular)",
                         f"positions {_position_names(range(n))} give a singular system",
                         path=path, key="positions", line=problem.lines[0] if problem.lines else None)
    k = freudenstein_ratios(phi, psi)
    if np.any(np.abs(k[:2]) < 1e-12):
        raise InputError("positions that determine finite input and output links",
                         f"positions {_position_names(range(n))} give an infinite link",
                         path=path, key="positions", line=problem.lines[0] if problem.lines else None)
    a, b2, c = lengths_from_ratios(k, d)
    if b2 <= 0:
        raise InputError("positions that a real coupler can join",
                         f"positions {_position_names(range(n))} need coupler^2 = {b2:.6g} <= 0",
                         path=path, key="positions", line=problem.lines[0] if problem.lines else None)
    b = float(np.sqrt(b2))
    notes = []
    # A negative length is the same link turned by 180 deg: the physical angle shifts.
    phi_phys = phi + (np.pi if a < 0 else 0.0)
    psi_phys = psi + (np.pi if c < 0 else 0.0)
    if a < 0:
        notes.append("Freudenstein ratio K1 < 0: the input link points opposite to the input "
                     "angle (the crank sits at phi + 180); its length is reported positive")
    if c < 0:
        notes.append("Freudenstein ratio K2 < 0: the output link points opposite to the output "
                     "angle (the rocker sits at psi + 180); its length is reported positive")
    a, c = abs(a), abs(c)

    # Branch that holds the positions: the one whose closure reproduces psi best.
    errs = {}
    for branch in ("open", "crossed"):
        p = pose(a, b, c, d, phi_phys, branch)
        errs[branch] = (np.where(p.valid, np.abs(wrap(p.psi - psi_phys)), np.inf), p)
    per_pos = np.argmin(np.vstack([errs["open"][0], errs["crossed"][0]]), axis=0)
    branch = "open" if np.sum(errs["open"][0] ** 2) <= np.sum(errs["crossed"][0] ** 2) else "crossed"
    if n == 3 and len(set(per_pos)) > 1:
        split = {b_: [i + 1 for i in range(n) if ("open", "crossed")[per_pos[i]] == b_] for b_ in ("open", "crossed")}
        notes.append("branch defect: positions " + ", ".join(map(str, split["open"]))
                     + " lie on the open branch and " + ", ".join(map(str, split["crossed"]))
                     + " on the crossed branch; the linkage must be disassembled to pass them all")

    method, evaluations = "freudenstein", 1
    sign = -1.0 if branch == "open" else 1.0
    if n > 3:
        (a, b, c), _, calls = _refine(phi_phys, psi_phys, a, b, c, d, sign)
        method, evaluations = "freudenstein+lm", 1 + calls
    p = pose(a, b, c, d, phi_phys, branch)
    if not np.all(p.valid):
        bad = [i + 1 for i in range(n) if not p.valid[i]]
        return Solution(status=Status.INFEASIBLE, linkage=FourBar(d, a, b, c, branch),
                        message=f"the linkage cannot assemble at positions {', '.join(map(str, bad))}",
                        notes=notes)
    err = wrap(p.psi - psi_phys)

    # Can the input move from the first to the last position without changing branch?
    sweep = float(phi[-1] - phi[0])
    arcs = input_arcs(a, b, c, d)
    if arcs is not None:
        arc = choose_arc(arcs, phi_phys[0])
        lo, hi = arc
        inside = np.mod(phi_phys - lo, TWO_PI) <= (hi - lo) + 1e-9
        travel_ok = bool(np.all(inside)) and (
            (sweep >= 0 and np.mod(phi_phys[-1] - lo, TWO_PI) >= np.mod(phi_phys[0] - lo, TWO_PI))
            or (sweep < 0 and np.mod(phi_phys[-1] - lo, TWO_PI) <= np.mod(phi_phys[0] - lo, TWO_PI)))
        if not travel_ok:
            notes.append("branch defect: the input cannot rotate from the first to the last position "
                         "without passing a limit position (the linkage would change branch)")
    status = Status.OK
    message = (f"exact through {n} positions" if n == 3 else
               f"least squares over {n} positions, refined on the true output-angle error")
    if any(note.startswith("branch defect") for note in notes):
        message += "; warning: branch defect (see notes)"
    return Solution(
        status=status,
        linkage=FourBar(ground=d, input=a, coupler=b, output=c, branch=branch),
        message=message,
        positions=Positions(kind="angle", input=phi_phys, target=psi_phys, achieved=p.psi, error=err),
        objective=float(err @ err),
        solver={"method": method, "seed": problem.meta.solver.seed, "evaluations": evaluations,
                "converged": True},
        notes=notes,
        working_span=(float(phi_phys[0]), sweep),
    )
