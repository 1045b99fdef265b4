"""Issue 17, "a longer step": would LuGre hold 0.1 % at 2-3 us if the contact's linear part rode
in the exact flow of the step? A float64 prototype in Python (not the C core), measured per cycle
against the C core at 0.125 us over step_study's drive matrix (docs/model.md, "What limits LuGre
past 1 us").

Each step of h (split at the drive's corners) linearises the LuGre force at the step's start,
F ~ F0 + Kf (x_rel - x_rel0) + Cf (v_rel - v_rel0) with Kf = dF/dx and Cf = dF/dv (the slopes the
C step uses for its implicit kick), and integrates exactly:
  --flow rod   the rod (piezo spring-damper plus Kf, Cf) under the linear anchor, the slider moving
               at its half-kicked velocity; the slider gets the exact impulse of the linear force;
  --flow both  rod and slider together (a 6 x 6 matrix exponential a step: slow, for the study);
then advances the bristle z by LuGre's relaxation over the step's relative displacement, and
kicks both bodies by half a step of the remainder F(end state) - F_linear(end) (without it the
scheme is first order: 0.15 % at 0.25 us).

    PYTHONPATH=hil:bench .venv/bin/python bench/lugre_flow_study.py --steps-us 1,2,3 [--flow both]
"""

from __future__ import annotations

import argparse
import math

import numpy as np
import scipy.linalg
import step_study as SS

from stickslip.independent.plant import sawtooth_segments
from stickslip.model import ActuatorParams, Sawtooth

P = ActuatorParams.table1()
FS, FC = P.fs_n, P.fc_n
S0, S1, S2 = P.sigma0_n_per_m, P.sigma1_ns_per_m, P.sigma2_ns_per_m
VS = P.stribeck_velocity_m_per_s
K, C = P.piezo_stiffness_n_per_m, P.piezo_damping_kg_per_s
MR, MS, GAIN = P.rod_mass_kg, P.slider_mass_kg, P.piezo_gain_m_per_v


def level(v: float) -> tuple[float, float]:
    """Stribeck level g(v) and its slope."""
    if v == 0.0:
        return FS, 0.0
    r = v / VS
    e = math.exp(-r * r)
    return FC + (FS - FC) * e, -2.0 * (FS - FC) * r / VS * e


def force(z: float, v: float) -> tuple[float, float, float]:
    """LuGre's force at (z, v) and its slopes dF/dv, dF/dx (as ss_lugre_force_end_f32)."""
    g, slope = level(v)
    k = S0 * z / g
    sg = (v > 0) - (v < 0)
    dzdv = 1.0 - sg * k + abs(v) * k * slope / g
    return S0 * z + S1 * (v - abs(v) * k) + S2 * v, S1 * dzdv + S2, S0 * max(0.0, 1.0 - sg * k)


def relax(z: float, dx: float, h: float) -> float:
    """LuGre's bristle over the relative displacement dx in h (velocity frozen, exact)."""
    if dx == 0.0:
        return z
    g, _ = level(dx / h)
    z_ss = math.copysign(g / S0, dx)
    return z_ss + (z - z_ss) * math.exp(-S0 * abs(dx) / g)


def free_flow(kt: float, ct: float, h: float) -> tuple[float, float, float, float]:
    """Flow of MR e'' + ct e' + kt e = 0 over h on (e, e')."""
    wn2, sig = kt / MR, 0.5 * ct / MR
    wd2 = wn2 - sig * sig
    if wd2 > 0:
        wd = math.sqrt(wd2)
        co, si = math.cos(wd * h), math.sin(wd * h) / wd
    elif wd2 < 0:
        w = math.sqrt(-wd2)
        co, si = math.cosh(w * h), math.sinh(w * h) / w
    else:
        co, si = 1.0, h
    e = math.exp(-sig * h)
    return e * (co + sig * si), e * si, -e * wn2 * si, e * (co - sig * si)


def step_rod(s: list[float], h: float, a0: float, b: float) -> list[float]:
    xr, vr, xs, vs, z = s
    f0, cf, kf = force(z, vr - vs)
    vs_d = vs + f0 / MS * 0.5 * h  # the slider's velocity over the drift
    dv0 = vr - vs  # the linear force's reference relative velocity
    kt, ct = K + kf, C + cf
    # MR x'' + ct x' + kt x = p + q t: the anchor a0 + b t, the slider at xs + vs_d t
    p = K * a0 - f0 + kf * xr + cf * (vs_d + dv0)
    q = K * b + kf * vs_d
    bb = q / kt
    aa = (p - ct * bb) / kt
    e0, ed0 = xr - aa, vr - bb
    f00, f01, f10, f11 = free_flow(kt, ct, h)
    e1, ed1 = f00 * e0 + f01 * ed0, f10 * e0 + f11 * ed0
    xr1, vr1 = aa + bb * h + e1, bb + ed1
    int_x = aa * h + 0.5 * bb * h * h - (MR * (ed1 - ed0) + ct * (e1 - e0)) / kt
    impulse = (
        f0 * h + kf * (int_x - xr * h - 0.5 * vs_d * h * h) + cf * (xr1 - xr - (vs_d + dv0) * h)
    )
    vs1 = vs + impulse / MS
    xs1 = xs + 0.5 * (vs + vs1) * h
    lin1 = f0 + kf * (xr1 - xr - vs_d * h) + cf * (vr1 - vs_d - dv0)
    return remainder_kick([xr1, vr1, xs1, vs1, relax(z, (xr1 - xr) - (xs1 - xs), h)], lin1, h)


def step_both(s: list[float], h: float, a0: float, b: float) -> list[float]:
    xr, vr, xs, vs, z = s
    f0, cf, kf = force(z, vr - vs)
    c0 = f0 - kf * (xr - xs) - cf * (vr - vs)  # F = c0 + kf x_rel + cf v_rel
    m = np.zeros((6, 6))  # state (xr, vr, xs, vs, 1, t)
    m[0, 1] = m[2, 3] = m[5, 4] = 1.0
    m[1, :6] = [(-K - kf) / MR, (-C - cf) / MR, kf / MR, cf / MR, (K * a0 - c0) / MR, K * b / MR]
    m[3, :5] = [kf / MS, cf / MS, -kf / MS, -cf / MS, c0 / MS]
    xr1, vr1, xs1, vs1 = (float(q) for q in (scipy.linalg.expm(m * h) @ [xr, vr, xs, vs, 1, 0])[:4])
    lin1 = c0 + kf * (xr1 - xs1) + cf * (vr1 - vs1)
    return remainder_kick([xr1, vr1, xs1, vs1, relax(z, (xr1 - xr) - (xs1 - xs), h)], lin1, h)


def remainder_kick(s: list[float], lin1: float, h: float) -> list[float]:
    """Half a step of the force the linearisation missed at the step's end, on both bodies."""
    xr, vr, xs, vs, z = s
    r = force(z, vr - vs)[0] - lin1
    return [xr, vr - r * 0.5 * h / MR, xs, vs + r * 0.5 * h / MS, z]


def run(w: Sawtooth, h: float, step) -> tuple[np.ndarray, np.ndarray]:
    """The slider's position after each step of h, the drive's straight pieces from the
    independent generator's reading of the sawtooth (each step split at its corners), held at
    the offset for a step past the last period (a step count's rounding)."""
    t0s, t1s, v0s, v1s = sawtooth_segments(
        w.frequency_hz, w.amplitude_v, w.offset_v, w.rise_fraction, w.direction, w.cycles, h
    )
    rates = ((v1s - v0s) / (t1s - t0s)).tolist()  # Python floats: the steps are scalar code
    t0l, v0l = t0s.tolist(), v0s.tolist()
    s = [GAIN * v0l[0], 0.0, 0.0, 0.0, 0.0]
    n = int(round(w.duration_s / h))
    xs = np.zeros(n + 1)
    for i in range(n):
        t0, t1 = i * h, (i + 1) * h
        inside = t1s[(t1s > t0 + 1e-15) & (t1s < t1 - 1e-15)]
        cuts = [t0, *inside.tolist(), t1]
        for u0, u1 in zip(cuts[:-1], cuts[1:]):
            k = int(np.searchsorted(t1s, 0.5 * (u0 + u1), side="right"))
            volts = v0l[k] + rates[k] * (u0 - t0l[k])
            s = step(s, u1 - u0, GAIN * volts, GAIN * rates[k])
        xs[i + 1] = s[2]
    return np.arange(n + 1) * h, xs


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps-us", default="1,2,3")
    ap.add_argument("--flow", choices=("rod", "both"), default="rod")
    a = ap.parse_args()
    step = step_rod if a.flow == "rod" else step_both
    hs = [float(x) * 1e-6 for x in a.steps_us.split(",")]
    for f_hz, fall in SS.DRIVES:
        for d in (1, -1):
            w = Sawtooth(
                frequency_hz=f_hz, amplitude_v=100.0, direction=d, cycles=SS.CYCLES[f_hz]
            ).with_fall_time(fall)
            ref = SS.steps("lugre", f_hz, d, fall, SS.REF_DT_S)
            errs = []
            for h in hs:
                t, xs = run(w, h, step)
                k = np.arange(w.cycles + 1) * w.period_s
                pc = np.diff(np.interp(k[k <= t[-1] + 1e-12], t, xs))[1:]
                m = min(len(pc), len(ref))
                errs.append(100 * float(np.max(np.abs(pc[:m] - ref[:m]) / np.abs(ref[:m]))))
            cells = "  ".join(f"{h * 1e6:g} us {e:.3f} %" for h, e in zip(hs, errs))
            print(
                f"{f_hz:6.0f} Hz {'fwd' if d > 0 else 'rev'} {fall * 1e6:4.0f} us  {cells}",
                flush=True,
            )


if __name__ == "__main__":
    main()
