"""The firmware node's real-time step (issue 17, docs/model.md "Real time on the target"): deadline
misses of its paced free run in QEMU against the step, for a part of a given clock.

QEMU's `-icount shift=3` runs the image at one instruction per 8 ns (125 MHz). A step of S at
the target's clock f is emulated by a model step of S f / 125 MHz: each slot then holds the
instructions the part has in S. The port's clock reads to 40 ns (5 instructions). Each line: the
drive, the law, the step at f, the instructions a slot, and the misses of the run (from the node's
RUN reply).

    .venv/bin/python bench/realtime_node.py                       (the tables of BENCHMARKS.md)
    .venv/bin/python bench/realtime_node.py --steps-us 9,9.5,10 --decimation 1,5,10
"""

from __future__ import annotations

import argparse

from stickslip.hil.client import NodeClient, QemuNode
from stickslip.hil.protocol import NODE_LAWS
from stickslip.hil.session import play
from stickslip.model import Sawtooth

QEMU_HZ = 125e6  # -icount shift=3
# (name, waveform): the paper's drive, and the 15 us fall at 100 Hz, 2 kHz and 300 Hz reversed
DRIVES = {
    "paper 500 Hz": Sawtooth(cycles=10),
    "100 Hz 15 us": Sawtooth(frequency_hz=100.0, cycles=10).with_fall_time(15e-6),
    "2 kHz 15 us": Sawtooth(frequency_hz=2000.0, cycles=40).with_fall_time(15e-6),
    "300 Hz rev 15 us": Sawtooth(frequency_hz=300.0, cycles=10, direction=-1).with_fall_time(15e-6),
}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--target", default="qemu-m4f")
    ap.add_argument("--clock-mhz", type=float, default=168.0, help="the part's clock")
    ap.add_argument("--steps-us", default="7.6,8.4,8.8,9.4,9.5,10", help="steps at that clock")
    ap.add_argument("--drives", nargs="+", choices=DRIVES, default=list(DRIVES))
    ap.add_argument("--decimation", default="100", help="rows every n steps (several: a sweep)")
    a = ap.parse_args()
    steps = [float(x) * 1e-6 for x in a.steps_us.split(",")]
    decs = [int(x) for x in a.decimation.split(",")]
    head = (
        f"| drive | law | step at {a.clock_mhz:g} MHz | instructions a slot | decimation | misses |"
    )
    print(head)
    print("|---|---|---|---|---|---|")
    with QemuNode(a.target, icount_shift=3) as q, NodeClient(q.url, timeout_s=60) as c:
        for name in a.drives:
            for law, index in NODE_LAWS.items():
                c.set("friction_model", index)
                for s in steps:
                    c.set("step_s", s * a.clock_mhz * 1e6 / QEMU_HZ)
                    for dec in decs:
                        r = play(c, DRIVES[name], "free", dec, 1)
                        slot = s * a.clock_mhz * 1e6
                        print(
                            f"| {name} | {law} | {s * 1e6:g} us | {slot:.0f} | {dec} | "
                            f"{r.telemetry.deadline_misses} of {r.steps} |",
                            flush=True,
                        )


if __name__ == "__main__":
    main()
