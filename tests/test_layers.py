"""The house's one rule: a folder of the package imports only from the folders above it.

The order is the pipeline's (docs/guide/design.md): geometry, raster, targets, scoring, compression
(the gray images' coder: nothing from the binary fitting), discovery, fitting, studies, teaching, then
the command line; the top-level helpers (errors, data, names, paths,
threads, progress) may be imported from anywhere.
"""
import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "ifslib"
ORDER = ["geometry", "raster", "targets", "scoring", "compression", "discovery", "fitting", "studies", "teaching", "cli"]
HELPERS = {"errors", "data", "names", "paths", "threads", "progress"}


def folder_of(module: str) -> str | None:
    """The folder of ``ifslib.a.b`` (``a``), or None for a top-level helper or the package itself."""
    parts = module.split(".")
    if len(parts) < 2 or parts[1] in HELPERS or parts[1] in ("__init__", "__main__"):
        return None
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


MODULES = sorted(p for p in PACKAGE.rglob("*.py") if p.parent != PACKAGE or p.stem.startswith("cli"))


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_imports_only_from_folders_above(path):
    own = "cli" if path.stem.startswith("cli") and path.parent == PACKAGE else path.relative_to(PACKAGE).parts[0]
    rank = ORDER.index(own)
    for name in imports(path):
        other = folder_of(name)
        if other is None or other == own or (own == "cli" and other == "the package's namespace"):
            continue  # the command line is the one module that uses the public namespace
        assert other in ORDER, f"{path.name} imports {name}, from a folder outside the house's order"
        assert ORDER.index(other) < rank, f"{path.relative_to(PACKAGE)} ({own}) imports {name} ({other}, below it)"


def test_the_order_names_every_folder():
    folders = {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    assert folders == set(ORDER) - {"cli"}
