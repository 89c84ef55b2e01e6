"""Read a student's cells, without running them, for what changes the checks instead of answering them (`scan`): the
grader's and the kernel's check (`harness.run_answer`). The grader's reading of a whole submission, which alone knows
the student's cells from the lesson's and so judges their imports, is ``course/notebook_scan.py``."""
from __future__ import annotations

import ast
import builtins
from dataclasses import dataclass
from typing import Iterable

#: Calls that change or read a namespace by name, or run text as code.
FORBIDDEN_CALLS = frozenset({
    "setattr", "delattr", "exec", "eval", "compile", "globals", "vars", "locals", "__import__",
    "breakpoint", "get_ipython", "open", "input",
})
#: Dunder attributes that reach a function's code, an object's class or a namespace.
SAFE_DUNDERS = frozenset({"__init__", "__name__", "__doc__", "__repr__", "__str__", "__len__", "__call__"})
#: Methods a class may define: its constructor, and how it prints.
SAFE_METHODS = frozenset({"__init__", "__repr__", "__str__", "__call__", "__post_init__"})
#: Base classes whose instances a test compares: a subclass can answer ``==`` with anything.
VALUE_TYPES = frozenset({"int", "float", "complex", "str", "bytes", "bool", "tuple", "list", "dict", "set",
                         "frozenset", "ndarray", "generic", "floating", "integer", "number", "float64", "int64",
                         "float32", "Tensor", "Parameter", "Number", "Real", "Integral", "IFS", "Target"})
#: IPython line magics that only time or print; any other magic or shell escape is a finding.
SAFE_MAGICS = frozenset({"time", "timeit", "matplotlib", "precision"})
#: Names a test may read whatever the notebook holds: rebinding them changes the check, not the answer.
BUILTIN_NAMES = frozenset(name for name in dir(builtins) if not name.startswith("_"))


@dataclass(frozen=True)
class Finding:
    """One construct of a student's cell (``cell``: its label, ``line`` in it) that a check cannot trust."""

    cell: str
    line: int
    kind: str
    what: str

    def __str__(self) -> str:
        return f"cell {self.cell}, line {self.line}: {self.what} ({self.kind})"


def python_source(source: str) -> str:
    """A cell's source as plain Python: IPython's magics and shell escapes turned into the calls they make."""
    try:
        from IPython.core.inputtransformer2 import TransformerManager
    except ImportError:   # no IPython: a magic line is a syntax error, reported as such
        return source
    return TransformerManager().transform_cell(source)


def _root(node: ast.AST) -> str | None:
    """The name an attribute or subscript chain starts from (``np`` for ``np.linalg.norm[0]``)."""
    while isinstance(node, (ast.Attribute, ast.Subscript, ast.Call)):
        node = node.func if isinstance(node, ast.Call) else node.value
    return node.id if isinstance(node, ast.Name) else None


def _dotted(node: ast.AST) -> str:
    try:
        return ast.unparse(node)
    except Exception:  # noqa: BLE001  only for the message
        return type(node).__name__


def _global_bindings(tree: ast.Module) -> list[tuple[str, int]]:
    """(name, line) of each binding of a global name: at the cell's top level, or declared ``global``."""
    out = []
    declared = {name for node in ast.walk(tree) if isinstance(node, ast.Global) for name in node.names}

    def targets(node):
        if isinstance(node, ast.Name):
            yield node.id
        elif isinstance(node, (ast.Tuple, ast.List)):
            for element in node.elts:
                yield from targets(element)
        elif isinstance(node, ast.Starred):
            yield from targets(node.value)

    def top_level(body):
        for node in body:
            yield node
            for field in ("body", "orelse", "finalbody", "handlers"):
                inner = getattr(node, field, None)
                if isinstance(inner, list) and not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef,
                                                                      ast.ClassDef)):
                    yield from top_level(inner)

    for node in top_level(tree.body):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            out.append((node.name, node.lineno))
        elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign)):
            for target in (node.targets if isinstance(node, ast.Assign) else [node.target]):
                out += [(name, node.lineno) for name in targets(target)]
        elif isinstance(node, (ast.For, ast.AsyncFor)):
            out += [(name, node.lineno) for name in targets(node.target)]
        elif isinstance(node, (ast.With, ast.AsyncWith)):
            out += [(name, node.lineno) for item in node.items if item.optional_vars is not None
                    for name in targets(item.optional_vars)]
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            out += [((a.asname or a.name).split(".")[0], node.lineno) for a in node.names]
    for node in ast.walk(tree):
        if isinstance(node, ast.NamedExpr):
            out.append((node.target.id, node.lineno))
        elif declared and isinstance(node, ast.Name) and isinstance(node.ctx, (ast.Store, ast.Del)) \
                and node.id in declared:
            out.append((node.id, node.lineno))
    return out


def scan(cells: Iterable[tuple[str, str]], modules: Iterable[str] = (), protected: Iterable[str] = (),
         own: dict[str, set[str]] | None = None) -> list[Finding]:
    """What in ``cells`` (``(label, source)``) changes the checks: rebinding ``modules`` or the lesson's ``protected``
    names, beyond what each cell's exercise asks for (``own``)."""
    modules, protected, own = set(modules), set(protected), own or {}
    findings: list[Finding] = []
    for label, source in cells:
        findings += _scan_cell(str(label), source, modules, protected, own.get(str(label), set()))
    return findings


def _scan_cell(label: str, source: str, modules: set[str], protected: set[str], own: set[str]) -> list[Finding]:
    try:
        tree = ast.parse(python_source(source))
    except SyntaxError:
        return []  # a cell that does not parse cannot hide anything from the checks: it raises when run
    found: list[Finding] = []

    def add(node, kind, what):
        found.append(Finding(label, getattr(node, "lineno", 0), kind, what))

    aliases = set(modules) | {"__builtins__", "builtins"}
    # %timeit and its like become get_ipython().run_line_magic("timeit", ...): that get_ipython is IPython's
    timed = {id(n) for call in ast.walk(tree) if isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute)
             and call.func.attr == "run_line_magic" and call.args and isinstance(call.args[0], ast.Constant)
             and call.args[0].value in SAFE_MAGICS for n in ast.walk(call.func.value)}
    for node in ast.walk(tree):
        # an alias of a module (m = np, e = ifslib.exercises) is a module too
        if isinstance(node, ast.Assign) and _root(node.value) in aliases and \
                isinstance(node.value, (ast.Name, ast.Attribute)):
            for target in node.targets:
                if isinstance(target, ast.Name):
                    aliases.add(target.id)
    for node in ast.walk(tree):
        if isinstance(node, (ast.Assign, ast.AugAssign, ast.AnnAssign, ast.Delete)):
            targets = node.targets if isinstance(node, (ast.Assign, ast.Delete)) else [node.target]
            for target in targets:
                if isinstance(target, (ast.Attribute, ast.Subscript)) and _root(target) in aliases:
                    add(node, "rebinds a module", f"changes {_dotted(target)}, which the tests may call")
        elif id(node) in timed:
            continue
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            if node.func.id in FORBIDDEN_CALLS:
                add(node, "reaches a namespace", f"calls {node.func.id}()")
            elif node.func.id == "type" and len(node.args) == 3:
                add(node, "makes a class", "calls type() with three arguments")
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) \
                and node.func.attr in ("run_line_magic", "run_cell_magic", "system", "getoutput"):
            magic = node.args[0].value if node.args and isinstance(node.args[0], ast.Constant) else None
            if node.func.attr != "run_line_magic" or magic not in SAFE_MAGICS:
                add(node, "runs a magic", f"runs IPython's {magic or node.func.attr}")
        elif isinstance(node, ast.Attribute) and node.attr.startswith("__") and node.attr.endswith("__") \
                and node.attr not in SAFE_DUNDERS:
            add(node, "reaches inside an object", f"reads {_dotted(node)}")
        elif isinstance(node, ast.Name) and node.id in ("__builtins__", "get_ipython", "_ih", "In", "Out", "_oh"):
            add(node, "reaches a namespace", f"uses {node.id}")
        elif isinstance(node, ast.ClassDef):
            bases = {_dotted(b).rsplit(".", 1)[-1] for b in node.bases}
            if bases & VALUE_TYPES:
                add(node, "fakes a value", f"class {node.name} subclasses {', '.join(sorted(bases & VALUE_TYPES))}")
            for item in node.body:
                if isinstance(item, (ast.FunctionDef, ast.AsyncFunctionDef)) and item.name.startswith("__") \
                        and item.name not in SAFE_METHODS:
                    add(item, "fakes a value", f"class {node.name} defines {item.name}")
            if node.keywords:
                add(node, "fakes a value", f"class {node.name} sets a metaclass or class keywords")
    for name, line in _global_bindings(tree):
        if name in own:
            continue
        if name in BUILTIN_NAMES:
            found.append(Finding(label, line, "shadows a name", f"binds {name}, one of Python's builtins"))
        elif name in modules and not _is_import_of(tree, name, line):
            found.append(Finding(label, line, "shadows a name", f"binds {name}, a module the tests use"))
        elif name in protected:
            found.append(Finding(label, line, "shadows a name", f"binds {name}, the lesson's, which a test reads"))
    return found


def _is_import_of(tree: ast.Module, name: str, line: int) -> bool:
    """Whether the binding of ``name`` at ``line`` is an import statement (re-importing numpy as np is fine)."""
    return any(isinstance(node, (ast.Import, ast.ImportFrom)) and node.lineno == line
               and any((a.asname or a.name).split(".")[0] == name for a in node.names)
               for node in ast.walk(tree))

