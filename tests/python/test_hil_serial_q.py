"""The fixed-point node (stickslip_node_q: app/ built with SS_NODE_MODEL_Q) over its
serial link: the same protocol as stickslip_node, and telemetry that is the host's q model
converted by the node's rule (docs/protocol.md), bit for bit."""

from dataclasses import replace

import numpy as np
import pytest

from stickslip.hil.client import HostNode, NodeClient, NodeError, Telemetry
from stickslip.hil.session import play
from stickslip.model import ActuatorParams, Sawtooth, simulate


@pytest.fixture(params=["pty", "tcp"])
def node(request):
    with HostNode(request.param, variant="q") as n:
        yield n


def assert_same(tel: Telemetry, want: Telemetry) -> None:
    assert np.array_equal(tel.step, want.step)
    for name in ("drive_v", "x_rod_m", "x_slider_m", "friction_n"):
        assert np.array_equal(getattr(tel, name), getattr(want, name)), name


def test_hello_says_fixed_point(node):
    with NodeClient(node.url) as c:
        assert c.info.variant == "q" and c.info.model == "ls"
        assert c.info.dt_s == np.float32(1099512 * 2.0**-40)  # Table I's dt_q40
        assert c.get("sigma0_n_per_m") == 1e7


def test_lockstep_is_the_q_model_bit_for_bit(node):
    w = Sawtooth(cycles=2)
    drive = simulate(w, variant="q").drive_v.astype(np.float32)  # Q16.16 values: exact in float32
    # lock-step feeds the node the player's samples, one a step: the drive linear between them.
    # The player's own run also takes a corner inside a step (the last peak lies 1.3e-3 of a
    # step off q's grid, whose step is 1.00000034 us), so the reference is the sampled run
    dt_q = 1099512 * 2.0**-40
    r = simulate(drive_v=drive, drive_interval_s=dt_q, variant="q")
    assert np.array_equal(drive.astype(np.float64), r.drive_v)
    with NodeClient(node.url) as c:
        c.reset(float(drive[0]))
        tel = c.lockstep(drive[1:])
        assert_same(tel, Telemetry.from_q_result(r))
        # the slider crosses the link exactly: hi + lo is the q position
        assert np.array_equal(tel.x_slider_m, r.x_slider_m[1:])
        assert c.stats.lost_frames == 0
        # play() sends the q player's drive to a fixed-point node
        run = play(c, w, "lockstep", decimation=10)
        assert_same(run.telemetry, Telemetry.from_q_result(r, slice(10, None, 10)))


def test_free_run_is_the_q_model(node):
    w = Sawtooth(cycles=2)
    r = simulate(w, variant="q")
    with NodeClient(node.url) as c:
        c.load_waveform(w)  # rise 0.95f converted on the node as on the host
        tel = c.run(4000, decimation=10)
        assert_same(tel, Telemetry.from_q_result(r, slice(10, None, 10)))


def test_set_param_through_the_converter(node):
    w = Sawtooth(cycles=1)
    r = simulate(w, params=replace(ActuatorParams.table1(), normal_force_n=12.5), variant="q")
    with NodeClient(node.url) as c:
        assert c.set("normal_force_n", 12.5) == 12.5
        with pytest.raises(NodeError) as e:
            c.set("rod_mass_kg", 1e-9)  # passes the float check, its kick does not fit Q40
        assert e.value.name == "out_of_range" and "rod_mass_kg" in e.value.reason
        c.load_waveform(w)
        tel = c.run(2000, decimation=100)
        assert_same(tel, Telemetry.from_q_result(r, slice(100, None, 100)))


def test_hil_run_command_starts_the_fixed_point_node(tmp_path, capsys):
    import json

    from stickslip import dataset as D
    from stickslip.cli import NODE_LINKS, main
    from stickslip.hil.client import QEMU_TARGETS

    # every QEMU target is offered by --node-link, and nothing else that starts with qemu-
    assert {n for n in NODE_LINKS if n.startswith("qemu-")} == set(QEMU_TARGETS)
    out = tmp_path / "ds"
    assert (
        main(["hil", "run", "--node-link", "tcp-q", "--cycles", "2", "--out", str(out), "--json"])
        == 0
    )
    s = json.loads(capsys.readouterr().out)
    assert s["node"]["variant"] == "q" and s["link"]["lost_frames"] == 0
    run = D.load(out).runs[0]
    r = simulate(run.waveform, variant="q")
    r = simulate(drive_v=r.drive_v, drive_interval_s=1099512 * 2.0**-40, variant="q")  # lock-step
    # row for row: the q node's step is Table I's dt_q40 (1.00000034 us), not 1 us
    assert len(run.x_m) == len(r.x_slider_m)
    assert np.max(np.abs(r.x_slider_m - run.x_m)) < 1e-12
