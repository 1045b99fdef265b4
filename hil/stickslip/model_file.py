"""stick-slip-model/1: an identified (or any) actuator model as a file (docs/model-file.md).

The JSON carries everything the C step needs (friction law, actuator and friction parameters,
effects, step) and where it came from; the C header carries the same model as
ss_actuator_config_f32_t (and, where the fixed-point family can run it, ss_actuator_config_q_t)
initialisers for firmware to compile in. Loading validates every field and names the one at
fault; the C library's own check has the last word."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field, fields
from pathlib import Path

from . import _native as N
from .model import DT_S, GMS_DECAY, GMS_STIFFNESS_RATIO, ActuatorParams, Effects
from .node_params import node_values

FORMAT = "stick-slip-model/1"
LAWS = ("ls", "lugre", "gms")
Q_LAWS = ("ls", "lugre")  # the fixed-point family's (no GMS)


class ModelFileError(ValueError):
    """A model file that cannot be used: the file and the field at fault, and why."""

    def __init__(self, path: str | Path, problem: str):
        self.file, self.problem = str(path), problem
        super().__init__(f"{path}: {problem}")


@dataclass(frozen=True)
class ModelFile:
    """A model the C step runs as it is: the gain is the ideal strain's (after any hysteresis
    convention, docs/diagnosis.md), the effects are absolute values."""

    params: ActuatorParams
    law: str = "ls"
    effects: Effects = field(default_factory=Effects)
    dt_s: float = DT_S
    causes: tuple[str, ...] = ()  # the diagnosis' causes the effects stand for
    source: dict = field(default_factory=dict)  # where it came from (free-form, kept as is)
    gms_decay: float = GMS_DECAY  # the GMS law's presliding shape (written for GMS only)
    gms_stiffness_ratio: float = GMS_STIFFNESS_RATIO

    def to_dict(self) -> dict:
        d = {
            "format": FORMAT,
            "law": self.law,
            "dt_s": self.dt_s,
            "actuator": self.params.to_dict(),
            "effects": self.effects.active(),
            "causes": list(self.causes),
            "source": self.source,
        }
        if self.law == "gms":
            d["gms_decay"] = self.gms_decay
            d["gms_stiffness_ratio"] = self.gms_stiffness_ratio
        return d

    @classmethod
    def from_dict(cls, d: object, path: str | Path = "<model>") -> ModelFile:
        def bad(what: str) -> ModelFileError:
            return ModelFileError(path, what)

        if not isinstance(d, dict):
            raise bad("top level must be an object")
        if d.get("format") != FORMAT:
            raise bad(f"format: must be {FORMAT!r}, got {d.get('format')!r}")
        unknown = sorted(
            set(d)
            - {
                "format",
                "law",
                "dt_s",
                "actuator",
                "effects",
                "causes",
                "source",
                "gms_decay",
                "gms_stiffness_ratio",
            }
        )
        if unknown:
            raise bad(f"unknown keys {unknown}")
        law = d.get("law", "ls")
        if law not in LAWS:
            raise bad(f"law: must be one of {', '.join(LAWS)}, got {law!r}")
        dt = _number(d.get("dt_s", DT_S), "dt_s", bad)
        if not 1e-9 <= dt <= 1e-3:
            raise bad(f"dt_s: must be in [1e-9, 1e-3] s, got {dt!r}")
        if not isinstance(d.get("actuator"), dict):
            raise bad("actuator: must be an object with every parameter of stick-slip-dataset/1")
        try:
            params = ActuatorParams.from_dict(d["actuator"], "actuator")
        except ValueError as e:
            raise bad(str(e)) from None
        eff = d.get("effects", {})
        if not isinstance(eff, dict):
            raise bad("effects: must be an object (effect name: value)")
        names = {f.name for f in fields(Effects)}
        unknown = sorted(set(eff) - names)
        if unknown:
            raise bad(f"effects: unknown keys {unknown} (known: {', '.join(sorted(names))})")
        effects = Effects(**{k: _number(v, f"effects.{k}", bad) for k, v in eff.items()})
        causes = d.get("causes", [])
        if not isinstance(causes, list) or not all(isinstance(c, str) for c in causes):
            raise bad("causes: must be a list of cause names")
        source = d.get("source", {})
        if not isinstance(source, dict):
            raise bad("source: must be an object")
        decay = _number(d.get("gms_decay", GMS_DECAY), "gms_decay", bad)
        ratio = _number(
            d.get("gms_stiffness_ratio", GMS_STIFFNESS_RATIO), "gms_stiffness_ratio", bad
        )
        m = cls(params, law, effects, dt, tuple(causes), source, decay, ratio)
        try:  # the library's check: ranges, and the rules between fields (Fc <= Fs, ...)
            N.check_config(m.config())
        except ValueError as e:
            raise bad(f"the C library refuses the model: {e}") from None
        return m

    def config(self) -> N.ActuatorConfig:
        return self.params.actuator_config(
            self.law, self.dt_s, self.effects, self.gms_decay, self.gms_stiffness_ratio
        )

    def config_q(self) -> N.ActuatorConfigQ | None:
        """The fixed-point config, or None when that family cannot run this model (GMS, an effect
        it does not model, or a value beyond its formats)."""
        return None if self.q_problem() else N.config_to_q(self.config())

    def q_problem(self) -> str | None:
        """Why the fixed-point family cannot run this model (None: it can)."""
        if self.law not in Q_LAWS:
            return f"{self.law} friction"
        try:
            N.config_to_q(self.config())
        except ValueError as e:
            return str(e)
        return None


def _number(v: object, where: str, bad) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise bad(f"{where}: expected a finite number, got {v!r}")
    return float(v)


def load(path: str | Path) -> ModelFile:
    p = Path(path)
    try:
        d = json.loads(p.read_text())
    except OSError as e:
        raise ModelFileError(p, f"cannot read: {e.strerror}") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise ModelFileError(p, f"invalid JSON: {e}") from None
    return ModelFile.from_dict(d, p)


def save(m: ModelFile, path: str | Path) -> Path:
    p = Path(path)
    p.write_text(json.dumps(m.to_dict(), indent=2, allow_nan=False) + "\n")
    return p


# ------------------------------------------------------------------ the C header


def c_header(m: ModelFile, guard: str = "SS_MODEL_H") -> str:
    """A header defining SS_MODEL_CONFIG_F32 (and SS_MODEL_CONFIG_Q where that family can run the
    model) as initialisers: `ss_actuator_config_f32_t cfg = SS_MODEL_CONFIG_F32;`."""
    src = json.dumps(m.source, sort_keys=True) if m.source else "{}"
    out = [
        f"/* stickslip model ({FORMAT}), from `stickslip model export` or `diagnose --export`.",
        f" * law {m.law}, dt {m.dt_s!r} s, causes: {', '.join(m.causes) or 'none'}",
        f" * source: {src.replace('*/', '* /')}",
        " * Generated: edit the JSON beside it and export again. */",
        f"#ifndef {guard}",
        f"#define {guard}",
        "",
        '#include "ss_actuator.h"',
        "",
        "/* ss_actuator_config_f32_t */",
        *N.c_define("SS_MODEL_CONFIG_F32", m.config()),
    ]
    if m.law in Q_LAWS:  # the node's parameter table in id order (docs/protocol.md)
        out += ["", "/* the node's parameters in id order (app/ss_node_params.def) */"]
        out.append("#define SS_MODEL_NODE_PARAMS \\")
        items = [f"    {N.c_value(v)}, /* {k} */" for k, v in node_values(m).items()]
        out += ["{ \\"] + [i + " \\" for i in items] + ["}"]
    q = m.config_q()
    out.append("")
    if q is None:
        why = m.q_problem()
        out.append(
            f"/* No SS_MODEL_CONFIG_Q: the fixed-point family cannot run this model ({why}). */"
        )
    else:
        out += ['#include "ss_actuator_q.h"', "", "/* ss_actuator_config_q_t */"]
        out += N.c_define("SS_MODEL_CONFIG_Q", q)
    out += ["", f"#endif /* {guard} */", ""]
    return "\n".join(out)


def export(m: ModelFile, out_dir: str | Path) -> tuple[Path, Path]:
    """Write model.json and stickslip_model.h into out_dir (created)."""
    d = Path(out_dir)
    d.mkdir(parents=True, exist_ok=True)
    j = save(m, d / "model.json")
    h = d / "stickslip_model.h"
    h.write_text(c_header(m))
    return j, h
