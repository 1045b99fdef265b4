"""The fixed-point firmware (fw/main_q_cortex_m.c) in QEMU: it plays the paper's drive
on the q core and sends the staircase over its emulated UART; compared here, integer for integer,
with the host's q core."""

from __future__ import annotations

import subprocess
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .. import _native as N
from ..model import DT_S, ActuatorParams, Sawtooth, simulate
from .client import firmware_elf

CYCLES = 6  # as main_q_cortex_m.c
EVERY = 100
WAVEFORM = replace(Sawtooth(), cycles=CYCLES)  # the paper's drive, CYCLES periods
STEPS_PER_CYCLE = round(WAVEFORM.period_s / DT_S)  # 2000: 500 Hz at Table I's 1 us
PRESETS = ("cortex-m0plus", "cortex-m3", "cortex-m4f")


def q_firmware_elf(preset: str) -> Path:
    """build/<preset>/fw/stickslip_q_fw.elf (see client.firmware_elf)."""
    return firmware_elf(preset, "stickslip_q_fw.elf")


@dataclass
class QFirmwareRun:
    header: dict[str, int]
    rows: np.ndarray  # (step, x_slider_q40) as int64
    end: list[str]

    @property
    def steps_m(self) -> np.ndarray:
        """Slider travel over each period (m)."""
        ends = self.rows[:: STEPS_PER_CYCLE // EVERY, 1]
        return np.diff(ends) * N.q_scale("x_slider_q40")


def run_q_firmware(elf: Path, timeout_s: float = 60.0) -> QFirmwareRun:
    """Boot the image on QEMU's mps2-an385 (the M0+ image runs there too: ARMv6-M is a subset)
    with its UART on stdio, and parse what it sends."""
    board = "mps2-an386" if "cortex-m4f" in str(elf) else "mps2-an385"
    cmd = ["qemu-system-arm", "-M", board, "-nographic", "-monitor", "none"]
    cmd += ["-semihosting-config", "enable=on,target=native", "-serial", "stdio", "-kernel"]
    proc = subprocess.run(
        [*cmd, str(elf)],
        stdin=subprocess.DEVNULL,
        capture_output=True,
        text=True,
        timeout=timeout_s,
    )
    if proc.returncode != 0:
        raise RuntimeError(
            f"{elf.name} exited {proc.returncode}: {proc.stdout[-300:]}{proc.stderr}"
        )
    lines = proc.stdout.splitlines()
    if len(lines) < 3 or not lines[0].startswith("# stickslip q staircase:"):
        raise RuntimeError(f"{elf.name}: unexpected UART output {proc.stdout[:200]!r}")
    header = {k: int(v) for k, v in (f.split("=") for f in lines[0].split(":", 1)[1].split())}
    rows = np.array([[int(c) for c in ln.split(",")] for ln in lines[2:-1]], dtype=np.int64)
    return QFirmwareRun(header, rows, lines[-1].split())


def host_reference() -> tuple[dict[str, int], np.ndarray]:
    """What the firmware must send: the host converter's configs and the host q core's rows."""
    cq, wq = N.to_q(ActuatorParams.table1().actuator_config("ls", DT_S), WAVEFORM.config())
    header = {"dt_q40": cq.dt_q40, "steps": CYCLES * STEPS_PER_CYCLE, "every": EVERY}
    for name in ("frequency_mhz", "amplitude_q16", "offset_q16", "rise_q32", "direction", "cycles"):
        header[name] = getattr(wq, name)
    r = simulate(WAVEFORM, variant="q", decimation=EVERY)
    # x_slider_m is x_slider_q40 * 2^-40 in float64, exact below 2^53 LSB: rounding recovers them
    steps = np.round(r.t_s / r.dt_s).astype(np.int64)
    x = np.round(r.x_slider_m / N.q_scale("x_slider_q40")).astype(np.int64)
    return header, np.column_stack([steps, x])
