"""Issue 17's accuracy criterion against the model's step (docs/model.md, "Per-cycle error over
the drive matrix"): the worst per-cycle step error of the C core against a converged run, over
the 15 us fall at 100 Hz to 2 kHz and the paper's drive (100 us fall at 500 Hz), both directions,
100 V, for LS and LuGre. The first cycle (from rest) is left out, and a last one that the run
does not reach the end of (SimResult.per_cycle_steps); the reference is the same core
at 0.125 us (it differs from 0.03125 us by at most 0.013 % per cycle on the worst case).
With --variant q the fixed-point core runs the steps, against the same float reference.

    PYTHONPATH=hil .venv/bin/python bench/step_study.py [--steps-us 0.5,1,1.25,2] [--variant q]
        [--models ls,lugre,gms] [--param piezo_damping_kg_per_s=62 ...]

--coarse N runs the steps with coarse steps of up to N where the contact sticks, 2 where it rings
(LuGre, LS; a row every N steps, docs/model.md "Coarse steps while the contact sticks") and prints
each drive's error and model steps per microsecond (issue 17's figures: LuGre 8 at 1 us, LS 8 at
1.5 us, LS's in split steps, docs/model.md "The split step"). --edge reads each cycle's step at
the last row before each fast edge (edge_cycle_steps) instead of at the period's boundary, where
rows 12 us apart interpolated across the slip put 0.2 % of the record's coarseness into LS's figure:

    PYTHONPATH=hil .venv/bin/python bench/step_study.py --models lugre --steps-us 1 --coarse 8
    PYTHONPATH=hil .venv/bin/python bench/step_study.py --models ls --steps-us 1.5 --coarse 8 --edge

--stick L adds LuGre's stick steps of L where the contact has stopped ringing (docs/model.md,
"Stick steps"), with rows every L steps; the per-cycle steps of the run and of its reference are
then read before each fast edge (edge_cycle_steps), and the table compares with the same run
without them (issue 17's figure: 40 at 1.5 us with coarse steps of 4, a run with stick steps
taking its fine steps on a fast edge in parts):

    PYTHONPATH=hil .venv/bin/python bench/step_study.py --models lugre --steps-us 1.5 --coarse 4 \
        --stick 40

--param sets an actuator parameter (ActuatorParams' names) for every run, reference included: an
experiment on what limits the step (docs/model.md), not the criterion, which is Table I's.
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

from stickslip.model import ActuatorParams, Sawtooth, simulate

REF_DT_S = 0.125e-6
CYCLES = {100.0: 4, 300.0: 6, 500.0: 8, 1000.0: 10, 2000.0: 12}  # about 40 ms of drive or more
# (frequency, fall) of each drive; the paper's is 5 % of its 2 ms period
DRIVES = [(f, 15e-6) for f in CYCLES] + [(500.0, 100e-6)]


def steps(*args, **kw) -> np.ndarray:
    """Each cycle's step after the first (from rest) of a run(): model, frequency, direction,
    fall, step[, variant, params, coarse]."""
    return run(*args, **kw)[0]


def simulated(
    model: str,
    f_hz: float,
    direction: int,
    fall_s: float,
    dt_s: float,
    variant: str = "f32",
    params: ActuatorParams | None = None,
    coarse: int = 1,
    stick: int = 0,
    rows: int = 0,
):
    """The run (a SimResult) and the model steps a microsecond it took; rows every `rows` steps
    (0: every stick or coarse step's length)."""
    w = Sawtooth(frequency_hz=f_hz, amplitude_v=100.0, direction=direction, cycles=CYCLES[f_hz])
    r = simulate(
        w.with_fall_time(fall_s),
        params=params,
        model=model,
        dt_s=dt_s,
        decimation=rows or stick or coarse,  # a coarse or stick step never crosses a row
        variant=variant,
        coarse_steps=coarse,
        stick_steps=stick,
    )
    n_steps = r.meta.get("model_steps", len(r.t_s) - 1)
    return r, n_steps / (w.duration_s * 1e6)


def run(*args, **kw) -> tuple[np.ndarray, float]:
    """The per-cycle steps after the first of a simulated() run, and its model steps a
    microsecond."""
    r, per_us = simulated(*args, **kw)
    return r.per_cycle_steps()[1:], per_us


def edge_cycle_steps(r, ref) -> tuple[np.ndarray, np.ndarray]:
    """The slider's travel in r and in ref between r's last rows before each fast edge: once the
    runs are periodic, a cycle's step, read where the slider has stuck longest. Rows a stick step
    apart (tens of us) interpolated across the slip at a period's boundary would put the record's
    coarseness into the figure (0.1-0.8 % at 40-128 us on the 1 and 2 kHz drives, the same with or
    without stick steps), and so would a point between rows; at r's own rows (the reference
    interpolated there, at its 0.125 us) it does not. The first value spans the first fall, from
    rest: left out, as the boundary figures' first."""
    w = r.waveform
    t = r.t_s - r.t_s[0]
    # the fast edge: at the end of a forward period, at the start of a reversed one
    edge = w.rise_fraction if w.direction > 0 else 1.0
    ends = (np.arange(w.cycles) + edge) * w.period_s
    rows = np.unique(np.searchsorted(t, ends[ends <= t[-1]], side="right") - 1)
    rows = rows[rows >= 0]
    t_ref = ref.t_s - ref.t_s[0]
    return np.diff(r.x_slider_m[rows])[1:], np.diff(np.interp(t[rows], t_ref, ref.x_slider_m))[1:]


def parse_params(items: list[str]) -> ActuatorParams:
    """Table I with NAME=VALUE overrides; a name ActuatorParams does not have is an error."""
    fields = {f.name for f in dataclasses.fields(ActuatorParams)}
    values: dict[str, float] = {}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or name not in fields:
            raise SystemExit(
                f"--param {item}: expected NAME=VALUE with NAME an ActuatorParams field"
            )
        try:
            values[name] = float(value)
        except ValueError:
            raise SystemExit(f"--param {item}: {value!r} is not a number") from None
    return dataclasses.replace(ActuatorParams(), **values)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps-us", default="0.5,1,1.25,2,2.5,5")
    ap.add_argument(
        "--variant", choices=("f32", "q"), default="f32", help="the core that runs the steps"
    )
    ap.add_argument("--models", default="ls,lugre", help="laws, comma-separated (ls, lugre, gms)")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--coarse", type=int, default=1, metavar="N", help="coarse steps of up to N")
    ap.add_argument(
        "--stick", type=int, default=0, metavar="L", help="stick steps of L (LuGre, with --coarse)"
    )
    ap.add_argument(
        "--edge", action="store_true", help="read each cycle's step before its fast edge (coarse)"
    )
    a = ap.parse_args()
    params = parse_params(a.param)
    models = a.models.split(",")
    dts = [float(x) * 1e-6 for x in a.steps_us.split(",")]
    worst: dict[tuple[str, float], tuple[float, str]] = {}
    rows = []
    for model in models:
        for f_hz, fall_s in DRIVES:
            for direction in (1, -1):
                drive = (model, f_hz, direction, fall_s)
                if a.stick or a.edge:
                    ref_run = simulated(*drive, REF_DT_S, params=params)[0]
                else:
                    ref = steps(*drive, REF_DT_S, params=params)
                case = f"{f_hz:g} Hz {'fwd' if direction > 0 else 'rev'} {fall_s * 1e6:g} us"
                for dt in dts:
                    if a.stick:
                        # the same rows without stick steps: what the figure itself gives there
                        r0, per_us0 = simulated(*drive, dt, a.variant, params, a.coarse, 0, a.stick)
                        s0, ref0 = edge_cycle_steps(r0, ref_run)
                        err0 = 100 * float(np.max(np.abs(s0 / ref0[: len(s0)] - 1)))
                        r, per_us = simulated(*drive, dt, a.variant, params, a.coarse, a.stick)
                        s, ref = edge_cycle_steps(r, ref_run)
                    elif a.edge:
                        r, per_us = simulated(*drive, dt, a.variant, params, a.coarse)
                        s, ref = edge_cycle_steps(r, ref_run)
                    else:
                        s, per_us = run(*drive, dt, a.variant, params, a.coarse)
                    n = len(s)  # a run that stops short of its drive's end has one cycle fewer
                    err = 100 * float(np.max(np.abs(s / ref[:n] - 1)))
                    if a.stick:
                        rows.append(
                            f"| {model} | {case} | {dt * 1e6:g} | {err0:.3f} % | {err:.3f} % | "
                            f"{per_us0:.3f} | {per_us:.3f} |"
                        )
                    else:
                        rows.append(
                            f"| {model} | {case} | {dt * 1e6:g} | {err:.3f} % | {per_us:.3f} |"
                        )
                    if err > worst.get((model, dt), (-1.0, ""))[0]:
                        worst[(model, dt)] = (err, case)
    if a.stick:
        print(
            f"| law | drive | step (us) | error before the fast edge, coarse steps of {a.coarse}, "
            f"rows every {a.stick} | ... and stick steps of {a.stick} | model steps per us | "
            "... with stick steps |"
        )
        print("|---|---|---|---|---|---|---|")
        print("\n".join(rows))
    elif a.coarse > 1:
        where = " before each fast edge" if a.edge else ""
        print(
            f"| law | drive | step (us) | per-cycle error{where}, coarse steps of {a.coarse} | "
            "model steps per us |"
        )
        print("|---|---|---|---|---|")
        print("\n".join(rows))
    names = {"ls": "LS", "lugre": "LuGre", "gms": "GMS"}
    print(
        "| step (us) | steps to the 15 us fall | "
        + " | ".join(f"{names.get(m, m)} worst per-cycle error | where" for m in models)
        + " |"
    )
    print("|---|---|" + "---|---|" * len(models))
    for dt in dts:
        n_fall = 15e-6 / dt
        whole = abs(n_fall - round(n_fall)) < 1e-9
        fall = f"{n_fall:g}" if whole else f"{n_fall:.2f} (a corner inside a step)"
        cells = [f"{dt * 1e6:g}", fall]
        for model in models:
            err, case = worst[(model, dt)]
            cells += [f"{err:.3f} %", case]
        print("| " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
