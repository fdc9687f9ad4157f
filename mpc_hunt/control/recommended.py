"""The controller ``mpc-hunt simulate`` runs unless told otherwise, and the paper's capture stage.

RECOMMENDED_CONTROLLER with RECOMMENDED's solver settings is the strategy that
captured most often in the committed 500-hunt sweep of random hunts
(studies/sweep/, docs/robustness.md), every solve well inside the 0.1 s time
step: the enclose controller (docs/formulations.md, "Objectives") with its
capture problem on rti and HPIPM over ten steps,
``make_controller(RECOMMENDED_CONTROLLER, scenario, **RECOMMENDED)``. The
solver settings are also the CLI's default for ``--controller paper``. PAPER
is the capture stage as published (the one-step NLP on IPOPT): the
reproduction, the problem sets and the Python ``simulate(scenario)`` without a
controller use it.
"""

from __future__ import annotations

RECOMMENDED_CONTROLLER = "enclose"
RECOMMENDED = {"formulation": "rti", "backend": "hpipm", "horizon": 10}
PAPER = {"formulation": "nlp", "backend": "ipopt", "horizon": 1}
