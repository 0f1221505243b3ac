"""Steady running: the speed fluctuation over a cycle, and the flywheel by the energy method,
checked against the integration.

Energy method (Norton, Design of Machinery, sec. 11.11; Shigley & Uicker, Theory of Machines and
Mechanisms, ch. 16): at the mean speed w_m the linkage asks its drive for the torque T_L(q) that
keeps the speed constant (inverse dynamics at q'' = 0: inertia, gravity, springs, dampers and
friction); a drive delivering its mean T_m = mean(T_L) gives the linkage the energy
E(q) = integral (T_m - T_L) dq, and the flywheel that holds the speed within w_m (1 +- Cs / 2)
stores the difference of its extremes:

    dE = max E - min E,         I = dE / (Cs w_m^2)

(the linkage's own inertia neglected, as the method does): the inertia turning with the drive,
of which [dynamics] flywheel_inertia (a motor's rotor, a pulley) is already there and the rest
is the flywheel to add. Mean speed: `mean_speed`, the drive
then delivering T_m constantly; or, for a motor, the speed where its torque equals the mean load
(T_motor(w) = mean T_L(w), the highest such speed: where the motor's curve falls through the
load, a stable running point). E(q) is integrated spectrally (the load is periodic: its Fourier
series integrated term by term) and its extremes located where T_L = T_m by root finding.

Check: the linkage with the flywheel added, driven as above, run over cycles from q = 0 until
its speed at the start of a cycle repeats (a secant on w(2 pi) - w(0) when the drive or
dissipation sets the orbit; a linkage that neither gains nor loses runs the orbit it starts on,
at the mean speed); the speed's extremes are found as events (q'' = 0), and
Cs = (max - min) / ((max + min) / 2). The same is reported for the linkage as given.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

TWO_PI = 2.0 * math.pi
CYCLE_POINTS = 1024  # load torque samples over a turn (spectral integration)
ORBIT_ITERATIONS = 30
ORBIT_RTOL = 1e-10


def load_torque(system, q, speed: float):
    """T_L at internal drive values q turning at the constant `speed` (inverse dynamics)."""
    from linkcli.analysis.dynamics.history import state
    return state(system, q, np.full(len(q), speed), acceleration=np.zeros(len(q))).torque


def mean_load(system, speed: float) -> float:
    q = np.arange(CYCLE_POINTS) * (TWO_PI / CYCLE_POINTS)
    return float(np.mean(load_torque(system, q, speed)))


def running_speed(system) -> float | None:
    """The motor's running point: the highest speed where its torque equals the mean load, the
    motor's torque falling through it (module docstring); None when there is none."""
    from scipy.optimize import brentq
    law = system.drive.law
    lo, hi = float(law.x[0]), float(law.x[-1])
    span = hi - lo
    speeds = np.linspace(lo, hi + 0.25 * span, 121)  # past the last row: a curve through 0 runs on
    speeds = speeds[np.abs(speeds) > 1e-9 * span]
    gap = np.array([system.drive.scalar(w) - mean_load(system, w) for w in speeds])
    down = np.nonzero((gap[:-1] > 0) & (gap[1:] <= 0))[0]
    if not len(down):
        return None
    k = down[-1]
    return float(brentq(lambda w: system.drive.scalar(w) - mean_load(system, w), speeds[k], speeds[k + 1],
                        xtol=1e-14 * max(abs(speeds[k + 1]), 1.0), rtol=1e-15, maxiter=200))


def energy_fluctuation(system, speed: float, mean_torque: float) -> float:
    """dE over a turn (module docstring): E(q) = integral (T_m - T_L) dq spectrally, its extremes
    where T_L = T_m (brentq on the exact load)."""
    from scipy.optimize import brentq
    n = CYCLE_POINTS
    q = np.arange(n) * (TWO_PI / n)
    excess = mean_torque - load_torque(system, q, speed)
    spectrum = np.fft.rfft(excess) / n

    def energy(x):
        x = np.atleast_1d(x)
        terms = np.zeros(len(x))
        for j in range(1, len(spectrum)):
            factor = 1.0 if (n % 2 == 0 and j == n // 2) else 2.0
            terms += factor * np.real(spectrum[j] / (1j * j) * np.exp(1j * j * x))
        return terms + np.real(spectrum[0]) * x

    def gap(x):
        return float(mean_torque - load_torque(system, np.array([x]), speed)[0])

    points = [0.0]
    for i in np.nonzero(np.sign(excess) != np.sign(np.roll(excess, -1)))[0]:
        a, b = q[i], q[i] + TWO_PI / n
        if gap(a) * gap(b) < 0:
            points.append(brentq(gap, a, b, xtol=1e-15, rtol=1e-15))
    values = energy(np.array(points))
    return float(np.max(values) - np.min(values))


def section(system, meta, notes: list) -> tuple[dict | None, tuple[str, str] | None]:
    """(the `flywheel` section, None) or (None, (status, why)) when the motor has no running
    point."""
    from linkcli.model.dynamics import MOTOR, TORQUE, Drive
    dyn = meta.dynamics
    units = meta.units
    if not system.full_turn:
        raise system.error("fluctuation", "a drive that turns fully for a flywheel (it evens the speed "
                           "over a turn)", "a drive that rocks")
    motor = dyn.drive.kind == MOTOR and dyn.mean_speed is None
    speed = running_speed(system) if motor else dyn.mean_speed
    if speed is None:
        return None, ("infeasible", "the motor cannot drive the linkage: its torque never meets the "
                      "mean load torque over its curve (no running speed for the flywheel)")
    mean_torque = system.drive.scalar(speed) if motor else mean_load(system, speed)
    d_energy = energy_fluctuation(system, speed, mean_torque)
    cs = dyn.fluctuation
    inertia = d_energy / (cs * speed * speed)
    m = system.node_values[:, 0]
    drive = dyn.drive if motor else Drive(TORQUE, torque=mean_torque)
    added = max(inertia - dyn.flywheel_inertia, 0.0)
    out = {"fluctuation": cs, "mean_speed": float(units.from_rad(speed)), "mean_torque": mean_torque,
           "energy_fluctuation": d_energy, "inertia": inertia, "added_inertia": added,
           "linkage_inertia": {"min": float(np.min(m)), "max": float(np.max(m))}}
    as_given = _orbit(system, replace(dyn, drive=drive), speed, system.error)
    with_flywheel = _orbit(system, replace(dyn, drive=drive, flywheel_inertia=dyn.flywheel_inertia + added),
                           speed, system.error)
    out["as_given"] = _said(as_given, units)
    out["with_flywheel"] = _said(with_flywheel, units)
    if as_given is None:
        notes.append("flywheel: without the flywheel the linkage finds no steady cycle at this drive "
                     "(it stalls or runs away)")
    return out, None


def _said(orbit, units):
    if orbit is None:
        return None
    high, low = orbit
    mean = 0.5 * (high + low)
    return {"max_speed": float(units.from_rad(high)), "min_speed": float(units.from_rad(low)),
            "fluctuation": (high - low) / mean}


def _orbit(system, dyn, speed: float, error):
    """(max, min) speed over the steady cycle of the system with `dyn` (module docstring), or
    None when there is none (it stalls, reverses or does not settle)."""
    from linkcli.analysis.dynamics.system import System
    other = System(system.mech, dyn, system.case, system.units, system.metres, path=system.path)
    direction = 1.0 if speed > 0 else -1.0
    settles = dyn.drive.kind == "motor" or dyn.friction > 0 or any(e.role == "damper" for e in other.elements)

    def cycle(w0):
        run = _one_cycle(other, w0, direction, speed)
        return run

    if not settles:
        result = cycle(speed)
        return None if result is None else result[1]
    w0, w1 = speed, speed * (1.0 + 1e-3)
    r0, r1 = cycle(w0), cycle(w1)
    if r0 is None or r1 is None:
        return None
    g0, g1 = r0[0] - w0, r1[0] - w1
    for _ in range(ORBIT_ITERATIONS):
        if abs(g1) <= ORBIT_RTOL * abs(speed):
            return r1[1]
        if g1 == g0:
            return None
        w2 = w1 - g1 * (w1 - w0) / (g1 - g0)
        if not math.isfinite(w2) or w2 * direction <= 0:
            return None
        r2 = cycle(w2)
        if r2 is None:
            return None
        w0, g0, w1, r1 = w1, g1, w2, r2
        g1 = r2[0] - w2
    return None


def _one_cycle(system, w0: float, direction: float, speed: float):
    """(speed after one turn from q = 0, (max, min) speed over it), or None when the turn is not
    completed (the drive stalls or reverses)."""
    from linkcli.analysis.dynamics import motion
    period = TWO_PI / abs(speed)
    run = motion.integrate(system, 0.0, w0, 20.0 * period, stop=direction * TWO_PI, method=system.dyn.method,
                           dead_points=False, extremes=True)
    if run.end != "stop" or any(e[0] == "reversal" for e in run.events):
        return None
    speeds = [w0, run.events[-1][3]] + [e[3] for e in run.events if e[0] == "extreme"]
    return run.events[-1][3], (max(speeds, key=lambda v: v * direction), min(speeds, key=lambda v: v * direction))
