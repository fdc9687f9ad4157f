"""Problem sets shipped with the package (JSON; see mpc_hunt.problem_set)."""
