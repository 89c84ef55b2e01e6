"""Progress output: a live bar where someone watches it (a terminal, Jupyter), one line per stage where a log
records it (a bar's redraws would pile up in a file); notes go to standard error."""
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
    """Whether a live progress bar helps: ``stream`` (standard error by default) is a terminal, or Jupyter."""
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
