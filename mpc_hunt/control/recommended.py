"""The capture-stage settings a solving controller runs with unless told otherwise, defined once for the command
line, the sweep, the environments and the Python API (:class:`mpc_hunt.control.spec.ControllerSpec` applies them;
``HuntingStrategy``, ``CaptureMPC`` and ``CaptureSolver`` default none: they are told theirs).

RECOMMENDED_CONTROLLER with RECOMMENDED's solver settings is, among the solving
controllers, the one that captures the largest share of the comfortable hunts
averaged over every attacker behaviour in the committed attackers study, or, where
the paired 95 % interval of their captures cannot tell it from that one, the quicker
(studies/attackers/; its ``--check`` fails otherwise; the Voronoi baseline, which
solves nothing, captures a little less: 61.2 % to its 64.8 %), every solve well inside the 0.1 s time step: the trap
controller (docs/model.md, E16), which reads nothing of the attacker's law, with
its capture problem on rti and HPIPM over ten steps. Chosen over every attacker,
not over the paper's alone: against the paper's attacker the enclose controller,
which is given that attacker's law, does about as well, and against any other it
loses most hunts. RECOMMENDED is the default of
every solving controller (:data:`~mpc_hunt.control.controllers.SOLVING`) by
name: ``mpc-hunt simulate --controller C``, the sweep's ``--strategy C``, the
environments' controller C and ``make_controller(C, scenario)`` all run ``ControllerSpec(C)``. PAPER is the
capture stage as published (the one-step NLP on IPOPT): ``mpc-hunt solve``, the
reproduction, the problem sets and the Python ``simulate(scenario)`` without a
controller use it. A formulation other than the default's runs on its own
default backend over OTHER_HORIZON steps.
"""

RECOMMENDED_CONTROLLER = "trap"
"""The recommended controller's name (the module's docstring): what ``mpc-hunt simulate`` runs by default."""
RECOMMENDED = {"formulation": "rti", "backend": "hpipm", "horizon": 10}
"""The recommended capture stage: the formulation, its backend and the horizon a solving controller runs with
unless told otherwise."""
PAPER = {"formulation": "nlp", "backend": "ipopt", "horizon": 1}
"""The paper's capture stage as published: the one-step NLP on IPOPT."""
OTHER_HORIZON = 1  # the horizon of a formulation other than the default's, unless one is given
