"""Store a notebook's teaching run in the notebook itself (``python notebooks/run.py --only 02 08`` calls it).

The stored outputs are what readers see: the notebook on GitHub and in JupyterLab, the book and the
slides. `store` executes a notebook top to bottom in a fresh kernel at its teaching values (its
``parameters`` cell, nothing injected, so the stored cells are the source's), drops the progress
bars and records the run in ``metadata["ifslib"]["stored"]``: the preset, the torch thread count
and the parameters it ran with (tests/notebooks/test_stored_runs.py holds the stored notebooks to
them), and its time in whole seconds, the one source of the times that the notebooks' first cells
and docs/guide/teaching.md give (tests/teaching/test_run_times.py holds them to it). `run.py` reads
the teaching values and hands them here, and also writes the figure to ``figures/``; the quick
values (``make test``) never reach the stored outputs.

Progress bars are not stored: a tqdm widget's view is stored without its final state, so a
reader sees it at "0%", and a bar on standard error is hundreds of redraws. The kernels run with
``TQDM_DISABLE=1`` (tqdm's default for ``disable``, which a call that passes ``disable`` itself
overrides, as the library's bars do), and `drop_progress_bars` removes whatever bar is left: the
widget views whose text is a bar, and the bar lines of standard error. Every other output is kept.
"""
from __future__ import annotations

import os
import re
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient

#: What the kernel of a stored run has in its environment, and ``make test-stored``'s kernels too
#: (tests/nbval_stored.py): no progress bar, and torch's CPU kernels at their AVX2 build on any x86-64
#: machine. Without that pin torch takes the widest the CPU has, and an AVX-512 machine rounds some
#: sums in another order: notebook 08's 10-map splat fit reselects 2 maps there and 4 on AVX2
#: (measured, the same commit), so a stored run would hold only on the kind of machine that made it.
KERNEL_ENV = {"TQDM_DISABLE": "1", "ATEN_CPU_CAPABILITY": "avx2"}

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


#: The first cell's line on the run's time, as the lessons write it.
HOW_LONG = re.compile(r"(\*\*How long it runs\*\*:\s*(?:about\s+)?)(.*?)( at the teaching values)", re.S)
#: A row of the table in docs/guide/teaching.md: its notebook, and its last (teaching) column.
GUIDE_ROW = re.compile(r"^(\|[^|\n]*\|\s*\[[^\]]*\]\(\.\./\.\./notebooks/(\w+)\.ipynb\)(?:\s*\|[^|\n]*){3}\|\s*)"
                       r"([^|\n]*?)(\s*\|\s*)$", re.M)


def as_text(seconds: int) -> str:
    """A run time as the lessons write it: ``7 min 18 s``, ``44 s``."""
    minutes, rest = divmod(int(seconds), 60)
    return f"{minutes} min {rest} s" if minutes else f"{rest} s"


def write_time(book, seconds: int) -> None:
    """The first cell's "How long it runs" line set to the stored run's time (the one source of it)."""
    first = book.cells[0]
    first.source = HOW_LONG.sub(lambda m: f"{m.group(1)}{as_text(seconds)}{m.group(3)}", first.source, count=1)


def write_guide_times(guide: Path, seconds: dict[str, int]) -> None:
    """The teaching column of ``guide``'s table set to each stored run's time (``stem -> seconds``)."""
    text = GUIDE_ROW.sub(lambda m: f"{m.group(1)}{as_text(seconds[m.group(2)]) if m.group(2) in seconds else m.group(3)}"
                                   f"{m.group(4)}", guide.read_text(encoding="utf-8"))
    guide.write_text(text, encoding="utf-8")


def store(path: Path, dest: Path, figures: Path, parameters: dict, timeout: int = 1800) -> None:
    """Execute the notebook at ``path`` at its teaching values in a fresh kernel, write it with its outputs to ``dest``.

    ``parameters`` are those teaching values (its cell tagged ``parameters``, as `run.teaching_parameters`
    reads it), recorded with the run; the cell itself runs as it is, nothing injected.
    ``dest`` may be ``path`` itself (stored in place). The kernel runs in the notebook's folder, at
    this process's ``IFSLIB_THREADS``, with its figure written to ``figures`` (``IFSLIB_FIGURES``:
    an empty ``save_to`` falls back on it), the inline backend and no progress bar.
    """
    started = time.perf_counter()
    book = nbformat.read(path, as_version=4)
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}  # inline: the figures are stored
    env.update(KERNEL_ENV, IFSLIB_FIGURES=str(figures))
    NotebookClient(book, timeout=timeout, kernel_name="python3", record_timing=False,  # no timestamps to churn
                   resources={"metadata": {"path": str(path.parent)}}).execute(env=env)
    drop_progress_bars(book)
    for cell in book.cells:  # a timestamp left by an editor or an older run would describe another run
        cell.metadata.pop("execution", None)
    meta = book.metadata.setdefault("ifslib", {})
    meta.pop("threads", None)  # recorded in "stored" now
    threads = env.get("IFSLIB_THREADS", "auto")
    meta["stored"] = {"preset": "teaching", "threads": int(threads) if threads.isdigit() else threads,
                      "parameters": parameters, "seconds": round(time.perf_counter() - started)}
    write_time(book, meta["stored"]["seconds"])
    dest.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(book, dest)
