"""A model file as the node's parameter table holds it (docs/protocol.md, app/ss_node_params.def):
every parameter in id order, for the header's SS_MODEL_NODE_PARAMS (model_file) and for the
clients' SET_MODEL (hil.node.model_values)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .hil import protocol as P

if TYPE_CHECKING:
    from .model_file import ModelFile

NODE_DT_S = 1e-6  # the node's default step (its step_s parameter; HELLO reports it)


def node_values(model: ModelFile) -> dict[str, float]:
    """Every node parameter (protocol.PARAM_NAMES, in id order) for a model file, its step
    included; ValueError for a model the node cannot run (a law it has not: GMS)."""
    if model.law not in P.NODE_LAWS:
        raise ValueError(
            f"the node runs {' or '.join(P.NODE_LAWS)} friction, the model {model.law}"
        )
    values = {k: float(v) for k, v in model.params.to_dict().items()}
    values["friction_model"] = P.NODE_LAWS[model.law]
    for k in P.EFFECT_PARAMS:
        values[k] = float(getattr(model.effects, k))
    values["step_s"] = float(model.dt_s)
    return {k: values[k] for k in P.PARAM_NAMES}
