"""The lecture decks' condensing (``docs/slides.py``), without a browser: what goes on a slide and
what goes to the speaker notes, on small notebooks built here and on the real lecture file.

``browser_tests/test_slides.py`` measures the built decks in Chromium; these run in a few seconds.
"""
import io
import re
from pathlib import Path

import nbformat
from common_testing import load_module
import numpy as np
import pytest
from PIL import Image

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
