"""The human side of a diagnosis: a Markdown report with PNG plots (measured against simulated
position, per-cycle steps, residual signatures, candidates) next to the JSON."""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .. import dataset as D  # noqa: E402
from .catalog import CAUSES, FRICTION_LAW, FRICTION_LAW_TEXT  # noqa: E402
from .evidence import (  # noqa: E402
    MIN_BIC_DROP,
    MIN_MSE_DROP_OVER_NOISE,
    UNEXPLAINED_RMSE_OVER_NOISE,
)
from .fit import FitRun, Model, cycle_steps, predict_all, prepare_all  # noqa: E402
from .guards import (  # noqa: E402
    CV_MAX_HARM,
    CV_MIN_DROP,
    FINAL_SHARE,
    FWD_SHARE,
    UNEXPLAINED_FINAL_SHARE,
)
from .pipeline import LAW_SPREAD_TIGHT, NOT_SEPARATED  # noqa: E402
from .result import Diagnosis  # noqa: E402


def _signatures(runs: list[FitRun], model: Model) -> dict[str, np.ndarray]:
    """Per-cycle step residual (simulated - measured, m) along the drive direction (> 0: the model
    steps further than measured) with the conditions of each cycle, and the position residual,
    also along the drive direction, against phase within the cycle. Along the direction, a load
    or an asymmetry shows as opposite signs in the two directions, and the two directions do not
    cancel in the phase median. In metres rather than relative: runs that hardly step (100 Hz)
    would otherwise drown the rest."""
    rows: dict[str, list] = {k: [] for k in ("rel", "dir", "freq", "amp", "pos", "cycle", "tfrac")}
    phase, pres = [], []
    for run, x in zip(runs, predict_all(runs, model)):  # all at once: a heat chain runs once
        if run.waveform is None:
            continue
        w = run.waveform
        s_meas, s_sim = cycle_steps(run, run.x_m), cycle_steps(run, x)
        k = np.arange(w.cycles)
        starts = np.interp(k * w.period_s, run.t_s - run.t_s[0], run.x_m)
        rows["rel"].extend(w.direction * (s_sim - s_meas))
        rows["dir"].extend([w.direction] * w.cycles)
        rows["freq"].extend([w.frequency_hz] * w.cycles)
        rows["amp"].extend([w.amplitude_v] * w.cycles)
        rows["pos"].extend(starts)
        rows["cycle"].extend(k)
        rows["tfrac"].extend(k / max(1, w.cycles - 1))
        # within-cycle shape: residual minus its value at the cycle start
        t = run.t_s - run.t_s[0]
        inside = t < w.duration_s
        cyc = np.floor(t[inside] / w.period_s).astype(int)
        r = w.direction * (x - run.x_m)[inside]
        r0 = np.array([r[cyc == c][0] for c in range(w.cycles)])
        phase.extend((t[inside] / w.period_s) % 1.0)
        pres.extend(r - r0[cyc])
    out = {k: np.asarray(v, float) for k, v in rows.items()}
    out["phase"], out["phase_res"] = np.asarray(phase), np.asarray(pres)
    return out


def _plot_signatures(path: Path, sig: dict[str, np.ndarray], title: str) -> None:
    fig, axes = plt.subplots(2, 3, figsize=(13, 7))
    c = np.where(sig["dir"] > 0, "tab:blue", "tab:red")
    panels = [
        ("dir", "direction"),
        ("freq", "frequency (Hz)"),
        ("amp", "amplitude (V)"),
        ("pos", "slider position at cycle start (um)"),
        ("cycle", "cycle within run"),
    ]
    for ax, (key, label) in zip(axes.flat, panels):
        xs = sig[key] * (1e6 if key == "pos" else 1.0)
        jitter = 0.08 * (np.random.default_rng(0).random(len(xs)) - 0.5) if key == "dir" else 0
        ax.scatter(xs + jitter, 1e9 * sig["rel"], s=6, c=c, alpha=0.6)
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xlabel(label)
        ax.set_ylabel("step error along drive, sim - meas (nm)")
        if key == "freq":
            ax.set_xscale("log")
    ax = axes.flat[5]
    bins = np.linspace(0, 1, 41)
    idx = np.digitize(sig["phase"], bins) - 1
    med = [np.median(sig["phase_res"][idx == i]) if np.any(idx == i) else np.nan for i in range(40)]
    ax.plot(0.5 * (bins[1:] + bins[:-1]), 1e9 * np.asarray(med), "k.-")
    ax.set_xlabel("phase within the cycle")
    ax.set_ylabel("residual along drive since cycle start (nm)")
    fig.suptitle(title + "  (blue: forward runs, red: reverse)")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def write_report(d: Diagnosis, out_dir: str | Path) -> Path:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    runs = prepare_all(D.load(d.dataset).runs)
    val = [r for r in runs if r.id in d.val_ids]
    models = {
        "nominal": d.nominal_model,
        "baseline": d.baseline.fit.model,
        "extended": d.chosen.fit.model,
    }
    # every run under each model, at once (a thermal model predicts the runs one after another)
    pred = {
        name: dict(zip([r.id for r in runs], predict_all(runs, m))) for name, m in models.items()
    }

    # 1. measured against simulated position on the validation runs
    n = len(val)
    cols = min(2, n)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(6.5 * cols, 3.3 * rows), squeeze=False)
    for ax, run in zip(axes.flat, val):
        t = 1e3 * (run.t_s - run.t_s[0])
        ax.plot(t, 1e6 * run.x_m, color="0.6", lw=2.5, label="measured")
        for name, style in (("nominal", ":"), ("baseline", "--"), ("extended", "-")):
            ax.plot(t, 1e6 * pred[name][run.id], style, lw=1, label=name)
        ax.set_title(run.id)
        ax.set_xlabel("t (ms)")
        ax.set_ylabel("slider (um)")
    axes.flat[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "positions.png", dpi=90)
    plt.close(fig)

    # 2. per-cycle steps, every run
    fig, ax = plt.subplots(figsize=(12, 4))
    off = 0
    ticks = []
    for run in runs:
        sm = cycle_steps(run, run.x_m)
        k = off + np.arange(len(sm))
        ax.plot(k, 1e6 * sm, "k.", ms=4, label="measured" if off == 0 else None)
        for name, style in (("baseline", "C1-"), ("extended", "C2-")):
            ss = cycle_steps(run, pred[name][run.id])
            ax.plot(k, 1e6 * ss, style, lw=1, label=name if off == 0 else None)
        ticks.append((off + len(sm) / 2, run.id + (" (val)" if run.id in d.val_ids else "")))
        off += len(sm) + 3
    ax.set_xticks([t for t, _ in ticks], [s for _, s in ticks], rotation=30, fontsize=7, ha="right")
    ax.set_ylabel("step per cycle (um)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "steps.png", dpi=90)
    plt.close(fig)

    # 3. residual signatures of the calibrated base model and of the extended model
    _plot_signatures(
        out / "signatures_baseline.png",
        _signatures(runs, models["baseline"]),
        "Residual signatures, calibrated base model",
    )
    if d.chosen.causes:
        _plot_signatures(
            out / "signatures_extended.png",
            _signatures(runs, models["extended"]),
            "Residual signatures, extended model (" + " + ".join(d.chosen.causes) + ")",
        )

    j = d.to_json()
    (out / "diagnosis.json").write_text(json.dumps(j, indent=2) + "\n")
    (out / "report.md").write_text(_markdown(d, j))
    return out / "report.md"


def _nm(v: float) -> str:
    return f"{v * 1e9:.3g} nm" if v < 1e-6 else f"{v * 1e6:.3g} um"


def _describe(name: str) -> str:
    return FRICTION_LAW_TEXT if name == FRICTION_LAW else CAUSES[name]


def _verdict(causes: list[str], d: Diagnosis, law: str) -> str:
    if causes == ["none"] and not d.unexplained:
        return (
            "**No missing physics.** The base model, calibrated on this data, explains it down "
            "to the measurement noise."
        )
    if causes == ["parameter_miscalibration"]:
        return (
            "**Parameter miscalibration, no missing physics.** The nominal parameters are off; "
            "calibrated, the base model explains the data down to the noise."
        )
    if causes == ["none"]:
        return (
            "**Unexplained.** No cause in the catalog explains the residuals, which stay well "
            "above the noise, and none passed the guards. The data holds something the model "
            "does not describe: see *What is wrong with the model* below."
        )
    named = "; ".join(
        f"`{c}`: {_describe(c)}" + (f" (the data prefer **{law}**)" if c == FRICTION_LAW else "")
        for c in causes
    )
    verdict = f"**Cause{'s' if len(causes) > 1 else ''}: {named}.**"
    if d.unexplained:
        verdict += " Even so, residuals stay well above the noise: part of it is unexplained."
    return verdict


def _not_separated(d: Diagnosis) -> str:
    """The twins the final step could not tell apart (pipeline._twins_separated), or ""."""
    pair = sorted(
        c for c, v in d.verdicts.items() if any(r.startswith(NOT_SEPARATED) for r in v.reasons)
    )
    if not pair:
        return ""
    return (
        " The data hold a force that depends on the direction of motion, "
        + " or ".join(f"`{c}`" for c in pair)
        + ", which these runs do not tell apart: neither is named (their figures are under "
        "*Candidates*)."
    )


def _params_table(j: dict) -> list[str]:
    lines = [
        "| parameter | calibrated base | +- | extended | +- |",
        "|---|---|---|---|---|",
    ]
    bp, ep = j["baseline"]["params"], j["extended"]["params"]
    bu, eu = j["baseline"].get("uncertainty", {}), j["extended"].get("uncertainty", {})

    def fmt(v) -> str:
        return "" if v is None else (v if isinstance(v, str) else f"{v:.5g}")

    def err(u: dict, k: str) -> str:
        if k not in u:
            return ""
        if not u[k]["identifiable"]:
            return "not identifiable (held at nominal)"
        return "" if u[k]["stderr"] is None else f"{u[k]['stderr']:.2g}"

    for k in sorted(set(bp) | set(ep)):
        lines.append(f"| {k} | {fmt(bp.get(k))} | {err(bu, k)} | {fmt(ep.get(k))} | {err(eu, k)} |")
    return lines


def _markdown(d: Diagnosis, j: dict) -> str:
    noise = d.sensor_noise_m  # the verdicts are judged against it
    lines = [f"# Diagnosis of `{d.dataset}`", ""]
    if d.warnings:  # suspicions about the data itself come before anything read from it
        lines += ["**Warnings about the data:**", ""] + [f"- {w}" for w in d.warnings] + [""]
    causes = j["causes"]
    lines += [_verdict(causes, d, d.chosen.law) + _not_separated(d), ""]
    if not d.causes_sought:
        lines += [
            f"The calibrated {d.base.law} model is within {UNEXPLAINED_RMSE_OVER_NOISE:g} x the "
            "sensor noise "
            f"({_nm(d.base.val.rmse_m)} against {_nm(noise)}), so no cause was fitted: what is "
            "left is the noise, the C model's own numerical error (about 3 nm RMS at its 1 us "
            "step with 15 us edges) and any difference in the friction law's form, and a flexible "
            "term would take a part of each. The candidates below are first-order figures.",
            "",
        ]
    lines += [
        "| model | validation RMSE | RMSE / noise | step error |",
        "|---|---|---|---|",
    ]
    for name in ("nominal", "baseline", "extended"):
        b = j[name]
        lines.append(
            f"| {name} | {_nm(b['validation_rmse_m'])} | {b['validation_rmse_m'] / noise:.2f} | "
            f"{100 * b['validation_step_error']:.2f} % |"
        )
    if j["baseline"]["validation_rmse_m"] > j["nominal"]["validation_rmse_m"]:
        lines += [
            "",
            "The calibrated base model predicts the held-out runs worse than the nominal one: "
            "fitted to data it cannot describe, the friction parameters absorb the missing "
            "effect on the training runs and carry the wrong correction to the others. That is "
            "evidence the base model lacks something, not of a bad calibration.",
        ]
    lines += [
        "",
        f"Gain of the extension over the calibrated base model: **{100 * j['gain']:.1f} %** of "
        f"the validation RMSE. Sensor noise: {_nm(noise)} RMS per sample ({d.noise_source}).",
        "",
        f"Fitted on {', '.join(d.train_ids)}; every figure above is measured on the held-out "
        f"runs {', '.join(d.val_ids)}.",
        "",
        "## Friction law",
        "",
        "Each law calibrated on the training runs with every parameter the runs can identify "
        "(a parameter whose standard error exceeds 30 % of its value is held at nominal):",
        "",
        "| law | validation RMSE | RMSE / noise | score | not identifiable |",
        "|---|---|---|---|---|",
    ]
    for name, c in sorted(j["friction_laws"].items(), key=lambda kv: kv[1]["score"]):
        lines.append(
            f"| {name} | {_nm(c['validation_rmse_m'])} | {c['validation_rmse_m'] / noise:.2f} | "
            f"{c['score']:.1f} | {', '.join(c['not_identifiable']) or '-'} |"
        )
    if d.law_verdict is not None:
        v = d.law_verdict
        lines += [
            "",
            f"The data prefer {d.best_other_law.law if d.best_other_law else ''}: "
            + (
                "confirmed by the guards."
                if v.confirmed
                else "not confirmed (" + "; ".join(v.reasons) + ")."
            ),
        ]
    lines += ["", "## Parameters", ""] + _params_table(j)
    lines += [
        "",
        "Standard errors from the Jacobian at the optimum, scaled by the reduced chi-square "
        "where the model does not reach the noise. The residual samples are correlated in time, "
        "so they are lower bounds; the guards below, not these errors, decide what is named.",
        "",
        "## Candidates",
        "",
        "Each cause fitted on the calibrated "
        f"{d.base.law} model (every base parameter its calibration identified freed again; the "
        "causes first screened to first order and only the promising ones fitted), ranked on the "
        "validation runs by BIC (lower is better). A cause is named only when it beats the model "
        f"so far (BIC drop > {MIN_BIC_DROP:g}, mean-square error down by > "
        f"{100 * MIN_MSE_DROP_OVER_NOISE:g} % of the noise variance) and passes the guards: "
        "parameters in their physical range, at least "
        f"{100 * FWD_SHARE:.0f} % of the error above the noise removed (and {100 * FINAL_SHARE:.0f}"
        " % in the final model; a first cause that leaves the model unexplained, "
        f"{100 * UNEXPLAINED_FINAL_SHARE:.0f} % of the best model's without it, or "
        f"{100 * FINAL_SHARE:.0f} % for a hysteresis or a base compliance whose size agrees "
        f"within {LAW_SPREAD_TIGHT:g} x under every friction law), and a gain that "
        "carries over to run families it was not fitted "
        f"on (each frequency and amplitude left out in turn: better in most, by > {CV_MIN_DROP:g} "
        f"noise variances in total, and none worse by more than {CV_MAX_HARM:g} x).",
        "",
        "| candidate | validation RMSE | RMSE / noise | would reduce the error by | score | "
        "fitted | verdict |",
        "|---|---|---|---|---|---|---|",
        f"| (calibrated {d.base.law}) | {_nm(d.base.val.rmse_m)} | "
        f"{d.base.val.rmse_m / noise:.2f} | | {d.base.score:.1f} | | |",
    ]
    for c in j["candidates"]:
        ps = ", ".join(
            f"{k.split('.', 1)[1]}={v:.4g}" if not isinstance(v, str) else v
            for k, v in c["params"].items()
        )
        g = c.get("guards")
        if c["confirmed"]:
            verdict = "**named**"
        elif g is not None:
            verdict = "not confirmed: " + "; ".join(g["reasons"])
        elif c.get("screened_only"):
            verdict = "screened to first order, not fitted (figures predicted)"
        else:
            verdict = "not put to the guards" if c["name"] != FRICTION_LAW else ""
        red = c.get("would_reduce_error_by")
        lines.append(
            f"| {c['name']} | {_nm(c['validation_rmse_m'])} | "
            f"{c['validation_rmse_m'] / noise:.2f} | "
            f"{'' if red is None else f'{100 * red:.0f} %'} | {c['score']:.1f} | {ps} | "
            f"{verdict} |"
        )
    for i, rnd in enumerate(d.rounds[1:], start=2):
        # a round on first causes that did not pass alone (pipeline.PROVISIONAL_WIDTH)
        provisional = all(
            c.parent is not None and c.parent.verdict is not None and not c.parent.verdict.confirmed
            for c in rnd
        )
        on = "first causes that did not pass alone" if provisional else "the causes kept so far"
        lines += ["", f"Round {i} (adding to {on}):", ""]
        for c in rnd:
            lines.append(f"- {' + '.join(c.causes)}: {_nm(c.val.rmse_m)}, score {c.score:.1f}")
    if d.unexplained:
        lines += ["", "## What is wrong with the model", ""] + _unexplained(d, j)
    lines += [
        "",
        "## What the simulation gets wrong",
        "",
        "Measured against simulated position on the validation runs:",
        "",
        "![positions](positions.png)",
        "",
        "Per-cycle step sizes, every run:",
        "",
        "![steps](steps.png)",
        "",
        "Residual signatures of the calibrated base model. Each physical cause leaves its own "
        "pattern: a load or asymmetry splits the directions, a slew limit grows with frequency, "
        "hysteresis depends on amplitude, position-dependent friction on where the slider is, "
        "heat and creep on the time within a run. Errors are along the drive direction: above "
        "zero, the model steps further than measured.",
        "",
        "![signatures](signatures_baseline.png)",
        "",
    ]
    if d.chosen.causes:
        lines += [
            "The same with the extended model:",
            "",
            "![signatures extended](signatures_extended.png)",
            "",
        ]
    t = d.timing_s
    lines += [
        f"Wall time {t.get('total_s', 0):.1f} s (friction laws {t.get('laws_s', 0):.1f} s, "
        f"candidates {t.get('candidates_s', 0):.1f} s, selection {t.get('selection_s', 0):.1f} s).",
        "",
    ]
    return "\n".join(lines)


def _unexplained(d: Diagnosis, j: dict) -> list[str]:
    """Which runs, which phase of the cycle, by how much; and what would help, unconfirmed."""
    noise = d.sensor_noise_m
    res = j["residual"]
    worst = sorted(res["per_run_rmse_m"].items(), key=lambda kv: -kv[1])
    lines = [
        f"The final model leaves {_nm(d.chosen.val.rmse_m)} RMS on the held-out runs, "
        f"{d.chosen.val.rmse_m / noise:.1f} x the noise (more than "
        f"{UNEXPLAINED_RMSE_OVER_NOISE:g} x is unexplained). By run, all runs (RMS error, "
        "x noise):",
        "",
        "| run | RMS error | x noise |",
        "|---|---|---|",
    ]
    lines += [f"| {k} | {_nm(v)} | {v / noise:.1f} |" for k, v in worst]
    ph = res["phase_rms_m"]
    nb = res["phase_bins"]
    k = int(np.argmax(ph))
    lines += [
        "",
        "Error accumulated since the start of each cycle, RMS by phase within the cycle (0 = "
        "start of the slow edge; the fast edge is at the end for forward runs, at the start for "
        "reverse ones):",
        "",
        "| phase | " + " | ".join(f"{i / nb:.1f}-{(i + 1) / nb:.1f}" for i in range(nb)) + " |",
        "|---|" + "---|" * nb,
        "| RMS | " + " | ".join(_nm(v) for v in ph) + " |",
        "",
        f"The largest share builds up in phase {k / nb:.1f}-{(k + 1) / nb:.1f}.",
        "",
    ]
    unconfirmed = [c for c in j["candidates"] if not c["confirmed"] and c.get("guards")]
    if unconfirmed:
        lines.append("Candidates that would reduce the error, not confirmed:")
        lines.append("")
        for c in unconfirmed:
            red = c.get("would_reduce_error_by")
            lines.append(
                f"- `{c['name']}`"
                + (f" would reduce the error by {100 * red:.0f} %" if red is not None else "")
                + ", not confirmed: "
                + "; ".join(c["guards"]["reasons"])
            )
    return lines
