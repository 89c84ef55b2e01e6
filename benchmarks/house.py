"""The size of the house (issue 64): the library's lines, the lines a reader of the paper's notebooks reaches,
and the options `ifslib.fit` takes.

    python benchmarks/house.py            # the three figures, and the reached modules largest first
    python benchmarks/house.py --quiet    # the three figures only

A notebook *reaches* a module when one of its code cells imports it (``import ifslib.x``, ``from ifslib.x
import y``) or names it through the package (``ifslib.fit`` is `ifslib.core.fitting.fit`, by
``ifslib._PUBLIC``); then, read as text with ``ast``, whatever those modules import, at the top or inside a
function, and the modules ``importlib.import_module`` loads: a relative literal, or every module of the
package when the name is made at run time (``f".{name}"``: a lazy table, a folder of shapes); with each package's ``__init__.py`` on the way. Lines are the files' lines, blank and comment
lines included (what ``wc -l`` counts). Nothing is imported or run.
"""
from __future__ import annotations

import argparse
import ast
import inspect
import json
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "ifslib"
PAPER_NOTEBOOKS = sorted((ROOT / "notebooks").glob("0[0-6]_*.ipynb"))


def module_path(name: str) -> Path | None:
    """The file of module ``ifslib.a.b`` (a package's ``__init__.py``), or None when it is not a module."""
    base = ROOT.joinpath(*name.split("."))
    for path in (base.with_suffix(".py"), base / "__init__.py"):
        if path.is_file():
            return path
    return None


def with_parents(name: str) -> list[str]:
    """``ifslib.a.b`` and the packages it loads on the way: ``ifslib``, ``ifslib.a``."""
    parts = name.split(".")
    return [".".join(parts[: i + 1]) for i in range(len(parts))]


def public_names() -> dict[str, str]:
    """``ifslib.<name>`` -> the module that holds it, from the package's own table (read, not imported)."""
    tree = ast.parse((PACKAGE / "__init__.py").read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.AnnAssign | ast.Assign):
            target = node.target if isinstance(node, ast.AnnAssign) else node.targets[0]
            if isinstance(target, ast.Name) and target.id == "_PUBLIC":
                table = ast.literal_eval(node.value)
                return {key: f"ifslib.{where}" for key, (where, _) in table.items()}
    return {}


def imported_by(path: Path, name: str) -> set[str]:
    """The ifslib modules a module's text imports, anywhere in it."""
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    tree = ast.parse(path.read_text())
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            if module.startswith("ifslib"):
                found.add(module)
                found.update(f"{module}.{a.name}" for a in node.names if module_path(f"{module}.{a.name}"))
        elif isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.startswith("ifslib"))
        elif isinstance(node, ast.Call) and getattr(node.func, "attr", "") == "import_module" and node.args:
            first = node.args[0]
            if isinstance(first, ast.Constant) and str(first.value).startswith("."):
                found.add(f"{package}{first.value}")
            elif (isinstance(first, ast.JoinedStr) and name != "ifslib" and first.values
                  and isinstance(first.values[0], ast.Constant) and str(first.values[0].value).startswith(".")):
                # a submodule named at run time (a lazy table, a folder of shapes): every module of the package
                folder = ROOT.joinpath(*package.split("."))
                found.update(f"{package}.{p.stem}" for p in folder.glob("*.py") if p.stem != "__init__")
    return {m for m in found if module_path(m)}


def notebook_roots(path: Path, public: dict[str, str]) -> set[str]:
    """The ifslib modules a notebook's code cells import or name through the package."""
    cells = [c["source"] for c in json.loads(path.read_text())["cells"] if c["cell_type"] == "code"]
    text = "\n".join("".join(c) if isinstance(c, list) else c for c in cells)
    roots = {"ifslib"}
    roots.update(m for m in re.findall(r"(?:from|import)\s+(ifslib(?:\.\w+)*)", text) if module_path(m))
    for attribute in re.findall(r"\bifslib\.(\w+)", text):
        if attribute in public:
            roots.add(public[attribute])
        elif module_path(f"ifslib.{attribute}"):
            roots.add(f"ifslib.{attribute}")
    return roots


def reach(roots: set[str]) -> set[str]:
    """The import closure of ``roots``, packages on the way included."""
    seen: set[str] = set()
    todo = [p for r in roots for p in with_parents(r)]
    while todo:
        name = todo.pop()
        if name in seen or not module_path(name):
            continue
        seen.add(name)
        todo += [p for m in imported_by(module_path(name), name) for p in with_parents(m)]
    return seen


def lines(path: Path) -> int:
    return len(path.read_text().splitlines())


def fit_options() -> tuple[int, list[str]]:
    """`ifslib.fit`'s options: its own parameters, the IFS and the target aside (an options object passed whole,
    ``options=`` or ``strategy=``, is one), and, were it to take ``**settings``, every field those could reach."""
    sys.path.insert(0, str(ROOT))
    from ifslib.core.fitting import fit as fit_module

    signature = inspect.signature(fit_module.fit)
    own = [p.name for p in signature.parameters.values()
           if p.kind is not inspect.Parameter.VAR_KEYWORD][2:]
    forwarded: list[str] = []
    if any(p.kind is inspect.Parameter.VAR_KEYWORD for p in signature.parameters.values()):
        import dataclasses

        from ifslib.core.fitting import options
        for cls in (options.RunOptions, getattr(options, "StrategyOptions", None)):
            if cls is not None:
                forwarded += [f.name for f in dataclasses.fields(cls) if f.name not in own]
    return len(own) + len(forwarded), own + forwarded


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quiet", action="store_true", help="the three figures only")
    args = parser.parse_args(argv)
    library = sorted(PACKAGE.rglob("*.py"))
    public = public_names()
    reached = reach(set().union(*(notebook_roots(p, public) for p in PAPER_NOTEBOOKS)))
    files = sorted(((lines(module_path(m)), m) for m in reached), reverse=True)
    count, names = fit_options()
    print(f"library: {sum(map(lines, library))} lines in {len(library)} modules")
    print(f"reached by notebooks 00-06: {sum(n for n, _ in files)} lines in {len(files)} modules")
    print(f"fit: {count} options ({', '.join(names)})")
    if not args.quiet:
        by_folder: dict[str, int] = {}
        for n, m in files:
            folder = ".".join(m.split(".")[:3]) if m.startswith("ifslib.core") else ".".join(m.split(".")[:2])
            by_folder[folder] = by_folder.get(folder, 0) + n
        print("reached, by folder: " + ", ".join(f"{k} {v}" for k, v in sorted(by_folder.items(), key=lambda kv: -kv[1])))
        for n, m in files[:25]:
            print(f"  {n:5d}  {m}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
