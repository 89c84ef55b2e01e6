"""The house's rules: the paper's core imports no extension, and a folder imports only from the folders above it.

The order (docs/guide/design.md): the core's stages (geometry, raster, targets, scoring, fitting), then
the extensions, each using the core (compression, splatting, the learned guess, the automatic path, measures), then
studies, teaching and the command line; the top-level helpers (errors, data, names, paths, threads,
progress) may be imported from anywhere.
"""
import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "ifslib"
CORE = ["core.geometry", "core.raster", "core.targets", "core.scoring", "core.fitting"]
EXTENSIONS = ["compression", "splatting", "learned", "automatic", "measures"]
ORDER = CORE + EXTENSIONS + ["studies", "teaching", "cli"]
HELPERS = {"errors", "data", "names", "paths", "threads", "progress"}


def folder_of(module: str) -> str | None:
    """The place of ``ifslib.a.b`` in ORDER (``a``; ``core.b`` in the core), or None for a top-level helper
    or the package itself."""
    parts = module.split(".")
    if len(parts) < 2 or parts[1] in HELPERS or parts[1] in ("__init__", "__main__"):
        return None
    if parts[1] == "core":
        return "core" if len(parts) == 2 else f"core.{parts[2]}"
    return parts[1] if (PACKAGE / parts[1]).is_dir() else "the package's namespace"


def imports(path: Path) -> list[str]:
    """The absolute names of the ifslib modules ``path`` imports."""
    module = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    package = package.removesuffix(".__init__")
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            if name.startswith("ifslib"):
                out += [name] if node.module else [f"{name}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            out += [a.name for a in node.names if a.name.startswith("ifslib")]
    return out


def place_of(path: Path) -> str:
    """The place in ORDER of a module of the package."""
    parts = path.relative_to(PACKAGE).parts
    if path.parent == PACKAGE:
        return "cli"
    if parts[0] == "core":
        return "core" if len(parts) == 2 else f"core.{parts[1]}"
    return parts[0]


MODULES = sorted(p for p in PACKAGE.rglob("*.py") if p.parent != PACKAGE or p.stem.startswith("cli"))


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_only_from_folders_above(path):
    own = place_of(path)
    if own == "core":
        assert not imports(path), "ifslib/core/__init__.py only names the core's folders"
        return
    rank = ORDER.index(own)
    for name in imports(path):
        other = folder_of(name)
        if other is None or other == own or (own == "cli" and other == "the package's namespace"):
            continue  # the command line is the one module that uses the public namespace
        assert other in ORDER, f"{path.name} imports {name}, from a folder outside the house's order"
        assert ORDER.index(other) < rank, f"{path.relative_to(PACKAGE)} ({own}) imports {name} ({other}, below it)"


@pytest.mark.parametrize("path", [p for p in MODULES if place_of(p).startswith("core")],
                         ids=lambda p: str(p.relative_to(PACKAGE)))
def test_the_core_imports_no_extension(path):
    for name in imports(path):
        other = folder_of(name)
        assert other is None or other.startswith("core"), f"{path.relative_to(PACKAGE)} imports {name}, an extension"


def test_the_order_names_every_folder():
    folders = {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    folders = (folders - {"core"}) | {f"core.{p.name}" for p in (PACKAGE / "core").iterdir() if (p / "__init__.py").exists()}
    # an extension's folder may be still to come; every folder there is must have its place
    assert folders <= set(ORDER) - {"cli"} and set(CORE) <= folders


def _module_name(path: Path) -> str:
    return ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts).removesuffix(".__init__")


def test_no_import_circle():
    # every import counts, those inside functions too: a circle there is a knot however it is loaded
    known = {_module_name(p) for p in PACKAGE.rglob("*.py")}
    graph = {}
    for path in PACKAGE.rglob("*.py"):
        found = set()
        for name in imports(path):
            while name and name not in known:  # `from .x import name` names a module or an attribute of one
                name = name.rpartition(".")[0]
            if name and name != _module_name(path) and not name.endswith(("ifslib", ".threads")):
                found.add(name)
        graph[_module_name(path)] = found
    state = {}

    def visit(node, trail):
        state[node] = "open"
        for other in graph.get(node, ()):
            if other in graph.get(node, ()) and other.startswith(node + "."):
                continue  # a package's __init__ naming its own modules is not a circle
            if state.get(other) == "open":
                raise AssertionError(" -> ".join(trail[trail.index(other):] + [other]) if other in trail else other)
            if other not in state:
                visit(other, trail + [other])
        state[node] = "done"

    for module in sorted(graph):
        if module not in state:
            visit(module, [module])


RUN_THE_CORE = """
import importlib, pathlib, sys
import ifslib
package = pathlib.Path(ifslib.__file__).parent
for path in sorted((package / "core").rglob("*.py")):
    importlib.import_module(".".join(path.relative_to(package.parent).with_suffix("").parts).removesuffix(".__init__"))
target = ifslib.load_target(ifslib.patterns.koch(depth=2), 24)
start = ifslib.initialize(ifslib.patterns.koch(depth=2), target)
for name in ifslib.names.STRATEGIES:  # an extension's name is refused, not loaded
    try:
        ifslib.fit(start, target, steps=8, strategy=name, progress=False)
    except ifslib.IFSError as refused:
        assert "not imported" in str(refused), refused
ifslib.render(start, 24, "attractor"); ifslib.chaos_game(start, 100, seed=0); ifslib.evaluate(start, target)
print(" ".join(sorted(m for m in sys.modules if m.startswith("ifslib."))))
"""


def test_the_core_at_run_time_loads_no_extension():
    """Every core module imported, a fit asked of every strategy name (the core's run, an extension's refused),
    a render, the chaos game and the scores, in a fresh interpreter: no module of an extension is loaded, by an
    import or by name."""
    import subprocess
    import sys

    done = subprocess.run([sys.executable, "-c", RUN_THE_CORE], capture_output=True, text=True, timeout=300,
                          cwd=PACKAGE.parent)
    assert done.returncode == 0, done.stderr[-2000:]
    loaded = done.stdout.split()
    assert any(m.startswith("ifslib.core.fitting") for m in loaded)
    extensions = [m for m in loaded if folder_of(m) not in (None,) and not folder_of(m).startswith("core")]
    assert not extensions, f"the core loaded {extensions}"
