"""Is each best known of benchmarks/constrained_variants.json (path-prescribed, path-free,
function) a local optimum?  An independent check: scipy SLSQP, started from the best-known
design, on the problem as the docs state it (own closure, own objective, own smooth
constraints), then the end point screened by linkcli itself (path: solve.violations +
solve.solution -> bench.printed_objective; function: Model.evaluate + describe_violations via
solve.build_solution -> printed_objective).

The cache keeps only the linkage of each run (no timing / start angles): those are
reconstructed here (free timing: each target's nearest point on the coupler curve, then a
timing-only SLSQP if needed; prescribed offset: a 1-D scan; function: a scan of the input start
with the optimal output start, then a 2-variable SLSQP) and the reconstruction is accepted only
when linkcli's objective there equals best_known within 1e-9 (relative). Otherwise the best run
is re-run (same method, budget, seed) to read the timing from its report.

Usage: PYTHONPATH=src python3 benchmarks/check_best_known.py [case ids...] [--out FILE]
(one process, OPENBLAS_NUM_THREADS=1; results in FILE, default /tmp/check_best_known.json).

Run on 2026-11-27 over the 105 path and function cases of the cache: every kept case's best
known (`binds`) reproduced to 6e-10 and confirmed a local optimum, or within 1.5e-7 (relative)
of a nearby point (function cases 38, 50, 74, 82, 122, 126: 2.4e-8 to 1.5e-7, inside the
study's WITHIN); lower feasible designs only in cases the study does not keep (path-free 1,
37, 49: their constraints do not bind). Where SLSQP stops at once (a start a few 1e-9 outside
a binding constraint, inside linkcli's tolerance), trust-constr and small perturbations of the
start settle it. Motion cases: benchmarks/check_best_known_motion.py.
"""
from __future__ import annotations

import json
import math
import os
import sys
import time
import types
import warnings

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
BENCH = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, BENCH)
import constrained_variants as cv  # noqa: E402
import numpy as np  # noqa: E402
from scipy.optimize import Bounds, NonlinearConstraint, minimize  # noqa: E402

from linkcli.bench import printed_objective  # noqa: E402
from linkcli.reading.load import load  # noqa: E402
from linkcli.search.budget import Budget  # noqa: E402
from linkcli.solution import Status  # noqa: E402
from linkcli.types.function_generation import model as fgm  # noqa: E402
from linkcli.types.function_generation import solve as fgs  # noqa: E402
from linkcli.types.path_generation import model as pgm  # noqa: E402
from linkcli.types.path_generation import solve as pgs  # noqa: E402

TWO_PI = 2 * math.pi
REPRO = 1e-9  # relative agreement with best_known required before trusting anything
TIME_CAP = 60.0
warnings.filterwarnings("ignore")


class TimeUp(Exception):
    pass


def wrap(x):
    return (x + math.pi) % TWO_PI - math.pi


# ============================================================ path generation (own model)

def own_points(X, sign, phi):
    """Coupler points (N, n) complex of rows X (N, 9) at input angles phi (N, n): the closure
    of docs/format.md written here (B from the circles, theta = arg(B - A))."""
    d, a, b, c, px, py, gx, gy, gam = (X[:, k:k + 1] for k in range(9))
    A = a * np.exp(1j * phi)
    v = A - d
    rho = np.abs(v)
    ca = (rho * rho + c * c - b * b) / (2 * rho * c)
    alpha = np.arccos(np.clip(ca, -1, 1))
    psi = np.angle(v) + sign * alpha
    B = d + c * np.exp(1j * psi)
    e = (B - A) / np.abs(B - A)
    P = A + (px + 1j * py) * e
    return (gx + 1j * gy) + np.exp(1j * gam) * P, rho


class PathProblem:
    def __init__(self, text):
        self.problem = load("case.toml", text)
        self.design = pgm.build(self.problem)
        D = self.design
        self.T = D.targets[:, 0] + 1j * D.targets[:, 1]
        self.n = len(self.T)
        self.free = np.flatnonzero(D.hi > D.lo)
        self.L = D.scale

    def phi(self, X, s):
        D = self.design
        if D.timing == "prescribed":
            return D.base_phi[None, :] + X[:, 9:10]
        steps = np.concatenate([np.zeros((len(X), 1)), np.cumsum(X[:, 10:], axis=1)], axis=1)
        return X[:, 9:10] + s * steps

    def residuals(self, X, sign, s):
        P, _ = own_points(X, sign, self.phi(X, s))
        r = (P - self.T[None]) / self.L
        return np.concatenate([r.real, r.imag], axis=1)

    def objective(self, X, sign, s):
        P, _ = own_points(X, sign, self.phi(X, s))
        return np.sum(np.abs(P - self.T[None]) ** 2, axis=1)

    def structure(self, x, s):
        """Whether phi = 0 / pi lie inside the span of the targets (held during a local run)."""
        ph = self.phi(x[None], s)[0]
        lo, w = ph.min(), ph.max() - ph.min()
        return [(at, bool(np.mod(at - lo, TWO_PI) <= w)) for at in (0.0, math.pi)]

    def cons(self, X, sign, s, struct):
        """Smooth constraints g >= 0 (dimensionless), per docs/path_generation.md."""
        D = self.design
        L2 = self.L ** 2
        d, a, b, c = (X[:, k] for k in range(4))
        ph = self.phi(X, s)
        out = []
        links = np.stack([d, a, b, c], axis=1)
        margin = pgm.GRASHOF_MARGIN * links.sum(axis=1)
        if D.grashof in pgm.SHORTEST:
            k = pgm.SHORTEST[D.grashof]
            others = [j for j in range(4) if j != k]
            for j in others:
                rest = [o for o in others if o != j]
                out.append(-(links[:, k] + links[:, j] - links[:, rest[0]] - links[:, rest[1]] + margin) / self.L)
        elif D.grashof == "triple-rocker":
            srt = np.sort(links, axis=1)
            out.append((srt[:, 0] + srt[:, 3] - srt[:, 1] - srt[:, 2] - margin) / self.L)
        rho2 = a[:, None] ** 2 + d[:, None] ** 2 - 2 * a[:, None] * d[:, None] * np.cos(ph)
        extra = [a ** 2 + d ** 2 - 2 * a * d * math.cos(at) for at, inside in struct if inside]
        span_r2 = np.concatenate([rho2] + [e[:, None] for e in extra], axis=1)
        bc_hi, bc_lo = (b + c) ** 2, (b - c) ** 2
        out += list((bc_hi[:, None] - span_r2).T / L2) + list((span_r2 - bc_lo[:, None]).T / L2)
        if D.window is not None:
            r2 = np.stack([(d - a) ** 2, (d + a) ** 2], axis=1) if D.full_turn else span_r2
            cosmu = (b[:, None] ** 2 + c[:, None] ** 2 - r2) / (2 * b[:, None] * c[:, None])
            out += list((math.cos(D.window[0]) - cosmu).T) + list((cosmu - math.cos(D.window[1])).T)
        if D.timing == "free":
            out.append(TWO_PI - X[:, 10:].sum(axis=1))
        return np.stack(out, axis=1)

    # ---------------- linkcli's screen
    def screen(self, x, sign, s):
        """(accepted, linkcli objective (design.objective), printed objective, violations, in bounds)."""
        D = self.design
        xw = D.wrapped(x[None])[0]
        inb = bool(np.all(x >= D.lo - 1e-12 * np.maximum(1, abs(D.lo))) and
                   np.all(x <= D.hi + 1e-12 * np.maximum(1, abs(D.hi))))
        v = pgs.violations(D, xw, sign, s)
        obj = float(D.objective(xw[None], np.array([sign]), np.array([s]))[0])
        cand = pgs.Candidate(xw, sign, s, True)
        sol = pgs.solution(self.problem, D, cand, v, "multistart", Budget(1), True)
        pr = printed_objective(self.problem, sol)
        return (sol.status is not Status.INFEASIBLE) and inb, obj, pr, v, inb, sol


def path_x_from_linkage(pp: PathProblem, lk):
    u = pp.problem.meta.units
    x = np.zeros(pp.design.nx)
    x[:4] = [lk["ground"], lk["input"], lk["coupler"], lk["output"]]
    x[4:6] = lk["coupler_point"]
    x[6:8] = lk["ground_pivot"]
    x[8] = float(u.to_rad(lk["ground_angle"])) if hasattr(u, "to_rad") else (
        lk["ground_angle"] if u.angle == "rad" else math.radians(lk["ground_angle"]))
    sign = -1.0 if lk["branch"] == "open" else 1.0
    return x, sign


def reconstruct_prescribed(pp: PathProblem, x, sign):
    D = pp.design
    if not D.free[9]:
        x = x.copy()
        x[9] = D.lo[9]
        return [(x, 1.0)]
    lo, hi = D.lo[9], D.hi[9]
    grid = np.linspace(lo, hi, 40001)
    X = np.repeat(x[None], len(grid), axis=0)
    X[:, 9] = grid
    f = pp.objective(X, sign, 1.0)
    order = np.argsort(f)
    out = []
    from scipy.optimize import minimize_scalar
    h = grid[1] - grid[0]
    for i in order[:400]:
        if len(out) >= 6:
            break
        g0 = grid[i]
        r = minimize_scalar(lambda t: pp.objective(np.concatenate([x[:9], [t], x[10:]])[None], sign, 1.0)[0],
                            bounds=(max(lo, g0 - h), min(hi, g0 + h)), method="bounded",
                            options=dict(xatol=1e-14))
        y = x.copy()
        y[9] = r.x
        if not any(abs(y[9] - z[0][9]) < 1e-9 for z in out):
            out.append((y, 1.0))
    return out


def reconstruct_free(pp: PathProblem, x, sign):
    """Timing from the nearest point of the coupler curve to each target; each direction."""
    D = pp.design
    from scipy.optimize import minimize_scalar
    grid = np.linspace(-math.pi, math.pi, 14400, endpoint=False)
    P, rho = own_points(x[None, :9], sign, grid[None])
    P, rho = P[0], rho[0]
    d, a, b, c = x[:4]
    ok = (rho <= b + c) & (rho >= abs(b - c))
    phis = []
    for T in pp.T:
        dist = np.where(ok, np.abs(P - T), np.inf)
        i = int(np.argmin(dist))
        h = grid[1] - grid[0]
        r = minimize_scalar(lambda t: abs(own_points(x[None, :9], sign, np.array([[t]]))[0][0, 0] - T),
                            bounds=(grid[i] - h, grid[i] + h), method="bounded", options=dict(xatol=1e-14))
        phis.append(r.x)
    phis = np.array(phis)
    out = []
    dirs = {"ccw": (1.0,), "cw": (-1.0,)}.get(D.direction, (1.0, -1.0))
    for s in dirs:
        steps = np.mod(s * np.diff(phis), TWO_PI)
        y = x.copy()
        y[9] = phis[0]
        y[10:] = steps
        out.append((y, s))
    return out


def timing_from_report(pp: PathProblem, x, sign, rep):
    u = pp.problem.meta.units
    torad = (lambda v: v) if u.angle == "rad" else math.radians
    D = pp.design
    y = x.copy()
    if D.timing == "prescribed":
        y[9] = torad(rep["timing"].get("input_offset", 0.0)) if D.free[9] else D.lo[9]
        return [(y, 1.0)]
    phis = np.array([torad(r["input"]) for r in rep["positions"]])
    s = 1.0 if rep["timing"]["direction"] == "ccw" else -1.0
    y[9] = phis[0]
    y[10:] = np.mod(s * np.diff(phis), TWO_PI)
    return [(y, s)]


def fd_jac(fun, u, h):
    """Central differences of a vectorized fun (rows) at u: (m, k)."""
    k = len(u)
    U = np.concatenate([u + h * np.eye(k), u - h * np.eye(k)])
    F = fun(U)
    return (F[:k] - F[k:]).T / (2 * h)


def slsqp_scaled(residuals_of, cons_of, x0, idx, w, lo, hi, fscale, maxiter, t_end):
    """SLSQP on the variables `idx` of x0, u = (x - x0) / w, within [lo, hi] (full vectors):
    minimize |residuals_of(X)|^2 / fscale subject to cons_of(X) >= 0 (rows X), slopes by
    central differences. Returns (the end x, scipy's result); an infeasible end gives way to
    the lowest iterate that met the constraints."""
    def X_of(U):
        X = np.repeat(x0[None], len(U), axis=0)
        X[:, idx] = x0[idx] + U * w
        return X

    cache = {}

    def ev(u):
        key = u.tobytes()
        if key not in cache:
            if t_end is not None and time.time() > t_end:
                raise TimeUp
            cache.clear()
            r = residuals_of(X_of(u[None]))[0]
            J = fd_jac(lambda U: residuals_of(X_of(U)), u, 1e-7)
            g = cons_of(X_of(u[None]))[0]
            G = fd_jac(lambda U: cons_of(X_of(U)), u, 1e-7)
            cache[key] = (r, J, g, G)
        return cache[key]

    lo_u, hi_u = (lo[idx] - x0[idx]) / w, (hi[idx] - x0[idx]) / w
    track = [(math.inf, None)]

    def cb(u):  # the lowest iterate that meets the own constraints (SLSQP may end infeasible)
        u = np.clip(u, lo_u, hi_u)
        r, _, g, _ = ev(u)
        f = float(r @ r)
        if g.min() >= -1e-13 and f < track[0][0]:
            track[0] = (f, u.copy())

    res = minimize(lambda u: float(ev(u)[0] @ ev(u)[0]) / fscale, np.zeros(len(idx)),
                   jac=lambda u: 2 * ev(u)[1].T @ ev(u)[0] / fscale,
                   bounds=Bounds(lo_u, hi_u),
                   constraints=[NonlinearConstraint(lambda u: ev(u)[2], 0, np.inf, jac=lambda u: ev(u)[3])],
                   method="SLSQP", options=dict(ftol=1e-15, maxiter=maxiter), callback=cb)
    u = np.clip(res.x, lo_u, hi_u)
    r, _, g, _ = ev(u)
    if g.min() < -1e-13 and track[0][1] is not None:
        u = track[0][1]
        res.message = str(res.message) + " [end infeasible: best feasible iterate]"
    return X_of(u[None])[0], res


def slsqp_path(pp: PathProblem, x0, sign, s, vars_idx=None, maxiter=3000, t_end=None):
    """SLSQP on the free variables (or `vars_idx`), scaled: lengths and positions by L,
    angles in rad. Returns the end x."""
    D = pp.design
    idx = pp.free if vars_idx is None else vars_idx
    w = np.array([pp.L if j < 8 else 1.0 for j in idx])
    struct = pp.structure(x0, s)
    f0 = max(float(pp.objective(x0[None], sign, s)[0]), 1e-300)
    return slsqp_scaled(lambda X: pp.residuals(X, sign, s), lambda X: pp.cons(X, sign, s, struct), x0, idx, w,
                        D.lo, D.hi, f0 / pp.L ** 2, maxiter, t_end)  # residuals are /L: f/L^2


def best_run(entry):
    """The case's long run with the lowest objective (its design is the best known's)."""
    good = [r for r in entry["runs"] if r["status"] != "infeasible" and r.get("objective") is not None]
    return min(good, key=lambda r: r["objective"])


def run_path(cid, entry, log):
    t0 = time.time()
    pp = PathProblem(entry["text"])
    best, run = entry["best_known"], best_run(entry)
    x, sign = path_x_from_linkage(pp, run["linkage"])
    D = pp.design
    # ---- reconstruct the timing
    if D.timing == "prescribed":
        cands = reconstruct_prescribed(pp, x, sign)
    else:
        cands = reconstruct_free(pp, x, sign)
    how = "reconstructed"
    rows = []
    for y, s in cands:
        acc, obj, pr, v, inb, _ = pp.screen(y, sign, s)
        rows.append((not acc, abs(obj - best), y, s, obj, pr, acc))
    if D.timing == "free":  # timing-only SLSQP (constraints held) from each reconstruction
        for y, s in list(cands):
            try:
                z = y
                for _ in range(3):
                    z, _ = slsqp_path(pp, z, sign, s, vars_idx=np.arange(9, D.nx), maxiter=500,
                                      t_end=time.time() + 10)
            except TimeUp:
                continue
            acc, obj, pr, v, inb, _ = pp.screen(z, sign, s)
            rows.append((not acc, abs(obj - best), z, s, obj, pr, acc))
    ok = [r for r in rows if r[6] and abs(r[4] - best) <= REPRO * max(abs(best), 1e-300)]
    if not ok:  # the run again, its report's timing
        log(f"  case {cid}: timing not reconstructed ({[(f'{r[4]:.10g}', r[6]) for r in rows][:4]}); rerun "
            f"{run['method']} seed {run['seed']} budget {run['budget']}")
        how = "rerun"
        rr = cv.solve_text(entry["text"], run["method"], run["budget"], run["seed"])
        rep = rr["report"]
        x2, sign2 = path_x_from_linkage(pp, rep["linkage"])
        for y, s in timing_from_report(pp, x2, sign2, rep):
            acc, obj, pr, v, inb, _ = pp.screen(y, sign2, s)
            rows.append((not acc, abs(obj - best), y, s, obj, pr, acc))
            if acc and abs(obj - best) <= REPRO * abs(best):
                ok.append(rows[-1])
                sign = sign2
        if not ok:
            log(f"  case {cid}: rerun gives {rr['objective']!r} ({rr['status']}), best known {best!r}")
    if not ok:
        r = min(rows, key=lambda r: (r[0], r[1]))
        return dict(start=r[4], start_printed=r[5], repro=False, how=how, low=None, acc=None,
                    seconds=time.time() - t0)
    r0 = min(ok, key=lambda r: r[1])
    _, _, x0, s, obj0, pr0, _ = r0
    own0 = float(pp.objective(x0[None], sign, s)[0])
    # ---- the independent local optimizer from the best-known design
    t_end = time.time() + TIME_CAP
    lows = []
    xs = x0
    msg = ""
    for attempt in range(3):  # SLSQP, restarted from its end while it lowers (binding set re-read)
        try:
            z, res = slsqp_path(pp, xs, sign, s, t_end=t_end)
            msg = f"{res.message} nit {res.nit}"
        except TimeUp:
            msg = "time cap"
            break
        acc, obj, pr, v, inb, _ = pp.screen(z, sign, s)
        g = pp.cons(z[None], sign, s, pp.structure(z, s))[0]
        # strict: also within the own constraints to 1e-12 (not only within linkcli's tolerances)
        acc = acc and float(g.min()) >= -1e-12
        lows.append((obj, pr, acc, float(g.min()), v, inb, z))
        if not acc or obj >= float(pp.objective(xs[None], sign, s)[0]) * (1 - 1e-12):
            break
        xs = z
    feas = [l for l in lows if l[2]]
    low = min(feas, key=lambda l: l[0]) if feas else None
    return dict(start=obj0, start_printed=pr0, own_start=own0, repro=True, how=how,
                low=None if low is None else low[0], low_printed=None if low is None else low[1],
                low_gmin=None if low is None else low[3],
                acc=None if low is None else low[2],
                rejected=[(l[0], [n for n, _, _ in l[4]], l[5], l[3]) for l in lows if not l[2]],
                msg=msg, seconds=time.time() - t0, design=None if low is None else low[6].tolist(),
                sign=sign, s=s)


# ============================================================ function generation

def law_values(expr, x):
    ns = {k: getattr(np, k) for k in ("sin", "cos", "tan", "exp", "log", "log10", "sqrt", "arcsin", "arccos",
                                      "arctan", "abs")}
    ns.update(pi=math.pi, e=math.e, x=x)
    return eval(expr, {"__builtins__": {}}, ns)


class FunctionProblem:
    def __init__(self, text):
        import tomllib
        self.problem = load("case.toml", text)
        self.model = fgm.Model(self.problem)
        p = self.problem
        raw = tomllib.loads(text)["target"]
        n = raw.get("points", 31)
        if raw.get("spacing", "uniform") == "chebyshev":
            k = np.arange(1, n + 1)
            t = (1 - np.cos((2 * k - 1) * math.pi / (2 * n))) / 2
        else:
            t = np.linspace(0, 1, n)
        x0, x1 = raw["x"]
        xs = x0 + t * (x1 - x0)
        fx = law_values(raw["function"], xs)
        f0, f1 = law_values(raw["function"], np.array([x0, x1]))
        self.t = t
        self.shape = (fx - f0) / (f1 - f0)
        self.check_t = float(np.max(np.abs(self.t - np.asarray(p.fractions))))
        self.check_shape = float(np.max(np.abs(self.shape - np.asarray(p.shape))))
        self.isweep = p.input_sweep
        self.osweep = p.output_sweep
        self.vars = self.model.variables
        self.lo, self.hi = self.model.lo, self.model.hi
        self.fixed = p.fixed
        self.scale = max(p.fixed.values())
        self.window = p.transmission
        self.grashof = p.grashof
        self.full = p.grashof in fgm.FULL_TURN_CLASSES

    def parts(self, V):
        cols = {k: V[:, i] for i, k in enumerate(self.vars)}
        g = lambda k: cols[k] if k in cols else np.full(len(V), float(self.fixed[k]))  # noqa: E731
        return g("input"), g("coupler"), g("output"), g("ground"), g("input_start"), g("output_start")

    def residuals(self, V, sign):
        a, b, c, d, phi0, psi0 = (z[:, None] for z in self.parts(V))
        phi = phi0 + self.t * self.isweep
        v = a * np.exp(1j * phi) - d
        rho = np.abs(v)
        alpha = np.arccos(np.clip((rho * rho + c * c - b * b) / (2 * rho * c), -1, 1))
        psi = np.angle(v) + sign * alpha
        return wrap(psi - (psi0 + self.shape * self.osweep))

    def objective(self, V, sign):
        r = self.residuals(V, sign)
        return np.sum(r * r, axis=1)

    def structure(self, v):
        a, b, c, d, phi0, psi0 = self.parts(v[None])
        lo = phi0[0] if self.isweep >= 0 else phi0[0] + self.isweep
        return [(at, bool(np.mod(at - lo, TWO_PI) <= abs(self.isweep))) for at in (0.0, math.pi)]

    def cons(self, V, struct):
        a, b, c, d, phi0, _ = self.parts(V)
        L2 = self.scale ** 2
        ends = [phi0, phi0 + self.isweep]
        r2 = [a * a + d * d - 2 * a * d * np.cos(e) for e in ends]
        r2 += [a * a + d * d - 2 * a * d * math.cos(at) for at, inside in struct if inside]
        r2 = np.stack(r2, axis=1)
        out = list(((b + c)[:, None] ** 2 - r2).T / L2) + list((r2 - (b - c)[:, None] ** 2).T / L2)
        if self.window is not None:
            rr = np.stack([(d - a) ** 2, (d + a) ** 2], axis=1) if self.full else r2
            cosmu = (b[:, None] ** 2 + c[:, None] ** 2 - rr) / (2 * b[:, None] * c[:, None])
            out += list(math.cos(self.window[0]) - cosmu.T) + list((cosmu - math.cos(self.window[1])).T)
        links = {"input": a, "coupler": b, "output": c, "ground": d}
        total = a + b + c + d
        margin = fgm.GRASHOF_MARGIN * total
        if self.grashof in fgm.SHORTEST:
            s = links[fgm.SHORTEST[self.grashof]]
            for k, xx in links.items():
                if k != fgm.SHORTEST[self.grashof]:
                    out.append((total - 2 * (s + xx) - margin) / self.scale)
        elif self.grashof == "triple-rocker":
            srt = np.sort(np.stack([a, b, c, d], axis=1), axis=1)
            out.append((srt[:, 0] + srt[:, 3] - srt[:, 1] - srt[:, 2] - margin) / self.scale)
        return np.stack(out, axis=1)

    def screen(self, v, branch):
        """linkcli: Model.evaluate, and build_solution's status (describe_violations) and the
        printed objective."""
        sign = fgm.BRANCH_SIGN[branch]
        inb = bool(np.all(v >= self.lo - 1e-12 * np.maximum(1, abs(self.lo))) and
                   np.all(v <= self.hi + 1e-12 * np.maximum(1, abs(self.hi))))
        batch = self.model.evaluate(v[None], sign)
        best = types.SimpleNamespace(branch=branch, v=v.copy(), u=self.model.units(v[None])[0], f=float(batch.f[0]))
        search = types.SimpleNamespace(answer=lambda: best, evaluations=types.SimpleNamespace(used=0), budget=0)
        sol = fgs.build_solution(self.problem, self.model, search, True, True)
        pr = printed_objective(self.problem, sol)
        acc = sol.status is not Status.INFEASIBLE and inb
        return acc, float(batch.f[0]), pr, float(batch.violation[0].max()), sol.message, inb


def reconstruct_function(fp: FunctionProblem, lk, best):
    """Start angles for the cached lengths: scan phi0 (optimal psi0 in closed form), then an
    SLSQP on the free starts with the constraints."""
    branch = lk["branch"]
    sign = fgm.BRANCH_SIGN[branch]
    v = np.array([lk[k] if k in fgm.LINK_ORDER else 0.0 for k in fp.vars], dtype=float)
    si = fp.vars.index("input_start") if "input_start" in fp.vars else None
    so = fp.vars.index("output_start") if "output_start" in fp.vars else None
    if si is None:
        grid = np.array([0.0])
    else:
        grid = np.linspace(fp.lo[si], fp.hi[si], 72001)
    V = np.repeat(v[None], len(grid), axis=0)
    if si is not None:
        V[:, si] = grid
    if so is not None:  # psi0 = circular-ish mean of psi - shape * sweep
        V[:, so] = 0.0
        r = fp.residuals(V, sign)
        ref = r[:, :1]
        m = ref[:, 0] + np.mean(wrap(r - ref), axis=1)
        V[:, so] = np.clip(wrap(m), fp.lo[so], fp.hi[so])
    f = fp.objective(V, sign)
    order = np.argsort(f)
    picked = []
    for i in order:
        if len(picked) >= 30:
            break
        if all(abs(V[i, si] - V[j, si]) > 2e-3 for j in picked) if si is not None else not picked:
            picked.append(i)
    out = []
    idx = [j for j in (si, so) if j is not None]
    for i in picked:
        z = V[i].copy()
        if idx:
            try:
                z = slsqp_function(fp, z, branch, vars_idx=np.array(idx), maxiter=300, t_end=time.time() + 5)[0]
            except TimeUp:
                pass
        acc, obj, pr, worst, msg, inb = fp.screen(z, branch)
        out.append((z, acc, obj, pr))
    return out


def slsqp_function(fp: FunctionProblem, v0, branch, vars_idx=None, maxiter=3000, t_end=None):
    sign = fgm.BRANCH_SIGN[branch]
    idx = np.arange(len(v0)) if vars_idx is None else vars_idx
    w = np.array([fp.scale if fp.vars[j] in fgm.LINK_ORDER else 1.0 for j in idx])
    struct = fp.structure(v0)
    f0 = max(float(fp.objective(v0[None], sign)[0]), 1e-300)
    return slsqp_scaled(lambda V: fp.residuals(V, sign), lambda V: fp.cons(V, struct), v0, idx, w,
                        fp.lo, fp.hi, f0, maxiter, t_end)


def run_function(cid, entry, log):
    t0 = time.time()
    fp = FunctionProblem(entry["text"])
    best, run = entry["best_known"], best_run(entry)
    lk = run["linkage"]
    branch = lk["branch"]
    rows = reconstruct_function(fp, lk, best)
    how = "reconstructed"
    ok = [r for r in rows if r[1] and abs(r[2] - best) <= REPRO * abs(best)]
    if not ok:
        log(f"  case {cid}: starts not reconstructed ({sorted((f'{r[2]:.10g}', r[1]) for r in rows)[:4]}); rerun")
        how = "rerun"
        rr = cv.solve_text(entry["text"], run["method"], run["budget"], run["seed"])
        rep = rr["report"]
        u = fp.problem.meta.units
        torad = math.radians if u.angle == "deg" else (lambda q: q)
        lk2 = rep["linkage"]
        v = np.array([lk2[k] if k in fgm.LINK_ORDER else torad(rep["target"][k]) for k in fp.vars], dtype=float)
        branch = lk2["branch"]
        acc, obj, pr, worst, msg, inb = fp.screen(v, branch)
        rows.append((v, acc, obj, pr))
        if acc and abs(obj - best) <= REPRO * abs(best):
            ok.append(rows[-1])
        else:
            log(f"  case {cid}: rerun gives {rr['objective']!r} ({rr['status']}), own screen {obj!r}")
    if not ok:
        r = min(rows, key=lambda r: (not r[1], abs(r[2] - best)))
        return dict(start=r[2], start_printed=r[3], repro=False, how=how, low=None, acc=None,
                    seconds=time.time() - t0)
    v0, _, obj0, pr0 = min(ok, key=lambda r: abs(r[2] - best))
    sign = fgm.BRANCH_SIGN[branch]
    own0 = float(fp.objective(v0[None], sign)[0])
    t_end = time.time() + TIME_CAP
    lows = []
    vs = v0
    msg = ""
    for attempt in range(3):
        try:
            z, res = slsqp_function(fp, vs, branch, t_end=t_end)
            msg = f"{res.message} nit {res.nit}"
        except TimeUp:
            msg = "time cap"
            break
        acc, obj, pr, worst, m, inb = fp.screen(z, branch)
        g = fp.cons(z[None], fp.structure(z))[0]
        acc = acc and float(g.min()) >= -1e-12  # strict, not by FEASIBLE's 1e-8 allowance
        lows.append((obj, pr, acc, float(g.min()), m, worst, z))
        if not acc or obj >= float(fp.objective(vs[None], sign)[0]) * (1 - 1e-12):
            break
        vs = z
    feas = [l for l in lows if l[2]]
    low = min(feas, key=lambda l: l[0]) if feas else None
    return dict(start=obj0, start_printed=pr0, own_start=own0, repro=True, how=how,
                low=None if low is None else low[0], low_printed=None if low is None else low[1],
                low_gmin=None if low is None else low[3], acc=None if low is None else low[2],
                low_worst=None if low is None else low[5],
                rejected=[(l[0], l[4], l[5]) for l in lows if not l[2]], msg=msg,
                seconds=time.time() - t0, design=None if low is None else dict(zip(fp.vars, low[6].tolist())),
                branch=branch, check_t=fp.check_t, check_shape=fp.check_shape)


# ============================================================ main

def main():
    cache = cv.load_cache(os.path.join(BENCH, "constrained_variants.json"))
    args = sys.argv[1:]
    out_json = "/tmp/check_best_known.json"
    if "--out" in args:
        i = args.index("--out")
        out_json = args[i + 1]
        args = args[:i] + args[i + 2:]
    ids = args or sorted(cache["cases"], key=int)
    results = {}
    if os.path.exists(out_json) and args:
        with open(out_json, encoding="utf-8") as fh:
            results = json.load(fh)

    def log(s):
        print(s, flush=True)

    for cid in ids:
        e = cache["cases"][cid]
        if e["family"] not in ("path-prescribed", "path-free", "function") or e.get("best_known") is None:
            continue
        try:
            r = (run_function if e["family"] == "function" else run_path)(cid, e, log)
        except Exception as exc:  # noqa: BLE001
            import traceback
            traceback.print_exc()
            r = dict(error=repr(exc))
        r.update(family=e["family"], best_known=e["best_known"], binds=e.get("binds"), kind=e.get("kind"),
                 constraint=e.get("constraint"))
        if r.get("low") is not None:
            r["gap"] = (r["low"] - e["best_known"]) / abs(e["best_known"]) if e["best_known"] else r["low"]
        results[cid] = r
        log(f"{cid:>4} {e['family']:<15} best {e['best_known']:.12g} start {r.get('start')!r} repro "
            f"{r.get('repro')} ({r.get('how')}) low {r.get('low')!r} gap {r.get('gap')!r} acc {r.get('acc')} "
            f"gmin {r.get('low_gmin')!r} {r.get('msg', r.get('error'))} {r.get('seconds', 0):.1f}s "
            f"rej {r.get('rejected')}")
        with open(out_json, "w") as fh:
            json.dump(results, fh, indent=1, default=float)


if __name__ == "__main__":
    main()
