"""``make test-stored``: the stored notebooks run again under nbval, their outputs and pictures compared.

A pytest plugin, loaded with ``-p tests.nbval_stored`` next to ``--nbval`` (the Makefile's
``test-stored``; it is no test module, so ``make test`` never collects it). It does three things:

* **The kernel's environment, as ``notebooks/store.py`` stores a run**: no ``MPLBACKEND`` (the
  inline backend, so the figure cells show their pictures; CI exports ``MPLBACKEND=Agg``),
  ``store.KERNEL_ENV`` (no progress bar, torch's AVX2 kernels), the figure that a notebook saves
  written into ``build/nbval-figures`` (``IFSLIB_FIGURES``), never over ``figures/``, and ``IFSLIB_THREADS=1`` unless it is set: the
  stored runs are made two notebooks at a time at one thread each (``notebooks/run.py``), and
  ``-n auto`` runs as many notebooks at once as the cores hold at that thread count.
* **Progress bars dropped from the run's outputs** by the function that drops them from the stored
  ones (``store.drop_progress_bars``), before nbval compares the text.
* **The pictures compared**: nbval leaves ``image/png`` out of its comparison (a PNG's bytes change
  with the renderer's rounding). Here each stored picture of a checked cell is decoded with Pillow
  next to the one the run draws, in order, and they must have the same size and differ by little:
  a mean absolute difference of at most `MEAN_LEVELS` levels (of 255, over every pixel and channel)
  and at most `CHANGED_SHARE` of the pixels changed by more than `CHANGED_LEVEL` levels in some
  channel. A failing pair is written to ``build/nbval-figures/failed/`` (stored, run, difference).
  The largest differences seen are printed at the end of the session. Two runs at one thread draw
  the same pixels (every picture of 00_explore, 00_tutorial, 01, 03 and the glossary: difference
  0.0000); the limits are set to catch the smallest real change measured: the tutorial's tangled fit
  from the paper's random start, 152 self-crossings stored and 156 drawn, moved 83 pixels of 240,000
  (0.035 %, a mean of 0.086 levels), so 0.05 levels and 0.01 %: a few re-rounded pixels pass, which
  a hash of the PNG would fail on.

nbval has no hook for its comparison, so the plugin wraps ``nbval.plugin.IPyNbCell.compare_outputs``:
nbval's own text comparison first (sanitized with ``--nbval-sanitize-with``), then the pictures.
"""
from __future__ import annotations

import base64
import io
import os
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
FIGURES = ROOT / "build" / "nbval-figures"

#: Largest mean absolute difference between a stored picture and the run's, in levels of 255.
MEAN_LEVELS = 0.05
#: Largest share of the pixels that may differ by more than `CHANGED_LEVEL` levels in some channel.
CHANGED_SHARE = 0.0001
CHANGED_LEVEL = 32

#: Seconds nbval waits for the kernel's next message once a cell has run (its 5 s fails cells of a
#: loaded 2-core machine: "Timeout of 5 seconds exceeded waiting for output"); a cell's own limit is
#: nbval's ``--nbval-cell-timeout``.
OUTPUT_SECONDS = 120

_seen = []  # (node id, picture index, mean levels, changed share): the session's pictures, for the summary


def pytest_configure(config):
    if not config.getoption("nbval", False):
        return
    os.environ.pop("MPLBACKEND", None)
    os.environ.update(_store().KERNEL_ENV)
    os.environ.setdefault("IFSLIB_THREADS", "1")
    os.environ.setdefault("IFSLIB_FIGURES", str(FIGURES))
    _wrap_nbval()


def pytest_xdist_auto_num_workers(config):
    """``-n auto``: as many notebooks at once as the cores hold at ``IFSLIB_THREADS`` threads each, as ``notebooks/run.py`` runs them."""
    from ifslib.threads import cores

    value = os.environ.get("IFSLIB_THREADS", "1")
    threads = int(value) if value.strip().isdigit() else 1
    return max(1, cores() // max(1, threads))


def _store():
    """``notebooks/store.py`` (not a package: its folder goes on the path, as ``notebooks/run.py`` has it)."""
    folder = str(ROOT / "notebooks")
    if folder not in sys.path:
        sys.path.insert(0, folder)
    import store

    return store


def without_bars(outputs):
    """``outputs`` (a cell's, from the run) less its progress bars, as ``store.drop_progress_bars`` stores a run."""
    import nbformat

    book = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell()])
    book.cells[0].outputs = list(outputs)
    _store().drop_progress_bars(book)
    return book.cells[0].outputs


def picture(data: str) -> np.ndarray:
    """A base64 PNG as an RGBA array of int16."""
    from PIL import Image

    with Image.open(io.BytesIO(base64.b64decode(data))) as image:
        return np.asarray(image.convert("RGBA"), dtype=np.int16)


def picture_difference(stored: str, run: str) -> tuple[float, float] | None:
    """(mean absolute difference in levels, share of pixels changed by more than `CHANGED_LEVEL`); None when the sizes differ."""
    a, b = picture(stored), picture(run)
    if a.shape != b.shape:
        return None
    diff = np.abs(a - b)
    return float(diff.mean()), float((diff.max(axis=-1) > CHANGED_LEVEL).mean())


def pictures(outputs) -> list[str]:
    return [o["data"]["image/png"] for o in outputs if "image/png" in o.get("data", {})]


def _keep_failed(item, k: int, stored: str, run: str) -> Path:
    from PIL import Image

    folder = FIGURES / "failed"
    folder.mkdir(parents=True, exist_ok=True)
    stem = f"{Path(str(item.fspath)).stem}-cell{item.cell_num}-{k}"
    for name, data in (("stored", stored), ("run", run)):
        (folder / f"{stem}-{name}.png").write_bytes(base64.b64decode(data))
    a, b = picture(stored), picture(run)
    if a.shape == b.shape:
        Image.fromarray((255 - np.abs(a - b).max(axis=-1)).clip(0, 255).astype(np.uint8)).save(folder / f"{stem}-diff.png")
    return folder / stem


def _wrap_nbval():
    from nbval.plugin import IPyNbCell

    if getattr(IPyNbCell.compare_outputs, "_ifslib", False):
        return
    text_compare = IPyNbCell.compare_outputs
    cell_setup = IPyNbCell.setup

    def setup(self):
        self.output_timeout = max(self.output_timeout, OUTPUT_SECONDS)
        cell_setup(self)

    def compare_outputs(self, test, ref, skip_compare=None):
        test = without_bars(test)
        if not text_compare(self, test, ref, skip_compare):
            return False
        stored, run = pictures(ref), pictures(test)
        if len(stored) != len(run):  # nbval compared the figures' text/plain, so this is rare
            self.comparison_traceback.append(f"{len(stored)} pictures stored, {len(run)} drawn by the run")
            return False
        for k, (a, b) in enumerate(zip(stored, run)):
            found = picture_difference(a, b)
            if found is not None:
                self.user_properties.append(("picture", (k, *found)))
            if found is None or found[0] > MEAN_LEVELS or found[1] > CHANGED_SHARE:
                where = _keep_failed(self, k, a, b)
                what = ("a picture of another size" if found is None else
                        f"mean difference {found[0]:.3f} levels (at most {MEAN_LEVELS}), "
                        f"{100 * found[1]:.3f} % of the pixels changed by more than {CHANGED_LEVEL} "
                        f"(at most {100 * CHANGED_SHARE:.3f} %)")
                self.comparison_traceback.append(
                    f"picture {k} of the cell differs from the stored one: {what}; see {where}-*.png")
                return False
        return True

    compare_outputs._ifslib = True
    IPyNbCell.compare_outputs = compare_outputs
    IPyNbCell.setup = setup


def pytest_runtest_logreport(report):
    if report.when == "call":
        _seen.extend((report.nodeid, *value) for name, value in report.user_properties if name == "picture")


def pytest_terminal_summary(terminalreporter):
    if not _seen:
        return
    mean = max(_seen, key=lambda s: s[2])
    share = max(_seen, key=lambda s: s[3])
    terminalreporter.write_line(
        f"pictures compared: {len(_seen)}; largest mean difference {mean[2]:.4f} levels ({mean[0]}), "
        f"largest share changed by more than {CHANGED_LEVEL} levels {100 * share[3]:.4f} % ({share[0]}); "
        f"limits {MEAN_LEVELS} levels, {100 * CHANGED_SHARE:.3f} %")
