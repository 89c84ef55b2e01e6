"""The lecture decks' condensing (``docs/slides.py``), without a browser: what goes on a slide and
what goes to the speaker notes, on small notebooks built here and on the real lecture file.

``browser_tests/test_slides.py`` measures the built decks in Chromium; these run in a few seconds.
"""
import base64
import html
import io
import re
from pathlib import Path

import nbformat
from common_testing import load_module
import numpy as np
import pytest
from PIL import Image

pytestmark = pytest.mark.slow  # make test-slow: the decks are built from the stored notebooks


ROOT = Path(__file__).resolve().parents[2]
v4 = nbformat.v4




slides = load_module("ifslib_docs_slides", ROOT / "docs" / "slides.py")
LIMIT = slides.CONDENSE.bullet_chars
LONG = ("The Hutchinson operator replaces a shape $S$ by the union of its images $H(S) = \\bigcup_i T_i(S)$, "
        "and repeating it converges to the attractor, whatever non-empty bounded shape we start from, "
        "since it is a contraction for the Hausdorff distance. A second sentence.")
GRADER = {"grade": True, "solution": True, "locked": False, "points": 1, "grade_id": "t-leaves",
          "schema_version": 3}
TEST = {"grade": True, "solution": False, "locked": True, "points": 1, "grade_id": "t-leaves-test",
        "schema_version": 3}


def _balanced_math(text: str) -> bool:
    return text.replace("$$", "").count("$") % 2 == 0


def test_first_sentence_stops_at_the_end_not_inside_a_formula_or_an_abbreviation():
    text = "Take $x = 1. Y$ as given, e.g. Eq. (1) here. Then more."
    assert slides.first_sentence(text) == "Take $x = 1. Y$ as given, e.g. Eq. (1) here."
    assert slides.first_sentence("No end") == "No end"


def test_shorten_keeps_short_lines_and_cuts_long_ones_at_a_clause_outside_formulas():
    assert slides.shorten("A short line.", LIMIT) == "A short line."
    cut = slides.shorten(slides.first_sentence(LONG), LIMIT)
    assert cut.endswith(" …") and LONG.startswith(cut[:-2])
    assert slides.visible_length(cut[:-2]) <= LIMIT and _balanced_math(cut)
    assert slides.shorten("x" * 300, LIMIT) is None          # no clause to cut at: no line at all


def test_visible_length_counts_what_shows():
    assert slides.visible_length("**bold** and `code` and [a link](http://x.y)") == len("bold and code and a link")
    assert slides.visible_length("$\\alpha$") == 2           # one glyph, wide


def test_paragraphs_keep_display_math_and_folded_hints_whole():
    source = "One\nline.\n\n$$\na\n\nb\n$$\n\n<details><summary>Hint</summary>\n\nx\n\n</details>\n\nLast."
    assert slides.paragraphs(source) == ["One\nline.", "$$\na\n\nb\n$$",
                                         "<details><summary>Hint</summary>\n\nx\n\n</details>", "Last."]


def _nb(*cells):
    return v4.new_notebook(cells=list(cells))


def _exercise_notebook():
    answer = v4.new_code_cell("leaves = None\n### BEGIN SOLUTION\nleaves = 8 ** 4\n### END SOLUTION\ncheck(leaves)",
                              metadata={"nbgrader": GRADER, "tags": ["exercise"]})
    answer.outputs = [v4.new_output("stream", name="stdout", text="correct\n")]
    code = v4.new_code_cell("draw()", outputs=[v4.new_output("stream", name="stdout", text="a: 1\nb: 2\n")])
    return _nb(v4.new_markdown_cell("# 9. A lesson\n\n" + LONG),
               v4.new_markdown_cell("Parameters."), v4.new_code_cell("size = 64", metadata={"tags": ["parameters"]}),
               v4.new_markdown_cell("## Counting\n\n" + LONG + "\n\nAnother paragraph, short."), code,
               v4.new_markdown_cell("**Exercise 2 (apply).** How many leaves at depth 4?\n\n"
                                    "<details><summary>Hint</summary>Count depth 1 first.</details>"),
               answer, v4.new_code_cell("assert leaves == 4096", metadata={"nbgrader": TEST}))


def test_a_section_becomes_short_slides_with_the_rest_in_the_notes():
    secs = slides.sections(_exercise_notebook())
    assert [(s.level, s.title) for s in secs] == [(1, "9. A lesson"), (2, "Counting")]
    title = slides.SectionSlides(secs[0], "t").build()
    assert len(title) == 1 and "size = 64" not in str(title)          # the parameters cell is skipped
    opening, exercise = slides.SectionSlides(secs[1], "t").build()
    bullets = re.findall(r"<li>(.*?)</li>", opening.body)
    assert 1 <= len(bullets) <= slides.CONDENSE.bullets and "A second sentence" not in opening.body
    assert "A second sentence" in "".join(opening.notes)                # the whole prose is in the notes
    # the two-line output shares the opening's slide (both short); its code is in the notes
    assert "a: 1" in opening.body and "draw()" not in opening.body and "draw()" in "".join(opening.notes)
    assert exercise.kind == "exercise" and exercise.title == "Exercise 2 (apply)"
    assert "How many leaves" in exercise.body and "8 ** 4" not in exercise.body and "Hint" not in exercise.body
    notes = "".join(exercise.notes)
    assert "leaves = 8 ** 4" in notes and "Count depth 1 first" in notes and "BEGIN SOLUTION" not in notes
    assert "4096" not in notes                                          # nbgrader's test cell is left out


def test_a_written_exercise_puts_its_model_answer_in_the_notes():
    answer = v4.new_markdown_cell("### BEGIN SOLUTION\nThe bound is $s^K d_0$. Rubric: 1 point.\n### END SOLUTION",
                                  metadata={"nbgrader": dict(GRADER, grade_id="t-proof")})
    sec = slides.sections(_nb(v4.new_markdown_cell("## Proofs\n\n**Exercise 3 (prove).** Show the bound."), answer))[0]
    opening, exercise = slides.SectionSlides(sec, "t").build()
    assert "Show the bound" in exercise.body and "Rubric" not in exercise.body
    assert "Rubric: 1 point" in "".join(exercise.notes)


def _grid(rows: int, cols: int, panel: int = 60, gap: int = 12) -> bytes:
    """A white figure of rows x cols black panels (a matplotlib grid's layout)."""
    pixels = np.full((rows * (panel + gap) + gap, cols * (panel + gap) + gap, 3), 255, np.uint8)
    for r in range(rows):
        for c in range(cols):
            y, x = gap + r * (panel + gap), gap + c * (panel + gap)
            pixels[y:y + panel, x:x + panel] = 0
    out = io.BytesIO()
    Image.fromarray(pixels).save(out, format="PNG")
    return out.getvalue()


def _size(png: bytes) -> tuple[int, int]:
    return Image.open(io.BytesIO(png)).size


def test_a_tall_grid_is_cut_into_rows_and_a_wide_one_is_kept():
    tall = _grid(4, 3, gap=4)             # rows three times as wide as tall, as 02's galleries
    pieces = slides.figure_pieces(tall)
    assert len(pieces) == 4 and all(_size(p) == (_size(tall)[0], 60) for p in pieces)
    assert slides.figure_pieces(_grid(1, 4)) == [_grid(1, 4)]            # already as wide as a slide
    assert slides.figure_pieces(_grid(1, 1)) == [_grid(1, 1)]            # one panel: nothing to cut
    pairs = slides.figure_pieces(_grid(8, 8, gap=4))    # wide rows go four a slide (width-bound anyway)
    assert [_size(p)[1] for p in pairs] == [4 * 64 - 4] * 2


def test_the_lecture_file_covers_every_lecture_notebook():
    lectures = slides.load_lectures()
    slides.check_coverage(lectures, ROOT / "notebooks")     # raises, naming the notebooks left out
    with pytest.raises(slides.DeckError, match="in no lecture"):
        slides.check_coverage(lectures[1:], ROOT / "notebooks")


def test_a_section_that_is_gone_fails_with_the_sections_there_are():
    secs = slides.sections(_exercise_notebook())
    with pytest.raises(slides.DeckError, match=r"no `##` section starting with 'Gone'.*\['Counting'\]"):
        slides.pick(secs, slides.Part("x", ("Gone",)), "notebooks/x.ipynb")


def test_the_real_decks_show_no_worked_answer_and_note_every_one():
    for lecture in slides.load_lectures():
        columns = slides.lecture_columns(lecture, ROOT / "notebooks")
        shown = [s for column in columns for s in column]
        assert all("BEGIN SOLUTION" not in s.body for s in shown), lecture.deck
        assert all("answer" in "".join(s.notes) for s in shown if s.kind == "exercise"), lecture.deck
        assert all(any("".join(s.notes).strip() for s in column) for column in columns), lecture.deck


def test_a_part_is_found_by_its_number_and_an_optional_one_may_be_missing(tmp_path):
    (tmp_path / "09_measures.ipynb").write_text("{}")
    assert slides.Part("09", None).path(tmp_path).name == "09_measures.ipynb"
    assert slides.Part("10", None, optional=True).path(tmp_path) is None
    with pytest.raises(slides.DeckError, match="matches nothing"):
        slides.Part("10", None).path(tmp_path)


def test_short_numbers_share_a_slide_only_while_they_fit():
    def number(height):
        return slides.Slide("s", "number", f"<pre>{height}</pre>", ["code"], "", height)

    room = slides.CONDENSE.room
    merged = slides.merge_short([slides.Slide("s", "opening", "<ul></ul>", height=100), number(100), number(room)], set())
    assert [s.kind for s in merged] == ["opening", "number"] and "<pre>100</pre>" in merged[0].body
    assert merged[1].body == f"<pre>{room}</pre>"


def test_talking_points_of_the_lecture_file_replace_the_bullets_and_must_match_a_section(tmp_path):
    nbformat.write(_exercise_notebook(), tmp_path / "09_lesson.ipynb")
    lecture = slides.Lecture("t", "Lecture 9: t", (slides.Part("09", None),), {"Count": ("One point.", "Two.")})
    columns = slides.lecture_columns(lecture, tmp_path)
    opening = columns[2][0]
    assert re.findall(r"<li>(.*?)</li>", opening.body) == ["One point.", "Two."]
    assert "A second sentence" in "".join(opening.notes)
    stale = slides.Lecture("t", "Lecture 9: t", lecture.parts, {"Gone": ("x",)})
    with pytest.raises(slides.DeckError, match=r"bullets for \['Gone'\] match no section"):
        slides.lecture_columns(stale, tmp_path)


def test_a_line_of_labels_stays_with_the_row_it_is_nearer():
    """Each row of panels has a label line 4 px under it and the next row 14 px further: a cut
    between rows keeps each row's labels (02's captions under its panels)."""
    width, rows = 228, []
    for _ in range(4):
        rows += [np.zeros((60, width)), np.full((4, width), 255), np.zeros((6, width)), np.full((14, width), 255)]
    pixels = np.concatenate(rows).astype(np.uint8)
    out = io.BytesIO()
    Image.fromarray(pixels).convert("RGB").save(out, format="PNG")
    pieces = slides.figure_pieces(out.getvalue())
    assert [_size(p)[1] for p in pieces] == [70] * 4


# ---------------------------------------------------------------------------------------------------
# Sections, exercises and captions as the later notebooks write them (headings inside a cell,
# "### Exercise N" headings, "*Figure: ...*" under the figure), and the real decks checked for each

def _png_output():
    out = io.BytesIO()
    Image.fromarray(np.zeros((40, 80, 3), np.uint8)).save(out, format="PNG")
    return v4.new_output("display_data", data={"image/png": base64.b64encode(out.getvalue()).decode(),
                                               "text/plain": "<Figure>"})


def test_a_heading_inside_a_cell_opens_a_section_and_the_cells_after_it_go_there():
    decoded = v4.new_code_cell("decode()", outputs=[_png_output()])
    book = _nb(v4.new_markdown_cell("# 10. A lesson"),
               v4.new_markdown_cell("## Blocks\n\nCut the image into blocks."),
               v4.new_markdown_cell("The mean is rounded.\n\n## Decoding\n\nThe file holds no pixels, only maps."),
               decoded,
               v4.new_markdown_cell("*Figure: the decoder's iterates from a black image.* The change falls fast."))
    secs = slides.sections(book)
    assert [s.title for s in secs] == ["10. A lesson", "Blocks", "Decoding"]
    figure = [s for s in slides.SectionSlides(secs[2], "t").build() if s.kind == "figure"]
    assert len(figure) == 1 and figure[0].title == "Decoding"
    # the caption written under the figure is its caption and its alt text
    assert figure[0].caption == "The decoder's iterates from a black image."
    assert 'alt="%s"' % html.escape("The decoder's iterates from a black image.") in figure[0].body


def test_an_exercise_heading_opens_an_exercise_with_its_table_on_the_slide():
    answer = v4.new_code_cell("d = None\n### BEGIN SOLUTION\nd = 1.5\n### END SOLUTION", metadata={"nbgrader": GRADER})
    book = _nb(v4.new_markdown_cell("## On your own\n\n### Exercise 3 (by hand). A box dimension from counts\n\n"
                                    "A student counted boxes:\n\n| side | 1/4 | 1/32 |\n|---|---|---|\n| boxes | 14 | 318 |\n\n"
                                    "Estimate the dimension."), answer)
    secs = slides.sections(book)
    assert [s.title for s in secs] == ["On your own"]          # the exercise's heading opens no section
    opening, exercise = slides.SectionSlides(secs[0], "t").build()
    assert exercise.kind == "exercise" and exercise.title == "Exercise 3 (by hand). A box dimension from counts"
    assert "<table>" in exercise.body and "318" in exercise.body and "Estimate the dimension" in exercise.body
    assert "d = 1.5" in "".join(exercise.notes) and "d = 1.5" not in exercise.body
    assert "Exercise 3 (by hand)" in opening.body             # an opening of exercises lists them


def test_a_long_statement_is_cut_at_a_clause_of_the_sentence_that_does_not_fit():
    long = ("Move the point over a grid within a wider range instead, compute the descent fields of both "
            "losses there with the library's gradient field, and store in a variable the share of arrows "
            "pointing toward the optimum for each loss, which your function of exercise 1 gives, then say "
            "which loss still leads back from further out, and why the other one does not, in a sentence or two.")
    slide = slides.exercise_slide(["**Exercise 3 (extension): further out.** The figure looked close. " + long])
    text = re.sub(r"<[^>]+>", "", slide.body)
    assert text.startswith("The figure looked close. Move the point") and text.endswith(" …")
    assert slides.visible_length(text) <= slides.CONDENSE.statement_chars + 2


def test_an_answer_cell_without_its_statement_fails_naming_the_cell():
    answer = v4.new_code_cell("x = None\n### BEGIN SOLUTION\nx = 1\n### END SOLUTION", metadata={"nbgrader": GRADER})
    sec = slides.sections(_nb(v4.new_markdown_cell("## Counting\n\nSome prose."), answer))[0]
    with pytest.raises(slides.DeckError, match="t-leaves.*no exercise before it"):
        slides.SectionSlides(sec, "t").build()


def test_the_opening_takes_no_bullet_from_a_paragraph_about_an_output_shown_later():
    number = v4.new_code_cell("print(l1)", outputs=[v4.new_output("stream", name="stdout", text="L1: 0.062\n")])
    sec = slides.sections(_nb(v4.new_markdown_cell("## Two ways\n\nThe histogram is a random estimate.\n\n"
                                                   "A second way pushes the mass."), number,
                              v4.new_markdown_cell("The two pictures agree to within the L1 printed above.")))[0]
    built = slides.SectionSlides(sec, "t").build()
    shown = "".join(s.body for s in built)
    assert "random estimate" in shown and "L1: 0.062" in shown
    assert "printed above" not in shown and "printed above" in "".join(built[0].notes)


def test_a_figure_is_captioned_by_the_sentence_that_points_at_it_else_by_its_title():
    cells = [v4.new_markdown_cell("## Fern\n\nThe stem map squashes the fern. Below, three choices drawn as histograms."),
             v4.new_code_cell("draw()", outputs=[_png_output()]),
             v4.new_code_cell('fig.suptitle(f"The measure at {size}², two ways")\nplt.show()', outputs=[_png_output()]),
             v4.new_code_cell('ax.set_title(f"iteration {k}: {psnr(x):.1f} dB")', outputs=[_png_output()])]
    assert slides.figure_caption(cells, 1) == "Three choices drawn as histograms."   # under it: no "Below"
    colon = [v4.new_markdown_cell("Below: the root, and box counting:"), cells[1]]
    assert slides.figure_caption(colon, 1) == "The root, and box counting."
    assert slides.figure_caption(cells, 2) == "The measure at `size`², two ways"      # after a figure: its title
    # a sentence that points "above" speaks of an earlier output
    back = [v4.new_markdown_cell("The target above is the library's. The last exercise is a curve drawn at random."),
            cells[1]]
    assert slides.figure_caption(back, 1) == "The last exercise is a curve drawn at random."
    # a computed title says nothing without its values: the section's heading is the last resort
    assert slides.figure_caption(cells, 3) == "Fern"
    assert slides.figure_caption([v4.new_markdown_cell("## Success rate"), cells[3]], 1) == "Success rate"


@pytest.fixture(scope="module")
def real_decks():
    return {lec.deck: (lec, slides.lecture_columns(lec, ROOT / "notebooks")) for lec in slides.load_lectures()}


def _headings(lecture):
    """The headings of the sections a deck shows: every `#`-`###` heading of its notebooks' kept sections,
    at a cell's top or inside it, but an exercise's."""
    found = []
    for part in lecture.parts:
        path = part.path(ROOT / "notebooks")
        secs = slides.pick(slides.sections(nbformat.read(path, as_version=4)), part, path.name)
        found += [s.title for s in secs]
    return found


def test_every_section_of_a_deck_has_its_slides_under_its_own_heading(real_decks):
    for deck, (lecture, columns) in real_decks.items():
        titles = {s.title for column in columns for s in column}
        missing = [h for h in _headings(lecture) if h not in titles]
        assert not missing, f"{deck}: no slide under the heading(s) {missing}"


def test_every_exercise_has_a_slide_with_its_statement(real_decks):
    for deck, (lecture, columns) in real_decks.items():
        answers = []
        for part in lecture.parts:
            path = part.path(ROOT / "notebooks")
            secs = slides.pick(slides.sections(nbformat.read(path, as_version=4)), part, path.name)
            answers += [c for s in secs for c in s.cells if slides._is_answer(c)]
        exercises = [s for column in columns for s in column if s.kind == "exercise"]
        assert len(exercises) == len(answers), f"{deck}: {len(exercises)} exercise slides, {len(answers)} answers"
        for slide in exercises:
            assert re.match(r"Exercise\b", slide.title) and "statement is not in" not in slide.body, (deck, slide.title)
            assert len(re.sub(r"<[^>]+>", "", slide.body).strip()) > 20, (deck, slide.title)


def test_lecture_6_shows_its_exercises_and_figures_where_the_notebooks_put_them(real_decks):
    lecture, columns = real_decks["lecture6"]
    shown = [s for column in columns for s in column]
    assert not any("statement is not in" in s.body for s in shown)
    assert sum(s.kind == "exercise" for s in shown) == 8
    table = next(s for s in shown if s.title.startswith("Exercise 3 (recall, by hand)"))
    assert "<table>" in table.body and "318" in table.body        # the counts, on the slide
    title = {s.caption: s.title for s in shown if s.kind == "figure"}
    assert title["The decoder's iterates from a black `size`² image (128²), with their PSNR against the photograph."] \
        == "Decoding: the attractor from a blank image"
    assert any(t.startswith("Rate and distortion") for c, t in title.items() if c.startswith("PSNR against bits"))
    assert not any("printed above" in s.body for s in shown if s.kind == "opening")


#: an alt text that names the image's file instead of what it shows (MyST-NB's default is the hash)
HASHLIKE = re.compile(r"^([0-9a-f]{16,}|.*\.(png|jpe?g|svg))$|^a figure$|^\s*$", re.I)


def test_no_figure_of_a_deck_has_an_alt_text_that_looks_like_a_hash(real_decks):
    for deck, (lecture, columns) in real_decks.items():
        alts = [html.unescape(a) for s in (s for c in columns for s in c) for a in re.findall(r'alt="([^"]*)"', s.body)]
        assert alts and not [a for a in alts if HASHLIKE.match(a.split(" (row")[0])], deck


def test_every_notebook_figure_has_a_caption_for_its_alt_text():
    """The book's copy of each notebook (docs/build.py) gives every figure its caption as alt text."""
    for path in sorted((ROOT / "notebooks").glob("*.ipynb")):
        book = nbformat.read(path, as_version=4)
        alts = slides.alt_texts(book)
        figures = [i for i, c in enumerate(book.cells) if slides._has_image(c)]
        assert sorted(alts) == figures, path.name
        assert not [a for a in alts.values() if HASHLIKE.match(a) or "`" in a or "**" in a], path.name


def test_the_books_copy_of_a_notebook_carries_the_alt_texts(tmp_path):
    build = load_module("ifslib_docs_build", ROOT / "docs" / "build.py")
    source = ROOT / "notebooks" / "10_fractal_compression.ipynb"
    build.student_exercises(source, tmp_path / source.name)
    copy = nbformat.read(tmp_path / source.name, as_version=4)
    alts = [c.metadata["mystnb"]["image"]["alt"] for c in copy.cells
            if c.cell_type == "code" and any("image/png" in o.get("data", {}) for o in c.get("outputs", []))]
    assert alts and all(not HASHLIKE.match(a) for a in alts)
    assert "The decoder's iterates from a black size² image (128²), with their PSNR against the photograph." in alts


def test_the_books_copy_shows_the_exercises_as_the_student_edition_has_them(tmp_path):
    """No worked answer, hidden test or answer's output in the book's copy (students read the book)."""
    build = load_module("ifslib_docs_build", ROOT / "docs" / "build.py")
    student = load_module("ifslib_student_edition", ROOT / "notebooks" / "student.py")
    for name in ("00_tutorial.ipynb", "09_measures_and_dimension.ipynb"):
        source = ROOT / "notebooks" / name
        assert build.student_exercises(source, tmp_path / name) > 0
        instructor, copy = nbformat.read(source, as_version=4), nbformat.read(tmp_path / name, as_version=4)
        shown = {line.strip() for c in copy.cells for line in c.source.splitlines()}
        shown |= {line.strip() for c in copy.cells if c.cell_type == "code" for o in c.outputs
                  for line in "".join(o.get("text", "")).splitlines()}
        assert not shown & (student.solution_lines(instructor) | student.hidden_lines(instructor)), name
        assert not [c for c in copy.cells if student.is_exercise(c) and c.cell_type == "code" and c.outputs]


def test_outline_lists_each_slide_with_its_heading_and_words(real_decks):
    lecture, columns = real_decks["lecture6"]
    lines = slides.outline(columns)
    assert len(lines) == sum(len(c) for c in columns)
    assert any(line.startswith(tuple(f"{h}." for h in range(len(columns)))) and " exercise | Exercise 3 (recall, by hand)" in line
               and "318" in line for line in lines)
