"""The README and the guide hang together and stay inside the repository.

* Every relative Markdown link in README.md and docs/*.md points to a file that exists, and its
  ``#anchor``, if any, to a heading of that page.
* Every path of the repository named in a page or in the source (``docs/model.md#classes`` in a
  docstring, ``tests/test_cli.py`` in a page) exists, with its anchor.
* Nothing sends a reader outside the repository: no page, docstring, comment or string literal (error
  messages included) names the notes and the paper that lived beside the repository during its
  development.
* The README and the guide lead to the page of the model, which cites the paper.
* The list of slow tests in docs/development.md names every test file that has one.
"""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
#: Every text a reader meets: the pages, the other Markdown files, the source and the CI script.
SOURCES = sorted({*PAGES, *ROOT.glob("*/*.md"), ROOT / ".ci" / "run",
                  *(p for folder in ("contin", "models", "studies", "tests", "examples")
                    for p in (ROOT / folder).rglob("*.py"))})
# [text](target) and ![alt](target "title"); fenced code and inline code are not links
LINK = re.compile(r"!?\[[^\]]*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
#: A path inside the repository as the text names it, with an optional anchor.
REPO_PATH = re.compile(r"(?<![\w/.])((?:contin|models|studies|tests|docs|examples)/[\w/.-]*\w\.(?:py|md|csv|json|toml|c))"
                       r"(?:#([\w-]+))?")
#: What the repository must not send a reader to: the development notes and the paper's text kept
#: beside it (``../shared/docs/physics.md``, ``design.md``, ``revolution.md``, ``../shared/seeds/...``).
OUTSIDE = re.compile(r"\.\./shared|shared/docs|shared/seeds|\.\./seeds/|\bphysics\.md|\bdesign\.md|\brevolution\.md"
                     r"|000_ce01afcb2c25b63a")
#: This file names what the scans look for, so they skip it.
THIS = Path(__file__).resolve()
MODEL_PAGE = ROOT / "docs" / "model.md"
PAPER_TITLE = "Snap-through eversion of axisymmetric shells under contact indentation"


def _without_code(text: str) -> str:
    return re.sub(r"```.*?```", "", text, flags=re.S)


def relative_links(page: Path) -> list[str]:
    """The relative link targets of a page (``file``, ``file#anchor`` or ``#anchor``), code excluded."""
    text = re.sub(r"`[^`\n]*`", "", _without_code(page.read_text()))
    targets = LINK.findall(text)
    # reference-style definitions: [label]: target
    targets += re.findall(r"^\s*\[[^\]]+\]:\s*(\S+)", text, flags=re.M)
    return [t for t in targets if not re.match(r"[a-zA-Z][a-zA-Z0-9+.-]*:", t)]


def heading_anchor(title: str) -> str:
    """The anchor GitHub gives a heading: lower case, punctuation dropped, spaces to hyphens."""
    title = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", title.strip())
    return re.sub(r"[^\w\- ]", "", title.lower()).replace(" ", "-")


def anchors(page: Path) -> set[str]:
    """The anchors of a page's headings (a repeated heading gets ``-1``, ``-2``, ... as on GitHub)."""
    seen: dict[str, int] = {}
    out = set()
    for title in re.findall(r"^#{1,6}[ \t]+(.+?)[ \t#]*$", _without_code(page.read_text()), flags=re.M):
        slug = heading_anchor(title)
        out.add(slug if slug not in seen else f"{slug}-{seen[slug]}")
        seen[slug] = seen.get(slug, 0) + 1
    return out


def missing_target(target: str, folder: Path, page: Path | None = None) -> str | None:
    """Why ``target`` does not resolve, or None.

    ``target`` is a path relative to ``folder`` with an optional ``#anchor``, or an anchor alone
    (``#anchor``) on ``page``.
    """
    path, _, anchor = target.partition("#")
    file = folder / path if path else page
    if file is None or not file.exists():
        return f"{target}: no such file"
    if anchor and file.suffix == ".md" and anchor not in anchors(file):
        return f"{target}: no heading with that anchor"
    return None


def outside_references(text: str) -> list[str]:
    """The lines of ``text`` (numbered from 1) that name something outside the repository."""
    return [f"{i}: {line.strip()}" for i, line in enumerate(text.splitlines(), 1) if OUTSIDE.search(line)]


def missing_repo_paths(text: str) -> list[str]:
    """The repository paths (with their anchors) named in ``text`` that do not resolve."""
    found = (missing_target(m.group(1) + (f"#{m.group(2)}" if m.group(2) else ""), ROOT) for m in REPO_PATH.finditer(text))
    return [why for why in found if why]


def _name(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


def test_the_readme_links_to_the_guide():
    assert "docs/guide.md" in relative_links(ROOT / "README.md")


def test_the_readme_and_the_guide_lead_to_the_model_page_which_cites_the_paper():
    assert "docs/model.md" in relative_links(ROOT / "README.md")
    assert "model.md" in relative_links(ROOT / "docs" / "guide.md")
    assert PAPER_TITLE in MODEL_PAGE.read_text()


@pytest.mark.parametrize("page", PAGES, ids=[_name(p) for p in PAGES])
def test_relative_links_resolve(page):
    missing = [why for t in relative_links(page) if (why := missing_target(t, page.parent, page))]
    assert not missing, f"{_name(page)} links to what does not exist: {missing}"


def test_every_named_repository_path_exists():
    missing = [f"{_name(p)}: {why}" for p in SOURCES if p != THIS for why in missing_repo_paths(p.read_text())]
    assert not missing, "paths named in the pages or the source that do not resolve:\n" + "\n".join(missing)


def test_nothing_points_outside_the_repository():
    found = [f"{_name(p)}:{hit}" for p in SOURCES if p != THIS for hit in outside_references(p.read_text())]
    assert not found, "references to files outside the repository:\n" + "\n".join(found)


def test_the_checks_flag_what_they_should():
    # the scans above find nothing on a clean tree; these texts show that they would find something
    assert outside_references("see ../shared/docs/physics.md section 5\nfine\n(``docs/revolution.md``)") == [
        "1: see ../shared/docs/physics.md section 5", "3: (``docs/revolution.md``)"]
    assert outside_references("the design notes (design.md)") and not outside_references("docs/development.md")
    assert missing_repo_paths("``docs/physics.md`` section 1") == ["docs/physics.md: no such file"]
    assert missing_repo_paths("docs/cli.md#no-such-section") == ["docs/cli.md#no-such-section: no heading with that anchor"]
    assert missing_repo_paths("(``docs/cli.md#contin-classify``), tests/test_docs_links.py, out/docs/x.md") == []
    assert heading_anchor("`contin trace` of the default scene, and what it writes") == \
        "contin-trace-of-the-default-scene-and-what-it-writes"
    assert heading_anchor("## 1. Exact derivatives".lstrip("# ")) == "1-exact-derivatives"


def test_every_file_with_slow_tests_is_listed():
    listed = (ROOT / "docs" / "development.md").read_text()
    with_slow = [p.name for p in sorted((ROOT / "tests").glob("test_*.py"))
                 if re.search(r"pytest\.mark\.slow\b", p.read_text())]
    assert with_slow
    missing = [name for name in with_slow if f"tests/{name}" not in listed]
    assert not missing, f"test files with slow tests missing from docs/development.md: {missing}"
