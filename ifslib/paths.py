"""Where things are: the repository root, and the figures and build folders inside it."""
from __future__ import annotations

from pathlib import Path


def repo_root() -> Path:
    """The repository root: the nearest folder above this package holding ``pyproject.toml``.

    Works the same from papermill, nbval, JupyterLab or a script, whatever the working directory.
    """
    here = Path(__file__).resolve().parent
    for folder in (here, *here.parents):
        if (folder / "pyproject.toml").is_file() and (folder / "ifslib").is_dir():
            return folder
    return here.parent


def figures_dir() -> Path:
    """``<root>/figures`` (created on demand)."""
    path = repo_root() / "figures"
    path.mkdir(exist_ok=True)
    return path


def load_script(relative: str, name: str):
    """The repository's script ``relative`` (a path from its root, such as ``notebooks/student.py``) imported
    once as module ``name``: the tools around the package (the course, the book, the student edition) use
    each other's functions without being part of it.

    The module is in ``sys.modules`` before it runs, so that a dataclass in it can look itself up.
    """
    import importlib.util
    import sys

    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, repo_root() / relative)
        sys.modules[name] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules[name])
    return sys.modules[name]
