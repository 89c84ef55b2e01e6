"""Progress output: a live bar where someone watches it, one line per stage where a log records it.

A tqdm bar redraws itself with carriage returns; on a terminal that is one line that moves, in a
file it is hundreds of updates. So a bar is drawn only when standard error is a terminal, or in a
Jupyter kernel (where tqdm draws a widget); otherwise a run stays silent while it works and `note`
writes one line when it ends. Notes go to standard error, beside the bars, so that standard output
holds only a command's result.
"""
from __future__ import annotations

import sys
from typing import TextIO

from tqdm.auto import tqdm


def _in_jupyter() -> bool:
    """True inside a Jupyter kernel (the test tqdm.auto makes before drawing a widget)."""
    shell = sys.modules.get("IPython")
    if shell is None:
        return False
    try:
        ip = shell.get_ipython()
    except AttributeError:
        return False
    return ip is not None and "IPKernelApp" in getattr(ip, "config", {})


def draw_bars(stream: TextIO | None = None) -> bool:
    """Whether a live progress bar helps: ``stream`` (standard error by default) is a terminal, or Jupyter.

    Parameters
    ----------
    stream : file object, optional
        Where the bar would be drawn; ``sys.stderr`` when None.

    Returns
    -------
    bool
        False for a file, a pipe or a closed stream: there a bar's redraws would pile up.
    """
    if _in_jupyter():
        return True
    stream = sys.stderr if stream is None else stream
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError, OSError):
        return False


def note(text: str) -> None:
    """Write one line on standard error, above a live bar when one is drawn."""
    tqdm.write(text, file=sys.stderr)
