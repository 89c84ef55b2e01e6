"""The checks that do not trust the student's namespace: `integrity.scan` (what the grader reads before the
notebook runs), the harness's watch over the library and its plain values."""
from __future__ import annotations

import re
import sys
import types
from pathlib import Path

import nbformat
import numpy as np
import pytest
import torch

import ifslib
from ifslib.teaching.exercises import integrity, plain, run_answer

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "course"))
import tricks_submission  # noqa: E402
from lazy_submission import answered  # noqa: E402
from notebook_scan import BANS, banned, forbidden_imports  # noqa: E402
from notebook_scan import scan_notebook as grader_scan  # noqa: E402

SOLUTION = re.compile(r"^([ \t]*)### BEGIN SOLUTION.*?### END SOLUTION[ \t]*$", re.S | re.M)


def released(source: str) -> str:
    """The answer cell as nbgrader releases it: the solution replaced by the stub at its indentation."""
    return SOLUTION.sub(lambda m: f"{m.group(1)}...  # YOUR CODE HERE", source)


def graded_notebooks():
    return [p for p in sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
            if any(c.metadata.get("nbgrader") for c in nbformat.read(p, as_version=4).cells)]


def scan_notebook(book) -> list[integrity.Finding]:
    """What the grader (``course/nbgrader_checks.ScanCells``) finds in ``book``, its lesson cells locked as
    the release has them."""
    for k, cell in enumerate(book.cells):
        if cell.cell_type == "code" and not cell.metadata.get("nbgrader"):
            cell.metadata["nbgrader"] = {"grade": False, "solution": False, "locked": True, "grade_id": f"lesson-{k}"}
    return [finding for _, finding in grader_scan(book, STUBS, BANS)]


def answer_cells(book):
    return {c.metadata["nbgrader"]["grade_id"]: c for c in book.cells
            if c.cell_type == "code" and c.metadata.get("nbgrader", {}).get("solution")}


#: grade_id -> the answer cell as released (the stub in place of the solution)
STUBS = {gid: released(c.source)
         for path in graded_notebooks() for gid, c in answer_cells(nbformat.read(path, as_version=4)).items()}


@pytest.mark.parametrize("path", graded_notebooks(), ids=lambda p: p.stem)
def test_the_instructors_answers_are_trusted(path):
    assert scan_notebook(nbformat.read(path, as_version=4)) == []


#: Tricks no reading of the source can tell from an honest answer: the watch refuses them when they run
#: (a route into the library by module), or they are right answers copied from an edition students no
#: longer see (the book shows the exercises as the student edition has them).
RUN_TIME = {"00_tutorial-loss", "07_your_own_image-copy-map"}
COPIED = {"00_tutorial-scaled-distance", "09_measures_and_dimension-box-by-hand", "09_measures_and_dimension-fern-stem"}


@pytest.mark.parametrize("path", graded_notebooks(), ids=lambda p: p.stem)
def test_every_trick_makes_its_test_untrusted(path):
    """The submission of tricks as the grader reads it: each trick's test comes after a finding."""
    book = nbformat.read(path, as_version=4)
    answers = answer_cells(book)
    for grade_id, cell in answers.items():
        if grade_id in tricks_submission.TRICKS:
            cell.source = answered(released(cell.source), tricks_submission.TRICKS[grade_id])
    findings = scan_notebook(book)
    order = {c.metadata.get("nbgrader", {}).get("grade_id"): k for k, c in enumerate(book.cells)}
    for grade_id in set(answers) & set(tricks_submission.TRICKS) - RUN_TIME - COPIED:
        touched = [f for f in findings if f.cell == grade_id or (
            f.kind != "uses the library's answer" and order[f.cell] < order[grade_id])]
        assert touched, grade_id


@pytest.mark.parametrize("source, kind", [
    ("ifslib.exercises.run_answer = lambda a, e, *x: a(*x)", "rebinds a module"),
    ("import numpy as numpy_\nnumpy_.allclose = lambda *a, **k: True", "rebinds a module"),
    ("E = ifslib.exercises\nE.as_number = float", "rebinds a module"),
    ("abs = lambda x: 0", "shadows a name"),
    ("np = None", "shadows a name"),
    ("runs = []", "shadows a name"),
    ("def f():\n    global runs\n    runs = []", "shadows a name"),
    ("class A(float):\n    pass", "fakes a value"),
    ("class A:\n    def __eq__(self, other):\n        return True", "fakes a value"),
    ("A = type('A', (float,), {})", "makes a class"),
    ("from unittest.mock import ANY\nx = ANY", "reaches the interpreter"),
    ("import types", "reaches the interpreter"),
    ("f = ifslib.chaos_game.__code__", "reaches inside an object"),
    ("setattr(ifslib, 'evaluate', None)", "reaches a namespace"),
    ("exec('abs = 0')", "reaches a namespace"),
    ("get_ipython().run_cell('abs = 0')", "reaches a namespace"),
    ("%run other.py", "runs a magic"),
    ("!cp fake.py ifslib/", "runs a magic"),
])
def test_each_kind_of_trick_is_named(source, kind):
    cells = [("answer", source)]
    findings = integrity.scan(cells, {"np", "ifslib", "numpy_"}, {"runs"}) + forbidden_imports(cells)
    assert kind in {f.kind for f in findings}, findings


def test_honest_constructs_are_not_named():
    honest = ("import numpy as np\nfrom scipy.spatial import cKDTree\n%timeit x = 1\n"
              "def f(a, b):\n    total = 0\n    for x in a:\n        total += abs(x)\n    return total\n"
              "class Point:\n    def __init__(self, x):\n        self.x = x\n"
              "p = Point(1)\np.x = 2\nd = {}\nd['a'] = 1\nprint(f([1, -2], None), sorted([2, 1]))")
    assert integrity.scan([("answer", honest)], {"np", "ifslib"}, {"runs"}) == []
    assert forbidden_imports([("answer", honest)]) == []


def test_a_ban_follows_the_names_an_answer_reads_from_other_cells():
    cells = [("helper", "K = ifslib.patterns.koch_unit()"), ("00_tutorial-koch-t3", "T3 = K.maps()[2]")]
    bans = BANS["00_tutorial-koch-t3"]
    assert {f.cell for f in banned(cells, "00_tutorial-koch-t3", bans)} == {"00_tutorial-koch-t3"}
    honest = [("00_tutorial-koch-t3", "T3 = [[1 / 6, 0.2886, 0.5], [-0.2886, 1 / 6, 0.2886], [0, 0, 1]]")]
    assert banned(honest, "00_tutorial-koch-t3", bans) == []


# -- the harness: the library watched by module, and plain values ----------------------------------

def test_a_route_the_switch_off_list_does_not_name_is_refused_by_module():
    from ifslib.automatic.moments import sqrtm_psd

    def copy_map(points, part):
        a = sqrtm_psd(np.cov(part.T)) @ np.linalg.inv(sqrtm_psd(np.cov(points.T)))
        return np.concatenate([a, (part.mean(0) - a @ points.mean(0))[:, None]], axis=1)

    cloud = np.random.default_rng(0).normal(size=(50, 2))
    with pytest.raises(AssertionError, match="ifslib.automatic.moments.sqrtm_psd"):
        run_answer(copy_map, "copy map", cloud, cloud[:20])


def test_a_copy_of_a_library_function_is_refused():
    game = ifslib.chaos_game
    clone = types.FunctionType(game.__code__.replace(), game.__globals__, "clone", game.__defaults__)

    def my_chaos_game(maps, n, seed=0):
        return clone(ifslib.patterns.affine(maps[:, :2]), n, seed=seed)

    halves = np.array([[[0.5, 0, 0], [0, 0.5, 0], [0, 0, 1]], [[0.5, 0, 0.5], [0, 0.5, 0], [0, 0, 1]]])
    with pytest.raises(AssertionError, match="ifslib's own"):
        run_answer(my_chaos_game, "chaos game", halves, 100, 0)


def test_a_refusal_caught_by_the_answer_still_fails_it():
    def sneaky(m, primitives, depth):
        try:
            ifslib.patterns.affine([[[0.3, 0, 0], [0, 0.3, 0]]] * m)
        except Exception:  # noqa: BLE001  the trick: swallow the refusal
            pass
        return primitives * m ** depth

    with pytest.raises(AssertionError, match="ifslib's own"):
        run_answer(sneaky, "leaf count", 8, 1, 2)


def test_an_answer_that_removes_the_watch_fails():
    def unwatched(m, primitives, depth):
        sys.setprofile(None)
        return primitives * m ** depth

    with pytest.raises(AssertionError):
        run_answer(unwatched, "leaf count", 8, 1, 2)


def test_the_watch_allows_what_the_exercise_is_made_of_and_is_gone_afterwards():
    before = sys.getprofile()
    line = ifslib.load_target(ifslib.patterns.koch(depth=0), 64)

    def my_start(pattern, target):
        pixels = ifslib.initialization.foreground_points(target)
        return np.repeat(pixels.mean(0)[None], pattern.n_points, 0)

    assert run_answer(my_start, "best-fit-line start", ifslib.patterns.koch(), line).shape == (5, 2)
    assert sys.getprofile() is before


class AnyInt(int):
    def __eq__(self, other):
        return True

    __hash__ = int.__hash__


@pytest.mark.parametrize("value", [AnyInt(3), np.ma.masked_array([1.0]), [AnyInt(1)], {"a": AnyInt(1)},
                                   types.SimpleNamespace(x=1), np.array([object()])])
def test_plain_refuses_what_may_redefine_equality(value):
    with pytest.raises(AssertionError, match="give"):
        plain(value)


def test_plain_keeps_numbers_arrays_and_a_losss_gradient():
    assert plain(np.float64(0.5)) == 0.5 and type(plain(np.float64(0.5))) is float
    assert type(plain(np.int64(3))) is int and plain((1, [2.0, "x"])) == (1, [2.0, "x"])
    assert plain(np.arange(3)).dtype == float
    loss = (torch.ones(2, requires_grad=True) * 2).sum()
    assert plain(loss).requires_grad
