"""The static HTML book (``make book`` -> ``build/book/html``) opened in Chromium over HTTP.

The front page says "ifslib" and links to the notebook pages, the results pages and the API
reference; a notebook page shows its figures (at least one image, none broken) and no traceback;
the API reference and a results page load with no console error, the API page of `ifslib.fit`
shows its signature, parameters and returns, and the results page the command that regenerates
it; the tutorial's formulas are typeset by the book's own MathJax, with no request to the network
and no raw TeX source left on the page. Without the built book the tests FAIL: run ``make book`` first. ``IFSLIB_BOOK_HTML`` points
them at another built tree.
"""
from __future__ import annotations

import functools
import http.server
import os
import threading
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
BOOK = Path(os.environ.get("IFSLIB_BOOK_HTML", ROOT / "build" / "book" / "html"))
NOTEBOOK_PAGE = "notebooks/00_explore.html"
API_PAGE = "docs/api/index.html"
FIT_PAGE = "docs/api/generated/ifslib.fit.html"
RESULTS_PAGE = "docs/results/strategies.html"
MATH_PAGE = "notebooks/00_tutorial.html"

# Every <img>: its address and whether it loaded (naturalWidth is 0 for a broken image).
_IMAGES = """() => [...document.images].map(i => ({src: i.currentSrc || i.src, ok: i.complete && i.naturalWidth > 0,
                                                 w: i.naturalWidth, h: i.naturalHeight}))"""


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def _require(page_path: str) -> None:
    """Fail (not skip, not error) when the book, or this page of it, has not been built."""
    if not (BOOK / page_path).is_file():
        pytest.fail(f"no built book page {BOOK / page_path}: run `make book` first", pytrace=False)


@pytest.fixture(scope="module")
def book():
    """The book folder served on 127.0.0.1 (a free port) from a thread; its base URL."""
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Quiet, directory=str(BOOK)))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()
    thread.join(timeout=5)


def _failed_local_requests(page, book: str) -> list:
    """Start recording the book's own resources (pages, CSS, scripts, images) that answer 4xx/5xx."""
    failed = []
    page.on("response", lambda r: r.status >= 400 and r.url.startswith(book) and not r.url.endswith("/favicon.ico")
            and failed.append(f"{r.status} {r.url}"))
    return failed


def test_front_page(page, book, shots):
    _require("index.html")
    failed = _failed_local_requests(page, book)
    response = page.goto(f"{book}/index.html", wait_until="load")
    assert response is not None and response.ok, f"index.html answered {response and response.status}"
    assert "ifslib" in page.title(), f"the front page's title is {page.title()!r}"
    assert "ifslib" in page.locator("h1").first.inner_text(), "the front page's heading does not say ifslib"
    links = page.eval_on_selector_all("a[href]", "els => els.map(a => a.getAttribute('href'))")
    for target in (NOTEBOOK_PAGE, API_PAGE, RESULTS_PAGE):
        assert any(h.split("#")[0].endswith(target) for h in links), f"the front page does not link to {target}"
    assert not failed, f"the front page's own resources failed: {failed}"
    page.screenshot(path=shots / "book_index.png")


def test_notebook_page_shows_its_figures(page, book, shots):
    _require("index.html")
    _require(NOTEBOOK_PAGE)
    failed = _failed_local_requests(page, book)
    response = page.goto(f"{book}/{NOTEBOOK_PAGE}", wait_until="load")
    assert response is not None and response.ok, f"{NOTEBOOK_PAGE} answered {response and response.status}"
    assert "ifslib" in page.title(), f"the notebook page's title is {page.title()!r}"
    images = page.evaluate(_IMAGES)
    shown = [i for i in images if i["ok"] and i["w"] >= 50 and i["h"] >= 50]
    broken = [i["src"] for i in images if not i["ok"] and i["src"].startswith(book)]
    assert shown, f"{NOTEBOOK_PAGE} shows no image (images: {images})"
    assert not broken, f"{NOTEBOOK_PAGE} has broken images: {broken}"
    assert "Traceback" not in page.locator("body").inner_text(), f"{NOTEBOOK_PAGE} shows a traceback"
    assert not failed, f"{NOTEBOOK_PAGE}'s own resources failed: {failed}"
    page.evaluate("src => [...document.images].find(i => (i.currentSrc || i.src) === src).scrollIntoView()",
                  shown[0]["src"])
    page.screenshot(path=shots / "book_notebook.png")


def _open_cleanly(page, book: str, path: str) -> None:
    """Open ``path`` and require: it answers, its own resources load, and the console shows no error."""
    _require(path)
    failed = _failed_local_requests(page, book)
    response = page.goto(f"{book}/{path}", wait_until="load")
    assert response is not None and response.ok, f"{path} answered {response and response.status}"
    assert "ifslib" in page.title(), f"{path}'s title is {page.title()!r}"
    assert "Traceback" not in page.locator("body").inner_text(), f"{path} shows a traceback"
    assert not failed, f"{path}'s own resources failed: {failed}"
    assert not page.console_errors, f"{path}: console errors {page.console_errors}"


def test_api_reference_lists_every_public_name_and_documents_fit(page, book, shots):
    import ifslib

    _open_cleanly(page, book, API_PAGE)
    links = page.eval_on_selector_all("a[href]", "els => els.map(a => a.getAttribute('href'))")
    missing = [n for n in ifslib.__all__ if not any(h.split("#")[0].endswith(f"ifslib.{n}.html") for h in links)]
    assert not missing, f"{API_PAGE} does not link to {missing}"
    page.screenshot(path=shots / "book_api.png")
    _open_cleanly(page, book, FIT_PAGE)
    entry = page.locator('dl.py.function:has(dt[id="ifslib.fit"])').inner_text()
    assert "fit(" in entry and "steps" in entry and "Parameters" in entry and "Returns" in entry, entry[:500]


def test_results_page_opens_with_its_command(page, book, shots):
    _open_cleanly(page, book, RESULTS_PAGE)
    first_code = page.locator("pre").first.inner_text()
    assert "benchmarks/convergence.py" in first_code, f"{RESULTS_PAGE}'s first code block: {first_code[:200]!r}"
    assert page.locator("table").count() >= 2, f"{RESULTS_PAGE} lost its tables"
    page.screenshot(path=shots / "book_results.png")


def test_formulas_are_typeset_with_no_network(page, book, shots):
    """The tutorial's formulas show as mathematics, typeset by the book's own MathJax: no raw ``\\(`` source."""
    _require(MATH_PAGE)
    outside = []
    page.on("request", lambda r: not r.url.startswith((book, "data:", "blob:")) and outside.append(r.url))
    _open_cleanly(page, book, MATH_PAGE)
    page.wait_for_selector("mjx-container", timeout=20_000)
    typeset = page.locator("mjx-container").count()
    # the page's text outside code blocks: where a formula MathJax did not typeset shows its TeX source
    text = page.evaluate("""() => { const c = document.querySelector('main') || document.body;
        const copy = c.cloneNode(true); copy.querySelectorAll('pre, code, mjx-container, script').forEach(e => e.remove());
        return copy.innerText; }""")
    raw = [m for m in ("\\(", "\\)", "\\[", "$$") if m in text]
    assert typeset >= 5, f"{MATH_PAGE}: only {typeset} formulas typeset"
    assert not raw, f"{MATH_PAGE} shows raw TeX source ({raw}) outside its code"
    assert not outside, f"{MATH_PAGE} asked the network for {outside[:5]}"
    page.screenshot(path=shots / "book_math.png")


# Every code block of a notebook page: its first line and whether it is wider than the column (a scroll bar).
_WIDE_CODE = """() => [...document.querySelectorAll('div.cell_input pre')]
    .filter(p => p.scrollWidth > p.clientWidth + 1)
    .map(p => p.textContent.split('\\n').find(l => l.length > 88) || p.textContent.slice(0, 80))"""


def test_notebook_code_fits_the_column(page, book):
    """No code cell of a notebook page scrolls sideways at a laptop's width (1280 px): the book's column holds it."""
    _require("index.html")
    page.set_viewport_size({"width": 1280, "height": 900})
    pages = sorted(p.relative_to(BOOK).as_posix() for p in (BOOK / "notebooks").glob("*.html"))
    assert pages, "no notebook pages in the book"
    wide = {}
    for name in pages:
        page.goto(f"{book}/{name}", wait_until="load")
        lines = page.evaluate(_WIDE_CODE)
        if lines:
            wide[name] = lines
    assert not wide, f"code wider than the book's column (a scroll bar): {wide}"
