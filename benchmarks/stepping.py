"""Shared by the step benchmarks: time warm steps and read the peak memory they needed."""
from __future__ import annotations

import resource
import statistics
import time
from typing import Callable


def timed_steps(step: Callable[[], None], repeat: int, device: str) -> tuple[float, int]:
    """Run ``step`` once to warm up, then ``repeat`` times; the median seconds and the peak bytes.

    On CPU the peak is the growth of the process's peak resident set (``ru_maxrss``) over its size
    before the first step; on CUDA, ``torch.cuda.max_memory_allocated``.
    """
    import torch

    cuda = device != "cpu" and torch.cuda.is_available()
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    if cuda:
        torch.cuda.reset_peak_memory_stats()
    step()
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        step()
        times.append(time.perf_counter() - t0)
    peak = torch.cuda.max_memory_allocated() if cuda else resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 - base
    return statistics.median(times), peak
