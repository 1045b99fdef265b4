"""What a diagnosis returns: candidate models (a fit, its validation, its score) and the
diagnosis itself, with its stick-slip-diagnosis/1 JSON (../shared/diagnosis-output.md)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..model import DT_S, major_loop_gain
from ..model_file import ModelFile
from .catalog import (
    BASE_LAW,
    CAUSE_PARAMS,
    FRICTION_LAW,
    cause_params,
)
from .fit import (
    Evaluation,
    FitResult,
    Model,
)
from .guards import (
    Verdict,
)
from .screen import (
    Screened,
    predicted_bic,
)

FORMAT = "stick-slip-diagnosis/1"


@dataclass
class Candidate:
    fit: FitResult  # None only for the nominal model's stand-in in beats
    val: Evaluation
    score: float  # BIC on the validation runs, lower is better
    parent: Candidate | None = None
    verdict: Verdict | None = None
    held: tuple[str, ...] = ()  # base parameters held at nominal: not identifiable
    k: int = 0  # parameters the model took from the data: its law's identifiable ones, causes'

    @property
    def causes(self) -> tuple[str, ...]:
        return self.fit.causes if self.fit else ()

    @property
    def law(self) -> str:
        return self.fit.model.law if self.fit else BASE_LAW

    @property
    def n_params(self) -> int:
        return self.k

    @property
    def mse_over_noise(self) -> float:
        return self.val.mse_over_noise


@dataclass
class Diagnosis:
    dataset: str
    noise_m: float
    noise_source: str
    train_ids: list[str]
    val_ids: list[str]
    nominal: Evaluation
    nominal_model: Model
    baseline: Candidate  # the base law, calibrated
    laws: dict[str, Candidate]  # every law, calibrated
    law_verdict: Verdict | None  # the guards on the preferred law, when it is not the base law
    base: Candidate  # what the causes were added to: the base law or the confirmed other law
    singles: list[Candidate]
    rounds: list[list[Candidate]]
    chosen: Candidate
    causes: list[str]
    unexplained: bool
    verdicts: dict[str, Verdict] = field(default_factory=dict)
    screened: list[Screened] = field(default_factory=list)  # causes on the base, to first order
    sensor_noise_m: float = 0.0  # per recorded sample (noise_m: on the filtered fit samples)
    residual: dict = field(default_factory=dict)
    # False: the calibrated base was already within 3 x the noise, and no cause was fitted
    causes_sought: bool = True
    timing_s: dict[str, float] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)  # the dataset's cross-checks' suspicions
    stroke_v: float = 0.0  # the dataset's largest drive amplitude (the hysteresis gain convention)

    @property
    def gain(self) -> float:
        b = self.baseline.val.rmse_m
        return 0.0 if b == 0 else max(0.0, 1.0 - self.chosen.val.rmse_m / b)

    def uncertainty(self, c: Candidate) -> dict:
        """Standard error and identifiability of every reported parameter of a model: fitted
        there, or held at the calibration of its law (which then vouches for it), or held at its
        nominal value because no fit could pin it down."""
        out: dict[str, dict] = {}
        for source in (self.laws[c.law], c):
            if source.fit is None:
                continue
            for name, sd in source.fit.stderr.items():
                out[_json_name(name, source.causes)] = {
                    "stderr": _finite(sd),
                    "identifiable": True,
                }
        for name in self.laws[c.law].held:
            out[_json_name(name, ())] = {"stderr": None, "identifiable": False}
        return out

    def model_file(self) -> ModelFile:
        """The chosen model as the C step runs it (stick-slip-model/1): the ideal strain's gain
        after the hysteresis convention at this dataset's stroke, as the fits simulated it."""
        m = self.chosen.fit.model
        return ModelFile(
            major_loop_gain(m.params, m.effects, self.stroke_v),
            m.law,
            m.effects,
            DT_S,
            tuple(m.causes),
            {
                "dataset": self.dataset,
                "diagnosis": FORMAT,
                "causes": self.causes,
                "validation_rmse_m": self.chosen.val.rmse_m,
                "validation_runs": self.val_ids,
                "nominal_gain_m_per_v": m.params.piezo_gain_m_per_v,
                "stroke_v": self.stroke_v,
            },
            m.gms_decay,
        )

    def to_json(self) -> dict:
        def block(c: Candidate | None, ev: Evaluation, with_params: bool = True) -> dict:
            d: dict = {"validation_rmse_m": ev.rmse_m, "validation_step_error": ev.step_error}
            if with_params and c is not None and c.fit is not None:
                params: dict = dict(c.fit.values)
                if c.law != BASE_LAW:
                    params["friction_law.law"] = c.law
                d["params"] = params
                d["uncertainty"] = self.uncertainty(c)
            return d

        cands: list[dict] = []
        for name, c in sorted(self.laws.items(), key=lambda kv: kv[1].score):
            if name == BASE_LAW:
                continue
            v = self.law_verdict if c is self.best_other_law else None
            cands.append(
                {
                    "name": FRICTION_LAW,
                    "validation_rmse_m": c.val.rmse_m,
                    "score": c.score,
                    "params": {"friction_law.law": name},
                    "confirmed": name == self.base.law,
                    **({"guards": v.to_json()} if v else {}),
                }
            )
        for c in self.singles:
            cause = c.causes[-1]
            v = self.verdicts.get(cause)
            cands.append(
                {
                    "name": cause,
                    "validation_rmse_m": c.val.rmse_m,
                    "score": c.score,
                    "params": {k: x for k, x in c.fit.values.items() if k.startswith(cause + ".")},
                    "confirmed": cause in self.causes,
                    "would_reduce_error_by": max(0.0, 1.0 - c.val.rmse_m / self.base.val.rmse_m),
                    **({"guards": v.to_json()} if v else {}),
                }
            )
        cands.sort(key=lambda d: d["score"])
        fitted = {c.causes[-1] for c in self.singles}
        n_val = self.base.val.n_samples
        for x in self.screened:
            if x.cause in fitted:
                continue
            k = self.base.k + len(CAUSE_PARAMS[x.cause])
            rmse = math.sqrt(x.rss_val / x.n_val) * self.noise_m
            cands.append(
                {
                    "name": x.cause,
                    "validation_rmse_m": rmse,
                    "score": predicted_bic(x, k, n_val, self.noise_m),
                    "params": {f"{x.cause}.{n}": v for n, v in x.values.items()},
                    "confirmed": False,
                    "would_reduce_error_by": max(0.0, 1.0 - rmse / self.base.val.rmse_m),
                    "screened_only": True,
                }
            )
        return {
            "format": FORMAT,
            "dataset": self.dataset,
            "causes": self.causes,
            "nominal": block(None, self.nominal, with_params=False),
            "baseline": block(self.baseline, self.baseline.val),
            "extended": block(self.chosen, self.chosen.val),
            "gain": self.gain,
            "unexplained": self.unexplained,
            "candidates": cands,
            "validation_runs": self.val_ids,
            "noise_m": self.noise_m,
            "sensor_noise_m": self.sensor_noise_m,
            "friction_laws": {
                name: {
                    "validation_rmse_m": c.val.rmse_m,
                    "score": c.score,
                    "not_identifiable": list(c.held),
                }
                for name, c in self.laws.items()
            },
            "residual": self.residual,
        }

    @property
    def best_other_law(self) -> Candidate | None:
        others = [c for n, c in self.laws.items() if n != BASE_LAW]
        return min(others, key=lambda c: c.score) if others else None


def _json_name(name: str, causes: tuple[str, ...]) -> str:
    """A fitted parameter as the JSON names it: mu_s for the Stribeck excess (mu_d is held, so
    the two have the same error), cause.name for a cause's."""
    if name == "stribeck_excess":
        return "mu_s"
    for c in causes:
        if any(p.name == name for p in cause_params(c)):
            return f"{c}.{name}"
    return name


def _finite(x: float) -> float | None:
    return float(x) if math.isfinite(x) else None
