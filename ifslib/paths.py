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
