"""stick-slip-model/1 (docs/model-file.md): round trip, a named error for every bad field, and
C headers that compile to exactly the configs the library builds."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest

from stickslip import model_file as MF
from stickslip.cli import main
from stickslip.model import ActuatorParams, Effects

ROOT = Path(__file__).resolve().parents[2]
LIB = ROOT / "build" / "host" / "lib" / "libstickslip.a"


def test_round_trip(tmp_path):
    m = MF.ModelFile(
        ActuatorParams.table1(),
        "lugre",
        Effects(load_n=0.05, slew_v_per_s=1e6),
        2e-6,
        ("external_load", "amplifier_slew_limit"),
        {"dataset": "x"},
    )
    assert MF.load(MF.save(m, tmp_path / "m.json")) == m


def test_a_gms_model_keeps_its_presliding_shape(tmp_path):
    m = MF.ModelFile(ActuatorParams.table1(), "gms", gms_decay=3.5, gms_stiffness_ratio=0.5)
    assert m.to_dict()["gms_decay"] == 3.5 and m.to_dict()["gms_stiffness_ratio"] == 0.5
    back = MF.load(MF.save(m, tmp_path / "m.json"))
    assert back == m and back.config().friction.gms_decay == 3.5
    assert back.config().friction.gms_stiffness_ratio == 0.5
    # other laws have no such shape: not written, the default when read
    assert "gms_decay" not in MF.ModelFile(ActuatorParams.table1()).to_dict()
    assert "gms_stiffness_ratio" not in MF.ModelFile(ActuatorParams.table1()).to_dict()


def _good() -> dict:
    return MF.ModelFile(ActuatorParams.table1()).to_dict()


BAD = [
    (lambda d: d.update(format="stick-slip-model/2"), "format: must be 'stick-slip-model/1'"),
    (lambda d: d.update(colour="red"), "unknown keys ['colour']"),
    (lambda d: d.update(law="dahl"), "law: must be one of ls, lugre, gms, got 'dahl'"),
    (lambda d: d.update(dt_s=1.0), "dt_s: must be in [1e-9, 1e-3] s, got 1.0"),
    (lambda d: d.update(dt_s="1us"), "dt_s: expected a finite number, got '1us'"),
    (lambda d: d.pop("actuator"), "actuator: must be an object"),
    (lambda d: d["actuator"].pop("mu_s"), "missing keys ['mu_s']"),
    (lambda d: d["actuator"].update(mu_s=float("nan")), "mu_s"),
    (lambda d: d.update(effects={"load": 1.0}), "effects: unknown keys ['load']"),
    (lambda d: d.update(effects={"load_n": "heavy"}), "effects.load_n: expected a finite number"),
    (lambda d: d.update(effects={"load_n": True}), "effects.load_n: expected a finite number"),
    (lambda d: d.update(effects={"slew_v_per_s": 1.0}), "the C library refuses the model"),
    (lambda d: d["actuator"].update(mu_d=0.5), "mu_d * normal_force_n (Fc, must not exceed Fs)"),
    (lambda d: d.update(causes="load"), "causes: must be a list of cause names"),
    (lambda d: d.update(source=[]), "source: must be an object"),
    (lambda d: d.update(gms_decay="steep"), "gms_decay: expected a finite number"),
    (lambda d: d.update(law="gms", gms_decay=50.0), "parameter gms_decay: parameter out of range"),
    (
        lambda d: d.update(law="gms", gms_stiffness_ratio=0.0),
        "parameter gms_stiffness_ratio: parameter out of range",
    ),
]


@pytest.mark.parametrize(("change", "words"), BAD, ids=[w for _, w in BAD])
def test_a_bad_field_is_named(tmp_path, change, words):
    d = _good()
    change(d)
    p = tmp_path / "model.json"
    p.write_text(json.dumps(d))
    with pytest.raises(MF.ModelFileError) as e:
        MF.load(p)
    assert words in str(e.value) and str(p) in str(e.value)


def test_unreadable_files_are_named(tmp_path):
    with pytest.raises(MF.ModelFileError, match="cannot read"):
        MF.load(tmp_path / "none.json")
    (tmp_path / "bad.json").write_text("{")
    with pytest.raises(MF.ModelFileError, match="invalid JSON"):
        MF.load(tmp_path / "bad.json")
    (tmp_path / "list.json").write_text("[]")
    with pytest.raises(MF.ModelFileError, match="top level must be an object"):
        MF.load(tmp_path / "list.json")


CHECK_C = r"""
#include <stdio.h>
#include "stickslip_model.h"
int main(void)
{
    const ss_actuator_config_f32_t f = SS_MODEL_CONFIG_F32;
    const unsigned char *p = (const unsigned char *)&f;
    for (size_t i = 0; i < sizeof f; ++i) printf("%02x", p[i]);
    printf("\n");
#ifdef SS_MODEL_CONFIG_Q
    const ss_actuator_config_q_t q = SS_MODEL_CONFIG_Q;
    const unsigned char *r = (const unsigned char *)&q;
    for (size_t i = 0; i < sizeof q; ++i) printf("%02x", r[i]);
#endif
    printf("\n");
    return 0;
}
"""


def _compiled(tmp_path: Path, m: MF.ModelFile) -> tuple[bytes, bytes]:
    """The f32 and q configs (bytes) that C code gets from the exported header."""
    MF.export(m, tmp_path)
    (tmp_path / "check.c").write_text(CHECK_C)
    exe = tmp_path / "check"
    inc = ["-I", str(tmp_path), "-I", str(ROOT / "lib" / "include")]
    cmd = ["cc", "-std=c99", "-Wall", "-Werror", *inc, str(tmp_path / "check.c"), str(LIB), "-lm"]
    subprocess.run([*cmd, "-o", str(exe)], check=True)
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.split("\n")
    return bytes.fromhex(out[0]), bytes.fromhex(out[1])


@pytest.mark.skipif(not LIB.exists() or not shutil.which("cc"), reason="host build or cc missing")
@pytest.mark.parametrize(
    "m",
    [
        MF.ModelFile(ActuatorParams.table1()),  # Table I: the library's own q constants
        MF.ModelFile(ActuatorParams.table1(), "lugre", dt_s=0.5e-6),
        MF.ModelFile(
            ActuatorParams.table1(),
            "ls",
            Effects(
                load_n=-0.1,
                slew_v_per_s=2e6,
                sensor_scale_error=0.02,
                friction_asymmetry=0.2,
                hysteresis_alpha=0.1,
                hysteresis_width_m=3e-7,
                base_mass_kg=0.02,
                base_freq_hz=4000.0,
                base_damping_ratio=0.05,
            ),
        ),
        MF.ModelFile(
            ActuatorParams.table1(),
            "gms",
            Effects(
                hysteresis_alpha=0.1,
                hysteresis_width_m=2e-7,
                load_n=-0.02,
                base_mass_kg=0.02,
                base_freq_hz=4000.0,
                base_damping_ratio=0.05,
            ),
            gms_decay=2.5,
        ),  # fmt: skip
    ],
    ids=["table1", "lugre_half_us", "ls_with_q_effects", "gms_with_effects"],
)
def test_the_c_header_compiles_to_the_librarys_config(tmp_path, m):
    f32, q = _compiled(tmp_path, m)
    assert f32 == bytes(m.config())  # every field bit for bit, effects included
    cq = m.config_q()
    assert q == (b"" if cq is None else bytes(cq))
    # the q family models the load, slew, sensor scale, asymmetry, hysteresis, base; not GMS
    assert (cq is None) == (m.law == "gms")
    if cq is not None:
        assert (cq.effects.load_q24, cq.effects.sensor_scale_q30) == (
            round(m.effects.load_n * 2**24),
            round(m.effects.sensor_scale_error * 2**30),
        )


def test_model_export_and_check_commands(tmp_path, capsys):
    out = tmp_path / "m"
    assert main(["model", "export", "--out", str(out), "--law", "lugre", "--set", "load_n=0.05",
                 "--set", "normal_force_n=12"]) == 0  # fmt: skip
    m = MF.load(out / "model.json")
    assert (m.law, m.effects.load_n, m.params.normal_force_n) == ("lugre", 0.05, 12.0)
    assert main(["model", "check", str(out / "model.json")]) == 0
    assert "a valid lugre model" in capsys.readouterr().out
    # refused by name, nothing written
    for args, words in [
        (["--set", "mu_d=0.5"], "must not exceed Fs"),
        (["--set", "load_n"], "--set: expected NAME=VALUE"),
        (["--set", "load_n=heavy"], "--set load_n: expected a number, got 'heavy'"),
        (["--set", "bogus=1"], "unknown keys ['bogus']"),
    ]:
        assert main(["model", "export", "--out", str(tmp_path / "never"), *args]) == 2
        assert words in capsys.readouterr().err
        assert not (tmp_path / "never").exists()


def test_hil_node_refuses_a_model_it_cannot_serve_before_it_starts(tmp_path, capsys):
    gms = MF.save(MF.ModelFile(ActuatorParams.table1(), "gms"), tmp_path / "gms.json")
    assert main(["hil", "node", "--link", "tcp", "--model", str(gms)]) == 2
    assert "the node runs ls or lugre friction, the model gms" in capsys.readouterr().err
    (tmp_path / "bad.json").write_text("{}")
    assert main(["hil", "node", "--link", "tcp", "--model", str(tmp_path / "bad.json")]) == 2
    assert "format: must be 'stick-slip-model/1'" in capsys.readouterr().err


NODE_C = r"""
#include <stdio.h>
#include "ss_node_core.h"
int main(void)
{
    static ss_node_core_t core;
    ss_node_core_init(&core);
    for (unsigned i = 0; i < SS_NODE_N_PARAMS; ++i) printf("%.9g\n", (double)core.params.value[i]);
    const unsigned char *p = (const unsigned char *)&core.cfg;
    for (size_t i = 0; i < sizeof core.cfg; ++i) printf("%02x", p[i]);
    printf("\n");
    return 0;
}
"""


def _node_with_header(tmp_path: Path, m: MF.ModelFile, variant: str) -> subprocess.CompletedProcess:
    """The node core compiled with the model's header (-DSS_MODEL_HEADER), as the firmware is."""
    MF.export(m, tmp_path)
    (tmp_path / "node.c").write_text(NODE_C)
    srcs = [ROOT / "app" / "ss_node_core.c", ROOT / "app" / f"ss_node_model_{variant}.c"]
    srcs += sorted((ROOT / "lib" / "src").glob("*.c")) + sorted(
        (ROOT / "proto" / "src").glob("*.c")
    )
    inc = [f"-I{ROOT / d}" for d in ("app", "lib/include", "proto/include")]
    defs = [f'-DSS_MODEL_HEADER="{tmp_path / "stickslip_model.h"}"']
    defs += ["-DSS_NODE_MODEL_Q"] if variant == "q" else []
    exe = tmp_path / "node"
    cmd = ["cc", "-std=c99", "-D_DEFAULT_SOURCE", *inc, *defs, str(tmp_path / "node.c")]
    return subprocess.run(
        [*cmd, *map(str, srcs), "-lm", "-o", str(exe)], capture_output=True, text=True
    )


@pytest.mark.skipif(not shutil.which("cc"), reason="no C compiler")
def test_a_model_header_compiled_into_the_node_is_its_default(tmp_path):
    from stickslip.hil.node import model_values

    # at a step other than the node's default 1 us: the header's step_s sets it
    m = MF.ModelFile(
        ActuatorParams.table1(), "lugre", Effects(load_n=0.05, slew_v_per_s=3e6), dt_s=2e-6
    )
    built = _node_with_header(tmp_path, m, "f32")
    assert built.returncode == 0, built.stderr
    out = subprocess.run([str(tmp_path / "node")], capture_output=True, text=True).stdout.split()
    values = [float(v) for v in out[:-1]]
    assert values == pytest.approx(list(model_values(m).values()), rel=1e-7)
    assert bytes.fromhex(out[-1]) == bytes(m.config())  # the config the node runs, bit for bit
    # the fixed-point node runs the load and the slew limit: its config is the header's q one
    q = _node_with_header(tmp_path / "q", m, "q")
    assert q.returncode == 0, q.stderr
    out = subprocess.run([str(tmp_path / "q" / "node")], capture_output=True, text=True).stdout
    assert bytes.fromhex(out.split()[-1]) == bytes(m.config_q())
    # an effect it does not model: the build says so instead of running without it
    h = MF.ModelFile(m.params, "lugre", Effects(creep_ratio=0.1, creep_tau_s=1e-2))
    q = _node_with_header(tmp_path / "qh", h, "q")
    assert q.returncode != 0 and "the fixed-point node cannot run this model" in q.stderr
