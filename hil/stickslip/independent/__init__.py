"""A second, independent truth generator for the diagnosis: stick-slip actuator datasets
(stick-slip-dataset/1) made by code that shares nothing with lib/ and never loads the C library.

Three friction laws (standard LuGre, the Generalized Maxwell-Slip model, and ls_b, an outside
reading of the LS paper), the physical effects of the diagnosis catalog implemented afresh, two
sensor errors outside the catalog, fixed-step RK4 in float64 under numba. The equations, the
integrator and its convergence study: docs/independent-generator.md.

    from stickslip.independent import generate, draw_effect
    truth = generate("out/ds", law="gms", effects={"external_load": {"load_n": 0.2}}, seed=3)
"""

from .design import DESIGNS, TABLE_I, RunSpec, generate, truth_path
from .effects import EFFECTS, OUTSIDE_EFFECTS, draw_effect, sensor_reading
from .laws import LAWS, friction_along
from .plant import Plant, run_sawtooth, sawtooth_segments

__all__ = [
    "DESIGNS",
    "EFFECTS",
    "LAWS",
    "OUTSIDE_EFFECTS",
    "TABLE_I",
    "Plant",
    "RunSpec",
    "draw_effect",
    "friction_along",
    "generate",
    "run_sawtooth",
    "sawtooth_segments",
    "sensor_reading",
    "truth_path",
]
