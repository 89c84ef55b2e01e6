"""Slides for the lectures: ``python docs/slides.py [PREFIX ...]`` (``make slides``).

One reveal.js deck per lecture notebook (``notebooks/[0-9][0-9]_*.ipynb``, or those whose name starts
with a PREFIX given), written to ``build/slides/NAME.html`` by nbconvert's ``SlidesExporter`` from the
notebook's own cells and their stored outputs: nothing is executed, and the notebook file is never
written (the slide types are given to an in-memory copy).

Which cell goes where (the notebooks carry no ``slideshow`` metadata; this rule gives each cell one,
from the lesson's structure):

* a markdown cell that opens with a ``#`` or ``##`` heading starts a **slide** (a step of the lesson,
  left to right);
* any other markdown cell (a ``###`` heading, the sentence of why, an exercise) starts a **sub-slide**
  (downwards, within the step);
* a code cell right after a short markdown cell (at most ``SHORT_MARKDOWN`` lines) is a **fragment** of
  that sub-slide: the explanation shows first, the call and its picture or number appear on the next
  key press; a code cell after a longer explanation or after another code cell starts a sub-slide of
  its own;
* **skipped**: the ``parameters`` cell (the preset's sizes, set by ``notebooks/run.py``), the one- or
  two-line markdown cell that introduces it, and empty cells;
* **speaker notes** (shown only in the speaker view, key ``S``): cells tagged ``solution``, markdown
  cells nbgrader marks as solutions, and every cell of a ``#``/``##`` section whose title starts with
  "Solution", so the students' screen does not show the answers; in an exercise cell, a worked answer
  between nbgrader's ``### BEGIN SOLUTION`` and ``### END SOLUTION`` becomes ``...  # YOUR CODE HERE``
  and the cell's stored output is dropped (as in the student edition, ``notebooks/student.py``);
* long outputs are shrunk: a text output keeps its first ``MAX_LINES`` lines and says how many were
  cut; pictures are scaled to fit the slide (CSS); an interactive widget, which needs a kernel, is
  replaced by a line saying so; a sub-slide still taller than the screen scrolls.

Offline: reveal.js and MathJax are the npm packages under ``build/npm`` (``make slides`` installs
them), referenced by paths relative to ``build/slides/``, so a deck opens from disk with no network;
require.js, jQuery, mermaid and the widget manager, which the template would take from a CDN, are left
out (the decks do not use them). The script fails when a written deck still names an ``http(s)://``
script or style sheet (the local style sheets it links are read too, with their ``@import``s: most
reveal.js themes import Google Fonts, so the theme is "white", whose fonts ship with reveal.js), or
when reveal.js or MathJax is missing.
"""

from __future__ import annotations

import argparse
import copy
import html.parser
import re
import sys
from pathlib import Path

import nbformat

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
OUT = ROOT / "build" / "slides"
NPM = ROOT / "build" / "npm" / "node_modules"
NOTEBOOK_GLOB = "[0-9][0-9]_*.ipynb"
#: reveal.js and MathJax as seen from a deck in build/slides/ (opened as a file).
REVEAL_PREFIX = "../npm/node_modules/reveal.js"
MATHJAX_URL = "../npm/node_modules/mathjax/es5/tex-mml-chtml.js"
#: "white": its fonts are reveal.js's own files ("simple" and most others @import Google Fonts).
THEME = "white"
REVEAL_FILES = ("dist/reveal.js", "dist/reveal.css", f"dist/theme/{THEME}.css", "plugin/notes/notes.js")
MAX_LINES = 12          # lines of a text output kept on a slide
SHORT_MARKDOWN = 6      # lines: a code cell after a longer explanation starts its own sub-slide
WIDGET_MIME = "application/vnd.jupyter.widget-view+json"
#: nbgrader's markers of a worked answer inside an exercise cell (see notebooks/student.py).
SOLUTION_BLOCK = re.compile(r"^([ \t]*)### BEGIN SOLUTION[ \t]*\n.*?^[ \t]*### END SOLUTION[ \t]*(\n|$)", re.M | re.S)
WIDGET_NOTE = "(an interactive widget: run the notebook in JupyterLab to use it)"

# The reveal template of nbconvert, with what it takes from a CDN replaced by the local copies:
# MathJax 3 (the template's script speaks MathJax 2), reveal.js loaded by <script> (no require.js).
TEMPLATE = r"""{%- extends 'index.html.j2' -%}
{%- block html_head_js -%}{%- endblock html_head_js -%}
{% block jupyter_widgets %}{% endblock jupyter_widgets %}
{%- block html_head_js_mathjax -%}
<script>
window.MathJax = {
  tex: {inlineMath: [['$', '$'], ['\\(', '\\)']], displayMath: [['$$', '$$'], ['\\[', '\\]']],
        processEscapes: true, processEnvironments: true, tags: 'ams'},
  options: {ignoreHtmlClass: 'jp-OutputArea|highlight', processHtmlClass: 'jp-MarkdownOutput'}
};
</script>
<script src="{{ resources.mathjax_url }}"></script>
{%- endblock html_head_js_mathjax -%}
{%- block html_head_css -%}
<style type="text/css">
/* the theme's sizes are for a few words a slide; a lesson's paragraphs and code need smaller ones */
.reveal { --r-main-font-size: 26px; --r-heading1-size: 1.7em; --r-heading2-size: 1.35em;
          --r-heading3-size: 1.1em; --r-heading-text-transform: none; }
.reveal .slides { text-align: left; }
:root { --jp-code-font-size: 16px; --jp-cell-prompt-width: 72px; }   /* an 88-character line fits */
/* a sub-slide taller than the screen scrolls (mouse wheel) instead of running off it */
.reveal .slides > section:not(.stack), .reveal .slides > section > section {
  height: 100%; overflow-y: auto; }
.reveal .jp-OutputArea-output img { max-height: 480px; width: auto; }
.reveal .jp-OutputArea-output pre { max-height: 320px; overflow: auto; }
.reveal .jp-InputArea pre { max-height: 300px; overflow: auto; }
</style>
{%- endblock html_head_css -%}
{% block footer_js %}
<script src="{{ resources.reveal.url_prefix }}/dist/reveal.js"></script>
<script src="{{ resources.reveal.url_prefix }}/plugin/notes/notes.js"></script>
<script>
Reveal.initialize({
  controls: true, progress: true, history: true, center: false,
  transition: "{{ resources.reveal.transition | default('slide', true) }}",
  slideNumber: "c/t",
  width: {{ resources.reveal.width | default('1100', true) }},
  height: {{ resources.reveal.height | default('750', true) }},
  plugins: [RevealNotes]
});
</script>
{% endblock footer_js %}
"""


def _heading(cell) -> tuple[int, str] | None:
    """(level, title) of the markdown heading a cell opens with, else None."""
    match = re.match(r"\s*(#{1,6})\s+(.*)", cell.source)
    return (len(match.group(1)), match.group(2).strip()) if cell.cell_type == "markdown" and match else None


def _shrink_outputs(cell) -> None:
    for out in cell.get("outputs", []):
        data = out.get("data", {})
        if WIDGET_MIME in data:
            out["data"] = {"text/plain": WIDGET_NOTE}
            continue
        for key, text in ((k, data[k]) for k in ("text/plain",) if k in data):
            data[key] = _cut(text)
        if out.get("output_type") == "stream":
            out["text"] = _cut(out["text"])


def _cut(text: str) -> str:
    lines = text.splitlines()
    if len(lines) <= MAX_LINES:
        return text
    return "\n".join(lines[:MAX_LINES] + [f"... ({len(lines) - MAX_LINES} more lines in the notebook)"])


def slide_types(nb) -> list[str]:
    """The slide type of each cell of ``nb`` by the rule of this module's docstring."""
    types, previous, lines, in_solutions = [], None, 0, False
    cells = nb.cells
    for index, cell in enumerate(cells):
        head = _heading(cell)
        if head and head[0] <= 2:
            in_solutions = head[1].lower().startswith("solution")
        tags = cell.metadata.get("tags", [])
        before_parameters = (index + 1 < len(cells) and "parameters" in cells[index + 1].metadata.get("tags", [])
                             and cell.cell_type == "markdown" and not head
                             and len(cell.source.strip().splitlines()) <= 2)
        if not cell.source.strip() or "parameters" in tags or before_parameters:
            kind = "skip"
        elif in_solutions or "solution" in tags or "solutions" in tags or (
                cell.cell_type == "markdown" and cell.metadata.get("nbgrader", {}).get("solution")):
            kind = "notes"
        elif head and head[0] <= 2:
            kind = "slide"
        elif cell.cell_type == "markdown":
            kind = "subslide"
        else:
            kind = "fragment" if previous == "markdown" and lines <= SHORT_MARKDOWN else "subslide"
        if kind not in ("skip", "notes"):
            previous, lines = cell.cell_type, len(cell.source.strip().splitlines())
        types.append(kind)
    return types


def lecture_copy(nb):
    """An in-memory copy of ``nb`` with slide types and shrunk outputs, and no saved widget state."""
    nb = copy.deepcopy(nb)
    nb.metadata.pop("widgets", None)
    for cell, kind in zip(nb.cells, slide_types(nb)):
        cell.metadata["slideshow"] = {"slide_type": kind}
        if cell.cell_type == "code" and kind != "notes" and SOLUTION_BLOCK.search(cell.source):
            cell.source = SOLUTION_BLOCK.sub(lambda m: f"{m.group(1)}...  # YOUR CODE HERE\n", cell.source).rstrip()
            cell.outputs = []        # the stored output ran the worked answer
        if cell.cell_type == "code":
            _shrink_outputs(cell)
    return nb


_CSS_URL = re.compile(r"""(?:@import\s*(?:url\()?|url\()\s*['"]?([^'")\s]+)""")
_REMOTE = re.compile(r"\s*(https?:)?//")


def _css_remote(css: str, base: Path, seen: set[Path]) -> list[str]:
    """The remote addresses a style sheet imports or loads, following its local @imports."""
    found = []
    for url in _CSS_URL.findall(re.sub(r"/\*.*?\*/", "", css, flags=re.S)):
        if _REMOTE.match(url):
            found.append(url)
        elif url.endswith(".css") and not url.startswith("data:"):
            path = (base / url.split("?")[0]).resolve()
            if path not in seen and path.is_file():
                seen.add(path)
                found += [f"{url} -> {u}" for u in _css_remote(path.read_text(errors="replace"), path.parent, seen)]
    return found


class _RemoteAssets(html.parser.HTMLParser):
    """Collects the http(s) addresses of scripts and style sheets: tags, CSS imports (also those of
    the local style sheets a deck links, followed) and JS module imports."""

    def __init__(self, base: Path):
        super().__init__()
        self.base, self.found, self._inline, self._seen = base, [], None, set()

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        url = attrs.get("src") if tag == "script" else attrs.get("href") if tag == "link" else None
        if url and _REMOTE.match(url):
            self.found.append(f"<{tag}> {url}")
        elif url and tag == "link" and url.split("?")[0].endswith(".css"):
            path = (self.base / url.split("?")[0]).resolve()
            if path.is_file():
                css = path.read_text(errors="replace")
                self.found += [f"<link> {url} -> {u}" for u in _css_remote(css, path.parent, self._seen)]
        self._inline = tag if tag in ("script", "style") else None

    def handle_endtag(self, tag):
        self._inline = None

    def handle_data(self, data):
        if self._inline:
            if self._inline == "style":
                self.found += [f"<style> {u}" for u in _css_remote(data, self.base, self._seen)]
            else:
                for url in re.findall(r"""(?:from\s+|import\s*\()\s*['"]((?:https?:)?//[^'"]+)""", data):
                    self.found.append(f"<script> {url}")


def remote_assets(page: str, base: Path = OUT) -> list[str]:
    """The http(s) scripts and style sheets ``page`` (a deck in the folder ``base``) would load."""
    parser = _RemoteAssets(base)
    parser.feed(page)
    return parser.found


def exporter():
    import jinja2
    from nbconvert import SlidesExporter

    return SlidesExporter(
        extra_loaders=[jinja2.DictLoader({"ifslib_slides.html.j2": TEMPLATE})],
        template_file="ifslib_slides.html.j2",
        reveal_url_prefix=REVEAL_PREFIX, mathjax_url=MATHJAX_URL, reveal_theme=THEME,
        embed_images=True)


def build(paths: list[Path]) -> list[str]:
    """Write one deck per notebook; return the problems found (remote assets, too few slides)."""
    OUT.mkdir(parents=True, exist_ok=True)
    slides, problems = exporter(), []
    for path in paths:
        nb = nbformat.read(path, as_version=4)
        body, _ = slides.from_notebook_node(lecture_copy(nb), resources={
            "metadata": {"name": path.stem, "path": str(path.parent)}})
        target = OUT / f"{path.stem}.html"
        target.write_text(body, encoding="utf-8")
        remote = remote_assets(body)
        problems += [f"{target.relative_to(ROOT)} loads {r}" for r in remote]
        kinds = slide_types(nb)
        print(f"{target.relative_to(ROOT)}: {kinds.count('slide')} slides, {kinds.count('subslide')} sub-slides, "
              f"{kinds.count('fragment')} fragments, {kinds.count('notes')} notes, {len(body) // 1024} KiB")
    return problems


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("prefixes", nargs="*", help="only the notebooks whose name starts with one of these")
    args = parser.parse_args(argv)
    missing = [f for f in REVEAL_FILES if not (NPM / "reveal.js" / f).is_file()]
    missing += [] if (OUT / MATHJAX_URL).resolve().is_file() else ["mathjax"]
    if missing:
        sys.exit(f"missing under {NPM}: {missing}: run `make slides` (it installs reveal.js and mathjax from npm)")
    paths = [p for p in sorted((ROOT / "notebooks").glob(NOTEBOOK_GLOB))
             if not args.prefixes or p.name.startswith(tuple(args.prefixes))]
    if not paths:
        sys.exit(f"no notebooks/{NOTEBOOK_GLOB} matches {args.prefixes}")
    problems = build(paths)
    for problem in problems:
        print("error:", problem, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
