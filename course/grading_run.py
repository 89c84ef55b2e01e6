"""What nbgrader runs of a lesson: the cells its checks need, at the lesson's grading sizes.

`needed_cells` reads a notebook's code cells with ``ast`` and keeps, walking up from the bottom, every
cell nbgrader knows (answers, tests, locked cells), the parameters cell, the cells that import, and
each cell that binds or changes a name a kept cell below it reads; the others are the lesson's
demonstrations. `with_grading_cell` puts a locked cell after the parameters cell that, only while
nbgrader executes the notebook (``NBGRADER_EXECUTION``), sets every parameter to its grading value
(``metadata["ifslib"]["grading"]``, else the quick one, else the teaching one) and skips the
demonstrations (``ifslib.teaching.grading.skip_cells``). The analysis is conservative where it
cannot see (a cell that does not parse, a star import): it keeps the cell. A cell it drops that a
check needed shows as a ``NameError`` when ``course/grading.py --check`` grades the instructor's source.
"""
from __future__ import annotations

import ast
import builtins

import nbformat

from ifslib.teaching.grading import cell_key

GRADE_ID = "grading-run"
BUILTINS = set(dir(builtins))


def parameters_index(book) -> int | None:
    where = [i for i, c in enumerate(book.cells) if "parameters" in c.metadata.get("tags", [])]
    return where[0] if where else None


def _modules(tree: ast.AST) -> set[str]:
    """Names bound by imports: calling a module's function is not taken as changing the module."""
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            out.update((a.asname or a.name).split(".")[0] for a in node.names)
    return out


def _base(node: ast.AST) -> str | None:
    """The name at the root of ``a.b[c].d``."""
    while isinstance(node, (ast.Attribute, ast.Subscript, ast.Starred)):
        node = node.value
    return node.id if isinstance(node, ast.Name) else None


class _Scope(ast.NodeVisitor):
    """The names a block binds or changes, and those it reads before binding them, statement by statement."""

    def __init__(self, modules: set[str], bound: set[str] | None = None):
        self.modules, self.bound = modules, set(bound or ())
        self.binds, self.free = set(), set()

    def bind(self, name: str | None) -> None:
        if name:
            self.binds.add(name)
            self.bound.add(name)

    def read(self, name: str) -> None:
        if name not in self.bound:
            self.free.add(name)

    def visit_Name(self, node):
        if isinstance(node.ctx, ast.Load):
            self.read(node.id)
        else:
            self.bind(node.id)

    def visit_Assign(self, node):  # the value is read before the targets are bound
        self.visit(node.value)
        for target in node.targets:
            self.visit(target)

    def visit_AnnAssign(self, node):
        if node.value:
            self.visit(node.value)
        self.visit(node.target)

    def visit_AugAssign(self, node):  # x += 1 reads x, then changes it
        self.visit(node.value)
        if isinstance(node.target, ast.Name):
            self.read(node.target.id)
        self.visit(node.target)

    def _store_into(self, node):  # x.a = ..., x[i] = ...: x changed
        if isinstance(node.ctx, (ast.Store, ast.Del)):
            base = _base(node)
            if base:
                self.read(base)
                self.binds.add(base)
        self.generic_visit(node)

    visit_Attribute = visit_Subscript = _store_into

    def visit_Call(self, node):  # x.append(...): x changed, unless x is a module
        if isinstance(node.func, ast.Attribute):
            owner = _base(node.func.value)
            if owner and owner not in self.modules:
                self.binds.add(owner)
        self.generic_visit(node)

    def visit_Import(self, node):
        for alias in node.names:
            self.bind((alias.asname or alias.name).split(".")[0])

    def visit_ImportFrom(self, node):
        if any(a.name == "*" for a in node.names):
            raise SyntaxError("a star import: its names cannot be read")
        for alias in node.names:
            self.bind(alias.asname or alias.name)

    def _inner(self, node, params: set[str], body: list):
        """A function, lambda or comprehension: the names it reads from outside (when it runs)."""
        inner = _Scope(self.modules, self.bound | params)
        for statement in body:
            inner.visit(statement)
        local = inner.binds | params
        self.free |= {n for n in inner.free if n not in local}

    def visit_FunctionDef(self, node):
        for default in node.args.defaults + [d for d in node.args.kw_defaults if d]:
            self.visit(default)
        for decorator in node.decorator_list:
            self.visit(decorator)
        self.bind(node.name)
        self._inner(node, _params(node.args), node.body)

    visit_AsyncFunctionDef = visit_FunctionDef

    def visit_Lambda(self, node):
        for default in node.args.defaults:
            self.visit(default)
        self._inner(node, _params(node.args), [ast.Expr(node.body)])

    def visit_ClassDef(self, node):
        for base in node.bases:
            self.visit(base)
        self.bind(node.name)
        self._inner(node, set(), node.body)

    def _comprehension(self, node):
        self.visit(node.generators[0].iter)
        inner = _Scope(self.modules, self.bound)
        for k, generator in enumerate(node.generators):
            if k:
                inner.visit(generator.iter)
            inner.visit(generator.target)
            for condition in generator.ifs:
                inner.visit(condition)
        for part in ("elt", "key", "value"):
            if getattr(node, part, None) is not None:
                inner.visit(getattr(node, part))
        self.free |= inner.free

    visit_ListComp = visit_SetComp = visit_GeneratorExp = visit_DictComp = _comprehension


def _params(args: ast.arguments) -> set[str]:
    every = args.posonlyargs + args.args + args.kwonlyargs + [a for a in (args.vararg, args.kwarg) if a]
    return {a.arg for a in every}


def names(source: str, modules: set[str]) -> tuple[set[str], set[str]] | None:
    """(names the cell binds or changes, names it reads before binding them); None when it cannot be read.

    A name is changed by an assignment into it (``x.a = ...``, ``x[i] = ...``, ``x += ...``) and by a
    call of one of its methods (``x.append(...)``), unless it is a module.
    """
    try:
        scope = _Scope(modules)
        for statement in ast.parse(source).body:
            scope.visit(statement)
    except SyntaxError:
        return None
    return scope.binds, scope.free - BUILTINS


def _always(cell) -> bool:
    return bool(cell.metadata.get("nbgrader")) or bool(
        {"parameters", "injected-parameters"} & set(cell.metadata.get("tags", [])))


def needed_cells(book) -> set[int]:
    """Indices of the code cells the checks need (see the module's docstring)."""
    code = [i for i, c in enumerate(book.cells) if c.cell_type == "code"]
    modules = set()
    for i in code:
        try:
            modules |= _modules(ast.parse(book.cells[i].source))
        except SyntaxError:
            pass
    needed, wanted = set(), set()
    for i in reversed(code):
        cell = book.cells[i]
        found = names(cell.source, modules)
        if found is None or _always(cell) or found[0] & wanted or not cell.source.strip():
            needed.add(i)
            wanted |= found[1] if found else set()
    return needed


def grading_values(book, teaching: dict) -> dict:
    """Every parameter at its grading value: ``grading`` over ``quick`` over the teaching value."""
    meta = book.metadata.get("ifslib", {})
    return {**teaching, **meta.get("quick", {}), **meta.get("grading", {})}


def grading_source(values: dict, skipped: list[str]) -> str:
    assignments = "".join(f"    {k} = {v!r}\n" for k, v in values.items())
    keys = ",\n".join(f"        {k!r}" for k in skipped)
    return (
        "# While nbgrader grades this notebook (autograde, or Validate), it runs at the grading sizes below\n"
        "# and skips the lesson's demonstrations that no exercise needs, so that grading takes seconds.\n"
        "# Run by you, this cell does nothing: you see the lesson at the sizes of the cell above.\n"
        "import os\n\n"
        "if os.environ.get(\"NBGRADER_EXECUTION\"):\n"
        f"{assignments}"
        "    from ifslib.teaching.grading import skip_cells\n\n"
        "    skip_cells([\n"
        f"{keys}\n"
        "    ])\n")


def with_grading_cell(book, name: str, teaching: dict):
    """``book`` (changed in place) with its grading cell, locked, after the parameters cell (and any
    values injected after it); a notebook without a parameters cell is returned as it is.

    ``teaching``: the parameters cell's values (``notebooks/run.py``'s ``teaching_parameters``)."""
    where = parameters_index(book)
    if where is None:
        return book
    while where + 1 < len(book.cells) and "injected-parameters" in book.cells[where + 1].metadata.get("tags", []):
        where += 1
    needed = needed_cells(book)
    skipped = [cell_key(c.source) for i, c in enumerate(book.cells) if c.cell_type == "code" and i not in needed]
    cell = nbformat.v4.new_code_cell(grading_source(grading_values(book, teaching), skipped))
    cell.metadata["nbgrader"] = {"grade": False, "solution": False, "locked": True,
                                 "grade_id": f"{name}-{GRADE_ID}", "schema_version": 3}
    cell.metadata["tags"] = ["grading-run"]
    book.cells.insert(where + 1, cell)
    return book
