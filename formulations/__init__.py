"""Formulations of the capture stage (Eqs. 12–15), one module each.

Each builds on the core of :mod:`mpc_hunt` (capture problem, model, backend
contract) and is found by name through :mod:`mpc_hunt.capture.registry`; importing this
package imports none of them.
"""
