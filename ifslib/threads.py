"""How many CPU threads torch uses: the free cores, or ``IFSLIB_THREADS`` (docs/results/threads.md). Importing it
sets ``MKL_CBWR`` and ``OMP_WAIT_POLICY`` unless the user did, the one write to the environment."""
from __future__ import annotations

import os
import time
from contextlib import contextmanager
from typing import Iterator

# Set before torch loads (every computing folder imports this module first; tests/test_threads.py checks the
# order), a user's value kept: MKL's strict mode gives a matrix product the same bits at any thread count.
os.environ.setdefault("MKL_CBWR", "AUTO,STRICT")
# OpenMP's idle threads sleep rather than spin: beside another busy process a spinning thread doubles a fit's
# CPU time and more (docs/results/threads.md).
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

import torch  # noqa: E402

from .errors import IFSError  # noqa: E402

#: The environment variable read by `configure_threads`.
ENV = "IFSLIB_THREADS"

#: How long `busy_cores` watches the machine, in seconds.
SAMPLE_SECONDS = 0.05

#: `refresh` looks at the machine again only after this many seconds (at most a tenth of the time goes to looking).
REFRESH_SECONDS = 0.5

_state = {"auto": False, "sampled": -float("inf")}


def cores() -> int:
    """The cores this process may run on (its CPU affinity where the system says, else ``os.cpu_count()``)."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return max(1, os.cpu_count() or 1)


def _busy_jiffies() -> tuple[int, int]:
    """Busy CPU time of the whole machine (``/proc/stat``) and of this process (``/proc/self/stat``), in clock ticks."""
    with open("/proc/stat") as f:
        fields = [int(v) for v in f.readline().split()[1:]]
    idle = fields[3] + (fields[4] if len(fields) > 4 else 0)  # idle + iowait
    with open("/proc/self/stat") as f:
        own = f.read().rsplit(")", 1)[1].split()
    return sum(fields[:8]) - idle, int(own[11]) + int(own[12])  # utime + stime


def busy_cores(seconds: float = SAMPLE_SECONDS) -> float | None:
    """How many cores other processes keep busy (the machine's busy time minus this process's, per second), sampled
    over ``seconds``; None where ``/proc`` is missing."""
    try:
        total0, own0 = _busy_jiffies()
        t0 = time.perf_counter()
        time.sleep(seconds)
        total1, own1 = _busy_jiffies()
    except (OSError, ValueError, IndexError):
        return None
    ticks = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100
    return max(0.0, ((total1 - total0) - (own1 - own0)) / ticks / (time.perf_counter() - t0))


def free_threads() -> int:
    """`cores` minus the cores other processes keep busy (rounded), at least 1; in a container's CPU set the busy
    share of the machine is taken as that of its own cores."""
    busy = busy_cores()
    _state["sampled"] = time.monotonic()
    n = cores()
    if busy is None:
        return n
    total = max(n, os.cpu_count() or n)
    return max(1, min(n, round(n - busy * n / total)))


def configure_threads(threads: int | str | None = None) -> int:
    """Set torch's thread count from ``threads`` or ``$IFSLIB_THREADS``: a positive integer, or ``"auto"`` (the
    default), the cores other processes leave free, picked again at each run (`refresh`)."""
    source = f"{ENV}={os.environ.get(ENV)!r}" if threads is None else f"threads={threads!r}"
    value = os.environ.get(ENV, "") if threads is None else threads
    if isinstance(value, str) and (value.strip().lower() or "auto") != "auto":
        try:
            value = int(value)
        except ValueError:
            value = None
    auto = isinstance(value, str)
    if not auto and (isinstance(value, bool) or not isinstance(value, int) or value < 1):
        raise IFSError(f"{source}: expected 'auto' or a positive integer number of threads")
    _state["auto"] = auto
    torch.set_num_threads(free_threads() if auto else value)
    return torch.get_num_threads()


def refresh() -> int:
    """In ``auto`` mode, pick the thread count again from the cores free now (at most every `REFRESH_SECONDS`);
    called at the start of every single run (and of benchmarks/batch.py's batch), so a long fit follows the machine's load."""
    if _state["auto"] and time.monotonic() - _state["sampled"] >= REFRESH_SECONDS:
        torch.set_num_threads(free_threads())
    return torch.get_num_threads()


@contextmanager
def fixed_threads(threads: int) -> Iterator[int]:
    """Run a block with exactly ``threads`` torch threads (no `refresh`), then restore the previous setting (the
    sweep's workers: one thread each)."""
    saved = (_state["auto"], torch.get_num_threads())
    try:
        yield configure_threads(threads)
    finally:
        _state["auto"] = saved[0]
        torch.set_num_threads(saved[1])


# Set when the package's first computing folder is imported (each folder's __init__ imports this module),
# before any of its modules runs torch: IFSLIB_THREADS=N fixes the count; unset, the free cores.
configure_threads()
