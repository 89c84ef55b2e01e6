"""How many CPU threads torch uses, set once for the whole package with ``IFSLIB_THREADS``.

torch picks one thread per core by default. On a shared machine, or when several fits run side by
side (the Dask sweep, a notebook beside a test run), that oversubscribes the cores; and at small
images one thread is often faster than two. ``IFSLIB_THREADS=N`` sets torch's intra-op thread
count when ``ifslib`` is imported, so a notebook, the CLI and the tests follow one setting without
a ``torch.set_num_threads`` line of their own.
"""
from __future__ import annotations

import os

import torch

from .errors import IFSError

#: The environment variable read by `configure_threads`.
ENV = "IFSLIB_THREADS"


def configure_threads(threads: int | str | None = None) -> int:
    """Set torch's CPU thread count from ``threads`` or, when None, from ``$IFSLIB_THREADS``.

    Parameters
    ----------
    threads : int or str, optional
        A positive number of threads. None reads ``IFSLIB_THREADS``; when that is unset or empty,
        torch's current setting is kept.

    Returns
    -------
    int
        The thread count now in force (``torch.get_num_threads()``).

    Raises
    ------
    IFSError
        If the value is not a positive integer.
    """
    source = f"{ENV}={os.environ.get(ENV)!r}" if threads is None else f"threads={threads!r}"
    value = os.environ.get(ENV, "") if threads is None else threads
    if isinstance(value, str):
        if not value.strip():
            return torch.get_num_threads()
        try:
            value = int(value.strip())
        except ValueError:
            raise IFSError(f"{source}: expected a positive integer number of threads") from None
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise IFSError(f"{source}: expected a positive integer number of threads")
    torch.set_num_threads(value)
    return torch.get_num_threads()
