"""Solver backends, one module each; registered by name in :mod:`mpc_hunt.solving.registry`."""
