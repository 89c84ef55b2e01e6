"""The exercises' test cells, run as nbgrader runs them (the whole cell, hidden tests included).

The instructor's answer passes; the blank release's answer, typical wrong answers and lazy answers
(the library's own function handed in, a ``functools.partial`` of it, a lambda or a closure calling
it, the target's truth) raise ``AssertionError`` with a hint; the installed package holds no answer key.
"""
from __future__ import annotations

import functools
import math
import re
import sys
from pathlib import Path

import nbformat
import numpy as np
import pytest
import torch

import ifslib
from ifslib.errors import IFSError

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "course"))
import targets as course_targets  # noqa: E402  the instructor's truths

GRADED = ["00_tutorial", "01_koch_iterations", "05_more_examples", "07_your_own_image"]
SOLUTION = re.compile(r"^([ \t]*)### BEGIN SOLUTION.*?### END SOLUTION[ \t]*(\n|\Z)", re.M | re.S)
HIDDEN = re.compile(r"^[ \t]*#+\s*BEGIN HIDDEN TESTS.*?#+\s*END HIDDEN TESTS[ \t]*$", re.M | re.S)


@functools.cache
def graded_cells(name: str) -> dict[str, nbformat.NotebookNode]:
    book = nbformat.read(ROOT / "notebooks" / f"{name}.ipynb", as_version=4)
    return {c.metadata["nbgrader"]["grade_id"]: c for c in book.cells if c.metadata.get("nbgrader")}


def cell_of(grade_id: str) -> nbformat.NotebookNode:
    return graded_cells(grade_id.split("-")[0])[grade_id]


def run(grade_id: str, answer_source: str | None = None, visible_only: bool = False, **names) -> dict:
    """Execute the exercise's answer cell (``answer_source``, or the instructor's) and then its test cell
    (the student's part alone with ``visible_only``), in one namespace."""
    namespace = {"np": np, "torch": torch, "ifslib": ifslib, "math": math, **names}
    exec(cell_of(grade_id).source if answer_source is None else answer_source, namespace)
    test = cell_of(f"{grade_id}-test").source
    exec(HIDDEN.sub("", test) if visible_only else test, namespace)
    return namespace


def blank(grade_id: str) -> str:
    """The answer cell as the release has it (nbgrader's ClearSolutions with course/nbgrader_config.py's stub)."""
    return SOLUTION.sub(lambda m: f"{m.group(1)}...  # YOUR CODE HERE\n", cell_of(grade_id).source)


def fails(grade_id: str, *words: str, answer_source: str | None = None, **names) -> str:
    with pytest.raises(AssertionError) as raised:
        run(grade_id, answer_source, **names)
    message = str(raised.value)
    for word in words:
        assert word in message, message
    return message


def test_every_exercise_is_an_answer_cell_and_a_locked_test_cell_with_hidden_tests_and_a_hint():
    auto, written = 0, 0
    for name in GRADED:
        book = nbformat.read(ROOT / "notebooks" / f"{name}.ipynb", as_version=4)
        for i, cell in enumerate(book.cells):
            grader = cell.metadata.get("nbgrader")
            if not grader or not grader["solution"]:
                continue
            assert grader["schema_version"] == 3 and grader["grade_id"].startswith(name)
            statement = next(c for c in reversed(book.cells[:i]) if c.cell_type == "markdown" and "Exercise" in c.source)
            assert "<details><summary>Hint</summary>" in statement.source, grader["grade_id"]
            assert "BEGIN SOLUTION" in cell.source and "END SOLUTION" in cell.source
            if cell.cell_type == "markdown":   # a written answer: graded by hand, with a rubric
                assert grader["grade"] and grader["points"] > 0 and "Rubric" in cell.source
                written += 1
                continue
            assert not grader["grade"] and not grader["locked"]
            test = book.cells[i + 1].metadata["nbgrader"]
            assert test == {"solution": False, "grade": True, "locked": True, "points": test["points"],
                            "grade_id": f"{grader['grade_id']}-test", "schema_version": 3}
            assert test["points"] > 0 and "### BEGIN HIDDEN TESTS" in book.cells[i + 1].source
            auto += 1
    assert (auto, written) == (16, 2)


CHEAP = ["00_tutorial-koch-t3", "00_tutorial-carpet-leaves", "00_tutorial-contraction", "00_tutorial-chaos-game",
         "00_tutorial-hausdorff", "00_tutorial-scaled-distance", "00_tutorial-loss", "00_tutorial-best-fit-line",
         "01_koch_iterations-leaf-map", "01_koch_iterations-depth-needed"]


@pytest.mark.parametrize("grade_id", CHEAP)
def test_the_instructors_answer_passes_and_the_blank_release_fails(grade_id):
    run(grade_id)
    fails(grade_id, answer_source=blank(grade_id))


def test_the_collage_answer_passes_with_the_students_hausdorff_and_the_blank_fails():
    hausdorff = run("00_tutorial-hausdorff")["my_hausdorff"]
    run("00_tutorial-collage", my_hausdorff=hausdorff)
    fails("00_tutorial-collage", answer_source=blank("00_tutorial-collage"), my_hausdorff=hausdorff)


def test_the_koch_depth_is_read_from_the_measured_distance():
    depth_needed = run("01_koch_iterations-depth-needed")["depth_needed"]
    # the poster is 16 times as wide: 29.6 px at 128 is 473.6 px there, 0.22 px at depth 7
    for size, expected in ((128, 7), (64, 6), (256, 7)):
        out = run("01_koch_iterations-koch-depth", depth_needed=depth_needed, distances=[29.6 / 128], size=size)
        assert out["koch_depth"] == expected
    fails("01_koch_iterations-koch-depth", answer_source="koch_depth = 3", distances=[29.6 / 128], size=128)
    fails("01_koch_iterations-koch-depth", answer_source="koch_depth = 4.0", distances=[29.6 / 128], size=128)


R3 = np.sqrt(3)


@pytest.mark.parametrize("answer, words", [
    ("T3 = [[1/6, -3**0.5/6, 1/2], [3**0.5/6, 1/6, 3**0.5/6], [0, 0, 1]]", ["wrong way"]),
    ("T3 = [[1/6, 3**0.5/6, 1/3], [-3**0.5/6, 1/6, 0], [0, 0, 1]]", ["paper's printed translation"]),
    ("T3 = [[1/3, 0, 1/2], [0, 1/3, 0], [0, 0, 1]]", ["direction of p2 -> p3"]),
    ("T3 = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]", ["scale 1/3"]),
    ("T3 = [[1/6, 3**0.5/6], [-3**0.5/6, 1/6]]", ["(3, 3) array"]),
    ("T3 = 'sqrt(3)/6'", ["array of numbers"]),
])
def test_koch_map_wrong_answers_get_their_hints(answer, words):
    fails("00_tutorial-koch-t3", *words, answer_source=answer)


def test_koch_map_from_the_library_is_right_so_a_written_part_grades_the_reasoning():
    # the library computes T3 (koch_unit): the auto test cannot tell, so exercise 1b asks for the reasoning
    run("00_tutorial-koch-t3", answer_source="T3 = ifslib.patterns.koch_unit().maps().detach().double().numpy()[2]")
    assert cell_of("00_tutorial-koch-t3-why").metadata["nbgrader"]["points"] == 2


def mine(grade_id: str, body: str, name: str) -> dict:
    """The answer cell with its solution replaced by ``body`` (at the block's indentation)."""
    source = SOLUTION.sub(lambda m: "".join(f"{m.group(1)}{line}\n" for line in body.splitlines()),
                          cell_of(grade_id).source)
    return {"answer_source": source}


@pytest.mark.parametrize("grade_id, body, words", [
    ("00_tutorial-carpet-leaves", "return primitives * m * depth", ["depth 0"]),
    ("00_tutorial-contraction", "L, t = M[:2, :2], M[:2, 2]\nreturn np.sqrt(abs(np.linalg.det(L))), "
                                "np.linalg.solve(np.eye(2) - L, t)", ["factor is 0.5"]),
    ("00_tutorial-contraction", "L, t = M[:2, :2], M[:2, 2]\nreturn np.linalg.svd(L)[1][0], t", ["fixed point"]),
    ("00_tutorial-chaos-game", "rng = np.random.default_rng(seed)\npoint = np.array([5.0, 5.0])\nout = []\n"
                               "for i in rng.integers(len(maps), size=n):\n"
                               "    point = maps[i, :2, :2] @ point + maps[i, :2, 2]\n    out.append(point)\n"
                               "return np.array(out)", ["where does your walk start"]),
    ("00_tutorial-chaos-game", "point = np.linalg.solve(np.eye(2) - maps[0, :2, :2], maps[0, :2, 2])\n"
                               "return np.repeat(point[None], n, 0)", ["at random"]),
    ("00_tutorial-hausdorff", "gaps = np.linalg.norm(a[:, None] - b[None], axis=-1)\nreturn gaps.min(1).max()",
     ["larger direction"]),
    ("00_tutorial-loss", "a, b = image[None, None], target[None, None]\ntotal = (a - b).square().mean()\n"
                         "for _ in range(4):\n    a, b = torch.nn.functional.avg_pool2d(a, 2), "
                         "torch.nn.functional.avg_pool2d(b, 2)\n    total = total + (a - b).square().mean()\n"
                         "return total", ["6"]),
    ("00_tutorial-loss", "return (image - target).square().mean()", ["plain pixel loss"]),
    ("00_tutorial-loss", "return torch.tensor(6.0)", ["gradient"]),
    ("00_tutorial-best-fit-line", "pixels = ifslib.initialization.foreground_points(target)\n"
                                  "return np.repeat(pixels.mean(0)[None], pattern.n_points, 0)", ["evenly"]),
    ("01_koch_iterations-leaf-map", "out = np.eye(3)\nfor i in word:\n    out = maps[i - 1] @ out\nreturn out",
     ["reversed"]),
    ("01_koch_iterations-leaf-map", "out = np.eye(3)\nfor i in word:\n    out = out @ maps[i]\nreturn out",
     ["IndexError"]),
    ("01_koch_iterations-depth-needed", "K = 1\nwhile s ** K * d0 > tol:\n    K += 1\nreturn K", ["depth 0"]),
    ("01_koch_iterations-depth-needed", "return int(np.log(tol / d0) / np.log(s))", ["off by one"]),
])
def test_wrong_answers_fail_with_a_hint(grade_id, body, words):
    fails(grade_id, *words, **mine(grade_id, body, grade_id))


def test_the_scaled_distance_of_the_papers_law_fails():
    fails("00_tutorial-scaled-distance", "paper's printed law", answer_source="distance_to_copy = 0.9")
    fails("00_tutorial-scaled-distance", "number", answer_source="distance_to_copy = '0.1'")


LAZY = [
    ("00_tutorial-chaos-game", "my_chaos_game = ifslib.chaos_game"),
    ("00_tutorial-chaos-game", "import functools\nmy_chaos_game = functools.partial(ifslib.chaos_game)"),
    ("00_tutorial-chaos-game", "my_chaos_game = lambda maps, n, seed=0: "
                               "ifslib.chaos_game(ifslib.patterns.affine(maps), n, seed=seed)"),
    ("00_tutorial-chaos-game", "from ifslib import chaos_game\n"
                               "def my_chaos_game(maps, n, seed=0):\n"
                               "    return chaos_game(ifslib.patterns.affine(maps), n, seed=seed)"),
    ("00_tutorial-chaos-game", "def outer():\n    game = ifslib.chaos_game\n"
                               "    return lambda maps, n, seed=0: game(ifslib.patterns.affine(maps), n, seed=seed)\n"
                               "my_chaos_game = outer()"),
    ("00_tutorial-hausdorff", "my_hausdorff = ifslib.core.scoring.metrics.hausdorff"),
    ("00_tutorial-loss", "import functools\n"
                         "my_loss = functools.partial(ifslib.core.scoring.losses.multiscale_mse, levels=5)"),
    ("00_tutorial-loss", "my_loss = lambda a, b: ifslib.core.scoring.losses.multiscale_mse(a, b, 5)"),
    ("00_tutorial-best-fit-line", "my_start = lambda p, t: ifslib.initialize(p, t).points.detach().numpy()"),
    ("00_tutorial-contraction", "my = ifslib.core.geometry.rules.singular_values\n"
                                "contraction_and_fixed_point = lambda M: (my(M), None)"),
]


@pytest.mark.parametrize("grade_id, answer", LAZY)
def test_lazy_answers_with_the_librarys_own_function_fail(grade_id, answer):
    fails(grade_id, "ifslib's own", answer_source=answer)


def test_the_package_holds_no_answer_key():
    public = set(dir(ifslib.exercises))
    assert not {n for n in public if n.startswith("check_") or "truth" in n or "reference" in n}, public
    package = Path(ifslib.__file__).parent
    for path in package.rglob("*.py"):
        text = path.read_text()
        for key in ("_truth", "_reference_multiscale", "hausdorff_pair", "BEGIN SOLUTION", "BEGIN HIDDEN TESTS",
                    "0.453805", "0.20826"):
            assert key not in text, f"{path.relative_to(package)} holds {key!r}"


FITS = [("00_tutorial-koch-fit", "my_fit", "koch_target", course_targets.koch_truth, ifslib.exercises.koch_target),
        ("05_more_examples-carpet-fit", "my_carpet", "odd_carpet", course_targets.carpet_truth,
         ifslib.exercises.carpet_target),
        ("07_your_own_image-two-maps", "my_two_maps", "two_maps", course_targets.two_map_truth,
         ifslib.exercises.two_map_target)]


@pytest.mark.parametrize("grade_id, answer, target, truth, shipped", FITS)
def test_the_shipped_target_is_the_hidden_truths_picture_and_the_truth_passes(grade_id, answer, target, truth, shipped):
    picture = shipped(64)
    assert (picture.mask == course_targets.mask(grade_id.split("-")[0] and
                                                {"koch_target": "koch", "odd_carpet": "carpet",
                                                 "two_maps": "two_maps"}[target], 64)).all()
    run(grade_id, f"{answer} = truth", truth=truth(), **{target: picture})       # hidden tests included
    fails(grade_id, answer_source=blank(grade_id), **{target: picture})
    fails(grade_id, answer_source=f"{answer} = {truth.__name__}()", **{target: picture},
          **{truth.__name__: lambda: ifslib.patterns.sierpinski_triangle() if "carpet" not in grade_id
             else ifslib.patterns.sierpinski_carpet()})


def test_the_carpets_hidden_test_catches_a_missing_copy_that_the_visible_test_forgives():
    # the true carpet with its first corner copy drawn twice in place of the last (8 maps, one copy
    # missing): the whole picture's IoU is over 0.8 (the visible test passes), but one of the 8
    # copies is empty (the hidden test fails)
    picture = ifslib.exercises.carpet_target(64)
    maps = course_targets.carpet_truth().maps().detach().double().numpy()
    missing = ifslib.patterns.affine(np.concatenate([maps[:7], maps[:1]])[:, :2], depth=3)
    test = cell_of("05_more_examples-carpet-fit-test").source
    visible = test[:test.index("    ### BEGIN HIDDEN TESTS")] + "\n\n_test()\n"
    exec(visible, {"np": np, "ifslib": ifslib, "my_carpet": missing, "odd_carpet": picture})
    fails("05_more_examples-carpet-fit", "copy 8 of 8", answer_source="my_carpet = missing", missing=missing,
          odd_carpet=picture)


def test_a_shipped_target_at_another_size_is_refused():
    with pytest.raises(IFSError, match="64, 128, 256"):
        ifslib.exercises.koch_target(100)


COPY_MAP = "07_your_own_image-copy-map"


def copy_map_names():
    """What the copy-map exercise's cells read from the notebook: the letter at 64² and foreground_points."""
    from ifslib.core.targets import silhouettes
    from ifslib.core.targets.target import foreground_points

    target = ifslib.load_target(silhouettes.letter("G", 64).astype(float), 64)
    return {"target": target, "foreground_points": foreground_points}


@pytest.mark.parametrize("body, words", [
    (None, ["returns nothing yet"]),   # the release's blank answer
    ("def copy_map(points, part):\n    return np.c_[np.eye(2), part.mean(0) - points.mean(0)]\n",
     ["covariance", "check A"]),        # the mean moved, the spread not
    ("def copy_map(points, part):\n    a = 0.5 * np.eye(2)\n    return np.c_[a, part.mean(0)]\n",
     ["mean", "check t"]),             # t forgets that A moves the whole's mean too
    ("def copy_map(points, part):\n    return np.eye(3)\n", ["2 x 3"]),
])
def test_copy_map_answer_passes_and_wrong_ones_get_their_hints(body, words):
    names = copy_map_names()
    run(COPY_MAP, **names)
    fails(COPY_MAP, *words, answer_source=blank(COPY_MAP) if body is None else body, **names)


@pytest.mark.parametrize("seed, m, lo, hi, shear", [(1000, 4, 0.3, 0.8, 0.8), (7000, 3, 0.3, 0.6, 0.5),
                                                    (2000, 3, 0.35, 0.55, 0.0), (5, 50, 0.3, 0.9, 2.0)])
def test_random_maps_are_contractions_of_largest_singular_value_at_most_hi(seed, m, lo, hi, shear):
    # the tests call them contractions: a shear must not stretch a map past hi (1000: once 1.004)
    maps = ifslib.exercises.random_maps(np.random.default_rng(seed), m, lo, hi, shear=shear)
    largest = np.linalg.svd(maps[:, :2, :2], compute_uv=False)[:, 0]
    assert maps.shape == (m, 3, 3) and np.allclose(maps[:, 2], [0, 0, 1])
    assert (largest <= hi + 1e-12).all(), largest
    if shear == 0:   # unsheared: a rotation times the two scales drawn, never rescaled
        assert (largest >= lo - 1e-12).all()


@pytest.mark.parametrize("lo, hi", [(0.3, 1.0), (0.5, 0.4), (0.0, 0.5)])
def test_random_maps_refuses_scales_that_make_no_contraction(lo, hi):
    with pytest.raises(IFSError, match="0 < lo <= hi < 1"):
        ifslib.exercises.random_maps(np.random.default_rng(0), 2, lo, hi)


def test_a_contraction_answer_that_checks_its_own_factor_passes():
    # a careful student asserts s < 1 on the maps the test calls contractions
    body = ("L, t = M[:2, :2], M[:2, 2]\ns = np.linalg.svd(L, compute_uv=False)[0]\n"
            "assert s < 1, f'not a contraction: s = {s}'\nreturn s, np.linalg.solve(np.eye(2) - L, t)")
    run("00_tutorial-contraction", **mine("00_tutorial-contraction", body, "00_tutorial-contraction"))


CHOOSE_MAPS = "08_real_fractals-choose-maps"


@pytest.mark.parametrize("score", ['1 - r["iou"] + cost * r["maps"]', 'cost * r["maps"] + 1 - r["iou"]',
                                   'cost * r["maps"] - r["iou"] + 1', '(1 - r["iou"]) + (cost * r["maps"])'])
def test_choose_maps_passes_in_any_order_of_summing_the_score(score):
    # the hidden tie must be exact in floating point whatever the order a correct answer adds its terms in
    from types import SimpleNamespace

    from ifslib.automatic import fractal

    table = [{"maps": 2, "iou": 0.61}, {"maps": 3, "iou": 0.93}, {"maps": 4, "iou": 0.94}]
    body = (f"best = min(table, key=lambda r: ({score}, r['maps']))\nreturn best['maps']")
    names = {"found": SimpleNamespace(table=table), "fractal": fractal}
    run(CHOOSE_MAPS, **mine(CHOOSE_MAPS, body, CHOOSE_MAPS), **names)
    fails(CHOOSE_MAPS, "fewer maps", answer_source=mine(CHOOSE_MAPS, body.replace("r['maps']))", "-r['maps']))"),
                                                         CHOOSE_MAPS)["answer_source"], **names)


def test_the_two_map_hidden_test_fails_a_fractal_that_matches_only_at_64():
    # the truth's maps 4.5% larger: its attractor passes the visible test at 64² (IoU 0.81) but not
    # the hidden one at 128² (IoU 0.64 against the true fractal's there, under 0.65)
    truth = course_targets.two_map_truth()
    maps = truth.maps().detach().double().numpy()[:, :2, :].copy()
    maps[:, :, :2] *= 1.045
    close = ifslib.patterns.affine(maps, depth=6)
    picture = ifslib.exercises.two_map_target(64)
    assert ifslib.evaluate(close, picture, depth="attractor")["iou"] >= 0.8  # the visible test's bar
    fails("07_your_own_image-two-maps", "drawn at 128²", answer_source="my_two_maps = close",
          close=close, two_maps=picture)


FLOAT32_ROTATION = """
def rotation(theta):
    R = torch.zeros(2, 2)
    R[0, 0], R[0, 1] = torch.cos(theta), -torch.sin(theta)
    R[1, 0], R[1, 1] = torch.sin(theta), torch.cos(theta)
    return R
"""


def test_the_rotation_answer_passes_and_a_float32_one_is_told_its_dtype():
    run("06_convergence_study-rotation")  # the instructor's answer, hidden gradcheck included
    run("06_convergence_study-rotation", FLOAT32_ROTATION.replace("torch.zeros(2, 2)",
                                                                  "torch.zeros(2, 2, dtype=theta.dtype)"))
    fails("06_convergence_study-rotation", "R is torch.float32 but theta is torch.float64",
          answer_source=FLOAT32_ROTATION)
    fails("06_convergence_study-rotation", "no gradient flows", answer_source=blank(
        "06_convergence_study-rotation").replace("...  # YOUR CODE HERE", "return torch.tensor("
        "[[torch.cos(theta), -torch.sin(theta)], [torch.sin(theta), torch.cos(theta)]])"))
