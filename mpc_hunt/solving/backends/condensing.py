"""A stage QP condensed to a dense QP in its controls: the states follow from the controls.

A stage QP (kind ``ocp-qp``, :mod:`mpc_hunt.formulations.rti`) has ξ_0 = 0 and gaps
ξ_k+1 + G_x ξ_k + G_u ν_k = 0, so its states follow from its controls: z = Z ν.
Condensed once per structure, as CasADi expressions of the step's inputs (θ,
reference), it is the dense QP

    min ½ νᵀ(ZᵀHZ)ν + (Zᵀg)ᵀν   s.t.  lbx_ν ≤ ν ≤ ubx_ν,  lbx_ξ ≤ Z_ξ ν ≤ ubx_ξ,  lba ≤ A Z ν ≤ uba

in 2N variables for a robot planning alone (``distributed``), the state bounds
that are finite becoming rows; the plan is affine in ν (plan₀ + P ν) and the
model's objective c₀ + ½νᵀHν + fᵀν. The condensed Hessian is positive definite
only where every control is weighted, as the ``enclose`` objective's smoothness
term does (the paper's Eq. 14 slacks enter linearly). The matrices are laid out
as DAQP reads them (:mod:`mpc_hunt.solving.backends.daqp_condensed`).
"""

from __future__ import annotations

from typing import Any

import numpy as np

INFINITY = 1e30  # DAQP's infinite bound (DAQP_INF)
CONDENSE = "mpc_hunt_condense"  # the condensing Function's name, as its generated C calls it


def condensed(graph) -> tuple[Any, dict]:
    """The condensing Function of a stage QP ``graph`` (:class:`mpc_hunt.formulations.rti.LinearisedStages`): (θ,
    reference) → (H, f, Aᵀ, bu, bl, plan₀, P, c₀), all dense (Aᵀ column by column is A row by row, as DAQP
    reads it), and its sizes."""
    import casadi as ca

    N, nxs, nus, ngs = graph.stages
    qp, z = graph.qp, graph.z
    nv = sum(nus)
    v = ca.SX.sym("v", nv)
    A = qp["a"]
    xi = ca.SX.zeros(nxs[0])
    parts: list[ca.SX] = []
    gaps: list[int] = []
    controls: list[int] = []
    states: list[range] = []
    row = col = used = 0
    for k in range(N + 1):
        parts.append(xi)
        states.append(range(col, col + nxs[k]))
        col += nxs[k]
        if k < N:
            nx, nu = nxs[k], nus[k]
            step = v[used : used + nu]
            parts.append(step)
            controls += range(col, col + nu)
            gx, gu = A[row : row + nxs[k + 1], col - nx : col], A[row : row + nxs[k + 1], col : col + nu]
            gaps += range(row, row + nxs[k + 1])
            xi = -(ca.mtimes(gx, xi) + ca.mtimes(gu, step))
            row += nxs[k + 1]
            col += nu
            used += nu
        row += ngs[k]
    Z = ca.jacobian(ca.vertcat(*parts), v)  # z = Z ν: ξ_0 = 0 and the gaps hold exactly

    def infinite(e, sign) -> bool:
        return bool(e.is_constant()) and float(e) == sign * np.inf

    lbx, ubx = qp["lbx"], qp["ubx"]
    bounded = [i for block in states[1:] for i in block if not (infinite(lbx[i], -1) and infinite(ubx[i], 1))]
    rows = [r for r in range(A.shape[0]) if r not in set(gaps)]
    select = ca.SX(len(bounded), z.shape[0])
    for r, i in enumerate(bounded):
        select[r, i] = 1
    constraint = ca.vertcat(ca.mtimes(select, Z), ca.mtimes(A[rows, :], Z))
    H = ca.mtimes([Z.T, qp["h"], Z])
    H = 0.5 * (H + H.T)
    zero = ca.DM.zeros(z.shape[0])
    outputs = [
        H,
        ca.mtimes(Z.T, qp["g"]),
        constraint.T,
        ca.fmin(ca.vertcat(ubx[controls], ubx[bounded], qp["uba"][rows]), INFINITY),
        ca.fmax(ca.vertcat(lbx[controls], lbx[bounded], qp["lba"][rows]), -INFINITY),
        ca.substitute(graph.plan, z, zero),
        ca.mtimes(ca.jacobian(graph.plan, z), Z),
        ca.substitute(graph.cost, z, zero),
    ]
    function = ca.Function(CONDENSE, graph.inputs, [ca.densify(o) for o in outputs])
    sizes = dict(
        nv=nv, m=nv + constraint.shape[0], ms=nv, n_theta=graph.inputs[0].numel(), n_reference=graph.inputs[1].numel()
    )
    return function, sizes
