"""The grader's side of `ifslib.teaching.exercises.integrity`: which cells of a submission are the student's, and
what in them changes the checks (`scan_notebook`). Plain Python and nbformat's cells, no nbgrader: the tests
import it too; ``course/grading.py`` copies it beside ``nbgrader_checks.py``, which imports it."""
from __future__ import annotations

import ast
from typing import Iterable

from ifslib.teaching.exercises.integrity import Finding, bound_names, global_reads, python_source, scan


def nbgrader_meta(cell) -> dict:
    """A cell's nbgrader metadata ({} for a cell nbgrader does not know)."""
    return cell.metadata.get("nbgrader", {}) or {}


def is_students(cell) -> bool:
    """An answer cell, or a cell the student added (a released lesson locks every other code cell)."""
    meta = nbgrader_meta(cell)
    return cell.cell_type == "code" and bool(meta.get("solution", False) or not meta.get("grade_id"))


def imported_names(sources: Iterable[str]) -> set[str]:
    """The names that import statements bind in ``sources`` (``np`` for ``import numpy as np``)."""
    names = set()
    for source in sources:
        try:
            tree = ast.parse(python_source(source))
        except SyntaxError:
            continue
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                for alias in node.names:
                    names.add((alias.asname or alias.name).split(".")[0])
    return names


def scan_notebook(book, stubs: dict[str, str], bans: dict[str, Iterable[str]]) -> list[tuple[int, Finding]]:
    """(cell index, finding) for each construct of ``book``'s student cells that changes its checks."""
    code = [(k, c) for k, c in enumerate(book.cells) if c.cell_type == "code"]
    mine = [(k, c) for k, c in code if is_students(c)]
    lesson = [c for _, c in code if not is_students(c)]
    label = {k: nbgrader_meta(c).get("grade_id") or f"added cell {k}" for k, c in mine}
    own = {label[k]: bound_names(stubs.get(label[k], "")) for k, _ in mine}
    tests = [c for c in lesson if nbgrader_meta(c).get("grade")]
    reads = set().union(*(global_reads(c.source) for c in tests))
    bound = set().union(*(bound_names(c.source) for c in lesson if not nbgrader_meta(c).get("grade")))
    findings = scan([(label[k], c.source) for k, c in mine], imported_names(c.source for c in lesson),
                    (reads & bound) - set().union(*own.values()), own,
                    {name: bans[name] for name in label.values() if name in bans})
    index = {v: k for k, v in label.items()}
    return [(index[f.cell], f) for f in findings]
