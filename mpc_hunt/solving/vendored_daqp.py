"""DAQP's C sources, vendored in ``vendor/daqp/`` (MIT, from its PyPI sdist): where they are, their version and digest.

The ``daqp-condensed`` backend compiles them into its step's library
(:mod:`mpc_hunt.solving.backends.condensed_compiled`) and the C export copies them
next to the step (:mod:`mpc_hunt.solving.export`). Their version is ``vendor/daqp/VERSION``,
the version pyproject.toml pins DAQP's Python package to (``vendor/daqp/README.md``), so
that the compiled step and its interpreted fallback run the same DAQP.
"""

from __future__ import annotations

import hashlib
from functools import cache
from pathlib import Path

DAQP_SOURCES = Path(__file__).resolve().parent / "vendor" / "daqp"
DAQP_VERSION = (DAQP_SOURCES / "VERSION").read_text(encoding="utf-8").strip()


@cache
def daqp_digest() -> str:
    """The vendored DAQP sources' SHA-256, so that a changed copy never loads a stale library."""
    digest = hashlib.sha256()
    for path in sorted(DAQP_SOURCES.rglob("*.[ch]")):
        digest.update(path.read_bytes())
    return digest.hexdigest()


def daqp_sources() -> list[Path]:
    """DAQP's C files, to compile with the step."""
    return sorted((DAQP_SOURCES / "src").glob("*.c"))
