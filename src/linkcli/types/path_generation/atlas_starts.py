"""Free-timing path starts from the coupler-curve atlas (linkcli.atlas): look the target points
up and place the nearest curves back as starts (numpy).

1. Which atlas four-bars may serve (`allowed`): the Grashof class and branch asked for;
   a shape whose lengths and coupler point some one scale brings inside every bound
   (`starts.scale_interval`); for an input that must turn fully, the transmission window
   over the turn (mu at rho = |d - a| and d + a).
2. The target as a stretch (`descriptors`): as given (its points in order) against every
   stretch of the `arcs` table: similarity |<X, Y>|^2 / (|X|^2 |Y|^2), its inner products
   exact (integer descriptors, one float32 matrix product), each direction the input may
   turn (the target run backwards, X_k (-1)^k, against the curves traced forwards); the
   HITS best (ties: the lower row first). When it looks closed (the gap from its last
   point back to its first at most CLOSING times its median gap) also as a whole loop,
   free of where it starts (`ring_scores`): its ring descriptor against every closed
   curve's, the RING_CANDIDATES best by the bound sum_k |c_k| |d_k| (free of start and
   turn), those matched over every start shift (descriptors.ring_match), the RING_HITS
   best first, then the CLOSED_ARC_HITS best stretches.
3. Each hit placed back: its stretch's start and length (a whole loop: the matched shift,
   the whole length) give every target an arc-length position on the curve (the target's
   chord-length share), hence an input angle (interpolated on the curve traced again,
   `family`, at PLACE_SAMPLES angles for a closed-looking target); LOCAL hypotheses around it (the
   start moved by SHIFTS of the stretch, its length scaled by SCALES) are fitted by the
   closed-form similarity of `starts.similarity` (scale within the bounds, a fixed pivot
   or ground angle kept), the best kept, and for a closed-looking target timed again by
   the curve's nearest points (`_retime`); then the best per four-bar, best first, and the coupler point and pivot by
   `starts.fit_linear`.

Returns the design's own variables (path_generation.model): lengths and coupler point
scaled, ground angle, pivot, first input angle and the increments, with branch signs and
turning directions, in the target's frame.
"""

from __future__ import annotations

import math

import numpy as np

from linkcli.atlas import descriptors, family
from linkcli.atlas.build import LOOP_REST, OPEN_COUNT, stretch_of
from linkcli.atlas.cache import Atlas
from linkcli.types.path_generation import starts as path_starts
from linkcli.types.path_generation.model import N_LINK, Design

HITS = 160  # nearest stretches placed back
RING_HITS = 160  # nearest whole loops placed back for a closed-looking target,
CLOSED_ARC_HITS = 40  # and nearest stretches beside them
RING_CANDIDATES = 2048  # whole loops matched over every start shift: the best bounds
CLOSING = 2.5  # a target whose closing gap is at most this many median gaps may be a loop
SHIFTS = (-0.12, 0.0, 0.12)  # local hypotheses: the stretch's start moved by these shares of it,
SCALES = (0.8, 1.0, 1.25)  # and its length scaled by these
RETIME = 2  # rounds of nearest-point timing of each placed hit (`_retime`)
RETIME_WINDOW = 24  # samples either side of where its arc-length share put a target
RETIME_MEMORY = 200_000  # hits x targets x window samples compared at once
PLACE_SAMPLES = 1024  # input angles a hit's curve is traced at to place it back (4 x the atlas's:
# a small crank at the edge turns its corner within a few of the atlas's samples)
CLASS_CODES = {name: k for k, name in enumerate(family.CLASSES)}


def looks_closed(points: np.ndarray) -> bool:
    gaps = np.sqrt(np.sum(np.diff(points, axis=0) ** 2, axis=1))
    closing = math.sqrt(float(np.sum((points[-1] - points[0]) ** 2)))
    return len(points) >= 5 and closing <= CLOSING * float(np.median(gaps))


def normalized(atlas: Atlas, rows: np.ndarray, nx: int) -> np.ndarray:
    """(len(rows), nx) design vectors of atlas four-bars at their own size (ground 1)."""
    x = np.zeros((len(rows), nx))
    x[:, 0] = 1.0
    x[:, 1:4] = atlas.linkages.lengths[rows]
    x[:, 4:6] = atlas.linkages.point[rows]
    return x


def allowed(design: Design, atlas: Atlas) -> np.ndarray:
    """(size,) bool: the four-bars that may serve this design (module docstring, 1)."""
    lk = atlas.linkages
    ok = np.ones(len(lk), dtype=bool)
    if design.grashof != "any":
        ok &= lk.kind == CLASS_CODES[design.grashof]
    if design.branch != "either":
        ok &= lk.sign == (-1.0 if design.branch == "open" else 1.0)
    rows = np.flatnonzero(ok)  # the scale test on the rows still in (the class and branch leave a fifth)
    lo, hi = path_starts.scale_interval(design, atlas.shapes[rows])
    ok[rows] = lo <= hi
    if design.window is not None:
        a, b, c = lk.lengths.T
        cos_mu = lambda r: (b * b + c * c - r * r) / (2 * b * c)
        fits = (cos_mu(np.abs(1.0 - a)) <= math.cos(design.window[0])) & (cos_mu(1.0 + a) >= math.cos(design.window[1]))
        ok &= fits | ~lk.closed
    return ok


def _columns(desc: np.ndarray, sense: int) -> tuple[np.ndarray, float]:
    """The two query columns (Re, Im of <X, Y> for every row Y) of a target descriptor
    (unrounded) run in direction `sense`, as integers, and 1 / its squared norm."""
    q = desc.copy()
    if sense < 0:
        q[:descriptors.HARMONICS] *= descriptors.REVERSED
        q[descriptors.HARMONICS:] *= descriptors.REVERSED
    q = np.rint(q * descriptors.QUANT)
    h = descriptors.HARMONICS
    re, im = q[:h], q[h:]
    size = float(q @ q)
    return np.stack([np.concatenate([re, im]), np.concatenate([-im, re])], axis=1), 1.0 / max(size, 1.0)


def _scores(table: np.ndarray, scale: np.ndarray, cols: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """(q, rows) |<X, Y>|^2 / (|X|^2 |Y|^2) of descriptors `table` (10, rows) and the q
    queries (`cols` (10, 2 q) and 1 / their squared norms `sizes`), `scale` the descriptors'
    1 / |X|^2 (0 for a curve not allowed). The inner products are exact (integers below
    2^24 in one float32 product); the rest is elementwise float32, rounded alike on every CPU."""
    dots = cols.T @ table  # (2 q, rows)
    re, im = dots[0::2], dots[1::2]
    score = re * re
    score += im * im
    score *= sizes[:, None]
    score *= scale
    return score


def _similar(table: np.ndarray, scale: np.ndarray, rows: int, queries: list, allowed_rows: np.ndarray):
    """The best score of each of the `rows` descriptors over the queries (`_scores`), block
    by block of the atlas's tables (cache.Atlas), and a function giving every query's
    score of given rows."""
    cols = np.concatenate([c for c, _ in queries], axis=1).astype(np.float32)
    sizes = np.array([s for _, s in queries], dtype=np.float32)
    width = table.shape[2]
    allowed = np.zeros(table.shape[0] * width, dtype=np.float32)
    allowed[:rows] = allowed_rows
    masked = scale * allowed.reshape(scale.shape)
    best = np.zeros(masked.shape, dtype=np.float32)  # a row not allowed scores 0 (its scale is 0)
    for b in range(table.shape[0]):
        mine = np.flatnonzero(masked[b])
        if 2 * len(mine) < width:  # mostly masked out: the allowed rows alone, the same values
            best[b, mine] = _scores(table[b][:, mine], masked[b, mine], cols, sizes).max(axis=0)
        else:
            best[b] = _scores(table[b], masked[b], cols, sizes).max(axis=0)

    def of(picked: np.ndarray) -> np.ndarray:
        blk, col = np.divmod(picked, width)
        return _scores(table[blk, :, col].T, masked[blk, col], cols, sizes)
    return best.ravel()[:rows], of


BLOCK = 64  # rows per block of the first pass of `_best`


def _best(score: np.ndarray, count: int) -> np.ndarray:
    """Indices of the `count` largest positive scores, largest first; ties: lower index
    first (the same choice on every machine, whatever partition algorithm numpy
    dispatches). First pass: the maxima of blocks of BLOCK rows; the count-th largest of
    them, m, is at most the count-th largest score (count blocks hold one score >= m
    each), so the rows scoring >= m hold the answer: a few, sorted exactly. Asked for as
    many as there are blocks or more (the ring's candidates), m is the count-th largest
    score itself (a value, whichever algorithm partitions): not every positive score sorted."""
    pad = (-len(score)) % BLOCK
    padded = np.concatenate([score, np.zeros(pad, dtype=score.dtype)]) if pad else score
    blocks = padded.reshape(-1, BLOCK).max(axis=1)
    if np.count_nonzero(blocks > 0.0) < count:  # fewer positive scores than asked, maybe
        count = min(count, int(np.count_nonzero(score > 0.0)))
    if count == 0:
        return np.zeros(0, dtype=np.int64)
    bound = -np.partition(-(blocks if count < len(blocks) else score), count - 1)[count - 1]
    sel = np.flatnonzero(score >= max(bound, np.finfo(score.dtype).tiny))
    return sel[np.lexsort((sel, -score[sel]))][:count]


def _rows_allowed(atlas: Atlas, ok: np.ndarray) -> np.ndarray:
    """`ok` per curve (1 or 0, float32), spread over the descriptors of the `arcs` table."""
    ok = ok.astype(np.float32)
    return np.concatenate([np.repeat(ok[:atlas.closed], LOOP_REST), np.repeat(ok[atlas.closed:], OPEN_COUNT)])


def _arc_hits(design: Design, atlas: Atlas, ok: np.ndarray, senses: tuple, count: int):
    """The `count` stretches of the `arcs` table most similar to the targets as a stretch
    (curve, start, length, sense, shares at the targets)."""
    desc, frac = descriptors.target_descriptors(design.targets, closed=False)
    arc_best, arc_scores = _similar(atlas.arcs, atlas.arc_scale, atlas.arc_rows,
                                    [_columns(desc[0], s) for s in senses], _rows_allowed(atlas, ok))
    picked = _best(arc_best, count)
    curve, slot = stretch_of(atlas.closed, atlas.size, "arcs", picked)
    closed = curve < atlas.closed
    start, length = np.zeros(len(picked)), np.zeros(len(picked))
    for is_closed in (True, False):
        mine = closed == is_closed
        if mine.any():
            st, ln = descriptors.stretch_starts(curve[mine], is_closed)
            start[mine] = np.take_along_axis(st, slot[mine][:, None], axis=1)[:, 0]
            length[mine] = np.take_along_axis(ln, slot[mine][:, None], axis=1)[:, 0]
    which = np.argmax(arc_scores(picked), axis=0)  # the first best query: ties alike everywhere
    sense = np.array(senses, dtype=float)[which]
    shares = np.where(sense[:, None] > 0, frac[None, :], 1.0 - frac[None, :])
    return curve, start, length, sense, shares


def ring_scores(atlas: Atlas, ok: np.ndarray, query: np.ndarray, senses: tuple):
    """Whole loops against a closed target's ring descriptor `query` (unrounded), start-free
    (descriptors.ring_match): the RING_CANDIDATES (loop, sense) pairs with the highest
    bound sum_k |c_k| |d_k| / (|c| |d|) (each sense: the target run backwards swaps d_k and
    d_-k), matched over every start shift. Returns (curve, sense, score |<c, d>|^2 /
    (|c|^2 |d|^2) at the best shift, that shift), in the order of the pairs (sense first,
    then the loop; ties broken by that order)."""
    allowed = ok[:atlas.closed] & (atlas.ring_norms > 0.0)
    norms = np.sqrt(np.where(allowed, atlas.ring_norms, 1.0))
    queries, bounds = [], []
    for s in senses:
        q = query if s > 0 else np.concatenate([query[:descriptors.RING_ORDERS.size][descriptors.RING_SWAP],
                                                query[descriptors.RING_ORDERS.size:][descriptors.RING_SWAP]])
        q = np.rint(q * descriptors.RING_QUANT)
        size = math.sqrt(max(float(np.sum(q * q)), 1.0))
        queries.append((q, size))
        bounds.append(np.where(allowed, descriptors.ring_bound(atlas.ring_mags, q) / (norms * size), 0.0))
    pairs = np.sort(_best(np.concatenate(bounds), RING_CANDIDATES))
    which, curve = np.divmod(pairs, atlas.closed)
    score, shift = np.zeros(len(pairs)), np.zeros(len(pairs))
    for j, (q, size) in enumerate(queries):
        mine = which == j
        if mine.any():
            power, shift[mine] = descriptors.ring_match(atlas.rings[curve[mine]].astype(np.float64), q)
            score[mine] = power / (atlas.ring_norms[curve[mine]] * size * size)
    return curve, np.array(senses)[which].astype(float), score, shift


def _ring_hits(design: Design, atlas: Atlas, ok: np.ndarray, senses: tuple, count: int):
    """The `count` whole loops most similar to the closed targets (`ring_scores`), as
    `_arc_hits` gives stretches: the loop's start at the matched shift, length 1."""
    query, frac = descriptors.target_ring(design.targets)
    curve, sense, score, shift = ring_scores(atlas, ok, query, senses)
    picked = _best(score, count)
    shares = np.where(sense[picked, None] > 0, frac[None, :], 1.0 - frac[None, :])
    return curve[picked], shift[picked], np.ones(len(picked)), sense[picked], shares


def hits(design: Design, atlas: Atlas, ok: np.ndarray):
    """The most similar stretches: (curve (H,), stretch start (H,), stretch length
    (H,), sense (H,): +1 forwards, -1 the target run backwards, share of the stretch at
    each target (H, n)): a closed-looking target's RING_HITS whole loops first, then the
    HITS stretches (CLOSED_ARC_HITS for a closed-looking target) of the `arcs` table."""
    senses = {"ccw": (1,), "cw": (-1,)}.get(design.direction, (1, -1))
    if not looks_closed(design.targets):
        return _arc_hits(design, atlas, ok, senses, HITS)
    rings = _ring_hits(design, atlas, ok, senses, RING_HITS)
    arcs = _arc_hits(design, atlas, ok, senses, CLOSED_ARC_HITS)
    return tuple(np.concatenate([r, a]) for r, a in zip(rings, arcs))


def starts(design: Design, atlas: Atlas, count: int):
    """Up to `count` placed starts (x, sign, s, cost), best first (module docstring), and
    the hypotheses fitted (evaluations); None when no four-bar of the atlas may serve."""
    ok = allowed(design, atlas)
    if not ok.any():
        return None
    curve, start, length, sense, shares = hits(design, atlas, ok)
    if not len(curve):
        return None
    found = curve
    closed = curve < atlas.closed
    # local hypotheses: (hit, shift, scale)
    shift, scale = (v.ravel() for v in np.meshgrid(SHIFTS, SCALES, indexing="ij"))
    h = len(shift)
    lam = np.minimum(np.repeat(length, h) * np.tile(scale, len(found)), 1.0)
    s0 = np.repeat(start, h) + np.tile(shift, len(found)) * np.repeat(length, h)
    rep_closed = np.repeat(closed, h)
    s0 = np.where(rep_closed, np.mod(s0, 1.0), np.clip(s0, 0.0, 1.0 - lam))
    at = s0[:, None] + lam[:, None] * np.repeat(shares, h, axis=0)
    at = np.where(rep_closed[:, None], np.mod(at, 1.0), np.clip(at, 0.0, 1.0))
    # input angles at those arc-length shares: each hit's curve traced again
    uniq, back = np.unique(curve, return_inverse=True)
    lk = atlas.linkages.take(uniq)
    loop = looks_closed(design.targets)  # whole loops were matched: placed finer and timed again
    phi_grid = family.input_angles(lk, PLACE_SAMPLES if loop else family.SAMPLES)
    gx, gy = family.coupler_points(lk, phi_grid, family.angle_sines(lk, phi_grid))
    frac = descriptors.arc_fractions(gx, gy)
    rows = np.repeat(back, h)
    (phi,) = descriptors.interpolate(frac, [phi_grid], at, rows)
    x = normalized(atlas, np.repeat(curve, h), design.nx)
    sign = atlas.linkages.sign[np.repeat(curve, h)]
    q, valid = path_starts.local_curve(x, sign, phi)
    s_lo, s_hi = path_starts.scale_interval(design, x)
    u, g, cost = path_starts.similarity(design, q, s_lo, s_hi, path_starts.fixed_pivot(design),
                                        path_starts.fixed_angle(design))
    cost = np.where(valid.all(axis=1) & np.isfinite(cost), cost, np.inf).reshape(len(found), h)
    pick = np.argmin(cost, axis=1)
    one = np.arange(len(found)) * h + pick
    best = cost[np.arange(len(found)), pick]
    # each hit's best hypothesis timed again by the nearest points of its curve (closed targets)
    fin = np.flatnonzero(np.isfinite(best)) if loop else np.zeros(0, dtype=np.int64)
    step = max(1, RETIME_MEMORY // (design.n_targets * (2 * RETIME_WINDOW + 1)))
    for part in range(0, len(fin), step):  # a block of hits at a time: bounded memory
        f = fin[part:part + step]
        r = one[f]
        new_phi, nu, ng, ncost = _retime(design, x[r], sign[r], phi_grid[rows[r]], gx[rows[r]] + 1j * gy[rows[r]],
                                         frac[rows[r]], at[r], phi[r], u[r], g[r], s_lo[r], s_hi[r],
                                         np.repeat(sense, h)[r], rep_closed[r])
        better = ncost < best[f]
        phi[r[better]], u[r[better]], g[r[better]] = new_phi[better], nu[better], ng[better]
        best[f[better]] = ncost[better]
    # the best hit of each four-bar, best first (ties: the more similar hit)
    order = np.lexsort((np.arange(len(found)), best))
    seen, keep = set(), []
    for i in order:
        if np.isfinite(best[i]) and curve[i] not in seen:
            seen.add(curve[i])
            keep.append(i)
    keep = np.array(keep[:count], dtype=int)
    if not len(keep):
        return None
    rows = one[keep]
    s = np.repeat(sense, h)[rows]
    x = x[rows]
    ph = phi[rows]
    x[:, N_LINK] = ph[:, 0]
    steps = s[:, None] * np.diff(ph, axis=1)
    steps = np.where(np.repeat(closed, h)[rows][:, None], np.mod(steps, 2.0 * math.pi), np.maximum(steps, 0.0))
    x[:, N_LINK + 1:] = steps
    x = path_starts.apply_similarity(design, x, u[rows], g[rows])
    x = path_starts.fit_linear(design, x, sign[rows], s)
    return x, sign[rows], s, best[keep], len(found) * h + len(keep)


def _retime(design: Design, x, sign, phi_grid, q_grid, frac, at, phi, u, g, s_lo, s_hi, sense, closed):
    """Free timing's own rule applied to placed hits (N rows): each target moved to the
    curve's sample nearest to it (the curve q_grid, traced at its PLACE_SAMPLES angles
    phi_grid in the four-bar's own frame by `family.coupler_points`, placed by the
    similarity u, g) within RETIME_WINDOW samples of where its arc-length share put it,
    the similarity fitted again; RETIME rounds. A row whose targets would leave their
    order (or the turn) keeps its last timing. Returns (phi, u, g, cost)."""
    n_grid = phi_grid.shape[1]
    t = design.targets[:, 0] + 1j * design.targets[:, 1]
    (index,) = descriptors.interpolate(frac, [np.broadcast_to(np.arange(n_grid, dtype=float), frac.shape)], at)
    index = np.rint(index).astype(np.int64)
    offsets = np.arange(-RETIME_WINDOW, RETIME_WINDOW + 1)
    g0, gamma0 = path_starts.fixed_pivot(design), path_starts.fixed_angle(design)
    cost = np.full(len(x), np.inf)
    for _ in range(RETIME):
        placed = g[:, None] + u[:, None] * q_grid
        cand = index[:, :, None] + offsets[None, None, :]  # within RETIME_WINDOW of 0 .. n_grid - 1:
        # a loop's samples wrap by one period (n_grid - 1, its last repeating its first), an arc's are clipped
        period = n_grid - 1
        wrapped = np.where(cand < 0, cand + period, np.where(cand >= period, cand - period, cand))
        cand = wrapped if closed.all() else np.where(closed[:, None, None], wrapped, np.clip(cand, 0, n_grid - 1))
        rows = np.arange(len(x))[:, None, None]
        gap = np.abs(placed[rows, cand] - t[None, :, None])
        gap = np.where(np.isfinite(gap), gap, np.inf)
        index = np.take_along_axis(cand, np.argmin(gap, axis=2)[:, :, None], axis=2)[:, :, 0]
        new_phi = np.take_along_axis(phi_grid, index, axis=1)
        steps = sense[:, None] * np.diff(new_phi, axis=1)
        turn = np.sum(np.mod(steps, 2.0 * math.pi), axis=1)
        ordered = np.where(closed, turn < 2.0 * math.pi, np.all(steps >= 0.0, axis=1))
        q, valid = path_starts.local_curve(x, sign, new_phi)
        nu, ng, ncost = path_starts.similarity(design, q, s_lo, s_hi, g0, gamma0)
        ncost = np.where(ordered & valid.all(axis=1) & np.isfinite(ncost), ncost, np.inf)
        take = ncost < cost
        phi, u, g = np.where(take[:, None], new_phi, phi), np.where(take, nu, u), np.where(take, ng, g)
        cost = np.where(take, ncost, cost)
    return phi, u, g, cost


def starts_for(design, count: int):
    """Up to `count` starts for a free-timing path design (path_generation.model.Design)
    from the atlas, best first: (x, sign, s, cost, evaluations) in the design's own
    variables and the targets' frame; None without an atlas (said on stderr once) or
    when none of its four-bars may serve the design's bounds and constraints."""
    from linkcli.atlas import cache
    atlas = cache.get()
    if atlas is None:
        return None
    return starts(design, atlas, count)
