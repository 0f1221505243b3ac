"""Whether a group of the plan (a class-III triad and the like) is drawn locked: its equations
singular at the drawing, so that it has no branch to keep. Pure Python (structure.analyse's
`check` runs without numpy).

Each link b of the group is a pose (x_b, y_b, theta_b), at the drawing (its first joint's place,
0); a joint J joining bodies b_0, b_1, ... gives p_{b_0}(J) - p_{b_i}(J) = 0 (two rows each) with
d p_b(J) / d(x_b, y_b, theta_b) = (1, 0, -(J_y - o_y)), (0, 1, J_x - o_x) (o: b's origin) for a
link of the group, 0 for a body placed before it. The measure is Hadamard's ratio |det J| /
prod_j |J_:,j| (in [0, 1], 0 exactly where the group locks, whatever the units of the
columns); for a dyad in these unknowns it is proportional to the sine of the angle between its
two links (a quarter of it for links of lengths 3.2 and 2), the measure structure._check_sides
holds to DEAD_RTOL: a group is refused where its ratio is at most DEAD_RTOL.
"""

from __future__ import annotations

import math


def lock_ratio(structure, links: tuple[str, ...]) -> float | None:
    """Hadamard's ratio of the group `links`' Jacobian at the drawing (module docstring);
    None for a group carrying a slider (its guide's rows: the analysis's Newton decides) or
    whose pins do not give as many equations as unknowns."""
    drawing = structure.drawing
    col = {b: 3 * k for k, b in enumerate(links)}
    origin = {b: drawing.joint(drawing.link(b).joints[0]).at for b in links}
    rows: list[list[float]] = []
    for joint in dict.fromkeys(j for b in links for j in drawing.link(b).joints):
        if drawing.joint(joint).slider is not None or joint in structure.slides:
            return None
        bodies = structure.pins[joint]
        if not any(b in col for b in bodies):
            continue
        jx, jy = drawing.joint(joint).at
        for other in bodies[1:]:
            if bodies[0] not in col and other not in col:
                continue  # two bodies placed before the group: their pin is not its equation
            rx, ry = [0.0] * (3 * len(links)), [0.0] * (3 * len(links))
            for body, sign in ((bodies[0], 1.0), (other, -1.0)):
                if body in col:
                    c, (ox, oy) = col[body], origin[body]
                    rx[c], rx[c + 2] = sign, -sign * (jy - oy)
                    ry[c + 1], ry[c + 2] = sign, sign * (jx - ox)
            rows += [rx, ry]
    if len(rows) != 3 * len(links):
        return None
    norms = 1.0
    for c in range(len(rows)):
        norms *= math.sqrt(sum(r[c] * r[c] for r in rows))
    return abs(_det(rows)) / norms if norms > 0.0 else 0.0


def _det(a: list[list[float]]) -> float:
    """det a by Gaussian elimination with partial pivoting (a copied)."""
    a = [list(r) for r in a]
    n, det = len(a), 1.0
    for k in range(n):
        p = max(range(k, n), key=lambda i: abs(a[i][k]))
        if a[p][k] == 0.0:
            return 0.0
        if p != k:
            a[k], a[p] = a[p], a[k]
            det = -det
        det *= a[k][k]
        for i in range(k + 1, n):
            f = a[i][k] / a[k][k]
            if f:
                for j in range(k, n):
                    a[i][j] -= f * a[k][j]
    return det
