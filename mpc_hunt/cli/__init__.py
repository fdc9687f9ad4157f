"""The command line, `mpc-hunt`: one module for the commands, one for the sweep's, one for what they share."""

from mpc_hunt.cli.commands import main

__all__ = ["main"]
