"""Build the static HTML book of the notebook series: ``python docs/build.py``.

1. Assemble the Sphinx source tree in ``build/book/src`` (fresh each time; nothing is copied into
   the repository): ``docs/index.md`` (README.md included + the toctrees), README.md, ``figures/``,
   every ``notebooks/*.ipynb`` (the numbered series, and pages index.md lists by name, such as
   the glossary) and the pages under ``docs/`` (results, guides, the API
   reference, whose per-name pages autosummary generates there). In the book's copy of a notebook
   the exercises are as the student edition has them: each solution stubbed, the hidden tests cut,
   no output of an answer or test cell (`student_exercises`); each figure gets its caption as alt
   text (``docs/slides.py`` finds the caption, as the slides show it).
2. Run ``sphinx-build -W --keep-going -n -E`` with ``docs/conf.py`` into ``build/book/html``
   (MyST-NB, stored outputs only, no execution, no network; autodoc imports ``ifslib``).
3. Check the result: index.html shows the README's title; each notebook page exists and holds
   at least one ``<img`` (its stored figure outputs), each with an alt text that is no file name,
   and no solution or hidden test; each results page (``docs/results/*.md``) exists and opens with
   a ``bash`` block, the command that regenerates it; every name of ``ifslib.__all__`` has an entry in the API reference; and no page loads a script or a style
   sheet from the network (MathJax is the book's own copy, from the npm package ``make book``
   installs into ``build/npm``).

Options: ``--no-check`` skips step 3; ``--check-only`` runs only step 3.
Exit status is non-zero on any warning, error or failed check.
"""

from __future__ import annotations

import argparse
import re
import shutil
import sys
import time
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT / "course"))
from scripts import load_script  # noqa: E402  course/scripts.py
BOOK = ROOT / "build" / "book"
SRC = BOOK / "src"
HTML = BOOK / "html"
DOCTREES = BOOK / "doctrees"
NOTEBOOK_GLOB = "[0-9][0-9]_*.ipynb"


def notebooks() -> list[Path]:
    found = sorted((ROOT / "notebooks").glob(NOTEBOOK_GLOB))
    if not found:
        sys.exit(f"no notebooks/{NOTEBOOK_GLOB} found under {ROOT}")
    return found


def _not_pages(folder: str, names: list[str]) -> set[str]:
    """What of docs/ is not a page of the book: the build's own files and the front page (copied to the root)."""
    skip = {n for n in names if n.endswith(".py") or n in ("__pycache__", "_templates")}
    return skip | ({"index.md"} if Path(folder) == DOCS else set())


def _empty_glob(entry: str, listed: set[str]) -> bool:
    """A toctree glob entry of index.md (``docs/*``) that matches no page of the assembled tree but those ``listed``."""
    if "*" not in entry or entry.startswith((":", "`")):
        return False
    found = {str(p.relative_to(SRC).with_suffix("")) for ext in (".md", ".ipynb", ".rst") for p in SRC.glob(entry + ext)}
    return not (found - listed)


#: MathJax's browser build, installed from the npm registry by ``make book`` (``build/npm``).
MATHJAX = ROOT / "build" / "npm" / "node_modules" / "mathjax" / "es5"
#: The parts of it the book loads: TeX and MathML in, HTML-CSS out with its fonts, the menu; the
#: speech engine (sre, 4 MB) and the SVG builds are left out.
MATHJAX_PARTS = ("tex-mml-chtml.js", "input", "output/chtml", "ui", "a11y", "adaptors")
#: ``docs/conf.py``'s ``html_static_path``: copied into the book's ``_static``.
STATIC = BOOK / "static"


def copy_mathjax() -> None:
    """Copy MathJax into the book's static files, so its formulas render with no network."""
    if not (MATHJAX / MATHJAX_PARTS[0]).is_file():
        sys.exit(f"MathJax is missing at {MATHJAX}: run `make book` (it installs the npm package mathjax)")
    shutil.rmtree(STATIC, ignore_errors=True)
    for part in MATHJAX_PARTS:
        source, target = MATHJAX / part, STATIC / "mathjax" / part
        if source.is_dir():
            shutil.copytree(source, target)
        elif source.is_file():
            target.parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, target)


def assemble() -> None:
    """Recreate build/book/src from the repository (copies into build/ only)."""
    copy_mathjax()
    shutil.rmtree(SRC, ignore_errors=True)
    (SRC / "notebooks").mkdir(parents=True)
    shutil.copy2(ROOT / "README.md", SRC / "README.md")
    shutil.copytree(ROOT / "figures", SRC / "figures")
    # The book's own pages keep their place (docs/results/x.md -> src/docs/results/x.md), so a link
    # in README.md or between pages resolves the same on GitHub and in the book.
    shutil.copytree(DOCS, SRC / "docs", ignore=_not_pages)
    # the numbered series and the notebooks index.md lists by name (the glossary), each a page
    for nb in sorted((ROOT / "notebooks").glob("*.ipynb")):
        student_exercises(nb, SRC / "notebooks" / nb.name)
    # index.md's toctrees glob docs/results/* and docs/* so that a page added there joins the book
    # without an edit here; a glob that matches no page yet is dropped (Sphinx would warn, and -W fail)
    lines = (DOCS / "index.md").read_text(encoding="utf-8").splitlines()
    listed = {line.strip() for line in lines if "/" in line and "*" not in line and not line.startswith(("`", ":"))}
    kept = [line for line in lines if not _empty_glob(line.strip(), listed)]
    (SRC / "index.md").write_text("\n".join(kept) + "\n", encoding="utf-8")
    _complete_api(SRC / "docs" / "api" / "index.md")


def _slides():
    """``docs/slides.py``, whose figure captions give the book's images their alt text."""
    return load_script("docs/slides.py", "ifslib_docs_slides")


def _student():
    """``notebooks/student.py``, which reads the solution markers (the student edition's tool)."""
    return load_script("notebooks/student.py", "ifslib_student_edition")


def student_exercises(source: Path, target: Path) -> int:
    """Copy the notebook ``source`` to ``target`` with its exercises as the student edition has them.

    Each marked solution (code or a written answer's model answer and rubric) is replaced by the
    student edition's stub, the hidden tests are cut from the test cells, and the outputs of answer and
    test cells are dropped (they print the answers): a student reading the book while an assignment is
    open learns no answer from it. Each figure's alt text is its caption (MyST-NB's own is the image
    file's name, a hash). Returns the number of exercise cells stubbed.
    """
    import nbformat

    student = _student()
    book = nbformat.read(source, as_version=4)
    for index, alt in _slides().alt_texts(book).items():
        options = book.cells[index].metadata.setdefault("mystnb", {})
        options["image"] = {**options.get("image", {}), "alt": alt}
    stubbed = 0
    for cell in book.cells:
        try:
            answer = student.is_exercise(cell)
            stub = student.CODE_STUB if cell.cell_type == "code" else student.MARKDOWN_STUB
            cell.source = student.HIDDEN.sub("", student.student_source(cell.source, stub))
        except student.MarkerError as error:
            sys.exit(f"{source.name}: {error}")
        stubbed += answer
        if cell.cell_type == "code" and (answer or student.is_test(cell)):
            cell.outputs, cell.execution_count = [], None
    nbformat.write(book, target)
    return stubbed


def _complete_api(page: Path) -> None:
    """Append to the API page an entry for each public name it does not list yet (a name exported since)."""
    import ifslib

    text = page.read_text(encoding="utf-8")
    listed = set(re.findall(r"^   (\w+)$", text, flags=re.M))
    missing = [name for name in ifslib.__all__ if name not in listed]
    if missing:
        entries = "\n".join(f"   {name}" for name in missing)
        text += ("\n## Other public names\n\n```{eval-rst}\n.. currentmodule:: ifslib\n\n.. autosummary::\n"
                 f"   :toctree: generated\n   :nosignatures:\n\n{entries}\n```\n")
        page.write_text(text, encoding="utf-8")


def sphinx() -> int:
    from sphinx.cmd.build import build_main

    shutil.rmtree(HTML, ignore_errors=True)
    args = [
        "-b", "html",
        "-c", str(DOCS),        # conf.py lives in docs/, the sources in build/book/src
        "-d", str(DOCTREES),
        "-E",                   # fresh environment: sources are re-copied every run
        "-W", "--keep-going",   # any warning fails the build (after reporting all of them)
        "-n",                   # nitpicky: unresolved references are warnings too
        "-q",
        str(SRC), str(HTML),
    ]
    return build_main(args)


def check() -> list[str]:
    """Sanity checks on the built site; returns the problems found."""
    problems = []
    index = HTML / "index.html"
    if not index.is_file():
        return [f"missing {index}"]
    text = index.read_text(encoding="utf-8")
    if not re.search(r"<h1[^>]*>\s*ifslib", text):
        problems.append("index.html: no <h1> starting with the README's title 'ifslib'")
    for name in re.findall(r"!\[\]\((figures/[^)]+)\)", (ROOT / "README.md").read_text()):
        if not (HTML / "_images" / Path(name).name).is_file():
            problems.append(f"index.html: README image {name} was not copied to _images/")
    for nb in notebooks():
        page = HTML / "notebooks" / f"{nb.stem}.html"
        if not page.is_file():
            problems.append(f"missing {page.relative_to(ROOT)}")
            continue
        body = page.read_text(encoding="utf-8")
        if "<img" not in body:
            problems.append(f"{page.relative_to(ROOT)}: no <img> (stored figure outputs missing)")
        problems += check_folded(nb, page, body) + check_alt(page, body)
        if f'href="notebooks/{nb.stem}.html"' not in text:
            problems.append(f"index.html: no toctree link to notebooks/{nb.stem}.html")
    problems += check_results() + check_api() + check_offline()
    return problems


def check_folded(nb: Path, page: Path, body: str) -> list[str]:
    """The page of ``nb`` shows none of its solution lines and none of its hidden tests' lines."""
    import html
    import nbformat

    book = nbformat.read(nb, as_version=4)
    answers = _student().solution_lines(book) | _student().hidden_lines(book)
    shown = html.unescape(re.sub(r"<[^>]+>", "", body))
    # whole lines: a solution line may be a part of a longer line that the page rightly shows
    found = sorted(answers & {line.strip() for line in shown.splitlines()})
    if "BEGIN SOLUTION" in body or "BEGIN HIDDEN TESTS" in body or found:
        return [f"{page.relative_to(ROOT)}: an answer or a hidden test shown: {(found or ['its markers'])[0]!r}"]
    return []


#: an alt text that names a file instead of saying what the image shows: a hash, a path
HASH_ALT = re.compile(r"^([0-9a-f]{16,}|.*\.(png|jpe?g|svg|gif))$", re.I)


def check_alt(page: Path, body: str) -> list[str]:
    """Every image of a notebook's page has an alt text that says what it shows (its caption)."""
    import html

    alts = [html.unescape(alt) for alt in re.findall(r'<img[^>]*\balt="([^"]*)"', body)]
    missing = len(re.findall(r"<img\b", body)) - len(alts)
    bad = [alt for alt in alts if not alt.strip() or HASH_ALT.match(alt.strip().rsplit("/", 1)[-1])]
    if missing or bad:
        return [f"{page.relative_to(ROOT)}: {missing + len(bad)} image(s) without a caption as alt text, "
                f"e.g. {(bad or ['(no alt)'])[0]!r}"]
    return []


def check_offline() -> list[str]:
    """No page loads a script or style sheet from another host (MathJax from a CDN, say)."""
    problems = []
    for page in sorted(HTML.rglob("*.html")):
        for url in re.findall(r'<(?:script|link)[^>]+(?:src|href)="((?:https?:)?//[^"]+)"', page.read_text(encoding="utf-8")):
            problems.append(f"{page.relative_to(ROOT)}: loads {url} from the network")
    if not (HTML / "_static" / "mathjax" / "tex-mml-chtml.js").is_file():
        problems.append("the book has no MathJax of its own in _static/mathjax")
    return problems[:20]


def check_results() -> list[str]:
    """Each results page (docs/results/*.md) is built and opens with the command that regenerates it."""
    problems = []
    for md in sorted((DOCS / "results").glob("*.md")):
        body = md.read_text(encoding="utf-8").split("\n## ")[0]
        if "```bash" not in body:
            problems.append(f"{md.relative_to(ROOT)}: no ```bash block (the command that regenerates it) before its first section")
        if not (HTML / "docs" / "results" / f"{md.stem}.html").is_file():
            problems.append(f"missing docs/results/{md.stem}.html")
    return problems


def check_api() -> list[str]:
    """Every public name of ifslib (``ifslib.__all__``) has an entry in the API reference."""
    import ifslib

    pages = HTML / "docs" / "api" / "generated"
    problems = []
    for name in ifslib.__all__:
        page = pages / f"ifslib.{name}.html"
        anchors = (f'id="ifslib.{name}"', f'id="module-ifslib.{name}"')
        if not page.is_file() or not any(a in page.read_text(encoding="utf-8") for a in anchors):
            problems.append(f"API reference: no entry for ifslib.{name} (add it to docs/api/index.md)")
    return problems


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-check", action="store_true", help="skip the sanity checks")
    parser.add_argument("--check-only", action="store_true", help="only check build/book/html")
    args = parser.parse_args()

    if not args.check_only:
        start = time.perf_counter()
        assemble()
        status = sphinx()
        if status:
            print(f"sphinx-build failed (status {status})", file=sys.stderr)
            return status
        print(f"built {HTML.relative_to(ROOT)}/index.html in {time.perf_counter() - start:.1f} s")
    if not args.no_check:
        problems = check()
        for p in problems:
            print(f"check failed: {p}", file=sys.stderr)
        if problems:
            return 1
        import ifslib

        print(f"checks passed: index.html, {len(notebooks())} notebook pages with figures, "
              f"{len(list((DOCS / 'results').glob('*.md')))} results pages, {len(ifslib.__all__)} API entries")
    return 0


if __name__ == "__main__":
    sys.exit(main())
