"""A four-bar from two dyads, its body poses for given input angles, and its defects.

Dyads (G1, M1) input and (G2, M2) output give, in the conventions of docs/format.md terms: A0 = G1,
B0 = G2, A_i = T_i(M1), B_i = T_i(M2); ground d = |B0 - A0|, input a = |A_i - A0|,
coupler b = |M2 - M1|, output c = |B_i - B0|; ground_angle the direction of A0 -> B0;
phi_i, psi_i the directions of A0 -> A_i, B0 -> B_i less ground_angle. Branch at pose i:
open iff (A_i - B0) x (B_i - B0) < 0 (psi = theta_rho - alpha, the conventions of docs/format.md), crossed
if > 0. The body origin in the coupler frame (origin A, x along A -> B) is coupler_point,
and the body x axis makes coupler_angle with A -> B.

Defects (Sandor & Erdman vol. 1 sec. 8; Balli & Chand, Mech. Mach. Theory 37, 2002):
* branch (circuit): the poses lie on different branches, or on different arcs of
  reachable input angles (four_bar.input_arcs): the linkage must be disassembled to
  pass through them all.
* order: on its branch the input does not reach the poses in the given order during one
  turn (crank) or one stroke (rocker), in either sense of rotation.
"""

from __future__ import annotations

from itertools import permutations

import numpy as np

from linkcli.mechanisms.four_bar import closure
from linkcli.mechanisms.four_bar import kinematics as kin

from .poses import as_poses, characteristic_length, to_global

TWO_PI = 2.0 * np.pi
PARAM_NAMES = ("ground_x", "ground_y", "ground_angle", "ground", "input", "coupler",
               "output", "coupler_x", "coupler_y", "coupler_angle")


def _angle(v):
    return np.arctan2(v[..., 1], v[..., 0])


def dyad_pair_params(poses, g1, m1, g2, m2):
    """Vectorized conversion of dyad pairs (each (..., 2)) to (params (..., 10) in
    PARAM_NAMES order, input angles phi (..., n), branch signs (..., n): -1 open, +1
    crossed); a and c are taken at pose 1 (equal at every pose for exact dyads)."""
    poses = as_poses(poses)
    g1, m1, g2, m2 = (np.asarray(v, float) for v in (g1, m1, g2, m2))
    a_pts = to_global(poses, m1[..., None, :])  # (..., n, 2)
    b_pts = to_global(poses, m2[..., None, :])
    link = g2 - g1
    ground_angle = _angle(link)
    d = np.linalg.norm(link, axis=-1)
    a = np.linalg.norm(a_pts[..., 0, :] - g1, axis=-1)
    c = np.linalg.norm(b_pts[..., 0, :] - g2, axis=-1)
    b = np.linalg.norm(m2 - m1, axis=-1)
    phi = kin.wrap(_angle(a_pts - g1[..., None, :]) - ground_angle[..., None])
    ra, rb = a_pts - g2[..., None, :], b_pts - g2[..., None, :]
    cross = ra[..., 0] * rb[..., 1] - ra[..., 1] * rb[..., 0]
    signs = np.where(cross < 0, -1.0, 1.0)  # open iff (A - B0) x (B - B0) < 0
    e = (m2 - m1) / np.where(b > 0, b, 1.0)[..., None]
    px = -(m1[..., 0] * e[..., 0] + m1[..., 1] * e[..., 1])
    py = -(-m1[..., 0] * e[..., 1] + m1[..., 1] * e[..., 0])
    cang = kin.wrap(-_angle(e))
    params = np.stack([g1[..., 0], g1[..., 1], ground_angle, d, a, b, c, px, py, cang], -1)
    return params, phi, signs


def linkage_from_dyads(poses, input_dyad, output_dyad) -> dict:
    """The four-bar of two dyads (G, M) (module docstring). Angles in rad. Returns the
    linkage keys (ground_pivot, ground_angle, ground, input, coupler, output, branch (at
    pose 1), coupler_point, coupler_angle, A0, B0, A, B (body frame), params: the 10
    values in PARAM_NAMES order) and per pose: input_angles, output_angles, branch_signs."""
    poses = as_poses(poses)
    g1, m1 = (np.asarray(v, float) for v in input_dyad)
    g2, m2 = (np.asarray(v, float) for v in output_dyad)
    params, phi, signs = dyad_pair_params(poses, g1, m1, g2, m2)
    psi = kin.wrap(_angle(to_global(poses, m2) - g2) - params[2])
    return {
        "ground_pivot": g1, "ground_angle": float(params[2]), "ground": float(params[3]),
        "input": float(params[4]), "coupler": float(params[5]), "output": float(params[6]),
        "branch": "open" if signs[0] < 0 else "crossed",
        "coupler_point": params[7:9].copy(), "coupler_angle": float(params[9]),
        "A0": g1, "B0": g2, "A": m1, "B": m2, "params": params,
        "input_angles": phi, "output_angles": psi, "branch_signs": signs,
    }


def body_frames(params, phi, branch):
    """The body at input angles phi (rad, local frame): its origin (x, y) and the unit vector
    (ex, ey) of its x axis, global, and the loop's closure (four_bar.closure.Frame: `valid`,
    `rho`). params (..., 10) in PARAM_NAMES order, branch "open", "crossed" or signs (-1/+1);
    lengths broadcast against phi like four_bar.pose. With g = e^{i ground_angle},

        x + i y = G + g (A + (coupler_x + i coupler_y) e^{i theta}),
        ex + i ey = g e^{i coupler_angle} e^{i theta},

    theta the coupler's direction A -> B: no angle computed per point (the searches' scores
    and residuals; `body_poses` takes the angle)."""
    p = np.asarray(params, float)
    gx, gy, gang, d, a, b, c, px, py, cang = (p[..., k, None] for k in range(10))
    fr = closure.frame(a, b, c, d, np.asarray(phi, float), kin.branch_sign(branch))
    lx, ly = fr.coupler_point(a, px, py)
    cg, sg = np.cos(gang), np.sin(gang)
    x = gx + cg * lx - sg * ly
    y = gy + sg * lx + cg * ly
    turn = gang + cang
    cb, sb = np.cos(turn), np.sin(turn)
    ex = cb * fr.ct - sb * fr.st
    ey = sb * fr.ct + cb * fr.st
    return x, y, ex, ey, fr


def body_poses(params, phi, branch) -> tuple[np.ndarray, np.ndarray]:
    """Body poses (..., 3) reached at input angles phi (rad, local frame), the angle in
    (-pi, pi] (angles.wrap's convention at -pi), and whether the linkage assembles there
    (`body_frames`)."""
    x, y, ex, ey, fr = body_frames(params, phi, branch)
    ang = np.arctan2(ey, ex)
    ang = np.where(ang <= -np.pi + kin.WRAP_SNAP, ang + TWO_PI, ang)
    return np.stack(np.broadcast_arrays(x, y, ang), -1), fr.valid


def pose_errors(target, achieved):
    """(position error |P_i - T_i|, angle error wrapped to (-pi, pi]) per pose."""
    target, achieved = np.asarray(target, float), np.asarray(achieved, float)
    pos = np.linalg.norm(achieved[..., :2] - target[..., :2], axis=-1)
    return pos, kin.wrap(achieved[..., 2] - target[..., 2])


def _strictly_monotone(values) -> bool:
    step = np.diff(values)
    return bool(np.all(step > 0) or np.all(step < 0))


def order_defect(phi, arcs) -> bool:
    """True if the poses are not reached in order (module docstring); phi in rad, arcs as
    four_bar.input_arcs (None: the input turns fully)."""
    phi = np.asarray(phi, float)
    if len(phi) < 3:
        return False
    if arcs is None:
        ccw = np.mod(phi - phi[0], TWO_PI)[1:]
        cw = np.mod(phi[0] - phi, TWO_PI)[1:]
        return not (np.all(np.diff(ccw) > 0) and ccw[0] > 0 or np.all(np.diff(cw) > 0) and cw[0] > 0)
    arc = kin.choose_arc(arcs, phi[0])
    return not _strictly_monotone(np.mod(phi - arc[0], TWO_PI))


def check_linkage(a, b, c, d, phi, branch_signs) -> dict:
    """Defects and figures of one linkage at its pose input angles (rad): branch_defect,
    order_defect, grashof (class dict), input_is_crank, transmission (rad per pose),
    transmission_min, transmission_max (rad), and `defects`, the names of those present."""
    phi = np.asarray(phi, float)
    branch_signs = np.asarray(branch_signs, float)
    arcs = kin.input_arcs(a, b, c, d)
    if arcs is None:
        arc_index = np.zeros(len(phi), int)
    elif not arcs:
        arc_index = np.full(len(phi), -1)
    else:
        arc_index = np.array([next((k for k, arc in enumerate(arcs)
                                    if kin.arc_contains(arc, x)), -1) for x in phi])
    branch_defect = bool(np.any(branch_signs != branch_signs[0]) or np.any(arc_index != arc_index[0])
                         or np.any(arc_index < 0))
    order = (not branch_defect) and order_defect(phi, arcs)
    rho = kin.ground_distance(a, d, phi)
    mu = kin.transmission_angle(b, c, rho)
    klass = kin.grashof(a, b, c, d)
    defects = [name for name, on in (("branch", branch_defect), ("order", order)) if on]
    return {"branch_defect": branch_defect, "order_defect": bool(order), "grashof": klass,
            "input_is_crank": arcs is None, "transmission": mu,
            "transmission_min": float(mu.min()), "transmission_max": float(mu.max()),
            "defects": defects}


def candidate_linkages(poses, grounds, movings) -> list[dict]:
    """Every ordered pair of distinct dyads (input, output) as a candidate linkage with its
    checks and its pose errors recomputed by body_poses; ranked: defect-free first, then
    by the worst transmission deviation from 90 deg, then by the input dyad's index."""
    poses = as_poses(poses)
    grounds, movings = np.asarray(grounds, float), np.asarray(movings, float)
    scale = characteristic_length(poses)
    out = []
    for i, j in permutations(range(len(grounds)), 2):  # <= 12 pairs of one problem
        if (np.linalg.norm(grounds[i] - grounds[j]) <= 1e-9 * scale
                or np.linalg.norm(movings[i] - movings[j]) <= 1e-9 * scale):
            continue
        link = linkage_from_dyads(poses, (grounds[i], movings[i]), (grounds[j], movings[j]))
        checks = check_linkage(link["input"], link["coupler"], link["output"], link["ground"],
                               link["input_angles"], link["branch_signs"])
        achieved, valid = body_poses(link["params"], link["input_angles"], link["branch_signs"])
        pos, ang = pose_errors(poses, achieved)
        if not np.all(valid):
            checks["defects"] = checks["defects"] + ["assembly"]
        out.append({"dyads": (i, j), "linkage": link, "checks": checks, "achieved": achieved,
                    "position_error": pos, "angle_error": ang})
    def rank(cand):
        mu = cand["checks"]["transmission"]
        return (len(cand["checks"]["defects"]) > 0, float(np.max(np.abs(mu - np.pi / 2))),
                cand["dyads"])
    return sorted(out, key=rank)
