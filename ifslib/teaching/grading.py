"""Grading runs: while nbgrader autogrades or validates a lesson, skip the demonstrations its checks do not need.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import hashlib
from typing import Iterable

#: What a skipped cell runs instead: a statement, so that the cell's output is empty.
SKIPPED = "pass  # a demonstration of the lesson: not needed by the checks, skipped while grading\n"


def cell_key(source: str) -> str:
    """A short hash naming a cell by its source: the stripped non-empty lines, joined."""
    lines = [line.strip() for line in source.splitlines() if line.strip()]
    return hashlib.sha256("\n".join(lines).encode()).hexdigest()[:16]


def skip_cells(keys: Iterable[str]) -> int:
    """Run ``pass`` instead of each later cell whose `cell_key` is one of ``keys``; returns how many keys.

    Does nothing outside IPython. Registered once per kernel: a second call replaces the first's keys.

    Parameters
    ----------
    keys : iterable of str
        `cell_key` values of the cells to skip.
    """
    keys = frozenset(keys)
    try:
        from IPython import get_ipython
    except ImportError:
        return 0
    shell = get_ipython()
    if shell is None:
        return 0
    transformers = shell.input_transformers_cleanup
    transformers[:] = [t for t in transformers if not getattr(t, "_ifslib_grading", False)]

    def skip(lines: list[str]) -> list[str]:
        return [SKIPPED] if cell_key("".join(lines)) in keys else lines

    skip._ifslib_grading = True
    transformers.insert(0, skip)
    return len(keys)
