"""The grader's side of `ifslib.teaching.exercises.integrity`: which cells of a submission are the student's, and
what in them changes the checks (`scan_notebook`), the names an answer may not mention (`BANS`) and the modules it
may not import (`FORBIDDEN_IMPORTS`) included. Plain
Python and nbformat's cells, no nbgrader: the tests import it too; ``course/grading.py`` copies it beside
``nbgrader_checks.py``, which imports it."""
from __future__ import annotations

import ast
import symtable
import types
from typing import Iterable

from ifslib.teaching.exercises.integrity import Finding, _global_bindings, python_source, scan

#: Names an answer cell (and the cells it reads from) may not mention, by the answer's nbgrader
#: ``grade_id``: the library's routes to a number or an object the exercise asks the student to work out,
#: which no switch-off can reach because the answer is a value, not a function.
BANS = types.MappingProxyType({
    "00_tutorial-koch-t3": frozenset({"koch_unit", "koch", "koch_like", "maps", "rules", "patterns"}),
    "00_tutorial-scaled-distance": frozenset({"distance_field", "render", "sdf_dense", "metrics"}),
    "01_koch_iterations-koch-depth": frozenset({"depth_to_attractor", "attractor_depth", "expand_attractor"}),
    "02_fitting_gallery-shifted-line": frozenset({"metrics", "scores", "evaluate", "distance_transform_edt"}),
    "03_gradient_fields-further-out": frozenset({"scores"}),
    "06_convergence_study-rotation": frozenset({"_rotation", "splatting", "parameters", "rules"}),
    "05_more_examples-carpet-fit": frozenset({"auto", "automatic", "discover", "fit_plan", "fit_many"}),
    "06_convergence_study-seeds-needed": frozenset({"binomtest", "proportion_ci", "proportion_confint"}),
    "07_your_own_image-two-maps": frozenset({"auto", "automatic", "discover", "fit_plan", "fit_many",
                                             "moment_maps", "shape_maps", "sqrtm_psd"}),
    "09_measures_and_dimension-box-by-hand": frozenset({"dimension", "box_counting", "box_dimension"}),
})


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


def global_reads(source: str) -> set[str]:
    """The global names a cell reads: at its top level before binding them, or from inside its functions."""
    try:
        table = symtable.symtable(python_source(source), "<cell>", "exec")
    except SyntaxError:
        return set()
    reads = {s.get_name() for s in table.get_symbols() if s.is_referenced() and not s.is_assigned()
             and not s.is_imported()}
    stack = list(table.get_children())
    while stack:
        child = stack.pop()
        stack += child.get_children()
        reads |= {s.get_name() for s in child.get_symbols() if s.is_referenced() and s.is_global()}
    return reads


def bound_names(source: str) -> set[str]:
    """The global names a cell binds (assignments, definitions, imports, loop targets, ``global`` declarations)."""
    try:
        tree = ast.parse(python_source(source))
    except SyntaxError:
        return set()
    return {name for name, _ in _global_bindings(tree)}


def banned(cells: list[tuple[str, str]], label: str, banned: set[str]) -> list[Finding]:
    """Mentions of ``banned`` names in the cell ``label`` and in the student's cells it reads from."""
    sources = dict(cells)
    if label not in sources:
        return []
    binders: dict[str, list[str]] = {}
    for other, source in cells:
        for name in bound_names(source):
            binders.setdefault(name, []).append(other)
    todo, seen, found = [label], set(), []
    while todo:
        current = todo.pop()
        if current in seen:
            continue
        seen.add(current)
        try:
            tree = ast.parse(python_source(sources[current]))
        except SyntaxError:
            continue
        for node in ast.walk(tree):
            words = set()
            if isinstance(node, ast.Name):
                words = {node.id}
            elif isinstance(node, ast.Attribute):
                words = {node.attr}
            elif isinstance(node, ast.Call):   # a name passed as a string: fit(..., strategy="auto")
                words = {a.value for a in [*node.args, *(k.value for k in node.keywords)]
                         if isinstance(a, ast.Constant) and isinstance(a.value, str)}
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                words = {part for a in node.names for part in a.name.split(".")}
                words |= set((node.module or "").split(".")) if isinstance(node, ast.ImportFrom) else set()
            for word in sorted(words & banned):
                found.append(Finding(label, getattr(node, "lineno", 0), "uses the library's answer",
                                     f"{'its cell' if current == label else 'cell ' + current} mentions "
                                     f"{word!r}: this exercise asks you to work it out"))
        todo += [b for name in global_reads(sources[current]) for b in binders.get(name, []) if b != current]
    return found


#: Modules an answer has no reason to import: they reach the interpreter, the files or other processes. A lesson's own
#: cells import some (io, pathlib), so only the grader, which knows the student's cells, judges imports.
FORBIDDEN_IMPORTS = frozenset({
    "builtins", "sys", "os", "gc", "ctypes", "inspect", "importlib", "types", "unittest", "mock", "shutil",
    "subprocess", "pathlib", "io", "pickle", "marshal", "code", "codeop", "runpy", "dis", "threading",
    "multiprocessing", "signal", "atexit", "IPython", "pytest", "_pytest", "nbgrader",
})


def forbidden_imports(cells: Iterable[tuple[str, str]]) -> list[Finding]:
    """Each import in ``cells`` (``(label, source)``) of a module of `FORBIDDEN_IMPORTS`."""
    found = []
    for label, source in cells:
        try:
            tree = ast.parse(python_source(source))
        except SyntaxError:
            continue  # it raises when run
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                module = node.module if isinstance(node, ast.ImportFrom) else None
                for name in ([module] if module else [a.name for a in node.names]):
                    if name and name.split(".")[0] in FORBIDDEN_IMPORTS:
                        found.append(Finding(str(label), node.lineno, "reaches the interpreter", f"imports {name}"))
    return found


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
    cells = [(label[k], c.source) for k, c in mine]
    findings = scan(cells, imported_names(c.source for c in lesson), (reads & bound) - set().union(*own.values()), own)
    findings += forbidden_imports(cells)
    for name in label.values():
        if name in bans:
            findings += banned(cells, name, set(bans[name]))
    index = {v: k for k, v in label.items()}
    return [(index[f.cell], f) for f in findings]
