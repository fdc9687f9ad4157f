"""Formulations of the capture stage (Eqs. 12–15), one module each.

Each builds on the capture contract (:mod:`mpc_hunt.capture`: the problem, its structure, the data kinds, the
solution) and nothing above it, and is found by name through :mod:`mpc_hunt.solving.registry`; importing this
package imports none of them.
"""
