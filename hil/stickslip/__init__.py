"""stickslip: simulate, test and identify stick-slip piezo actuators.

The models run in the C library (lib/, the code that goes into firmware), reached through
`stickslip._native`. Start with `stickslip.model.simulate`.
"""

__version__ = "0.1.0"
