"""Lecture slides: ``python docs/slides.py [DECK ...]`` (``make slides``) -> ``build/slides/DECK.html``,
and the students' decks ``build/slides/student/DECK.html``.

One reveal.js deck per lecture of the course (``docs/slides/lectures.yaml`` lists each lecture's
notebooks and sections), condensed from the notebooks' cells and their stored outputs: nothing is
executed and no notebook is written. Slides are across (one column per ``##`` section) and down (the
slides of a section). A ``#``, ``##`` or ``###`` heading opens a section wherever it stands, at the
top of a markdown cell or inside one, except an exercise's heading (``### Exercise 2 ...``). What a
slide holds, at 1280 x 720 (``Condense`` holds the limits):

* a section's **opening slide**: its heading and at most four short lines, the first sentence of
  each paragraph before the section's first figure or number, cut at a clause (or the talking
  points the lecture file gives; a section that opens on its exercises lists them); an opening that
  is empty or only repeats its figure's caption gives way to the figure;
* a **figure**: each picture a code cell stored, as large as the slide allows, under the section's
  heading and over its caption (`figure_caption`: a ``*Figure: ...*`` line written under the cell,
  else the sentence before the cell that says what it shows, else the title its code gives it, else
  the section's heading), which is also its alt text; a tall grid of panels is cut at its blank
  rows, a slide per row or per few rows, so that its labels stay legible;
* a **number**: a short printed output (at most twelve lines as set); short numbers share the slide
  before them while both fit;
* an **exercise**: its title and statement, its tables, code and formulas included (cut between
  sentences if long). A statement opens with ``**Exercise N (kind): title.**`` or a heading
  ``### Exercise N ...``; an answer cell with no statement before it fails the build. The worked
  answer is never on a slide.

Everything else goes to the **speaker notes** (``<aside class="notes">``, key ``S``) of the slide it
belongs to: the section's whole prose, every code cell, long outputs, exercise hints, and, in the
instructor's deck, the worked answers (the ``### BEGIN SOLUTION`` blocks of the instructor's
notebooks: code, and the model answers and rubrics of written exercises). The student's deck is the
same slides with none of these in its notes: the answer cell as the student edition has it
(``notebooks/student.py`` finds the markers), no hidden test, no answer cell's output (no deck shows
one). The first slide's notes are the lecture's objectives, class plan and homework from the course
page. Skipped: the ``parameters`` cell and the short paragraph that introduces it, nbgrader's test
cells, interactive widgets (they need a kernel), warnings on stderr.

Offline: reveal.js and MathJax are the npm packages under ``build/npm`` (``make slides`` installs
them), referenced by paths relative to each deck's folder; the build fails when a deck would load an
``http(s)://`` script or style sheet (the style sheets it links are read too, with their
``@import``s), when reveal.js or MathJax is missing, when the lecture file names a notebook or
section that is not there, or when a lecture notebook is in no lecture. ``--notebooks DIR`` builds
from another folder of notebooks, ``--out DIR`` into another folder; ``--outline`` prints each
slide's heading and words instead (``--student``: the students' decks), to read a deck through.
"""

from __future__ import annotations

import argparse
import base64
import copy
import dataclasses
import html
import html.parser
import os
import re
import sys
import textwrap
from pathlib import Path

import nbformat
import yaml

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
OUT = ROOT / "build" / "slides"
NPM = ROOT / "build" / "npm" / "node_modules"
LECTURES = DOCS / "slides" / "lectures.yaml"
CSS = DOCS / "slides" / "slides.css"
COURSE = DOCS / "guide" / "course.md"
NOTEBOOK_GLOB = "[0-9][0-9]_*.ipynb"
#: reveal.js and MathJax under build/npm, referenced from a deck by a path relative to its folder (opened as a file)
REVEAL = "reveal.js"
MATHJAX = "mathjax/es5/tex-mml-chtml.js"
#: the student's decks: a folder of the decks' folder (build/slides/student/)
STUDENT = "student"
#: "white": its fonts are reveal.js's own files ("simple" and most others @import Google Fonts).
THEME = "white"
REVEAL_FILES = ("dist/reveal.js", "dist/reveal.css", f"dist/theme/{THEME}.css", "plugin/notes/notes.js")
WIDGET_MIME = "application/vnd.jupyter.widget-view+json"
IMAGE_MIMES = ("image/png", "image/jpeg", "image/svg+xml")


@dataclasses.dataclass(frozen=True)
class Condense:
    """How much a slide holds; what does not fit goes to the speaker notes."""

    bullets: int = 4            # lines under a heading: more than four is a paragraph read aloud
    bullet_chars: int = 110     # visible characters of a line: two lines of the slide at most
    caption_chars: int = 150    # a figure's caption: two lines under the picture
    statement_chars: int = 360  # an exercise's statement on its slide: five lines; longer ones cut
    statement_rows: int = 8     # and under it, its tables, code and formulas: lines at 22-26 px
    text_lines: int = 12        # a printed output on a slide, in lines as set (longer ones wrap): what fits
    text_cols: int = 86         # characters of a line of output at 22 px across the slide; longer lines wrap
    figure_aspect: float = 2.1  # width / height of the room a figure has under a heading and over a caption
    split_below: float = 0.6    # a figure drawn narrower than this share of the room is cut into its rows
    min_gap: float = 0.004      # a blank line at least this share of a figure's size separates two panels
    room: int = 520             # px under a heading that short slides may share (of about 600: a margin)
    keep_rows: float = 0.8      # a grid's next row joins its slide unless the slide's picture then shrinks below this
    label_band: float = 0.4     # a band of a figure shorter than this share of its tallest is a title or labels


CONDENSE = Condense()
#: paragraphs that stay in the notes: for the one who runs the notebook, not for the room, and a
#: caption written under a figure (its slide shows it under the figure)
NOT_BULLETS = ("**How long it runs", "**What you need first", "Parameters", "*Figure:")


@dataclasses.dataclass(frozen=True)
class Part:
    notebook: str                       # a notebook's name, or its number ("09": the one 09_*.ipynb)
    sections: tuple[str, ...] | None    # heading prefixes of the `##` sections kept; None: all
    optional: bool = False              # a notebook still to come: left out while it is not there

    def path(self, notebooks: Path) -> Path | None:
        """The notebook's file, None for an optional one that is not there (else DeckError)."""
        found = [notebooks / f"{self.notebook}.ipynb"] if (notebooks / f"{self.notebook}.ipynb").is_file() \
            else sorted(notebooks.glob(f"{self.notebook}_*.ipynb"))
        if len(found) == 1:
            return found[0]
        if not found and self.optional:
            return None
        raise DeckError(f"{LECTURES.relative_to(ROOT)} names notebook {self.notebook!r}, which matches "
                        f"{[p.name for p in found] or 'nothing'} in {notebooks}")


@dataclasses.dataclass(frozen=True)
class Lecture:
    deck: str
    title: str
    parts: tuple[Part, ...]
    bullets: dict = dataclasses.field(default_factory=dict)   # heading prefix -> talking points


@dataclasses.dataclass
class Slide:
    title: str
    kind: str                   # "title", "opening", "figure", "number", "exercise"
    body: str = ""              # HTML on the slide
    notes: list[str] = dataclasses.field(default_factory=list)   # HTML in the speaker notes
    caption: str = ""           # a figure's or number's caption (markdown)
    height: float = 0           # about how tall its body is, in the slide's pixels (figures: the whole room)


class DeckError(Exception):
    """A lecture file or notebook the decks cannot be built from: the message says what to change."""


# ---------------------------------------------------------------------------------------------------
# The lecture file

def load_lectures(path: Path = LECTURES) -> list[Lecture]:
    """The lectures of ``path``, checked: every key known, every part a notebook name."""
    raw = yaml.safe_load(path.read_text(encoding="utf-8"))
    if not isinstance(raw, list):
        raise DeckError(f"{path}: expected a list of lectures")
    lectures = []
    for entry in raw:
        unknown = set(entry) - {"deck", "title", "parts", "bullets"}
        unknown |= {k for p in entry.get("parts", []) for k in p if k not in ("notebook", "sections", "optional")}
        if unknown or not {"deck", "title", "parts"} <= set(entry):
            raise DeckError(f"{path}: lecture {entry.get('deck')!r} needs deck, title and parts "
                            f"(and optionally bullets); unknown keys {sorted(unknown)}")
        parts = tuple(Part(str(p["notebook"]), tuple(p["sections"]) if "sections" in p else None,
                           bool(p.get("optional", False))) for p in entry["parts"])
        bullets = {k: tuple(v) for k, v in (entry.get("bullets") or {}).items()}
        lectures.append(Lecture(entry["deck"], entry["title"], parts, bullets))
    return lectures


def check_coverage(lectures: list[Lecture], notebooks: Path) -> None:
    """Raise when a lecture names a missing notebook or a lecture notebook is in no lecture."""
    listed = {path.stem for lec in lectures for p in lec.parts for path in [p.path(notebooks)] if path}
    present = {p.stem for p in notebooks.glob(NOTEBOOK_GLOB)}
    if present - listed:
        raise DeckError(f"notebooks {sorted(present - listed)} are in no lecture: add each to a lecture's "
                        f"parts in {LECTURES.relative_to(ROOT)} (the course page says which)")


# ---------------------------------------------------------------------------------------------------
# Markdown: paragraphs, sentences, short lines

_PROTECT = re.compile(r"\$\$.+?\$\$|\$[^$\n]+?\$|`[^`\n]*`|\[[^\]\n]*\]\([^)\n]*\)", re.S)
_SENTENCE_END = re.compile(r"(?<![ (]e\.g)(?<!i\.e)(?<!Eq)(?<!Fig)(?<!etc)(?<!vs)[.!?](?=\s+[A-Z(*$`\[])")
_HEADING = re.compile(r"\s*(#{1,6})\s+(.*)")


def heading(cell) -> tuple[int, str] | None:
    """(level, title) of the markdown heading a cell opens with, else None."""
    match = _HEADING.match(cell.source)
    if cell.cell_type != "markdown" or not match:
        return None
    return len(match.group(1)), match.group(2).strip()


def paragraphs(source: str) -> list[str]:
    """Blank-line separated blocks of ``source``, keeping code fences, ``$$`` and <details> whole."""
    blocks, current = [], []
    for line in source.splitlines():
        if not line.strip() and current and _balanced("\n".join(current)):
            blocks.append("\n".join(current))
            current = []
        elif line.strip() or current:
            current.append(line)
    if current:
        blocks.append("\n".join(current))
    return blocks


def _balanced(text: str) -> bool:
    return (text.count("```") % 2 == 0 and text.count("$$") % 2 == 0
            and text.count("<details") == text.count("</details>"))


def _spans(text: str) -> list[tuple[int, int]]:
    return [m.span() for m in _PROTECT.finditer(text)]


def _outside(pos: int, spans) -> bool:
    return all(not (a < pos < b) for a, b in spans)


def visible_length(text: str) -> int:
    """About how many characters ``text`` shows once rendered: markup dropped, formulas by their glyphs."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    # a formula's glyphs are wider than text and never break across lines: each counts 1.5
    text = re.sub(r"\$+([^$]*)\$+", lambda m: "x" * round(1.5 * len(re.sub(r"\\[a-zA-Z]+|[{}_^\\ ]", lambda c: (
        "x" if len(c.group()) > 1 else ""), m.group(1)))), text)
    return len(re.sub(r"[*`_\\]", "", text))


def sentences(text: str) -> list[str]:
    """The sentences of a paragraph (never cut inside a formula, code or link, nor after "e.g.")."""
    text = " ".join(text.split())
    spans, found, start = _spans(text), [], 0
    for match in _SENTENCE_END.finditer(text):
        if _outside(match.start(), spans):
            found.append(text[start:match.end()].strip())
            start = match.end()
    return found + ([text[start:].strip()] if text[start:].strip() else [])


def first_sentence(text: str) -> str:
    """The first sentence of a paragraph."""
    return (sentences(text) or [""])[0]


def shorten(text: str, limit: int) -> str | None:
    """``text`` if it shows at most ``limit`` characters, else cut at the last clause (``,;:``) that
    fits, with an ellipsis; None when no clause of a third of ``limit`` or more fits."""
    text = " ".join(text.split())
    if visible_length(text) <= limit:
        return text
    spans = _spans(text)
    cuts = [m.start() for m in re.finditer(r"[,;:](?=\s)| \(| (?:and|but|so|since|while|which|where) ",
                                           text) if _outside(m.start(), spans)]
    cuts = [c for c in cuts if limit // 3 <= visible_length(text[:c]) <= limit - 1]
    if not cuts:
        return None
    return text[:max(cuts)].rstrip(" ,;:") + " …"


def bullet_of(paragraph: str) -> str | None:
    """A short line standing for a paragraph: its first sentence, cut if long; None for a list."""
    if re.match(r"\s*([-*+]|\d+\.)\s", paragraph) or paragraph.lstrip().startswith(("<", "```", "$$", "|")):
        return None
    head = re.match(r"#{1,6}\s+(.*)", paragraph.strip())
    if head:
        return shorten(f"**{head.group(1).strip()}**", CONDENSE.bullet_chars)
    sentence = first_sentence(paragraph)
    return shorten(re.sub(r"^\*\*([^*]+?)[.:]?\*\*[.:]?\s*", r"**\1:** ", sentence), CONDENSE.bullet_chars)


def list_items(paragraph: str) -> list[str]:
    """The items of a markdown list paragraph (each joined onto one line)."""
    items = re.split(r"(?m)^\s*(?:[-*+]|\d+\.)\s+", paragraph)
    return [" ".join(i.split()) for i in items if i.strip()] if re.match(r"\s*([-*+]|\d+\.)\s", paragraph) else []


def md(text: str, inline: bool = False) -> str:
    """Markdown to HTML (formulas left for MathJax)."""
    from nbconvert.filters.markdown_mistune import markdown2html_mistune

    out = markdown2html_mistune(text).strip()
    if inline and out.startswith("<p>") and out.endswith("</p>") and out.count("<p>") == 1:
        out = out[3:-4]
    return out


#: code in the speaker notes: the speaker view shows the notes without the deck's style sheet
NOTES_PRE = "white-space: pre-wrap; font-size: 0.75em; line-height: 1.3"


def pre(text: str, cls: str = "") -> str:
    """``text`` preformatted: on a slide with the class ``cls``, in the notes (no class) wrapped."""
    attr = f'class="{cls}"' if cls else f'style="{NOTES_PRE}"'
    return f"<pre {attr}>{html.escape(text)}</pre>"


# ---------------------------------------------------------------------------------------------------
# Notebooks: sections, exercises, captions, and the slides of a section

#: An exercise's first paragraph: ``**Exercise 2 (apply): a title.**`` or a heading ``### Exercise 2 (apply). A title``
EXERCISE = re.compile(r"\s*(?:\*\*(Exercise\b[^*]*?)[.:]?\*\*[.:]?|#{1,6}[ \t]+(Exercise\b[^\n]*?)[.:]?[ \t]*(?:\n|$))\s*")
#: A figure's caption written under it (notebook 10's convention): ``*Figure: what it shows.*``
FIGURE_CAPTION = re.compile(r"\s*\*Figure:\s*(.+?)\.?\*(?=\s|$)", re.S)
_FENCE = re.compile(r"\s*(```|~~~)")


def _student():
    """``notebooks/student.py``: where the solution and hidden-test markers are read (the student edition's tool)."""
    if str(DOCS.parent / "course") not in sys.path:
        sys.path.insert(0, str(DOCS.parent / "course"))
    from scripts import load_script  # course/scripts.py

    return load_script("notebooks/student.py", "ifslib_student_edition")


@dataclasses.dataclass
class Section:
    level: int                  # 1: the notebook's title, 2: a step of the lesson, 3: a part of a step
    title: str
    cells: list


def _nbgrader(cell) -> dict:
    return cell.metadata.get("nbgrader", {})


def exercise_title(paragraph: str) -> str | None:
    """The title of the exercise ``paragraph`` opens (``Exercise 2 (apply): IoU``), else None."""
    match = EXERCISE.match(paragraph)
    return (match.group(1) or match.group(2)).strip() if match else None


def split_at_headings(cells) -> list:
    """The cells with each markdown cell cut before every heading inside it (outside code fences and
    ``$$``): a heading in the middle of a cell opens a section as one at its top does. nbgrader's
    cells stay whole (``### BEGIN SOLUTION`` is a marker, not a heading)."""
    out = []
    for cell in cells:
        if cell.cell_type != "markdown" or _nbgrader(cell):
            out.append(cell)
            continue
        pieces, current, fenced, maths = [], [], False, False
        for line in cell.source.splitlines():
            if _FENCE.match(line):
                fenced = not fenced
            elif not fenced and line.count("$$") % 2:
                maths = not maths
            if not fenced and not maths and _HEADING.match(line) and "".join(current).strip():
                pieces.append("\n".join(current).strip("\n"))
                current = []
            current.append(line)
        pieces.append("\n".join(current).strip("\n"))
        for text in pieces:
            piece = copy.deepcopy(cell)
            piece.source = text
            out.append(piece)
    return out


def sections(nb) -> list[Section]:
    """The notebook cut at its ``#``, ``##`` and ``###`` headings, in a cell or at its top (cells
    before the first: the title's); a heading ``### Exercise ...`` opens an exercise, not a section."""
    found = [Section(1, "", [])]
    for cell in split_at_headings(nb.cells):
        head = None if _nbgrader(cell) else heading(cell)   # "### BEGIN SOLUTION" is no heading
        if head and exercise_title(cell.source):
            head = None
        if head and head[0] <= 3 and (found[-1].cells or found[-1].title):
            found.append(Section(head[0], head[1], []))
        elif head and head[0] <= 3:
            found[-1].level, found[-1].title = head
        found[-1].cells.append(cell)
    return found


def pick(secs: list[Section], part: Part, where: str) -> list[Section]:
    """The title and the sections of ``part`` (a ``###`` goes with the ``##`` above it)."""
    if part.sections is None:
        return secs
    tops = [s.title for s in secs if s.level == 2]
    for prefix in part.sections:
        if not any(t.startswith(prefix) for t in tops):
            raise DeckError(f"{LECTURES.relative_to(ROOT)}: {where} has no `##` section starting with "
                            f"{prefix!r}; its sections are now {tops}")
    kept, keep = [], True
    for sec in secs:
        if sec.level <= 2:
            keep = sec.level == 1 or sec.title.startswith(part.sections)
        if keep:
            kept.append(sec)
    return kept


def _is_answer(cell) -> bool:
    """An exercise's answer cell (nbgrader's, tagged ``exercise``, or holding a marked solution)."""
    return _student().is_exercise(cell)


def _skipped(cells, index) -> bool:
    """The parameters cell, the short paragraph introducing it, nbgrader tests, empty cells."""
    cell = cells[index]
    after = cells[index + 1] if index + 1 < len(cells) else None
    intro = (cell.cell_type == "markdown" and after is not None and "parameters" in after.metadata.get("tags", [])
             and not heading(cell) and len(cell.source.strip().splitlines()) <= 3)
    return not cell.source.strip() or "parameters" in cell.metadata.get("tags", []) or intro or _student().is_test(cell)


def solution_text(cell) -> str:
    """The worked answer of an exercise cell: its BEGIN/END SOLUTION blocks (else the whole cell)."""
    blocks = [p.text for p in _student().split(cell.source) if p.solution]
    return "\n".join(textwrap.dedent(b).strip("\n") for b in blocks) if blocks else cell.source


def _has_image(cell) -> bool:
    return cell.cell_type == "code" and any(m in out.get("data", {}) for out in cell.get("outputs", [])
                                            for m in IMAGE_MIMES)


def _prose(paragraph: str) -> bool:
    """A paragraph of sentences: not a heading, list, table, formula, code or HTML block, nor an aside
    in parentheses."""
    text = paragraph.strip()
    return not (_HEADING.match(text) or re.match(r"([-*+]|\d+\.)\s", text)
                or text.startswith(("<", "```", "$$", "|")) or (text.startswith("(") and text.endswith(")")))


def pointer_sentence(paragraph: str) -> str:
    """The sentence of ``paragraph`` that says what the cell after it shows: one that opens with
    "Below" or "The picture" (bars, plot, figure), else a last sentence that ends in a colon, else
    the first that points "below" or at "the bars", else the first that does not point "above"
    (an exercise's lead and a figure caption written under the cell before are left out)."""
    text = FIGURE_CAPTION.sub("", paragraph, count=1)
    lead = EXERCISE.match(text)
    found = sentences(text[lead.end():] if lead else text)
    if not found:
        return ""
    ranked = [s for s in found if re.match(r"(Below\b|The (picture|pictures|bars|plot|figure)\b)", s)]
    ranked += [found[-1]] * found[-1].endswith(":")
    ranked += [s for s in found if re.search(r"\bbelow\b|\bthe bars\b|\bpictured\b", s, re.I)]
    ranked += [s for s in found if not re.search(r"\babove\b", s)]     # one that points back speaks of another output
    return (ranked or found)[0]


#: a figure's title in its code: fig.suptitle("...") or ax.set_title("..."), a literal or an f-string
_TITLE_CALL = re.compile(r"""\b(suptitle|set_title)\(\s*(f?)("[^"\n]*"|'[^'\n]*')""")


def _code_title(source: str) -> str:
    """The figure's title its code sets (``suptitle`` before ``set_title``), each ``{name}`` of an
    f-string shown as code; "" when there is none, or when it computes (an expression, not a name)."""
    for call in ("suptitle", "set_title"):
        for kind, prefix, literal in _TITLE_CALL.findall(source):
            if kind != call:
                continue
            text = literal[1:-1]
            fields = re.findall(r"\{([^{}]*)\}", text) if prefix else []
            if any(not re.fullmatch(r"\w+(:[^{}]*)?", f) for f in fields):
                continue
            text = re.sub(r"\{(\w+)(:[^{}]*)?\}", r"`\1`", text) if prefix else text
            if len(re.sub(r"`\w+`|[^\w]", " ", text).split()) >= 2:
                return text[0].upper() + text[1:]
    return ""


def figure_caption(cells, index: int) -> str:
    """The caption of the figure that the code cell ``cells[index]`` draws, as markdown:

    1. a caption written under the cell, ``*Figure: ...*`` (the convention of the later notebooks);
    2. else the sentence before it that says what it shows (`pointer_sentence`, without an opening
       "Below": the caption sits under the figure) in the last prose paragraph before the cell,
       looking back over code cells without a figure, not past a heading, another figure or an
       exercise's answer;
    3. else the title its code gives the figure (``suptitle``, ``set_title``);
    4. else the heading of its section.
    """
    after = cells[index + 1] if index + 1 < len(cells) else None
    if after is not None and after.cell_type == "markdown" and not _nbgrader(after):
        match = FIGURE_CAPTION.match(after.source)
        if match:
            text = " ".join(match.group(1).split())
            return text[0].upper() + text[1:] + "."
    head, blocked = "", False
    for cell in reversed(split_at_headings(cells[:index])):
        if cell.cell_type == "code":
            blocked = blocked or _has_image(cell) or _is_answer(cell)
            continue
        for paragraph in reversed(paragraphs(cell.source) if not _nbgrader(cell) else []):
            if _HEADING.match(paragraph) and not exercise_title(paragraph):
                head = _HEADING.match(paragraph).group(2).strip()
                break
            if not blocked and (_prose(paragraph) or exercise_title(paragraph)) and pointer_sentence(paragraph):
                return _under(pointer_sentence(paragraph))
        blocked = blocked or bool(_nbgrader(cell))
        if head:
            break
    # a figure that opens its section is captioned by the heading; one after another figure, by its title
    return (head if not blocked else "") or _code_title(cells[index].source) or head


def _under(sentence: str) -> str:
    """A sentence that points at a figure, as the caption placed under it: "Below, three choices
    drawn." reads "Three choices drawn." (a caption under its figure cannot say "below")."""
    text = re.sub(r"^Below\b[,:]?\s*", "", sentence)
    if text == sentence or not text:
        return sentence
    text = text[0].upper() + text[1:]
    return text[:-1] + "." if text.endswith(":") else text


def plain(text: str) -> str:
    """Markdown as the words it shows (an image's alt text): emphasis, code marks and links dropped."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)
    return " ".join(re.sub(r"[*`]|(?<!\\)\$", "", text).split())


def alt_texts(nb) -> dict[int, str]:
    """Each figure cell's alt text (its caption in plain words), by the cell's index in ``nb``."""
    return {i: plain(figure_caption(nb.cells, i)) for i, cell in enumerate(nb.cells) if _has_image(cell)}


def exercise_slide(statement: list[str]) -> Slide:
    """An exercise's slide: its title and statement, tables, formulas and code blocks included, cut
    between sentences when long; the whole statement and its hint go to the notes."""
    lead = EXERCISE.match(statement[0])
    title = exercise_title(statement[0]) or "Exercise"
    blocks = [statement[0][lead.end():] if lead else statement[0], *statement[1:]]
    blocks = [b for b in blocks if b.strip() and not b.lstrip().startswith("<")]   # a folded hint stays in the notes
    shown, used, rows, cut = [], 0, 0, False
    for block in blocks:
        if block.lstrip().startswith(("|", "$$", "```")):
            # a table, a formula or code is shown whole or not at all (a table's |---| row and a code
            # block's fences are not drawn; a formula takes about two lines)
            lines = [r for r in block.strip().splitlines() if not re.fullmatch(r"[\s|:-]+|\s*(```|~~~).*", r)]
            cost = 2 if block.lstrip().startswith("$$") else len(lines)
            if rows + cost > CONDENSE.statement_rows:
                cut = True
                break
            shown.append(block.strip())
            rows += cost
            continue
        kept = []
        for sentence in sentences(block):
            if used + visible_length(sentence) > CONDENSE.statement_chars:
                # the sentence that does not fit is shown up to a clause that does, when one does
                part = shorten(sentence, CONDENSE.statement_chars - used)
                kept += [part.removesuffix(" …")] if part else []
                cut = True
                break
            kept.append(sentence)
            used += visible_length(sentence)
        if kept:
            shown.append(" ".join(kept))
        if cut:
            break
    if not shown and blocks:
        shown = [shorten(first_sentence(blocks[0]), CONDENSE.statement_chars) or title]
    if cut and shown[-1].startswith(("|", "$$", "```")):     # the rest is in the notes
        shown.append("…")
    elif cut:
        shown[-1] += " …"
    body = "\n\n".join(shown)
    slide = Slide(title, "exercise", f'<div class="statement">{md(body)}</div>')
    slide.notes.append(md("\n\n".join(statement)))
    return slide


def answer_notes(answer, student: bool) -> str:
    """What the speaker notes say of an exercise's answer cell: the worked answer (the instructor's
    deck), or the cell as the student edition has it, its solution stubbed (the student's deck)."""
    if student:
        if answer.cell_type != "code":
            return "<p><em>A written answer, graded by hand.</em></p>"
        stubbed = _student().student_source(answer.source)
        return "<p>The answer cell, as the student edition has it:</p>" + pre(_student().HIDDEN.sub("", stubbed))
    if answer.cell_type == "code":
        return "<p><strong>Worked answer</strong> (the notebook's solution block):</p>" + pre(solution_text(answer))
    return "<p><strong>Model answer and rubric:</strong></p>" + md(solution_text(answer))


def _bands(blank, size: int) -> list[tuple[int, int]]:
    """The stretches of non-blank lines between blank gaps (rows of panels), a short one (a title or a
    line of labels, under ``label_band`` of the tallest) joined to the nearer of its neighbours."""
    gap = max(2, round(CONDENSE.min_gap * size))
    bands, start, run = [], None, 0
    for i, empty in enumerate(list(blank) + [True] * gap):
        run = run + 1 if empty else 0
        if not empty and start is None:
            start = i
        if start is not None and run == gap:
            bands.append((start, i - gap + 1))
            start = None
    while len(bands) > 1:
        tallest = max(b - a for a, b in bands)
        small = [i for i, (a, b) in enumerate(bands) if b - a < CONDENSE.label_band * tallest]
        if not small:
            break
        i = min(small, key=lambda k: bands[k][1] - bands[k][0])
        above = bands[i][0] - bands[i - 1][1] if i > 0 else size
        below = bands[i + 1][0] - bands[i][1] if i + 1 < len(bands) else size
        j = i - 1 if above <= below else i + 1
        lo, hi = min(i, j), max(i, j)
        bands[lo:hi + 1] = [(bands[lo][0], bands[hi][1])]
    return bands


def _png(image) -> bytes:
    import io

    buffer = io.BytesIO()
    image.save(buffer, format="PNG")
    return buffer.getvalue()


def figure_pieces(png: bytes) -> list[bytes]:
    """A figure laid out for the slide's room: a tall grid of panels cut at its blank rows into
    pieces about as wide as the room, a strip of panels so long that it is drawn larger in two rows
    folded; else unchanged."""
    import io

    import numpy as np
    from PIL import Image

    image = Image.open(io.BytesIO(png)).convert("RGBA")
    width, height = image.size
    pixels = np.asarray(image)
    blank = (pixels[..., 3] < 10) | (pixels[..., :3].min(axis=-1) > 245)
    aspect = width / height
    if aspect < CONDENSE.split_below * CONDENSE.figure_aspect:
        rows = _bands(blank.all(axis=1), height)
        if len(rows) < 2:
            return [png]
        def scale(h):               # how much the room magnifies a piece h pixels tall
            return min(1 / width, 1 / (CONDENSE.figure_aspect * h))

        pieces, top = [], rows[0][0]
        for previous, row in zip(rows, rows[1:]):      # a piece ends before a row that would shrink it
            if scale(row[1] - top) < CONDENSE.keep_rows * scale(previous[1] - top):
                pieces.append((top, previous[1]))
                top = row[0]
        pieces.append((top, rows[-1][1]))
        return [_png(image.crop((0, a, width, b))) for a, b in pieces] if len(pieces) > 1 else [png]
    if aspect / 4 > CONDENSE.figure_aspect:            # folded in two rows, it is drawn larger
        cols = _bands(blank.all(axis=0), width)
        if len(cols) < 4:
            return [png]
        half = len(cols) // 2
        left, right = image.crop((0, 0, cols[half][0], height)), image.crop((cols[half][0], 0, width, height))
        folded = Image.new("RGBA", (max(left.width, right.width), 2 * height), (255, 255, 255, 255))
        folded.paste(left, (0, 0))
        folded.paste(right, (0, height))
        return [_png(folded)]
    return [png]


def _image_src(out) -> list[str]:
    data = out.get("data", {})
    found = []
    for mime in IMAGE_MIMES:
        if mime in data:
            payload = data[mime]
            if mime == "image/svg+xml":
                text = payload if isinstance(payload, str) else "".join(payload)
                payload = base64.b64encode(text.encode()).decode()
            payload = "".join(payload.split())
            if mime == "image/png":
                found += [f"data:{mime};base64,{base64.b64encode(p).decode()}"
                          for p in figure_pieces(base64.b64decode(payload))]
            else:
                found.append(f"data:{mime};base64,{payload}")
            break
    return found


def _text_of(out) -> str:
    if out.get("output_type") == "stream":
        return out["text"] if out.get("name") == "stdout" else ""
    data = out.get("data", {})
    if out.get("output_type") == "execute_result" and set(data) <= {"text/plain"}:
        text = data.get("text/plain", "")
        return "" if text.startswith("<") else text
    return ""


def caption_of(paragraph: str | None) -> str:
    """A printed number's caption: the sentence of the paragraph before it that says what it shows."""
    if not paragraph or not _prose(paragraph) or paragraph.lstrip().startswith(NOT_BULLETS):
        return ""
    return shorten(pointer_sentence(paragraph), CONDENSE.caption_chars) or ""


class SectionSlides:
    """The slides of one section, cell by cell: ``SectionSlides(sec, where).build(bullets)``;
    ``student=True``: the student's deck, with no worked answer, model answer or rubric in the notes."""

    def __init__(self, section: Section, where: str, student: bool = False):
        self.section, self.where, self.student = section, where, student
        self.opening = Slide(section.title, "title" if section.level == 1 else "opening")
        self.slides = [self.opening]
        self.prose: list[str] = []          # paragraphs that are not exercises: the opening's notes
        # the paragraphs before the section's first figure or number: the opening's bullets (a later
        # one speaks of an output the opening does not show, "the L1 printed above")
        self.lead: list[str] = []
        self.statement: list[str] | None = None     # the paragraphs of an exercise being read
        self.pending: Slide | None = None   # the exercise slide whose answer cell is still to come
        self.last: str | None = None        # the paragraph just before a cell: a number's caption

    def build(self, bullets: tuple[str, ...] | None = None) -> list[Slide]:
        cells = self.section.cells
        for index, cell in enumerate(cells):
            if _skipped(cells, index):
                continue
            if _is_answer(cell):
                self.answer(cell)
            elif cell.cell_type == "markdown":
                self.markdown(cell)
            else:
                self.flush()
                self.code(cells, index)
        self.flush()
        self.close()
        lines = list(bullets) if bullets else self.bullets()
        if not lines and len(self.slides) > 1 and self.slides[1].kind == "exercise":
            # a section that opens on its exercises ("On your own"): its opening lists them
            lines = [f"**{s.title}**" for s in self.slides[1:] if s.kind == "exercise"][:CONDENSE.bullets]
        self.opening.body = "<ul>" + "".join(f"<li>{md(b, inline=True)}</li>" for b in lines) + "</ul>" if lines else ""
        self.opening.notes.insert(0, md("\n\n".join(self.prose)) if self.prose else "")
        self.opening.height = sum(_text_height(b, 30, 1190) + 16 for b in lines)
        shown = [s.caption for s in self.slides[1:]]
        if len(self.slides) > 1 and self.section.level > 1 and self.slides[1].kind in ("figure", "number") \
                and all(_repeats(b, shown) for b in lines):
            # an opening that is empty or would only repeat its figures' captions: its notes go to the next slide
            self.slides[1].notes[:0] = self.opening.notes
            return self.slides[1:]
        return merge_short(self.slides, set(lines))

    def bullets(self) -> list[str]:
        found = []
        for paragraph in (p for p in self.lead if not p.lstrip().startswith(NOT_BULLETS)):
            items = list_items(paragraph)
            found += [s for s in (shorten(i, CONDENSE.bullet_chars) for i in items) if s] if items \
                else [b for b in [bullet_of(paragraph)] if b]
        return found[:CONDENSE.bullets]

    def markdown(self, cell) -> None:
        exercise = exercise_title(cell.source)
        source = _HEADING.sub("", cell.source, count=1) if heading(cell) and not exercise else cell.source
        in_statement = False        # the paragraphs after an exercise's first, in its cell, are its own
        for paragraph in paragraphs(source):
            if exercise_title(paragraph):
                self.flush()
                self.close()
                self.statement, in_statement = [paragraph], True
            elif self.statement is not None and (in_statement or paragraph.lstrip().startswith("<details")):
                self.statement.append(paragraph)
            else:
                self.prose.append(paragraph)
                if not any(s.kind in ("figure", "number") for s in self.slides):
                    self.lead.append(paragraph)
                self.last = paragraph

    def flush(self) -> None:
        """The exercise being read becomes its slide, which waits for its answer cell."""
        if self.statement:
            self.pending = exercise_slide(self.statement)
            self.slides.append(self.pending)
        self.statement = None

    def close(self) -> None:
        """An exercise slide whose answer never came: the notes say so."""
        if self.pending is not None and not self.student:
            self.pending.notes.append(f"<p><em>No worked answer in {self.where}.</em></p>")
        self.pending = None

    def answer(self, cell) -> None:
        self.flush()
        if self.pending is None:
            grader = _nbgrader(cell).get("grade_id") or cell.get("id", "?")
            raise DeckError(f"{self.where}: the answer cell {grader} (section {self.section.title!r}) has no "
                            "exercise before it: open its statement with **Exercise N (kind): title.** or a "
                            "heading ### Exercise N ...")
        self.pending.notes.append(answer_notes(cell, self.student))
        self.pending, self.last = None, None

    def code(self, cells, index: int) -> None:
        cell = cells[index]
        figures = [pieces for out in cell.get("outputs", []) for pieces in [_image_src(out)] if pieces]
        text = "".join(_text_of(out) for out in cell.get("outputs", [])).strip("\n")
        source = _student().HIDDEN.sub("", _student().student_source(cell.source)) if self.student else cell.source
        code = pre(source)
        full = figure_caption(cells, index) if figures else ""
        caption = (shorten(full, CONDENSE.caption_chars) or "") if figures else caption_of(self.last)
        for pieces in figures:
            for i, src in enumerate(pieces):
                part = f" (row {i + 1} of {len(pieces)})" if len(pieces) > 1 else ""
                notes = [code] if i == 0 else [f"<p>Row {i + 1} of {len(pieces)} of the figure, a slide each.</p>"]
                slide = Slide(self.section.title, "figure", _figure(src, caption + part, plain(full) + part), notes, caption)
                self.slides.append(slide)
            code = ""
        caption = "" if figures else caption    # the figure above says what the cell shows
        rows = sum(-(-max(len(line), 1) // CONDENSE.text_cols) for line in text.splitlines())
        if text and rows <= CONDENSE.text_lines:
            height = 30 * rows + 52 + (_text_height(caption, 24, 1190) + 10 if caption else 0)
            self.slides.append(Slide(self.section.title, "number", pre(text, "output") + _caption(caption), [code],
                                     caption, height))
        elif text:
            self.slides[-1].notes += [code, "<p>Its output:</p>" + pre(text)]
        elif code and not figures and not _imports_only(cell.source):
            self.slides[-1].notes.append(code)
        self.last = None


def _text_height(text: str, font: int, width: int) -> float:
    """About how tall ``text`` is set at ``font`` px in a box ``width`` px wide (1.3 lines apart)."""
    per_line = width / (0.48 * font)          # characters a line of this font holds
    return -(-visible_length(text) // per_line) * 1.3 * font


def _repeats(line: str, others) -> bool:
    """Whether ``line`` says what one of ``others`` says (the same sentence, cut or not)."""
    line = line.removesuffix(" …")
    return bool(line) and any(o and (o.removesuffix(" …").startswith(line) or line.startswith(o.removesuffix(" …")))
                              for o in others)


def merge_short(slides: list[Slide], bullets: set[str]) -> list[Slide]:
    """Slides with a printed number joined to the slide before them (an opening or another number)
    while both fit under one heading; a caption that repeats one of the opening's lines is dropped."""
    out = slides[:1]
    for slide in slides[1:]:
        last = out[-1]
        if slide.kind == "number" and last.kind in ("opening", "number") and last.height + slide.height <= CONDENSE.room:
            body = slide.body.replace(_caption(slide.caption), "") if _repeats(slide.caption, bullets) else slide.body
            last.body += body
            last.notes += slide.notes
            last.height += slide.height
            last.kind = "number" if last.kind == "number" else "opening"
        else:
            out.append(slide)
    return out


def _imports_only(source: str) -> bool:
    return all(re.match(r"\s*(import|from)\s", line) or not line.strip() for line in source.splitlines())


def _caption(text: str) -> str:
    return f'<p class="caption">{md(text, inline=True)}</p>' if text else ""


def _figure(src: str, caption: str, alt: str) -> str:
    """A figure with its caption (markdown) under it and ``alt`` (plain words) as its alt text."""
    return f'<div class="figure"><img src="{src}" alt="{html.escape(alt, quote=True)}"></div>' + _caption(caption)


# ---------------------------------------------------------------------------------------------------
# Decks

def course_notes(title: str, course: Path = COURSE) -> str:
    """The course page's objectives, class plan and homework for the lecture ``title`` (speaker notes)."""
    key = title.split(":")[0].strip()
    text = course.read_text(encoding="utf-8") if course.is_file() else ""
    match = re.search(rf"^## {re.escape(key)}\b.*?$(.*?)(?=^## |\Z)", text, re.M | re.S)
    if not match:
        return f"<p>The course page ({course.relative_to(ROOT)}) has no section for {key}.</p>"
    kept = [p for p in paragraphs(match.group(1)) if p.startswith(("**Objectives", "**In class", "**At home"))]
    return md("\n\n".join(kept)) if kept else md(match.group(1))


def lecture_columns(lecture: Lecture, notebooks: Path, student: bool = False) -> list[list[Slide]]:
    """The deck's columns (left to right), each a list of slides (top to bottom); ``student``: the
    student's deck (no worked answer, model answer, rubric or hidden test in its notes)."""
    title = Slide(lecture.title, "title", notes=[course_notes(lecture.title)])
    columns, used = [[title]], set()
    for part in lecture.parts:
        path = part.path(notebooks)
        if path is None:
            continue
        nb = nbformat.read(path, as_version=4)
        names, kept = [], pick(sections(nb), part, f"notebooks/{path.name}")
        # a notebook shown in part: its title slide lists the parts shown, not the whole lesson's intro
        shown = tuple(_title_md(s.title) for s in kept if s.level == 2)[:CONDENSE.bullets] if part.sections else None
        for sec in kept:
            keys = [k for k in lecture.bullets if sec.title.startswith(k)]
            used.update(keys)
            points = lecture.bullets[keys[0]] if keys else shown if sec.level == 1 else None
            slides = SectionSlides(sec, f"notebooks/{path.name}", student).build(points)
            slides[0].notes.append(f"<p><em>notebooks/{path.name}, {html.escape(sec.title)}</em></p>")
            if sec.level == 3 and len(columns) > 1:
                columns[-1] += slides
            else:
                columns.append(slides)
            names.append(sec.title) if sec.level == 1 else None
        title.body += "".join(f"<li>{_title(n)}</li>" for n in names)
    title.body = f"<ul>{title.body}</ul>"
    stale = set(lecture.bullets) - used
    if stale:
        raise DeckError(f"{LECTURES.relative_to(ROOT)}: {lecture.deck}'s bullets for {sorted(stale)} match no section")
    return columns


def _title_md(text: str) -> str:
    """A heading's text as markdown that stays one line ("1. IFS" is a title, not a list)."""
    return re.sub(r"^(\d+)\.", r"\1\\.", text)


def _title(text: str) -> str:
    return md(_title_md(text), inline=True)


def slide_html(slide: Slide) -> str:
    tag = "h1" if slide.kind == "title" else "h2"
    notes = "".join(n for n in slide.notes if n)
    return (f'<section class="{slide.kind}"><div class="page"><{tag}>{_title(slide.title)}</{tag}>'
            f"{slide.body}</div>\n<aside class=\"notes\">{notes}</aside></section>\n")


PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1.0">
<title>{title}</title>
<link rel="stylesheet" href="{reveal}/dist/reveal.css">
<link rel="stylesheet" href="{reveal}/dist/theme/{theme}.css">
<style>
{css}
</style>
<script>
window.MathJax = {{
  tex: {{inlineMath: [['$', '$'], ['\\\\(', '\\\\)']], displayMath: [['$$', '$$'], ['\\\\[', '\\\\]']],
        processEscapes: true}},
  options: {{ignoreHtmlClass: 'notes|tex2jax_ignore', processHtmlClass: 'tex2jax_process'}}
}};
</script>
<script src="{mathjax}"></script>
</head><body>
<div class="reveal"><div class="slides">
{slides}</div></div>
<script src="{reveal}/dist/reveal.js"></script>
<script src="{reveal}/plugin/notes/notes.js"></script>
<script>
Reveal.initialize({{width: {width}, height: {height}, margin: 0.02, center: false, hash: true,
  controls: false, slideNumber: "c/t", transition: "fade", plugins: [RevealNotes]}});
</script>
</body></html>
"""
WIDTH, HEIGHT = 1280, 720       # the slide's box: a 720p projector, and the browser test's viewport


def npm_path(folder: Path, name: str) -> str:
    """``name`` under build/npm/node_modules as a deck in ``folder`` refers to it."""
    return Path(os.path.relpath(NPM / name, folder)).as_posix()


def deck_html(lecture: Lecture, columns: list[list[Slide]], folder: Path = OUT, student: bool = False) -> str:
    """The deck's page, to be written into ``folder``."""
    body = ""
    for column in columns:
        inner = "".join(slide_html(s) for s in column)
        body += f"<section>\n{inner}</section>\n" if len(column) > 1 else inner
    title = html.escape(lecture.title + (" (student's deck)" if student else ""))
    return PAGE.format(title=title, reveal=npm_path(folder, REVEAL), theme=THEME, mathjax=npm_path(folder, MATHJAX),
                       css=CSS.read_text(encoding="utf-8"), slides=body, width=WIDTH, height=HEIGHT)


def index_html(lectures: list[Lecture]) -> str:
    items = "".join(f'<li><a href="{lec.deck}.html">{html.escape(lec.title)}</a> (the instructor\'s: worked '
                    f'answers in the notes; <a href="{STUDENT}/{lec.deck}.html">the students\'</a>: none)</li>'
                    for lec in lectures)
    return (f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>Lecture slides</title></head>'
            f"<body><h1>Lecture slides</h1><ul>{items}</ul><p>Key S opens the speaker notes. The students' decks "
            f"hold no worked answer, model answer, rubric or hidden test: share those.</p></body></html>\n")


def outline(columns: list[list[Slide]]) -> list[str]:
    """Each slide as one line, ``H.V kind | heading | text``, the way a reader goes through the deck
    (``python docs/slides.py --outline``): a slide's words without its markup, a figure by its alt text."""
    lines = []
    for h, column in enumerate(columns):
        for v, slide in enumerate(column):
            body = re.sub(r'<img[^>]*alt="([^"]*)"[^>]*>', r"[figure: \1]", slide.body)
            text = " ".join(html.unescape(re.sub(r"<[^>]+>", " ", body)).split())
            lines.append(f"{h}.{v} {slide.kind} | {slide.title} | {text}")
    return lines


# ---------------------------------------------------------------------------------------------------
# Offline: no deck may load a script or style sheet from the network

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



def build(lectures: list[Lecture], notebooks: Path = ROOT / "notebooks", out: Path = OUT) -> list[str]:
    """Write one deck per lecture into ``out`` and its student's deck into ``out/student``, and an
    index; return the problems found (remote assets)."""
    problems = []
    for folder, student in ((out, False), (out / STUDENT, True)):
        folder.mkdir(parents=True, exist_ok=True)
        for lecture in lectures:
            if not any(part.path(notebooks) for part in lecture.parts):
                print(f"{lecture.deck}: none of its notebooks is there yet, no deck")
                continue
            columns = lecture_columns(lecture, notebooks, student)
            page = deck_html(lecture, columns, folder, student)
            target = folder / f"{lecture.deck}.html"
            target.write_text(page, encoding="utf-8")
            problems += [f"{target} loads {r}" for r in remote_assets(page, folder)]
            slides = [s for c in columns for s in c]
            kinds = {k: sum(s.kind == k for s in slides) for k in ("figure", "number", "exercise")}
            print(f"{target}: {len(slides)} slides in {len(columns)} columns "
                  f"({kinds['figure']} figures, {kinds['number']} numbers, {kinds['exercise']} exercises), "
                  f"{sum(bool(''.join(s.notes)) for s in slides)} with speaker notes, {len(page) // 1024} KiB")
        if len(lectures) == len(load_lectures()):     # a whole build: decks of an earlier layout go
            kept = {folder / f"{lec.deck}.html" for lec in lectures} | {out / "index.html"}
            for stale in sorted(set(folder.glob("*.html")) - kept):
                stale.unlink()
                print(f"{stale}: removed (no such deck now)")
    (out / "index.html").write_text(index_html(lectures), encoding="utf-8")
    return problems


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("decks", nargs="*", help="only these decks (lecture1 ...); default: all")
    parser.add_argument("--notebooks", type=Path, default=ROOT / "notebooks", help="the notebooks' folder")
    parser.add_argument("--out", type=Path, default=OUT, help="the decks' folder (default build/slides)")
    parser.add_argument("--outline", action="store_true",
                        help="print each slide's heading and text (the instructor's decks) instead of writing the decks")
    parser.add_argument("--student", action="store_true", help="with --outline: the students' decks")
    args = parser.parse_args(argv)
    out = args.out.resolve()
    try:
        lectures = load_lectures()
        check_coverage(lectures, args.notebooks)
        chosen = [lec for lec in lectures if not args.decks or lec.deck in args.decks]
        if not chosen:
            raise DeckError(f"no deck named {args.decks}; the decks are {[lec.deck for lec in lectures]}")
        if args.outline:
            for lecture in chosen:
                print(f"# {lecture.deck}: {lecture.title}")
                print("\n".join(outline(lecture_columns(lecture, args.notebooks, args.student))))
            return 0
        missing = [f for f in REVEAL_FILES if not (NPM / REVEAL / f).is_file()]
        missing += [] if (NPM / MATHJAX).is_file() else ["mathjax"]
        if missing:
            sys.exit(f"missing under {NPM}: {missing}: run `make slides` (it installs reveal.js and mathjax from npm)")
        problems = build(chosen, args.notebooks, out)
    except DeckError as err:
        sys.exit(f"error: {err}")
    for problem in problems:
        print("error:", problem, file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
