"""Regenerate examples/hidden-effect/, the dataset the demo diagnoses (seeded, reproducible):

    .venv/bin/python examples/make_example.py

It follows the standard experiment design (docs/diagnosis.md, section 3). What it hides is in
examples/README.md, not in dataset.json: the diagnosis must find it blind."""

from pathlib import Path

import numpy as np

from stickslip import synth

SEED = 2026
HIDDEN = ("external_load",)


def main() -> None:
    rng = np.random.default_rng(SEED)
    truth = synth.draw_truth(HIDDEN, rng, miscalibrate=True)
    out = Path(__file__).resolve().parent / "hidden-effect"
    synth.generate(
        out,
        truth,
        seed=SEED,
        description="Example stick-slip stage: 12 runs of the standard design (synthetic).",
    )
    print(f"wrote {out}")
    print(
        f"hidden: {truth.effects.active()}; true normal_force_n {truth.params.normal_force_n:.4g}, "
        f"mu_s {truth.params.mu_s:.4g}"
    )


if __name__ == "__main__":
    main()
