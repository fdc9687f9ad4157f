"""Problem sets shipped with the package (JSON; see mpc_hunt.bench.problem_set)."""
