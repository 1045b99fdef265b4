"""The firmware (the node application on the Cortex-M port) in QEMU's MPS2 boards, driven over
its emulated UART: the same trajectory as the host's batch simulator (float32 node), and the
same bytes as the host's stickslip_node_q (fixed-point node)."""

import os
import shutil

import numpy as np
import pytest

from stickslip.hil.client import (
    QEMU_TARGETS,
    HostNode,
    NodeClient,
    QemuNode,
    Telemetry,
    firmware_elf,
)
from stickslip.hil.session import play
from stickslip.model import Sawtooth, simulate


def f32(x):
    return np.asarray(x, dtype=np.float32)


def need_firmware(target: str) -> None:
    """Skip when QEMU or the image is missing, except under CI (which installs QEMU and builds the
    firmware with scripts/setup.sh --dev): there the test must run."""
    must_run = bool(os.environ.get("CI"))
    if shutil.which("qemu-system-arm") is None and not must_run:
        pytest.skip("qemu-system-arm is not installed (bash scripts/setup.sh --dev)")
    _, preset, image = QEMU_TARGETS[target]
    try:
        firmware_elf(preset, image)
    except FileNotFoundError as e:
        if must_run:
            raise
        pytest.skip(str(e))


@pytest.mark.parametrize("target", ["qemu-m4f", "qemu-m3"])
def test_firmware_lockstep_matches_host(target):
    need_firmware(target)
    w = Sawtooth(cycles=2)
    r = simulate(w)
    with QemuNode(target) as q, NodeClient(q.url, timeout_s=20) as c:
        assert c.info.version and c.info.dt_s == pytest.approx(1e-6)
        run = play(c, w, "lockstep")
        tel = run.telemetry
        # float32 on the target (hardware FPU on the M4F, soft float on the M3) against glibc's
        # float32 on the host: the same operations in the same order. Bit for bit here; the
        # stated tolerance for float targets is 1e-12 m on the slider (half an ulp at 10 um)
        assert np.array_equal(f32(tel.x_rod_m), f32(r.x_rod_m[1:]))
        assert np.max(np.abs(tel.x_slider_m - r.x_slider_m[1:])) < 1e-12
        assert run.mean_step_m() == pytest.approx(r.mean_step_m, rel=1e-6)
        assert c.get("sigma0_n_per_m") == pytest.approx(1e7)


def test_firmware_paced_run_counts_deadline_misses():
    # The M4F image at 125 MHz (QEMU -icount shift=3: one instruction per 8 ns of its clock) runs
    # the float32 LS node's step in about 600 instructions with the waveform, the clock and the
    # link: 4.8 us, so a real-time run of 1 us steps misses every deadline, and one slowed 8 times
    # (1000 instructions a slot) none. The counts come from the node (RUN reply, telemetry).
    need_firmware("qemu-m4f")
    w = Sawtooth(cycles=1)  # 2000 steps of the paper's drive
    with QemuNode("qemu-m4f", icount_shift=3) as q, NodeClient(q.url, timeout_s=20) as c:
        real_time = play(c, w, "free", 100, 1)
        assert real_time.steps == 2000
        assert real_time.telemetry.deadline_misses == 2000
        slowed = play(c, w, "free", 100, 8)
        assert slowed.telemetry.deadline_misses == 0
        # an unpaced run has no deadlines
        assert play(c, w, "free", 100, 0).telemetry.deadline_misses == 0
        # the trajectory does not depend on the pacing
        assert np.array_equal(real_time.telemetry.x_slider_m, slowed.telemetry.x_slider_m)


def rows_of(c: NodeClient, drive: np.ndarray) -> list[tuple]:
    """The raw rows (float32 fields as sent) of a lock-step run from rest."""
    c.reset(float(drive[0]))
    rows: list[tuple] = []
    for i in range(1, len(drive), 40):
        rows += c.drive_block(drive[i : i + 40])
    return rows


@pytest.mark.parametrize("target", ["qemu-m3-q", "qemu-m4f-q", "qemu-m0plus-q"])
def test_q_firmware_lockstep_is_bit_exact_with_host_q_node(target):
    need_firmware(target)
    w = Sawtooth(cycles=2)
    r = simulate(w, variant="q")
    drive = r.drive_v.astype(np.float32)  # the q player's Q16.16 samples, exact in float32
    with HostNode("pty", variant="q") as h, NodeClient(h.url) as hc:
        host = rows_of(hc, drive)
        hc.set("normal_force_n", 12.5)  # a parameter set the converter makes on each side
        host_n = rows_of(hc, drive[:801])
        host_info = hc.info
    with QemuNode(target) as q, NodeClient(q.url, timeout_s=20) as c:
        assert c.info == host_info and c.info.variant == "q"
        fw = rows_of(c, drive)
        c.set("normal_force_n", 12.5)
        fw_n = rows_of(c, drive[:801])
    # row for row, every float32 field identical to the host q node's
    assert fw == host and fw_n == host_n
    want = Telemetry.from_q_result(r)
    tel = Telemetry.from_rows(fw)
    assert np.array_equal(tel.x_slider_m, want.x_slider_m)
    assert np.array_equal(tel.friction_n, want.friction_n)
