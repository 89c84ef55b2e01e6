"""Store the notebooks' outputs: run each in place, top to bottom, with its ci preset: ``python notebooks/store.py``.

The stored outputs are what readers see on GitHub and in the book, and what nbval compares the
cells tagged ``nbval-check-output`` with. They are made at ``STORE_THREADS`` torch threads and the
count is recorded in each notebook's metadata (``metadata["ifslib"]["threads"]``); the tests run
the notebooks at another count (`tests/conftest.py`), so that a checked output which depends on
the summation order fails in the tests rather than on a reader's machine.

    python notebooks/store.py            # every notebook
    python notebooks/store.py 02 08      # those whose names start so
"""
from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from run import notebooks  # notebooks/run.py: this script's folder is first on sys.path

#: The torch thread count at which the stored outputs are made (the tests use another).
STORE_THREADS = 1


def store(path: Path, timeout: int = 1200) -> float:
    """Execute the notebook at ``path`` in a fresh kernel and write it back with its outputs; returns seconds."""
    book = nbformat.read(path, as_version=4)
    started = time.perf_counter()
    NotebookClient(book, timeout=timeout, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}}).execute()
    book.metadata["ifslib"] = {"threads": STORE_THREADS}
    nbformat.write(book, path)
    return time.perf_counter() - started


def main(argv: list[str]) -> int:
    os.environ["IFSLIB_THREADS"] = str(STORE_THREADS)  # the kernels inherit the environment
    os.environ.pop("MPLBACKEND", None)  # the inline backend, so that the figures are stored
    os.environ.pop("IFSLIB_FIGURES", None)  # the ci preset writes no figure
    for path in notebooks(argv):
        print(f"{path.name}: {store(path):.0f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
