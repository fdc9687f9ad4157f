"""The condensed step without a compiler: the condensing interpreted by CasADi, DAQP through its Python package.

The fallback of the compiled step (:mod:`mpc_hunt.solving.backends.condensed_compiled`),
with its buffer's calls and its codes: the same condensing
(:mod:`mpc_hunt.solving.backends.condensing`), the same warm start from the last
working set and cold retry, the same read-back. DAQP's Python package is pinned to
the vendored sources' version (:mod:`mpc_hunt.solving.vendored_daqp`), so both run
the same DAQP.
"""

from __future__ import annotations

import numpy as np

from mpc_hunt.solving.backends.condensed_compiled import NON_FINITE_INPUT, NON_FINITE_PLAN


class InterpretedBuffer:
    """The same step without a compiler: the condensing interpreted by CasADi, DAQP through its Python package."""

    def __init__(self, function):
        self.function = function
        self.model = None
        self.arrays = [None] * 4
        self.code = self.flag = self.iterations = 0

    def set_arg(self, i: int, view) -> None:
        self.arrays[i] = np.frombuffer(view, dtype=float)

    def set_res(self, i: int, view) -> None:
        self.arrays[2 + i] = np.frombuffer(view, dtype=float)

    def evaluate(self) -> None:
        import daqp

        theta, reference, plan, objective = self.arrays
        plan[:] = reference
        self.iterations, self.code = 0, NON_FINITE_INPUT
        self.flag = self.code
        if not (np.all(np.isfinite(theta)) and np.all(np.isfinite(reference))):
            return
        H, f, At, bu, bl, plan0, P, c0 = (np.array(o) for o in self.function(theta, reference))
        f, bu, bl = f.ravel(), bu.ravel(), bl.ravel()
        A = np.ascontiguousarray(At.T)
        if not all(np.all(np.isfinite(a)) for a in (H, f, A, bu, bl)):
            return
        if self.model is None:
            self.model = daqp.Model()
            self.model.setup(H, f, A, bu, bl)
            attempts: list[dict[str, np.ndarray] | None] = [None]
        else:
            attempts = [dict(H=H, f=f, A=A, bupper=bu, blower=bl), dict(sense=np.zeros(len(bu), dtype=np.intc))]
        for update in attempts:
            if update is not None:
                self.model.update(**update)
            x, _, flag, info = self.model.solve()
            self.iterations += int(info["iterations"])
            self.flag = int(flag)
            if flag > 0:
                break
        if self.flag <= 0:
            self.code = self.flag
            return
        x = np.asarray(x)
        new = plan0.ravel() + P @ x
        if not np.all(np.isfinite(new)):
            self.code = self.flag = NON_FINITE_PLAN
            return
        plan[:] = new
        if objective is not None:
            objective[0] = c0.item() + 0.5 * x @ H @ x + f @ x
        self.code = 0
