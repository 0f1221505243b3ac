"""How a four-bar is drawn to scale in its global placement (matplotlib imported lazily).

Geometry follows the conventions of docs/format.md: in the local frame A0 = (0, 0), B0 = (d, 0),
A = a e^{i phi}, B = B0 + c e^{i psi}, coupler point P = A + (px + i py) e^{i theta};
the global frame puts A0 at `ground_pivot` and turns the ground line by `ground_angle`:
X = G + R(ground_angle) x. The closure itself is `kinematics.pose`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkcli.mechanisms.four_bar import kinematics as kin
from linkcli.mechanisms.four_bar.model import FourBar
from linkcli.noise import snap
from linkcli.plots.common import LINK_COLORS, ground_mark, num
from linkcli.units import Units


@dataclass(frozen=True)
class Geometry:
    """A four-bar from a report's `linkage` section: lengths, branch, global placement."""

    a: float
    b: float
    c: float
    d: float
    branch: str
    coupler_point: tuple[float, float] | None
    ground_pivot: tuple[float, float]
    ground_angle: float  # rad

    @classmethod
    def of(cls, source) -> Geometry:
        """The linkage a Result solved (`result.solution.linkage`). A report dict is still
        read (its `linkage` section, in the file's units) for a plot module written before
        the plots drew from the Result."""
        if isinstance(source, dict):
            return cls._of_report(source)
        return cls.of_linkage(source.solution.linkage)

    @classmethod
    def of_linkage(cls, fb: FourBar) -> Geometry:
        """A FourBar (lengths in the length unit, angles in radians) to draw."""
        cp = fb.coupler_point
        size = max(fb.abcd)
        return cls(a=float(fb.input), b=float(fb.coupler), c=float(fb.output), d=float(fb.ground),
                   branch=fb.branch,
                   coupler_point=(snap(float(cp[0]), size), snap(float(cp[1]), size)) if cp is not None else None,
                   ground_pivot=(snap(float(fb.ground_pivot[0]), size), snap(float(fb.ground_pivot[1]), size)),
                   ground_angle=snap(float(kin.wrap(fb.ground_angle)), 1.0))  # the report's angle

    @classmethod
    def _of_report(cls, report: dict) -> Geometry:
        lk = report["linkage"]
        u = Units(**report.get("units", {}))
        cp = lk.get("coupler_point")
        gp = lk.get("ground_pivot") or (0.0, 0.0)
        return cls(a=float(lk["input"]), b=float(lk["coupler"]), c=float(lk["output"]),
                   d=float(lk["ground"]), branch=lk.get("branch", "open"),
                   coupler_point=(float(cp[0]), float(cp[1])) if cp is not None else None,
                   ground_pivot=(float(gp[0]), float(gp[1])),
                   ground_angle=float(u.angles_to_rad(float(lk.get("ground_angle", 0.0)))))

    @property
    def size(self) -> float:
        """The longest link: the drawing's length scale."""
        return max(self.a, self.b, self.c, self.d)

    def to_global(self, x, y):
        """X = G + R(ground_angle) x (the conventions of docs/format.md: global placement)."""
        cg, sg = math.cos(self.ground_angle), math.sin(self.ground_angle)
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        return self.ground_pivot[0] + cg * x - sg * y, self.ground_pivot[1] + sg * x + cg * y

    def pose(self, phi):
        return kin.pose(self.a, self.b, self.c, self.d, phi, self.branch)

    def joints(self, phi) -> dict:
        """Global coordinates of A0, B0, A, B (and P) at input angles phi, with the pose."""
        p = self.pose(phi)
        ax, ay = self.a * np.cos(p.phi), self.a * np.sin(p.phi)
        bx, by = self.d + self.c * np.cos(p.psi), self.c * np.sin(p.psi)
        out = {"A0": self.to_global(0.0, 0.0), "B0": self.to_global(self.d, 0.0),
               "A": self.to_global(ax, ay), "B": self.to_global(bx, by), "pose": p}
        if self.coupler_point is not None:
            out["P"] = self.to_global(*p.coupler_point(self.a, *self.coupler_point))
        return out

    def motion(self, near=None) -> kin.Motion:
        return kin.motion(self.a, self.b, self.c, self.d, self.branch, near=near)


def input_grid(mot: kin.Motion, n: int = 721, centre: float | None = None) -> np.ndarray:
    """Input angles (rad) over the whole motion: a full turn starting 180 deg before
    `centre` (rounded to 45 deg) so that the targets sit mid-axis, or the reachable arc."""
    if mot.input_full_turn:
        start = 0.0 if centre is None else math.radians(45.0 * round((math.degrees(centre) - 180.0) / 45.0))
        return start + np.linspace(0.0, kin.TWO_PI, n)
    lo, hi = mot.input_arc
    return np.linspace(lo, hi, n)


def on_grid(grid: np.ndarray, phi) -> np.ndarray:
    """Input angles moved by whole turns into [grid[0], grid[0] + 360 deg)."""
    return grid[0] + np.mod(np.asarray(phi, dtype=float) - grid[0], kin.TWO_PI)


def draw_linkage(ax, geo: Geometry, phi: float, *, ghost: bool = False, labels: bool = True) -> None:
    """The four-bar at input angle phi (rad), to scale: ground line and pivots, crank,
    coupler (a triangle A-B-P when there is a coupler point), rocker, joints."""
    from matplotlib.patches import Polygon

    j = geo.joints(phi)
    if not bool(np.all(j["pose"].valid)):
        return
    alpha = 0.28 if ghost else 1.0
    lw = 1.6 if ghost else 3.2
    (x0, y0), (x1, y1) = j["A0"], j["B0"]
    (xa, ya), (xb, yb) = j["A"], j["B"]
    xa, ya, xb, yb = float(xa), float(ya), float(xb), float(yb)
    if not ghost:
        ax.plot([x0, x1], [y0, y1], color=LINK_COLORS["ground"], lw=1.4, ls=(0, (6, 3)), zorder=1)
        s = 0.08 * geo.size
        for x, y in ((x0, y0), (x1, y1)):
            ground_mark(ax, float(x), float(y), s, LINK_COLORS["ground"])
    if "P" in j:
        xp, yp = (float(v) for v in j["P"])
        ax.add_patch(Polygon([(xa, ya), (xb, yb), (xp, yp)], closed=True, zorder=2,
                             facecolor=LINK_COLORS["coupler"], alpha=0.18 * alpha,
                             edgecolor=LINK_COLORS["coupler"], lw=lw * 0.6))
    ax.plot([x0, xa], [y0, ya], color=LINK_COLORS["input"], lw=lw, alpha=alpha, zorder=3)
    ax.plot([xa, xb], [ya, yb], color=LINK_COLORS["coupler"], lw=lw, alpha=alpha, zorder=3)
    ax.plot([x1, xb], [y1, yb], color=LINK_COLORS["output"], lw=lw, alpha=alpha, zorder=3)
    joints = [(xa, ya), (xb, yb)] + ([(float(j["P"][0]), float(j["P"][1]))] if "P" in j else [])
    ax.scatter([p[0] for p in joints], [p[1] for p in joints], s=22 if ghost else 42, zorder=4,
               facecolor="white", edgecolor="black", linewidths=1.0, alpha=alpha)
    if ghost:
        return
    ax.scatter([x0, x1], [y0, y1], s=70, zorder=4, facecolor="black", edgecolor="black")
    if labels:
        names = [("A0", x0, y0), ("B0", x1, y1), ("A", xa, ya), ("B", xb, yb)]
        if "P" in j:
            names.append(("P", float(j["P"][0]), float(j["P"][1])))
        for name, x, y in names:
            ax.annotate(name, (float(x), float(y)), xytext=(7, 6), textcoords="offset points",
                        fontsize=10, fontweight="bold", zorder=5)


def link_legend(ax, geo: Geometry, length_unit: str, loc: str = "best") -> None:
    """One legend: the link lengths (and coupler point), then what the axes drew itself."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch
    lu = length_unit
    handles = [Line2D([], [], color=LINK_COLORS["input"], lw=3, label=f"input a = {num(geo.a)} {lu}"),
               Line2D([], [], color=LINK_COLORS["coupler"], lw=3, label=f"coupler b = {num(geo.b)} {lu}"),
               Line2D([], [], color=LINK_COLORS["output"], lw=3, label=f"output c = {num(geo.c)} {lu}"),
               Line2D([], [], color=LINK_COLORS["ground"], lw=1.4, ls=(0, (6, 3)),
                      label=f"ground d = {num(geo.d)} {lu}")]
    if geo.coupler_point is not None:
        px, py = geo.coupler_point
        handles.append(Patch(facecolor=LINK_COLORS["coupler"], alpha=0.18, edgecolor=LINK_COLORS["coupler"],
                             label=f"coupler point P = ({num(px)}, {num(py)}) {lu}"))
    own, _ = ax.get_legend_handles_labels()
    ax.legend(handles=handles + own, loc=loc, framealpha=0.85, title=f"{geo.branch} branch",
              title_fontsize=9.5)


def joint_paths(ax, geo: Geometry, grid: np.ndarray) -> None:
    """Thin dotted paths of A and B over the motion (the crank circle, the rocker arc)."""
    j = geo.joints(grid)
    ok = j["pose"].valid
    for name in ("A", "B"):
        x, y = j[name]
        ax.plot(np.where(ok, x, np.nan), np.where(ok, y, np.nan), color="#888888", lw=0.9,
                ls=(0, (1, 2.5)), zorder=0)
