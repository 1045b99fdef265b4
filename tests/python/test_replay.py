"""hil replay (issue 16): a model file into a node, a dataset's drive through it (its sawtooth by
the node's own player), and the error as the diagnosis computes it."""

from __future__ import annotations

import json

import numpy as np
import pytest
from test_firmware_qemu import need_firmware

from stickslip import dataset as D
from stickslip import synth
from stickslip.cli import main
from stickslip.diagnosis.fit import Model, evaluate, prepare_all
from stickslip.hil.client import HostNode, NodeClient, QemuNode
from stickslip.hil.replay import replay
from stickslip.model import ActuatorParams, Effects
from stickslip.model_file import ModelFile, save

NOISE_M = 2e-9


@pytest.fixture(scope="module")
def stage(tmp_path_factory):
    """A short dataset of a stage with a load and a slew limit, and its true model as a file. The
    300 Hz run's peaks fall inside a 1 us step: one drive sample a step would cut them."""
    effects = Effects(load_n=0.03, slew_v_per_s=3e6)
    truth = synth.Truth(ActuatorParams.table1(), effects, ("external_load", "amplifier_slew_limit"))
    design = [synth.RunDesign(f"f500_{d}", 500.0, 100.0, d, 4) for d in (1, -1)]
    design.append(synth.RunDesign("f300_1", 300.0, 100.0, 1, 4))
    root = tmp_path_factory.mktemp("replay")
    ds = synth.generate(root / "ds", truth, seed=3, design=design)
    source = {"validation_runs": ["f500_-1"]}
    m = ModelFile(truth.params, "ls", effects, causes=truth.causes, source=source)
    return D.load(ds), m, save(m, root / "model.json")


def test_replay_on_the_host_node_gives_the_batch_evaluation(stage):
    ds, m, _ = stage
    runs = prepare_all(ds.runs)
    ev = evaluate(runs, Model(m.params, m.effects, m.law, m.causes), NOISE_M)
    with HostNode("tcp") as node, NodeClient(node.url) as c:
        r = replay(c, ds, m)
    # the node steps the same C model with the same drive as the batch simulation, from the same
    # start of the slider (RESET's x0_m)
    assert r["rmse_m"] == pytest.approx(ev.rmse_m, rel=1e-5)
    for run in r["runs"]:
        assert run["rmse_m"] == pytest.approx(ev.per_run[run["id"]]["rmse_m"], rel=1e-5)
    assert r["rmse_m"] < 1.5 * NOISE_M  # the true model: down to the sensor noise
    # the wrong model (no effects) is seen: the replay is a test of the model, not a formality
    with HostNode("tcp") as node, NodeClient(node.url) as c:
        wrong = replay(c, ds, ModelFile(m.params))
    assert wrong["rmse_m"] > 10 * r["rmse_m"]


def test_replay_starts_the_slider_where_the_fit_did(tmp_path):
    # position-dependent friction sees where the slider is: the second run starts where the first
    # ended (8 um on), and a gradient of 2e4 /m changes the friction there by 16 %. The node's
    # RESET places the slider at the run's start, as the fit's simulation does, so the replay
    # gives the batch evaluation's figure back
    fx = Effects(friction_gradient_per_m=2e4)
    truth = synth.Truth(ActuatorParams.table1(), fx, ("position_dependent_friction",))
    design = [synth.RunDesign(f"f500_{d}", 500.0, 100.0, d, 4) for d in (1, -1)]
    design.append(synth.RunDesign("f300_1", 300.0, 100.0, 1, 4))
    ds = D.load(synth.generate(tmp_path / "ds", truth, seed=4, design=design))
    m = ModelFile(truth.params, "ls", fx, causes=truth.causes)
    runs = prepare_all(ds.runs)
    assert abs(runs[1].x_m[0]) > 5e-6
    ev = evaluate(runs, Model(m.params, m.effects, m.law, m.causes), NOISE_M)
    with HostNode("tcp") as node, NodeClient(node.url) as c:
        r = replay(c, ds, m)
    for run in r["runs"]:
        assert run["rmse_m"] == pytest.approx(ev.per_run[run["id"]]["rmse_m"], rel=1e-5)
    assert r["rmse_m"] < 1.5 * NOISE_M


def test_replay_on_the_firmware_in_qemu_matches_the_host(stage):
    need_firmware("qemu-m4f")
    ds, m, _ = stage
    one = D.Dataset(ds.path, ds.description, ds.actuator, ds.runs[:1], ds.sensor, [])
    with HostNode("tcp") as node, NodeClient(node.url) as c:
        host = replay(c, one, m)
    with QemuNode("qemu-m4f") as q, NodeClient(q.url, timeout_s=30) as c:
        fw = replay(c, one, m)
    # the same float32 model, effects included, bit for bit: the float step takes no libm function
    # (its exponential, sine and cosine are the library's own, lib/src/ss_exp_f32.h and
    # ss_trig_f32.h), so newlib and glibc cannot round differently (with libm's expf the RMS was
    # 6e-5 off)
    for a, b in zip(fw["runs"], host["runs"]):
        assert a["id"] == b["id"] and a["rows"] == b["rows"]
        assert a["rmse_m"] == b["rmse_m"]


def test_replay_command_writes_its_figures(stage, tmp_path, capsys):
    ds, m, path = stage
    out, rep = tmp_path / "replay.json", tmp_path / "report"
    argv = ["hil", "replay", str(ds.path), "--model", str(path), "--json", str(out)]
    assert main([*argv, "--report", str(rep)]) == 0
    j = json.loads(out.read_text())
    # the report: every run's figure, and its error as the JSON has it
    md = (rep / "report.md").read_text()
    for r in j["runs"]:
        assert (rep / f"positions_{r['id']}.png").stat().st_size > 10_000
        assert f"| {r['id']} | {r['rmse_m'] * 1e9:.3f} nm | {r['rows']} |" in md
    assert [r["id"] for r in j["runs"]] == ["f500_1", "f500_-1", "f300_1"]
    assert all(set(r) == {"id", "rmse_m", "rows"} for r in j["runs"])
    assert j["validation_rmse_m"] == pytest.approx(j["runs"][1]["rmse_m"])
    assert "all runs" in capsys.readouterr().out
    assert np.isfinite(j["rmse_m"])


def test_replay_of_chosen_runs_and_a_run_that_is_not_there(stage, capsys):
    ds, m, path = stage
    assert main(["hil", "replay", str(ds.path), "--model", str(path), "--runs", "validation"]) == 0
    out = capsys.readouterr().out
    assert "f500_-1" in out and "f500_1 " not in out
    assert main(["hil", "replay", str(ds.path), "--model", str(path), "--runs", "f100"]) == 2
    assert "runs ['f100'] are not in" in capsys.readouterr().err


def test_replay_on_the_fixed_point_node_and_the_m0plus_image(tmp_path):
    # a model with the effects the q family runs (all but creep, heat and position): the q node
    # on the host and the ARMv6-M image in QEMU give the same figures bit for bit (integer
    # arithmetic); against the float node the replay error moves by at most the q family's
    # per-cycle error, 4 cycles x 1 % of a 0.8 um step (docs/fixed-point.md)
    need_firmware("qemu-m0plus-q")
    fx = Effects(
        load_n=0.1,
        slew_v_per_s=3e6,
        sensor_scale_error=0.02,
        friction_asymmetry=0.1,
        hysteresis_alpha=0.1,
        hysteresis_width_m=3e-7,
        base_mass_kg=0.02,
        base_freq_hz=4000.0,
        base_damping_ratio=0.05,
    )
    truth = synth.Truth(ActuatorParams.table1(), fx, ("external_load",))
    design = [synth.RunDesign(f"f500_{d}", 500.0, 100.0, d, 4) for d in (1, -1)]
    design.append(synth.RunDesign("f300_1", 300.0, 100.0, 1, 4))
    ds = D.load(synth.generate(tmp_path / "ds", truth, seed=3, design=design))
    m = ModelFile(truth.params, "ls", fx)
    with HostNode("tcp") as n, NodeClient(n.url) as c:
        f = replay(c, ds, m)
    with HostNode("tcp", "q") as n, NodeClient(n.url) as c:
        q = replay(c, ds, m)
    with QemuNode("qemu-m0plus-q") as n, NodeClient(n.url, timeout_s=30) as c:
        m0 = replay(c, ds, m)
    assert m0["runs"] == q["runs"] and q["node"]["variant"] == "q"
    for a, b in zip(q["runs"], f["runs"]):
        assert abs(a["rmse_m"] - b["rmse_m"]) < 4 * 0.01 * 0.8e-6
