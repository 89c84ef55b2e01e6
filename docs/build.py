"""Build the static HTML book of the notebook series: ``python docs/build.py``.

1. Assemble the Sphinx source tree in ``build/book/src`` (fresh each time; nothing is copied into
   the repository): ``docs/index.md`` (README.md included + the toctree), README.md, ``figures/``
   and every ``notebooks/[0-9][0-9]_*.ipynb``.
2. Run ``sphinx-build -W --keep-going -n -E`` with ``docs/conf.py`` into ``build/book/html``
   (MyST-NB, stored outputs only, no execution, no network).
3. Check the result: index.html shows the README's title and each notebook page exists and holds
   at least one ``<img`` (its stored figure outputs).

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


def assemble() -> None:
    """Recreate build/book/src from the repository (copies into build/ only)."""
    shutil.rmtree(SRC, ignore_errors=True)
    (SRC / "notebooks").mkdir(parents=True)
    shutil.copy2(DOCS / "index.md", SRC / "index.md")
    shutil.copy2(ROOT / "README.md", SRC / "README.md")
    shutil.copytree(ROOT / "figures", SRC / "figures")
    for nb in notebooks():
        shutil.copy2(nb, SRC / "notebooks" / nb.name)


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
        if f'href="notebooks/{nb.stem}.html"' not in text:
            problems.append(f"index.html: no toctree link to notebooks/{nb.stem}.html")
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
        print(f"checks passed: index.html + {len(notebooks())} notebook pages with figures")
    return 0


if __name__ == "__main__":
    sys.exit(main())
