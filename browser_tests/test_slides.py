"""The lecture decks (``make slides`` -> ``build/slides/DECK.html``) opened from disk in Chromium at
1280 x 720.

Each deck of ``docs/slides/lectures.yaml`` is opened as a ``file://`` page with every request that
is not a file (or inline data) blocked and recorded: no request may leave the disk. reveal.js must
be initialised with its speaker-notes plugin, MathJax (the local copy) must have typeset the
formulas (no raw ``\\(`` or ``$$`` left in any slide's text outside code), and the right arrow key
must move to the next slide. Then every slide is shown in turn and measured:

* nothing overflows: every element of the slide lies within the slide's box, and the slide's page
  does not scroll;
* a figure is large (at least ``FIGURE_SHARE`` of the slide's width or height) and its caption and
  the slide's text are at least ``MIN_FONT_PX`` tall, in the slide's own pixels;
* every column (a lecture section: a notebook's title or one of its ``##`` steps) has speaker notes.

The students' decks (``build/slides/student/DECK.html``: the same slides, other notes) are opened
the same way, offline. A screenshot of every slide goes to ``build/browser/slides/DECK/H-V.png``.
Without the decks the tests FAIL: run ``make slides`` first. ``IFSLIB_SLIDES`` points them at another folder.
"""
from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
import yaml

ROOT = Path(__file__).resolve().parent.parent
SLIDES = Path(os.environ.get("IFSLIB_SLIDES", ROOT / "build" / "slides")).resolve()
LECTURES = yaml.safe_load((ROOT / "docs" / "slides" / "lectures.yaml").read_text(encoding="utf-8"))


def _notebooks(parts) -> list[Path]:
    """The notebooks a deck is built from: by name, or by number ("09": 09_*.ipynb); absent ones left out."""
    folder = ROOT / "notebooks"
    return [path for p in parts for name in [str(p["notebook"])]
            for path in ([folder / f"{name}.ipynb"] if (folder / f"{name}.ipynb").is_file()
                         else sorted(folder.glob(f"{name}_*.ipynb")))]


#: the decks `make slides` builds: those with a notebook there (a lecture of notebooks to come has none)
DECKS = {lec["deck"]: found for lec in LECTURES for found in [_notebooks(lec["parts"])] if found}
VIEWPORT = {"width": 1280, "height": 720}
MIN_SLIDES = 4          # "more than a few"
FIGURE_SHARE = 0.6      # a figure's drawn width over the slide's, or height over the slide's, at least
MIN_FONT_PX = 20        # the smallest text on a slide, in the slide's 1280 x 720 pixels
RAW_TEX = ("\\(", "\\)", "\\[", "\\]", "$$")
INLINE_DOLLARS = re.compile(r"\$[^$\s][^$\n]*\$")

# Every slide's text without its code, its typeset formulas, scripts and notes: where MathJax left a
# formula untypeset, its TeX source shows here (textContent: hidden slides count too).
_SLIDE_TEXT = """() => [...document.querySelectorAll('.reveal .slides section')].filter(s => !s.querySelector('section'))
    .map(s => { const c = s.cloneNode(true);
                c.querySelectorAll('pre, code, mjx-container, script, style, aside.notes').forEach(e => e.remove());
                return c.textContent; })"""

# The current slide measured in the slide's own pixels (the deck is scaled to fit the window).
_MEASURE = """() => {
  const slide = Reveal.getCurrentSlide(), box = document.querySelector('.reveal .slides').getBoundingClientRect();
  const scale = box.width / Reveal.getConfig().width, page = slide.querySelector('.page');
  const out = [], fonts = [], figures = [];
  for (const e of page.querySelectorAll('*')) {
    if (e.closest('mjx-assistive-mml')) continue;      // MathJax's copy for screen readers, clipped
    const r = e.getBoundingClientRect();
    if (r.width === 0 && r.height === 0) continue;
    if (r.left < box.left - 1 || r.right > box.right + 1 || r.top < box.top - 1 || r.bottom > box.bottom + 1)
      out.push(`${e.tagName.toLowerCase()}.${e.className} ${Math.round(r.left - box.left)},${Math.round(r.top - box.top)}`
               + ` to ${Math.round(r.right - box.left)},${Math.round(r.bottom - box.top)}`);
    const text = [...e.childNodes].some(n => n.nodeType === 3 && n.textContent.trim());
    if (text && !e.closest('mjx-container'))
      fonts.push(parseFloat(getComputedStyle(e).fontSize));
  }
  for (const img of page.querySelectorAll('.figure img')) {
    const r = img.getBoundingClientRect(), aspect = img.naturalWidth / img.naturalHeight;
    const w = Math.min(r.width, r.height * aspect), h = Math.min(r.height, r.width / aspect);
    figures.push([w / box.width, h / box.height, img.naturalWidth]);
  }
  // across, the element boxes above say it: MathJax's clipped copy for screen readers widens scrollWidth
  const scrolls = page.scrollHeight > page.clientHeight + 1;
  return {out, scrolls, figures, smallest: fonts.length ? Math.min(...fonts) : null, scale};
}"""


def _has_math(notebooks: list[Path]) -> bool:
    """Whether the notebooks' markdown holds a formula (``$...$``, ``$$``, ``\\(`` or ``\\[``)."""
    import nbformat

    text = "\n".join(c.source for path in notebooks for c in nbformat.read(path, as_version=4).cells
                     if c.cell_type == "markdown")
    text = re.sub(r"`[^`]*`", "", text)
    return bool(INLINE_DOLLARS.search(text)) or any(m in text for m in ("$$", "\\(", "\\["))


@pytest.fixture
def offline(page):
    """``page`` at 1280 x 720 with every request but ``file:``/``data:``/``blob:`` aborted; the list asked for."""
    page.set_viewport_size(VIEWPORT)
    asked = []
    local = ("file:", "data:", "blob:")
    page.on("request", lambda r: not r.url.startswith(local) and asked.append(r.url))

    def block(route):
        if route.request.url.startswith(local):
            route.continue_()
        else:
            asked.append(route.request.url)
            route.abort()

    page.route("**/*", block)
    return page, asked


def _open(page, name: str):
    deck = SLIDES / f"{name}.html"
    if not deck.is_file():
        pytest.fail(f"no deck {deck}: run `make slides` first", pytrace=False)
    page.goto(deck.as_uri(), wait_until="load")
    page.wait_for_function("() => window.Reveal && Reveal.isReady()", timeout=20_000)
    page.wait_for_function("() => window.MathJax && MathJax.startup && MathJax.startup.promise", timeout=20_000)
    page.evaluate("() => MathJax.startup.promise")      # MathJax has typeset the page
    page.evaluate("() => Reveal.configure({transition: 'none', backgroundTransition: 'none'})")


@pytest.mark.parametrize("name", sorted(DECKS) + [f"student/{deck}" for deck in sorted(DECKS)])
def test_deck_opens_offline_and_moves(offline, shots, name):
    page, asked = offline
    _open(page, name)
    assert page.evaluate("() => Reveal.hasPlugin('notes')"), f"{name}: no speaker view (reveal.js's notes plugin)"
    total = page.evaluate("() => Reveal.getTotalSlides()")
    assert total > MIN_SLIDES, f"{name}: only {total} slides"
    typeset = page.locator(".reveal .slides mjx-container").count()
    texts = page.evaluate(_SLIDE_TEXT)
    raw = [(i, m) for i, t in enumerate(texts) for m in RAW_TEX if m in t]
    raw += [(i, d.group()) for i, t in enumerate(texts) for d in [INLINE_DOLLARS.search(t)] if d]
    if _has_math(DECKS[name.rsplit("/", 1)[-1]]):
        assert typeset >= 1, f"{name}: its notebooks have formulas but none is typeset on its slides"
    assert not raw, f"{name}: raw TeX source on slides (slide, text): {raw[:5]}"

    first = page.evaluate("() => Reveal.getCurrentSlide().textContent")
    page.keyboard.press("ArrowRight")
    assert page.evaluate("() => Reveal.getIndices().h") == 1, f"{name}: the right arrow does not reach slide 2"
    assert page.evaluate("() => Reveal.getCurrentSlide().textContent") != first, f"{name}: slide 2 shows slide 1"
    errors = [e for e in page.console_errors if e.startswith("pageerror")]
    assert not errors, f"{name}: script errors {errors}"
    assert not asked, f"{name} asked for {asked[:5]}: a deck must open with no network"


@pytest.mark.parametrize("name", sorted(DECKS))
def test_every_slide_fits_and_reads(offline, shots, name):
    page, _ = offline
    _open(page, name)
    folder = shots / "slides" / name
    folder.mkdir(parents=True, exist_ok=True)
    problems = []
    for h, v in page.evaluate("() => Reveal.getSlides().map(s => [Reveal.getIndices(s).h, Reveal.getIndices(s).v || 0])"):
        page.evaluate(f"() => Reveal.slide({h}, {v})")
        m = page.evaluate(_MEASURE)
        where = f"{name} slide {h}-{v}"
        problems += [f"{where}: {e} runs off the 1280 x 720 slide" for e in m["out"][:3]]
        problems += [f"{where}: its page scrolls (too much on one slide)"] if m["scrolls"] else []
        if m["smallest"] is not None and m["smallest"] < MIN_FONT_PX:
            problems.append(f"{where}: text at {m['smallest']:.0f} px (at least {MIN_FONT_PX})")
        problems += [f"{where}: a figure drawn at {w:.0%} of the width and {h_:.0%} of the height"
                     for w, h_, natural in m["figures"] if max(w, h_) < FIGURE_SHARE or natural == 0]
        page.screenshot(path=folder / f"{h:02d}-{v:02d}.png")
    assert not problems, f"{len(problems)} problems:\n" + "\n".join(problems)


@pytest.mark.parametrize("name", sorted(DECKS))
def test_every_section_has_speaker_notes(offline, name):
    page, _ = offline
    _open(page, name)
    columns = page.evaluate("""() => [...document.querySelectorAll('.reveal .slides > section')].map(c =>
        [c.querySelector('h1, h2') ? c.querySelector('h1, h2').textContent : '?',
         [...c.querySelectorAll('aside.notes')].filter(a => a.textContent.trim()).length])""")
    bare = [title for title, notes in columns if notes == 0]
    assert len(columns) > 1 and not bare, f"{name}: sections without speaker notes: {bare}"
    unanswered = page.evaluate("""() => [...document.querySelectorAll('.reveal section.exercise')]
        .filter(s => !/answer/i.test((s.querySelector('aside.notes') || {}).textContent || ''))
        .map(s => s.querySelector('h2').textContent)""")
    assert not unanswered, f"{name}: exercises whose speaker notes hold no worked answer: {unanswered}"
