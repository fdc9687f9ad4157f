"""What a formulation is: it turns a capture problem into solver data and reads the answer back."""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache
from typing import Any, ClassVar, Generic, TypeVar

import numpy as np

from mpc_hunt.capture.data import SolvesData
from mpc_hunt.capture.evaluator import GEOMETRY_CONSTRAINTS
from mpc_hunt.capture.problem import OBJECTIVES, CaptureProblem
from mpc_hunt.capture.solution import Solution, WarmStart
from mpc_hunt.capture.structure import Structure

Built = TypeVar("Built")


@lru_cache(maxsize=128)
def _built(construction: Callable[..., Any], structure: Structure, options: tuple) -> Any:
    return construction(structure, *options)


class Formulation(Generic[Built]):
    """Base class: ``name``, the ``kind`` of problem it emits (``nlp``, ``qp``, ``socp``), and ``solve``.

    Any backend whose ``accepts`` holds ``kind`` can solve it; ``default_backend``
    is the one used when none is named. ``exact`` names the constraint families
    a solution keeps to solver accuracy; the others it keeps approximately.
    """

    name: ClassVar[str]
    kind: ClassVar[str]
    default_backend: ClassVar[str]
    # The constraint families (evaluator names) it keeps exactly: by default the robots' own geometry, posed as
    # is or approximated from inside (Eq. 13 an inscribed polygon, Eq. 15 and the separations linearised at the
    # last plan); Eq. 14 and the attacker distance rest on the attacker's prediction, linearised or smoothed.
    exact: ClassVar[frozenset[str]] = frozenset(GEOMETRY_CONSTRAINTS)
    per_robot: ClassVar[bool] = False  # one QP per robot (``distributed``), not one for the team
    objectives: ClassVar[tuple[str, ...]] = OBJECTIVES  # the capture objectives it poses
    # What it builds for a structure (its symbolic functions: seconds for a large team), called with the structure
    # and ``construction_options``, once: kept for the next solve of that structure.
    construction: Callable[..., Built]
    construction_options: ClassVar[tuple] = ()

    def prepare(self, structure: Structure) -> None:
        """Build (once, cached) the symbolic functions for ``structure``; timed as set-up."""
        self.built(structure)

    def built(self, structure: Structure) -> Built:
        """``construction`` for ``structure``: built on first use, then kept (the last 128 structures)."""
        return _built(type(self).construction, structure, self.construction_options)

    def solve(
        self, problem: CaptureProblem, backend: SolvesData, warm_plan: np.ndarray | None, duals: WarmStart | None
    ) -> Solution:
        """Solve ``problem`` on ``backend``; the :class:`Solution` carries ``plan`` (N, n, 2)."""
        raise NotImplementedError


def separation_pairs(nc: int, nf: int) -> list[tuple[int, int]]:
    """Pairs (i, j) constrained apart: controlled–controlled (i < j) and controlled–held (j ≥ nc)."""
    return [(i, j) for i in range(nc) for j in range(i + 1, nc + nf)]
