"""The lecture slides (``make slides`` -> ``build/slides/NAME.html``) opened from disk in Chromium.

Each deck is opened as a ``file://`` page with every request that is not a file (or inline data)
blocked and recorded: no request may leave the disk. reveal.js must be initialised
(``Reveal.isReady()``), the deck must hold more than a few slides, the right arrow key must move
to the next slide, and on a deck with mathematics MathJax (the local copy) must have typeset the
formulas: no raw ``\\(`` or ``$$`` source left in any slide's text outside code. Without the decks
the tests FAIL: run ``make slides`` first. ``IFSLIB_SLIDES`` points them at another folder.
"""
from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SLIDES = Path(os.environ.get("IFSLIB_SLIDES", ROOT / "build" / "slides")).resolve()
LECTURES = sorted(p.stem for p in (ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
MIN_SLIDES = 4          # "more than a few": slides and sub-slides together
RAW_TEX = ("\\(", "\\)", "\\[", "\\]", "$$")
INLINE_DOLLARS = re.compile(r"\$[^$\s][^$\n]*\$")

# Every slide's text without its code, its typeset formulas and its scripts: where MathJax left a
# formula untypeset, its TeX source shows here (textContent: hidden slides count too).
_SLIDE_TEXT = """() => [...document.querySelectorAll('.reveal .slides section')].filter(s => !s.querySelector('section'))
    .map(s => { const c = s.cloneNode(true);
                c.querySelectorAll('pre, code, mjx-container, script, style, aside.notes').forEach(e => e.remove());
                return c.textContent; })"""


def _has_math(name: str) -> bool:
    """Whether the notebook's markdown holds a formula (``$...$``, ``$$``, ``\\(`` or ``\\[``)."""
    import nbformat

    nb = nbformat.read(ROOT / "notebooks" / f"{name}.ipynb", as_version=4)
    text = "\n".join(c.source for c in nb.cells if c.cell_type == "markdown")
    text = re.sub(r"`[^`]*`", "", text)
    return bool(INLINE_DOLLARS.search(text)) or any(m in text for m in ("$$", "\\(", "\\["))


@pytest.fixture
def offline(page):
    """``page`` with every request but ``file:``/``data:``/``blob:`` aborted; the list of those asked for."""
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


@pytest.mark.parametrize("name", LECTURES)
def test_deck_opens_offline_and_moves(offline, shots, name):
    page, asked = offline
    deck = SLIDES / f"{name}.html"
    if not deck.is_file():
        pytest.fail(f"no deck {deck}: run `make slides` first", pytrace=False)
    page.goto(deck.as_uri(), wait_until="load")
    page.wait_for_function("() => window.Reveal && Reveal.isReady()", timeout=20_000)
    total = page.evaluate("() => Reveal.getTotalSlides()")
    assert total > MIN_SLIDES, f"{name}: only {total} slides"

    loaded = page.evaluate("() => !!(window.MathJax && MathJax.startup && MathJax.startup.promise)")
    assert loaded, f"{name}: MathJax did not load (the deck's local copy under build/npm)"
    page.evaluate("() => MathJax.startup.promise")      # MathJax has typeset the page
    typeset = page.locator(".reveal mjx-container").count()
    texts = page.evaluate(_SLIDE_TEXT)
    raw = [(i, m) for i, t in enumerate(texts) for m in RAW_TEX if m in t]
    raw += [(i, d.group()) for i, t in enumerate(texts) for d in [INLINE_DOLLARS.search(t)] if d]
    if _has_math(name):
        assert typeset >= 1, f"{name}: its notebook has formulas but none is typeset on its slides"
    assert not raw, f"{name}: raw TeX source on slides (slide, text): {raw[:5]}"

    page.screenshot(path=shots / f"slides_{name}_0.png")
    first = page.evaluate("() => Reveal.getCurrentSlide().textContent")
    for _ in range(20):                  # fragments of the first slide come first, then the next slide
        page.keyboard.press("ArrowRight")
        if page.evaluate("() => Reveal.getIndices().h") == 1:
            break
    assert page.evaluate("() => Reveal.getIndices().h") == 1, f"{name}: the right arrow does not reach slide 2"
    assert page.evaluate("() => Reveal.getCurrentSlide().textContent") != first, f"{name}: slide 2 shows slide 1"
    page.wait_for_timeout(1000)          # the slide transition
    page.screenshot(path=shots / f"slides_{name}_1.png")
    errors = [e for e in page.console_errors if e.startswith("pageerror")]
    assert not errors, f"{name}: script errors {errors}"
    assert not asked, f"{name} asked for {asked[:5]}: a deck must open with no network"
