"""Notebook 02's IoU and Chamfer exercises, their test cells run as nbgrader runs them (hidden tests included).

The instructor's answer passes; the blank release and a wrong answer fail; so do answers that hand in
the library's own function or wrap a call to it (the library is switched off while the answer runs).
"""
from __future__ import annotations

import re
from pathlib import Path
from types import SimpleNamespace

import nbformat
import numpy as np
import pytest
import torch

import ifslib

NOTEBOOK = Path(__file__).resolve().parents[2] / "notebooks" / "02_fitting_gallery.ipynb"
SOLUTION = re.compile(r"^([ \t]*)### BEGIN SOLUTION.*?### END SOLUTION[ \t]*(\n|\Z)", re.M | re.S)


def cell(grade_id: str) -> str:
    book = nbformat.read(NOTEBOOK, as_version=4)
    return next(c.source for c in book.cells if c.metadata.get("nbgrader", {}).get("grade_id") == grade_id)


def koch_results(size: int = 32) -> dict:
    """The names the Chamfer exercise's answer cell reads from the notebook: a small Koch target and a 'fit'."""
    ifs = ifslib.patterns.koch()
    return {"size": size, "results": {"koch": (ifslib.load_target(ifs, size), None, SimpleNamespace(best=ifs))}}


def run(grade_id: str, answer: str | None = None, **names) -> dict:
    """The answer cell (``answer``, or the instructor's), then its test cell, in one namespace."""
    namespace = {"np": np, "torch": torch, "ifslib": ifslib, **names}
    exec(cell(grade_id) if answer is None else answer, namespace)
    exec(cell(f"{grade_id}-test"), namespace)
    return namespace


def blank(grade_id: str) -> str:
    """The answer cell as the student edition has it."""
    return SOLUTION.sub(lambda m: f"{m.group(1)}...  # YOUR CODE HERE\n", cell(grade_id))


def with_body(grade_id: str, body: str) -> str:
    """The answer cell with ``body`` (a function's indented lines) in place of the instructor's answer."""
    return SOLUTION.sub(lambda m: body, cell(grade_id))


IOU, CHAMFER = "02_fitting_gallery-iou", "02_fitting_gallery-chamfer"


def test_the_instructors_answers_pass():
    run(IOU)
    run(CHAMFER, **koch_results())


@pytest.mark.parametrize("grade_id", [IOU, CHAMFER])
def test_the_blank_release_fails(grade_id):
    with pytest.raises(AssertionError, match="returns nothing yet"):
        run(grade_id, blank(grade_id), **koch_results())


@pytest.mark.parametrize("grade_id, body", [
    (IOU, "    return float((p & q).sum() / p.sum())\n"),   # over P, not the union
    (CHAMFER, "    a, b = np.argwhere(p), np.argwhere(q)\n"
              "    return cKDTree(b).query(a)[0].mean()\n"),  # one way only
])
def test_a_wrong_answer_fails(grade_id, body):
    with pytest.raises(AssertionError):
        run(grade_id, with_body(grade_id, body), **koch_results())


LAZY = [
    (IOU, "iou = ifslib.iou"),
    (IOU, "def iou(p, q):\n    return ifslib.iou(p, q)"),
    (IOU, "def iou(p, q):\n    return ifslib.metrics.iou(p, q)"),
    (IOU, "from ifslib.core.scoring.metrics import iou as theirs\ndef iou(p, q):\n    return theirs(p, q)"),
    (CHAMFER, "chamfer = ifslib.chamfer"),
    (CHAMFER, "def chamfer(p, q):\n    return ifslib.chamfer(p, q)"),
    (CHAMFER, "def chamfer(p, q):\n    return float(ifslib.core.scoring.metrics.chamfer(p, q))"),
]


@pytest.mark.parametrize("grade_id, answer", LAZY)
def test_the_librarys_own_function_or_a_wrapper_of_it_fails(grade_id, answer):
    names = koch_results()
    if grade_id == CHAMFER:   # the answer cell's last lines apply the function to the Koch fit
        tail = cell(grade_id).split("### END SOLUTION", 1)[1]
        answer = "from scipy.spatial import cKDTree\n" + answer + "\n" + tail
    with pytest.raises(AssertionError, match="ifslib's own"):
        run(grade_id, answer, **names)
