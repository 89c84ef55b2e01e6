"""The repository's scripts loaded by one another: the tools around the package (the course, the book, the student
edition) use each other's functions without being part of it. Its callers find it on ``sys.path`` (``course/``)."""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def load_script(relative: str, name: str):
    """The repository's script ``relative`` (a path from its root, such as ``notebooks/student.py``) imported
    once as module ``name``.

    The module is in ``sys.modules`` before it runs, so that a dataclass in it can look itself up.
    """
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, ROOT / relative)
        sys.modules[name] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(sys.modules[name])
    return sys.modules[name]
