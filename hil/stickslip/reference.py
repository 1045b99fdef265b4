"""Independent reference solution of the actuator equations (docs/model.md) with scipy's stiff
Radau solver in float64. It shares no code with the C core: the Masing memory is re-implemented
here, reversals and loop closures are located by root-finding events, and the waveform's corners
are integration boundaries. Slow; for verification and benchmarks only."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .model import ActuatorParams, Sawtooth

# docs/model.md: gross slip sets in above this share of Fs (SS_LS_BREAKAWAY_RATIO in C)
BREAKAWAY_RATIO = 0.9


class MasingMemory:
    """Masing branches of phi(u) = Fs (1 - exp(-sigma0 u / Fs)) with a stack of reversals."""

    def __init__(self, fs: float, sigma0: float):
        self.fs, self.k0 = fs, sigma0
        self.x0 = 0.0
        self.rev: list[tuple[float, float]] = []

    def force(self, x: float, d: int) -> tuple[float, float]:
        """F_M and dF_M/dx on the current branch at x, moving in direction d."""
        if not self.rev:
            u = x - self.x0
            a = self.k0 * abs(u) / self.fs
            return math.copysign(1.0, u) * -self.fs * math.expm1(-a), self.k0 * math.exp(-a)
        xr, fr = self.rev[-1]
        a = self.k0 * abs(x - xr) / (2.0 * self.fs)
        return fr - d * 2.0 * self.fs * math.expm1(-a), self.k0 * math.exp(-a)

    def closure(self) -> float | None:
        """Position where the current branch closes its minor loop."""
        if len(self.rev) >= 2:
            return self.rev[-2][0]
        if len(self.rev) == 1:
            return 2.0 * self.x0 - self.rev[0][0]
        return None


@dataclass
class ReferenceResult:
    t_s: np.ndarray
    x_rod_m: np.ndarray
    x_slider_m: np.ndarray
    force_n: np.ndarray
    waveform: Sawtooth
    reversals: int

    def slider_at(self, t: np.ndarray) -> np.ndarray:
        return np.interp(t, self.t_s, self.x_slider_m)

    def per_cycle_steps(self) -> np.ndarray:
        k = np.arange(self.waveform.cycles + 1) * self.waveform.period_s
        return np.diff(self.slider_at(k))


def _event(fn, direction: int):
    """Mark fn as a terminal solve_ivp event crossing zero in the given direction."""
    fn.terminal = True
    fn.direction = direction
    return fn


def _corners(w: Sawtooth) -> list[float]:
    """Times where the drive has a corner (edges of every period)."""
    r = w.rise_fraction if w.direction > 0 else 1.0 - w.rise_fraction
    ts = []
    for k in range(w.cycles):
        ts += [k * w.period_s, (k + r) * w.period_s]
    ts.append(w.cycles * w.period_s)
    return ts


def _drive(w: Sawtooth, t: float) -> float:
    if t >= w.duration_s:
        return w.offset_v
    phase = (t * w.frequency_hz) % 1.0
    p = 1.0 - phase if w.direction < 0 else phase
    r = w.rise_fraction
    shape = p / r if p < r else (1.0 - p) / (1.0 - r)
    return w.offset_v + w.amplitude_v * shape


def simulate_reference(
    waveform: Sawtooth,
    params: ActuatorParams | None = None,
    model: str = "ls",
    rtol: float = 1e-9,
    hold_s: float = 0.0,
    time_limit_s: float | None = None,
    method: str = "Radau",
) -> ReferenceResult:
    """Integrate to the end of the waveform (plus hold_s) with solve_ivp's method (Radau, or LSODA
    for the host bench of issue 17). Raises TimeoutError past time_limit_s of wall time (loose
    tolerances can chatter on the stick events). LS and LuGre only."""
    if model not in ("ls", "lugre"):
        raise ValueError(f"the reference solver integrates 'ls' and 'lugre', got {model!r}")
    if method not in ("Radau", "LSODA", "BDF"):
        raise ValueError(f"method must be Radau, LSODA or BDF (stiff solvers), got {method!r}")
    started = time.monotonic()
    p = params or ActuatorParams.table1()
    fs, fc, vs = p.fs_n, p.fc_n, p.stribeck_velocity_m_per_s
    k0, s1, s2 = p.sigma0_n_per_m, p.sigma1_ns_per_m, p.sigma2_ns_per_m
    k, c, mr, mc, gain = (
        p.piezo_stiffness_n_per_m,
        p.piezo_damping_kg_per_s,
        p.rod_mass_kg,
        p.slider_mass_kg,
        p.piezo_gain_m_per_v,
    )
    mem = MasingMemory(fs, k0)

    def g(v: float) -> float:
        return fc + (fs - fc) * math.exp(-((v / vs) ** 2))

    def gate(fm: float) -> float:
        tt = (abs(fm) / fs - BREAKAWAY_RATIO) / (1.0 - BREAKAWAY_RATIO)
        return 0.0 if tt <= 0 else 1.0 if tt >= 1 else tt * tt * (3.0 - 2.0 * tt)

    def friction(y, d: int) -> float:
        x, v = y[0] - y[2], y[1] - y[3]
        if model == "lugre":
            z = y[4]
            zdot = v - k0 * abs(v) * z / g(v)
            return k0 * z + s1 * zdot + s2 * v
        fm, kt = mem.force(x, d)
        vp = v * (1.0 - kt / k0) * gate(fm)
        zdot = vp * (1.0 - y[4] / g(vp))
        return (y[4] / fs) * fm + s1 * zdot + s2 * v

    def rhs(t, y, d, seg):
        t0, t1, u0, u1 = seg
        xp = gain * (u0 + (u1 - u0) * (t - t0) / (t1 - t0))
        x, v = y[0] - y[2], y[1] - y[3]
        f = friction(y, d)
        if model == "lugre":
            sdot = v - k0 * abs(v) * y[4] / g(v)
        else:
            fm, kt = mem.force(x, d)
            vp = v * (1.0 - kt / k0) * gate(fm)
            gp = g(vp)
            sdot = k0 * abs(vp) / gp * (gp - y[4])
        return [y[1], (k * (xp - y[0]) - c * y[1] - f) / mr, y[3], f / mc, sdot]

    x_p0 = gain * _drive(waveform, 0.0)
    y = np.array([x_p0, 0.0, 0.0, 0.0, 0.0 if model == "lugre" else fs])
    d = int(waveform.direction * np.sign(waveform.amplitude_v)) or 1
    bounds = _corners(waveform)
    if hold_s > 0:
        bounds.append(waveform.duration_s + hold_s)
    ts, xr, xc, ff = [0.0], [y[0]], [y[2]], [0.0]
    atol = np.array([1e-16, 1e-11, 1e-16, 1e-11, 1e-13])
    reversals = 0
    for t0, t1 in zip(bounds[:-1], bounds[1:]):
        if t1 - t0 <= 0:
            continue
        # the drive is linear between corners: read it inside and extrapolate to the ends
        ta, tb = t0 + 0.25 * (t1 - t0), t0 + 0.75 * (t1 - t0)
        ua, ub = _drive(waveform, ta), _drive(waveform, tb)
        slope = (ub - ua) / (tb - ta)
        seg = (t0, t1, ua - slope * (ta - t0), ub + slope * (t1 - tb))
        t = t0
        while t < t1:
            if time_limit_s is not None and time.monotonic() - started > time_limit_s:
                raise TimeoutError(f"reference solver: over {time_limit_s} s at t = {t:.6g} s")

            def ev_rev(tt, yy, *_):
                return yy[1] - yy[3]

            events = [_event(ev_rev, -d)]
            xcl = mem.closure() if model == "ls" else None
            if xcl is not None:

                def ev_close(tt, yy, dd, _seg, xcl=xcl):
                    return dd * ((yy[0] - yy[2]) - xcl)

                events.append(_event(ev_close, 1))
            sol = solve_ivp(
                rhs,
                (t, t1),
                y,
                method=method,
                rtol=rtol,
                atol=atol,
                events=events,
                args=(d, seg),
                dense_output=False,
                max_step=(t1 - t0),
            )
            if sol.status < 0:
                raise RuntimeError(f"reference solver failed at t={t}: {sol.message}")
            ts += list(sol.t[1:])
            xr += list(sol.y[0, 1:])
            xc += list(sol.y[2, 1:])
            ff += [friction(sol.y[:, i], d) for i in range(1, sol.y.shape[1])]
            y = sol.y[:, -1].copy()
            t = sol.t[-1]
            if sol.status == 1:  # an event ended the segment
                if sol.t_events[0].size:
                    # relative velocity reached zero: reverse if it is about to change sign
                    y[1] = y[3]  # the event's root: relative velocity exactly zero
                    acc = np.array(rhs(t, y, d, seg))
                    if np.sign(acc[1] - acc[3]) == -d:
                        if model == "ls":
                            fm, _ = mem.force(y[0] - y[2], d)
                            mem.rev.append((y[0] - y[2], fm))
                        d = -d
                        reversals += 1
                elif len(events) > 1 and sol.t_events[1].size:
                    if len(mem.rev) >= 2:
                        del mem.rev[-2:]
                    else:
                        mem.rev.clear()
    return ReferenceResult(
        np.array(ts), np.array(xr), np.array(xc), np.array(ff), waveform, reversals
    )
