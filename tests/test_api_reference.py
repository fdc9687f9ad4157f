"""The API reference (docs/reference/) and the public API (``__all__``) held together: every public subpackage has
its page, every page renders exactly its package's ``__all__``, every name of ``mpc_hunt.__all__`` is in the
reference's index, and every one of them has a docstring for the site to show. ``mkdocs build --strict`` (CI) fails
on a name a page lists that does not exist, and on a broken link or a missing page."""

from __future__ import annotations

import importlib
import pkgutil
import re
from pathlib import Path

import pytest

import mpc_hunt

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = ROOT / "docs" / "reference"
INTERNAL = {"formulations"}  # found by name through the registry; the reference's index says so
ERRORS = "errors"  # the exceptions exported at the top, documented on the index page


def subpackages() -> list[str]:
    return sorted(m.name for m in pkgutil.iter_modules(mpc_hunt.__path__) if m.ispkg)


def public() -> list[str]:
    return [name for name in subpackages() if name not in INTERNAL]


def listed(page: Path, module: str) -> list[str]:
    """The members the page's ``::: module`` block renders."""
    text = page.read_text(encoding="utf-8")
    block = text.split(f"::: {module}\n", 1)[1]
    members = block.split("members:\n", 1)[1]
    return re.findall(r"^ {8}- (\w+)$", members.split("\n\n", 1)[0], flags=re.M)


def test_every_subpackage_is_public_with_its_page_or_named_internal_on_the_index():
    index = (REFERENCE / "index.md").read_text(encoding="utf-8")
    for name in subpackages():
        module = importlib.import_module(f"mpc_hunt.{name}")
        if name in INTERNAL:
            assert not hasattr(module, "__all__") and f"`mpc_hunt.{name}`" in index, name
        else:
            assert module.__all__ and (REFERENCE / f"{name}.md").exists(), name
    assert {p.stem for p in REFERENCE.glob("*.md")} == set(public()) | {"index"}


@pytest.mark.parametrize("name", public())
def test_the_page_renders_exactly_the_packages_all(name):
    module = importlib.import_module(f"mpc_hunt.{name}")
    assert sorted(listed(REFERENCE / f"{name}.md", f"mpc_hunt.{name}")) == sorted(module.__all__)


def test_every_name_of_the_package_is_in_the_index_where_it_is_documented():
    index = (REFERENCE / "index.md").read_text(encoding="utf-8")
    errors = listed(REFERENCE / "index.md", f"mpc_hunt.{ERRORS}")
    for name in mpc_hunt.__all__:
        if name == "__version__":
            assert "| `__version__` |" in index
        elif name in errors:
            assert getattr(mpc_hunt, name) is getattr(importlib.import_module(f"mpc_hunt.{ERRORS}"), name)
            assert f"| `{name}` |" in index, name
        else:
            home = re.search(rf"^\| \[`{name}`\]\[mpc_hunt\.(\w+)\.{name}\] \|", index, flags=re.M)
            assert home, f"{name}: no row in docs/reference/index.md"
            package = importlib.import_module(f"mpc_hunt.{home.group(1)}")
            assert name in package.__all__ and getattr(package, name) is getattr(mpc_hunt, name), name
    rows = re.findall(r"^\| \[?`(\w+)`", index, flags=re.M)
    assert sorted(rows) == sorted(mpc_hunt.__all__)


def test_the_examples_public_api_is_the_references():
    from test_examples import PUBLIC_MODULES

    assert set(PUBLIC_MODULES) == {"mpc_hunt"} | {f"mpc_hunt.{name}" for name in public()}


def test_every_public_name_has_a_docstring_the_site_shows():
    griffe = pytest.importorskip("griffe")  # griffelib, in the test extra (and the docs one, through mkdocstrings)
    loader = griffe.GriffeLoader(search_paths=[str(ROOT)])
    package = loader.load("mpc_hunt")
    loader.resolve_aliases(implicit=True, external=False)
    pages = {name: listed(REFERENCE / f"{name}.md", f"mpc_hunt.{name}") for name in public()}
    pages[ERRORS] = listed(REFERENCE / "index.md", f"mpc_hunt.{ERRORS}")
    missing = []
    for module, names in pages.items():
        for name in names:
            target = package[f"{module}.{name}"]
            target = target.final_target if target.is_alias else target
            if target.docstring is None or not target.docstring.value.strip():
                missing.append(f"mpc_hunt.{module}.{name}")
    assert missing == []
