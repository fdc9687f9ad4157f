"""The capture stage ``mpc-hunt simulate`` runs unless told otherwise, and the paper's own.

RECOMMENDED is the paper's strategy with the capture-stage solver that captured
most often in the committed 500-hunt sweep of random hunts (studies/sweep/,
docs/robustness.md), every solve well inside the 0.1 s time step. PAPER is the
capture stage as published (the one-step NLP on IPOPT): the reproduction, the
problem sets and the Python ``simulate(scenario)`` without a controller use it.
"""

from __future__ import annotations

RECOMMENDED = {"formulation": "rti", "backend": "hpipm", "horizon": 5}
PAPER = {"formulation": "nlp", "backend": "ipopt", "horizon": 1}
