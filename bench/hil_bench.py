"""HIL link benchmarks (figures in BENCHMARKS.md): lock-step steps per second and round-trip
latency over serial (pty, TCP) and CAN (SLCAN over TCP), telemetry throughput of a free run as a
share of what the link could carry, and closed-loop positioning.

    .venv/bin/python bench/hil_bench.py
"""

from __future__ import annotations

import statistics
import time

from stickslip.hil import protocol as P
from stickslip.hil.can_client import CanNodeClient
from stickslip.hil.client import HostNode, NodeClient
from stickslip.hil.positioning import position
from stickslip.model import Sawtooth, simulate

UART_BPS = 1_000_000  # a 1 Mbaud UART: 10 bits per byte
CAN_BPS = 1_000_000
CAN_FRAME_BITS = 135  # 8-byte standard frame, worst-case stuffing, with interframe space


def median_rtt(fn, n: int = 200) -> float:
    t = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        t.append(time.perf_counter() - t0)
    return statistics.median(t)


def serial(link: str) -> None:
    w = Sawtooth(cycles=5)
    drive = simulate(w).drive_v
    with HostNode(link) as n, NodeClient(n.url) as c:
        rtt = median_rtt(lambda: c.get("mu_s"))
        c.reset(float(drive[0]))
        t0 = time.perf_counter()
        c.lockstep(drive[1:], block=40)
        lock = (len(drive) - 1) / (time.perf_counter() - t0)
        c.load_waveform(Sawtooth(cycles=50))
        t0 = time.perf_counter()
        tel = c.run(100_000, decimation=1)
        wall = time.perf_counter() - t0
        rows_s = len(tel.step) / wall
        frames = len(tel.step) / P.MAX_ROWS
        wire_bytes = frames * (
            P.MAX_ROWS * P.ROW.size + 7 + 6 + 6
        )  # payload, header/CRC, COBS + delimiter
        bps = wire_bytes * 10 / wall
        print(
            f"serial {link}: round trip {rtt * 1e6:.0f} us (median of 200 GET_PARAM); lock-step "
            f"{lock:.0f} steps/s (blocks of 40); free-run telemetry {rows_s:.0f} rows/s = "
            f"{bps / 1e6:.2f} Mbit/s on the wire, {bps / UART_BPS:.1f} x a 1 Mbaud UART"
        )


def can_slcan() -> None:
    w = Sawtooth(cycles=1)
    drive = simulate(w).drive_v
    with HostNode("can-tcp") as n, CanNodeClient(n.url) as c:
        rtt = median_rtt(lambda: c.get("mu_s"), 100)
        c.reset(float(drive[0]))
        t0 = time.perf_counter()
        c.lockstep(drive[1:2001], decimation=1)
        lock = 2000 / (time.perf_counter() - t0)
        c.load_waveform(Sawtooth(cycles=10))
        t0 = time.perf_counter()
        tel = c.run(4000, decimation=1)
        wall = time.perf_counter() - t0
        fps = 3 * len(tel.step) / wall
        bus = CAN_BPS / CAN_FRAME_BITS
        print(
            f"CAN (SLCAN over TCP, python-can): round trip {rtt * 1e6:.0f} us "
            "(median of 100 GET_PARAM); "
            f"lock-step {lock:.0f} steps/s (1 drive + 3 state frames a step); free-run telemetry "
            f"{fps:.0f} frames/s = {fps / bus:.2f} of a 1 Mbit/s bus ({bus:.0f} frames/s)"
        )


def positioning() -> None:
    with HostNode("tcp") as n, NodeClient(n.url) as c:
        for target in (30e-6, -12.3e-6, 2e-6, 100e-6):
            t0 = time.perf_counter()
            r = position(c, target, tolerance_m=5e-9, max_time_s=0.2)
            wall = time.perf_counter() - t0
            st = "not settled" if r.settle_time_s is None else f"{r.settle_time_s * 1e3:.1f} ms"
            print(
                f"position {target * 1e6:+.1f} um: {r.coarse_periods} coarse periods, "
                f"settled within 5 nm after {st} of model time, "
                f"final error {r.final_error_m * 1e9:+.2f} nm, wall {wall:.2f} s"
            )


def main() -> None:
    serial("pty")
    serial("tcp")
    can_slcan()
    positioning()


if __name__ == "__main__":
    main()
