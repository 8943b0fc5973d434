"""The README stays short and points at files that exist; its Python example is the getting-started one and
compiles; the docs sources hold the sections the site promises."""
from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _python_blocks(text: str) -> list:
    return re.findall(r"```python\n(.*?)```", text, re.S)


def test_readme_is_short_and_its_files_exist():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 150
    for ref in re.findall(r"\]\(([^)#]+)\)", text):  # images and links into the repository
        if "://" not in ref:
            assert (ROOT / ref).exists(), ref
    for name in ("LICENSE", "CITATION.cff", "CONTRIBUTING.md", "docs/conf.py"):
        assert (ROOT / name).is_file(), name
    for command in ("make app", "make test", "ringlab serve", "make docs"):
        assert command in text, command


def test_readme_example_is_the_getting_started_example_and_compiles():
    readme = _python_blocks((ROOT / "README.md").read_text(encoding="utf-8"))
    start = _python_blocks((ROOT / "docs" / "getting-started.md").read_text(encoding="utf-8"))
    example = readme[0]
    assert len(example.strip().splitlines()) <= 12 and example in start
    compile(example, "README example", "exec")


def test_docs_sections_exist():
    docs = ROOT / "docs"
    for page in ("index.md", "getting-started.md", "teacher/index.md", "teacher/hosting.md", "teacher/lessons.md",
                 "researcher/index.md", "researcher/engine.md", "researcher/cli.md", "researcher/runfiles.md",
                 "researcher/sweeps.md", "researcher/reproduce.md", "science/index.md", "science/model.md",
                 "science/verification.md", "science/departures.md", "science/longruns.md", "benchmarks/index.md",
                 "api/index.md", "tutorials/index.md", "changelog.md"):
        assert (docs / page).is_file(), page
    assert ":glob:" in (docs / "science" / "index.md").read_text()  # pages added to docs/science/ are included
    assert "build_parser" in (docs / "researcher" / "cli.md").read_text()  # the CLI reference is generated
