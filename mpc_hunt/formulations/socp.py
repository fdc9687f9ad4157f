"""``socp``: the ``qp`` linearisation with Eq. 13 as its exact second-order cone instead of a polygon."""

from __future__ import annotations

from mpc_hunt.formulations.qp import QPFormulation


class SOCPFormulation(QPFormulation):
    """The QP with the motion limit |p_di,k − p_di,k−1| ≤ r_d kept exactly, as a cone (conic backends)."""

    name = "socp"
    kind = "socp"
    default_backend = "clarabel"
    construction_options = (True,)  # LinearisedCapture's exact_motion_cone
