"""Store the notebooks' outputs: run each in place, top to bottom, with its ci preset: ``python notebooks/store.py``.

The stored outputs are what readers see on GitHub and in the book, and what nbval compares the
cells tagged ``nbval-check-output`` with. They are made at ``STORE_THREADS`` torch threads and the
count is recorded in each notebook's metadata (``metadata["ifslib"]["threads"]``); the tests run
the notebooks at another count (`tests/conftest.py`), so that a checked output which depends on
the summation order fails in the tests rather than on a reader's machine.

Progress bars are not stored: a tqdm widget's view is stored without its final state, so a
reader sees it at "0%", and a bar on standard error is hundreds of redraws. The kernels run with
``TQDM_DISABLE=1`` (tqdm's default for ``disable``, which a call that passes ``disable`` itself
overrides, as the library's bars do), and `drop_progress_bars` removes whatever bar is left: the
widget views whose text is a bar, and the bar lines of standard error. Every other output is kept.
So a cell tagged ``nbval-check-output`` must draw no bar (``progress=False``): nbval, which runs
with bars, would find an output that its stored copy lacks.

    python notebooks/store.py            # every notebook
    python notebooks/store.py 02 08      # those whose names start so
"""
from __future__ import annotations

import os
import re
import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from run import notebooks  # notebooks/run.py: this script's folder is first on sys.path

#: The torch thread count at which the stored outputs are made (the tests use another).
STORE_THREADS = 2

#: A tqdm bar as tqdm writes it: ``desc:  40%|####      | 2/5 [00:01<00:01, 1.9it/s]``, or without a
#: total ``desc: 7it [00:01, 6.2it/s]`` (the rate in any unit: ``it/s``, ``step/s``, ``s/it``).
PROGRESS_BAR = re.compile(r"\d+%\|[^\r\n]*\||\[\d+:\d\d(?::\d\d)?(?:<[^,\]]*)?, *[^\]]*(?:/s|s/\w+)[^\]]*\]")

#: The output type of a widget's view (a tqdm bar in a kernel is one).
WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"


def _bar_lines(text: str) -> str:
    """``text`` without its progress-bar pieces (a bar redraws itself after ``\\r``)."""
    kept = []
    for line in text.split("\n"):
        pieces = line.split("\r")
        if not any(PROGRESS_BAR.search(p) for p in pieces):
            kept.append(line)
        elif any(p and not PROGRESS_BAR.search(p) for p in pieces):
            kept.append("\r".join(p for p in pieces if p and not PROGRESS_BAR.search(p)))
    return "\n".join(kept)


def drop_progress_bars(book: nbformat.NotebookNode) -> int:
    """Remove the progress-bar outputs of ``book`` in place, and the state of widgets no view shows; returns how many.

    A bar is a widget view whose text is a bar (`PROGRESS_BAR`), or a stream's bar lines (the stream
    is dropped when nothing else is left in it).
    """
    dropped = 0
    for cell in book.cells:
        if cell.cell_type != "code":
            continue
        outputs = []
        for out in cell.outputs:
            if out.output_type in ("display_data", "execute_result") and WIDGET_VIEW in out.get("data", {}) \
                    and PROGRESS_BAR.search(str(out.data.get("text/plain", ""))):
                dropped += 1
                continue
            if out.output_type == "stream":
                text = _bar_lines(out.text)
                if text != out.text:
                    dropped += 1
                    if not text.strip():
                        continue
                    out.text = text
            outputs.append(out)
        cell.outputs = outputs
    _drop_unshown_widgets(book)
    return dropped


def _drop_unshown_widgets(book: nbformat.NotebookNode) -> None:
    """Keep in ``metadata["widgets"]`` only the models that a stored view shows, directly or as a child."""
    widgets = book.metadata.get("widgets", {})
    key = "application/vnd.jupyter.widget-state+json"
    if key not in widgets:
        return
    state = widgets[key].get("state", {})
    todo = [out.data[WIDGET_VIEW].get("model_id") for cell in book.cells if cell.cell_type == "code"
            for out in cell.outputs if WIDGET_VIEW in out.get("data", {})]
    shown = set()
    while todo:
        model = todo.pop()
        if model in shown or model not in state:
            continue
        shown.add(model)
        todo.extend(re.findall(r"IPY_MODEL_([0-9a-f]+)", str(state[model])))
    if shown:
        widgets[key]["state"] = {k: v for k, v in state.items() if k in shown}
    else:
        del book.metadata["widgets"]


def store(path: Path, timeout: int = 1200) -> float:
    """Execute the notebook at ``path`` in a fresh kernel and write it back with its outputs; returns seconds."""
    book = nbformat.read(path, as_version=4)
    started = time.perf_counter()
    NotebookClient(book, timeout=timeout, kernel_name="python3", resources={"metadata": {"path": str(path.parent)}}).execute()
    drop_progress_bars(book)
    book.metadata["ifslib"] = {"threads": STORE_THREADS}
    nbformat.write(book, path)
    return time.perf_counter() - started


def main(argv: list[str]) -> int:
    os.environ["IFSLIB_THREADS"] = str(STORE_THREADS)  # the kernels inherit the environment
    os.environ.pop("MPLBACKEND", None)  # the inline backend, so that the figures are stored
    os.environ.pop("IFSLIB_FIGURES", None)  # the ci preset writes no figure
    os.environ["TQDM_DISABLE"] = "1"  # no bar to store (see the module's docstring)
    for path in notebooks(argv):
        print(f"{path.name}: {store(path):.0f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
