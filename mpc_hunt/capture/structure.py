"""What fixes a formulation's sizes and expressions: a capture problem's structure.

Two problems of one structure differ only in numbers, so a formulation builds
its CasADi model once per structure and a backend sets its solver up once per
structure; a new structure (a defender joins the capture stage, a horizon
changes) is a new build.
"""

from __future__ import annotations

from dataclasses import dataclass, replace


@dataclass(frozen=True)
class Structure:
    """The defenders planned and held fixed, the obstacles, the horizon N and the objective.

    ``robot``: the problem of one robot of a team that plans apart (the ``distributed`` formulation): it plans
    itself (``planned`` = 1); ``fixed`` counts its neighbour slots, the nearest team-mates at each step, whose
    separation rows it keeps; the whole team's push on the attacker comes step by step in its parameters.
    """

    planned: int
    fixed: int
    obstacles: int
    horizon: int
    objective: str = "paper"
    robot: bool = False

    def __str__(self) -> str:
        if self.robot:
            return (
                f"one robot of a team with {self.fixed} neighbour slots, {self.obstacles} obstacles, "
                f"horizon {self.horizon}, objective {self.objective}"
            )
        return (
            f"{self.planned} planned and {self.fixed} held defenders, {self.obstacles} obstacles, "
            f"horizon {self.horizon}, objective {self.objective}"
        )

    @property
    def defenders(self) -> int:
        return self.planned + self.fixed

    @property
    def plan_size(self) -> int:
        """Numbers in the planned defenders' positions over the horizon: N · n_c · 2."""
        return self.horizon * self.planned * 2

    @property
    def reference_steps(self) -> int:
        """Steps of the reference the parameters carry: the ``enclose`` objective's N, the paper's none."""
        return self.horizon if self.objective == "enclose" else 0

    @property
    def stage(self) -> "Structure":
        """The structure of one stage (horizon 1): what a stage-wise model depends on."""
        return replace(self, horizon=1)
