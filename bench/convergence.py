"""Step-size convergence study of the C core (docs/model.md): settled per-cycle step of the
paper's run (500 Hz, 4.4 um, 100 us fall; cycles 3-10) against the integration step.

    .venv/bin/python bench/convergence.py
"""

from __future__ import annotations

import numpy as np

from stickslip.model import Sawtooth, simulate

DTS = [4e-6, 2e-6, 1e-6, 0.5e-6, 0.25e-6, 0.125e-6, 0.0625e-6]


def settled_step(model: str, dt: float, fall_s: float) -> float:
    w = Sawtooth(cycles=10).with_fall_time(fall_s)
    r = simulate(w, model=model, dt_s=dt, decimation=1)
    return float(np.mean(r.per_cycle_steps()[2:]))


def main() -> None:
    for fall in (100e-6, 20e-6):
        print(f"\nfall {fall * 1e6:.0f} us\n")
        print(
            "| dt (us) | LS step (um) | change on halving | LuGre step (um) | change on halving |"
        )
        print("|---|---|---|---|---|")
        prev = {}
        rows = []
        for dt in DTS:
            s = {m: settled_step(m, dt, fall) for m in ("ls", "lugre")}
            rows.append((dt, s))
        for i, (dt, s) in enumerate(rows):
            cells = [f"{dt * 1e6:g}"]
            for m in ("ls", "lugre"):
                nxt = rows[i + 1][1][m] if i + 1 < len(rows) else None
                ch = f"{abs(nxt / s[m] - 1) * 100:.3f} %" if nxt else ""
                cells += [f"{s[m] * 1e6:.5f}", ch]
            print("| " + " | ".join(cells) + " |")
            prev = s
        del prev


if __name__ == "__main__":
    main()
