"""The command line, `mpc-hunt`: one module for the commands, one for the sweep's, one for what they share."""

from __future__ import annotations

import sys

EXIT_INTERRUPTED = 130  # Ctrl-C's (128 + SIGINT), as mpc_hunt.arguments has it: set before any import can be cut


def main(argv: list[str] | None = None) -> int:
    """Run ``mpc-hunt`` with the arguments ``argv`` (default: the process's) and return its exit status, as
    :func:`mpc_hunt.cli.commands.main` does: ``mpc_hunt.cli.main(["simulate", "--json"])`` runs a command from
    Python as the shell would. Ctrl-C while the commands are still being imported is one line on stderr,
    ``mpc-hunt: interrupted``, and status 130, never a traceback."""
    try:
        from mpc_hunt.cli.commands import main as run
    except KeyboardInterrupt:
        print("mpc-hunt: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    return run(argv)


__all__ = ["main"]
