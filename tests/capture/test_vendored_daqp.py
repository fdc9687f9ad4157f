"""One DAQP: the vendored C sources (the compiled ``daqp-condensed`` step, the C export) are the version of the Python
package (the interpreted step), pinned in one place."""

from __future__ import annotations

import importlib.metadata
import tomllib
from pathlib import Path

from packaging.requirements import Requirement

from mpc_hunt.solving.vendored_daqp import DAQP_SOURCES, DAQP_VERSION

ROOT = Path(__file__).resolve().parents[2]


def test_the_vendored_sources_are_the_installed_packages_version():
    """DAQP's C API declares no version (no macro nor call in its headers): the vendored copy's is ``VERSION``."""
    assert not any("version" in path.read_text(encoding="utf-8").lower()
                   for path in (DAQP_SOURCES / "include").glob("*.h"))
    assert DAQP_VERSION == importlib.metadata.version("daqp")


def test_pyproject_pins_daqp_to_the_vendored_version():
    dependencies = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["dependencies"]
    daqp = [Requirement(d) for d in dependencies if Requirement(d).name == "daqp"]
    assert [str(r.specifier) for r in daqp] == [f"=={DAQP_VERSION}"]
