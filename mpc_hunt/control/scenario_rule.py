"""A batch's geometric controllers as one compiled rule: each hunt's controller knowledge as a batch's arrays.

A controller whose command is a compiled rule (``voronoi``, ``apf``) gives :meth:`batched` a
:class:`ScenarioRule` of its batch kernel: the rule holds, per hunt, what that hunt's controller knows (its
scenario, the defenders' belief: obstacles, speeds, packed parameters; its prediction setting), padded to the
batch's largest team and obstacle set, and hands them with the batch's observations to the kernel, which commands
every hunt of the batch in one call (:mod:`mpc_hunt.sim.batch`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from mpc_hunt.world.packed import SIZE


class ScenarioRule:
    """``kernel`` over a batch, each hunt with its controller's knowledge (the module's docstring); None in
    ``controllers``: a hunt commanded otherwise."""

    def __init__(self, controllers: Sequence, kernel: Callable):
        self.kernel = kernel
        B = len(controllers)
        N = max((len(c.scenario.defenders) for c in controllers if c is not None), default=1)
        M = max((len(c.scenario.obstacles) for c in controllers if c is not None), default=0)
        self.centres, self.radii = np.zeros((B, M, 2)), np.zeros((B, M))
        self.m, self.speeds = np.zeros(B, dtype=np.int64), np.ones((B, N))
        self.prm, self.prediction = np.zeros((B, SIZE)), np.zeros(B, dtype=bool)
        for b, c in enumerate(controllers):
            if c is not None:
                s = c.scenario
                m = len(s.obstacles)
                self.m[b], self.centres[b, :m], self.radii[b, :m] = m, s.obstacle_centres, s.obstacle_radii
                self.speeds[b, : len(s.defenders)], self.prm[b] = s.defender_max_speeds, s.packed
                self.prediction[b] = c.prediction

    def commands(self, mine: np.ndarray, p_a, previous, p_d, n, failed, velocities, capture, intercepts) -> None:
        """Every hunt of ``mine`` commanded from its observation (arrays of the batch), in one call."""
        self.kernel(mine, p_a, previous, p_d, n, failed, self.centres, self.radii, self.m, self.speeds, self.prm,
                    self.prediction, velocities, capture, intercepts)  # fmt: skip
