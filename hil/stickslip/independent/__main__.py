"""Command line: write a dataset from the independent generator.

python -m stickslip.independent OUT_DIR --law gms --effect external_load --seed 3 --rate 250e3
python -m stickslip.independent OUT_DIR --set external_load.load_n=-0.2 --true normal_force_n=8
"""

from __future__ import annotations

import argparse
import json
import sys

from .design import DEFAULT_DESIGN, DESIGNS, TABLE_I, generate, truth_path
from .effects import EFFECTS, OUTSIDE_EFFECTS
from .laws import LAWS
from .plant import DT_S


def _key_value(text: str) -> tuple[str, float]:
    key, sep, value = text.partition("=")
    if not sep:
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, got {text!r}")
    try:
        return key.strip(), float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {value!r}") from None


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog="python -m stickslip.independent",
        description="Write a stick-slip-dataset/1 folder from the independent truth generator "
        "(no code shared with lib/); the truth goes to OUT_DIR.truth.json beside it.",
    )
    ap.add_argument("out_dir", help="dataset folder to write")
    ap.add_argument("--law", choices=LAWS, default="gms", help="friction law (default gms)")
    ap.add_argument(
        "--effect",
        action="append",
        default=[],
        choices=EFFECTS + OUTSIDE_EFFECTS,
        help="hide this effect, parameters drawn from its range (repeatable)",
    )
    ap.add_argument(
        "--set",
        action="append",
        default=[],
        type=_key_value,
        metavar="EFFECT.PARAM=VALUE",
        help="set one effect parameter (implies --effect EFFECT; repeatable)",
    )
    ap.add_argument(
        "--true",
        action="append",
        default=[],
        type=_key_value,
        metavar="PARAM=VALUE",
        help=f"true actuator parameter, absolute (one of {', '.join(TABLE_I)})",
    )
    ap.add_argument(
        "--nominal",
        action="append",
        default=[],
        type=_key_value,
        metavar="PARAM=VALUE",
        help="nominal parameter written to dataset.json (default Table I)",
    )
    ap.add_argument("--design", choices=sorted(DESIGNS), default=DEFAULT_DESIGN)
    ap.add_argument("--seed", type=int, default=0, help="seeds effect draws and sensor noise")
    ap.add_argument("--rate", type=float, default=250e3, help="sample rate, S/s (default 250e3)")
    ap.add_argument("--noise", type=float, default=2e-9, help="sensor noise RMS, m (default 2e-9)")
    ap.add_argument("--resolution", type=float, default=1e-9, help="quantisation, m (default 1e-9)")
    ap.add_argument("--dt", type=float, default=DT_S, help=f"integration step, s (default {DT_S})")
    ap.add_argument("--rod-column", action="store_true", help="also write the true x_rod_m")
    ap.add_argument("--json", action="store_true", help="print the truth as JSON on stdout")
    return ap


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    effects: dict[str, dict] = {name: {} for name in args.effect}
    for key, value in args.set:
        name, _, param = key.partition(".")
        if name not in EFFECTS + OUTSIDE_EFFECTS or not param:
            print(f"--set {key}: expected EFFECT.PARAM with a known effect", file=sys.stderr)
            return 2
        effects.setdefault(name, {})[param] = value
    try:
        truth = generate(
            args.out_dir,
            law=args.law,
            effects=effects,
            seed=args.seed,
            sample_rate_hz=args.rate,
            design=args.design,
            noise_rms_m=args.noise,
            resolution_m=args.resolution,
            true_params=dict(args.true),
            nominal_params=dict(args.nominal),
            dt_s=args.dt,
            rod_column=args.rod_column,
        )
    except ValueError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps(truth, indent=2))
    else:
        causes = ", ".join(truth["causes"]) or "none"
        print(
            f"wrote {args.out_dir} ({len(truth['runs'])} runs, law {truth['law']}, "
            f"effects: {causes}) in {truth['wall_time_s']:.1f} s; truth: {truth_path(args.out_dir)}"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
