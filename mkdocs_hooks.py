"""MkDocs hooks of the documentation site (mkdocs.yml): the studies' committed reports as pages.

Each study writes its report to ``studies/<study>/README.md`` beside its figures; the site serves them under
``studies/<study>/`` unchanged, so the Results section is the reports the studies' ``--check`` holds to the code.
The concept pages of docs/ link to them as ``../studies/<study>/README.md`` (right on GitHub, from docs/); on the
site they are pages beside docs/'s own, so those links lose their ``../``. A report's link to a file that is no page
(a study's script, its results) is written as the file's path in the repository.
"""

from __future__ import annotations

import re
from pathlib import Path

from mkdocs.structure.files import File, Files

ROOT = Path(__file__).resolve().parent
STUDIES = ROOT / "studies"
SHOWN = (".md", ".png")  # the reports and their figures
FILE_LINK = re.compile(r"\[([^\]]+)\]\((?!https?:)([^)#]+\.(?:py|json|db|toml))\)")


def on_files(files: Files, config) -> Files:
    for path in sorted(STUDIES.glob("*/*")):
        if path.suffix in SHOWN and (path.parent / "README.md").exists():
            files.append(File.generated(config, path.relative_to(ROOT).as_posix(), abs_src_path=str(path)))
    return files


def on_page_markdown(markdown: str, page, config, files) -> str:
    uri = page.file.src_uri
    if uri.startswith("studies/"):
        folder = Path(uri).parent

        def repository_path(match: re.Match) -> str:
            target = (Path("/") / folder / match.group(2)).resolve().relative_to("/")
            return f"{match.group(1)} (`{target.as_posix()}`)"

        return FILE_LINK.sub(repository_path, markdown)
    if "/" not in uri:  # a page of docs/ itself
        return markdown.replace("](../studies/", "](studies/")
    return markdown
