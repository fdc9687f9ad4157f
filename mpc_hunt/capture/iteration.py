"""How a stage's QPs repeat within one control step: the one convergence rule of ``sqp``, ``rti``, ``stage-sqp``.

A step linearises at its reference and solves one QP; an iterated formulation
then relinearises at that QP's plan and solves again, until no defender
position moves by more than ``tolerance`` metres or ``max_qps`` QPs have run.
The Python iteration (:func:`mpc_hunt.formulations.sqp.iterate`), the control loop's
(:class:`mpc_hunt.solving.step.CaptureStep`) and the exported C step
(:mod:`mpc_hunt.solving.export`, whose wrapper is generated from these two
numbers) all apply :meth:`QPIteration.settled`.
"""

from __future__ import annotations

from dataclasses import dataclass

PACE_MARGIN = 1.5  # a cost budgeted ahead (a further QP, an iteration): this many times the one measured


@dataclass(frozen=True)
class QPIteration:
    """At most ``max_qps`` QPs a step; done when the largest move of a position is at most ``tolerance`` (m)."""

    max_qps: int
    tolerance: float

    def settled(self, move: float) -> bool:
        """Whether the step ends after a QP whose plan moved a position by at most ``move`` metres: always for a
        single QP (nothing to converge), else when ``move`` is within the tolerance."""
        return self.max_qps == 1 or move <= self.tolerance


ONE_QP = QPIteration(1, 0.0)


def another_fits(time_left: float | None, spent: float, count: int) -> bool:
    """Whether a step under a time limit starts a further QP: when ``time_left`` (s; None: no limit) covers
    :data:`PACE_MARGIN` × the mean time of the ``count`` QPs it has run in ``spent`` seconds (the first QP always
    runs). A QP that reads no clock (HPIPM's step) runs to its cap once started, so the limit is kept by not
    starting one that would not fit."""
    return time_left is None or count == 0 or time_left > PACE_MARGIN * spent / count
