"""MkDocs hooks of the documentation site (mkdocs.yml): the studies' committed reports and the formulations folder's
table as pages.

Each study writes its report to ``studies/<study>/README.md`` beside its figures; the site serves them under
``studies/<study>/`` unchanged, so the Results section is the reports the studies' ``--check`` holds to the code.
The concept pages of docs/ link to them as ``../studies/<study>/README.md`` (right on GitHub, from docs/); on the
site they are pages beside docs/'s own, so those links lose their ``../``. A report's link to a file that is no page
(a study's script, its results) is written as the file's path in the repository.

``formulations/README.md`` (each formulation, its module, kind and default backend; how to add one) is the page
``formulations-folder.md``; its links into docs/ become the pages', its link to the code the folder's path.

The docstrings cross-reference in Sphinx's roles (``:class:`~mpc_hunt.capture.solution.Solution```), which Markdown
renders as the role's name before the code; the reference shows the code alone, ``~`` keeping the last name only,
as Sphinx does.
"""

from __future__ import annotations

import re
from pathlib import Path

from mkdocs.structure.files import File, Files

ROOT = Path(__file__).resolve().parent
STUDIES = ROOT / "studies"
SHOWN = (".md", ".png")  # the reports and their figures
FORMULATIONS = ROOT / "formulations" / "README.md"
FORMULATIONS_PAGE = "formulations-folder.md"
CODE_LINK = re.compile(r"\[([^\]]+)\]\(\.\./(mpc_hunt/[^)]*)\)")
ROLE = re.compile(r":(?:class|meth|func|mod|data|attr|exc|obj):<code>(~?)([^<]*)</code>")
FILE_LINK = re.compile(r"\[([^\]]+)\]\((?!https?:)([^)#]+\.(?:py|json|db|toml))\)")


def on_files(files: Files, config) -> Files:
    for path in sorted(STUDIES.glob("*/*")):
        if path.suffix in SHOWN and (path.parent / "README.md").exists():
            files.append(File.generated(config, path.relative_to(ROOT).as_posix(), abs_src_path=str(path)))
    files.append(File.generated(config, FORMULATIONS_PAGE, abs_src_path=str(FORMULATIONS)))
    return files


def on_page_markdown(markdown: str, page, config, files) -> str:
    uri = page.file.src_uri
    if uri == FORMULATIONS_PAGE:
        markdown = CODE_LINK.sub(lambda m: f"{m.group(1)} (`{m.group(2)}`)", markdown)
        return markdown.replace("](../docs/", "](")
    if uri.startswith("studies/"):
        folder = Path(uri).parent

        def repository_path(match: re.Match) -> str:
            target = (Path("/") / folder / match.group(2)).resolve().relative_to("/")
            return f"{match.group(1)} (`{target.as_posix()}`)"

        return FILE_LINK.sub(repository_path, markdown)
    if "/" not in uri:  # a page of docs/ itself
        return markdown.replace("](../studies/", "](studies/")
    return markdown


def on_page_content(html: str, page, config, files) -> str:
    return ROLE.sub(lambda m: f"<code>{m.group(2).rsplit('.', 1)[-1] if m.group(1) else m.group(2)}</code>", html)
