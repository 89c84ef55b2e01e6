"""Convergence sweeps: many seeded Koch fits per cell (strategy x gradient x start x loss), in parallel, one torch
thread a task so the serial result equals the parallel one: ``"serial"``, ``"local"`` (a process pool, spawned:
run it under ``if __name__ == "__main__":``) or a Dask scheduler's address."""
from __future__ import annotations

import math
import multiprocessing
import os
import statistics
import time
import warnings
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import asdict, dataclass
from typing import Callable

from tqdm.auto import tqdm

from ..errors import IFSError, check_int
from ..names import DEFAULT_LR, DEFAULT_STEPS
from ..core.geometry import patterns
from ..progress import draw_bars
from ..core.geometry.rules import check_gradient_mode
from ..threads import cores, fixed_threads
from ..core.fitting.fit import fit
from ..core.fitting.options import Pyramid, RunOptions
from ..core.targets.placement import initialize
from ..core.scoring.losses import DEFAULT_LOSS, check_loss
from ..core.scoring.metrics import evaluate, point_error, self_crossings
from ..core.fitting.strategies import check_strategy
from ..core.targets.target import load_target

INITS = ("paper", "line")


@dataclass(frozen=True)
class Cell:
    """How the fits of one table row are made: a ``strategy``, a ``gradient`` mode, an ``init`` (``"paper"``: the paper's
    own start, `ifslib.patterns.koch_paper`; ``"line"``: the target's best-fit line jittered by 0.05) and a ``loss``."""

    strategy: str = "plain"
    gradient: str = "exact"
    init: str = "paper"
    loss: str = DEFAULT_LOSS


@dataclass(frozen=True)
class Setup:
    """What every fit of a sweep shares: the target (a paper image by name, or ``"rendered"``: the library's Koch curve,
    no data files), the size, depth, steps, lr, success threshold, and the early stop of the single-run strategies."""

    target: str = "koch"
    size: int = 128
    depth: int = 3
    steps: int = DEFAULT_STEPS
    lr: float = DEFAULT_LR
    success_chamfer: float = 1.0
    tol: float | None = None
    patience: int | None = None


def start_for(cell: Cell, seed: int, setup: Setup, target=None):
    """The starting IFS of one fit: the paper's Koch start, or the jittered best-fit line of ``target``."""
    if cell.init == "paper":
        return patterns.koch_paper(seed, depth=setup.depth)
    return initialize(patterns.koch(depth=setup.depth), target, jitter=0.05, seed=seed)


def load_setup_target(setup: Setup):
    """The sweep's `Target`: a paper image by name, or the library's Koch curve (``"rendered"``)."""
    return load_target(patterns.koch(depth=setup.depth) if setup.target == "rendered" else setup.target, setup.size)


def run_batch(cell: Cell, seeds: list[int], setup: Setup) -> list[dict]:
    """Fit one cell for each seed, with one torch thread; one row per fit (the task a worker runs)."""
    with fixed_threads(1):
        target = load_setup_target(setup)
        stop = {} if cell.strategy == "pyramid" else dict(tol=setup.tol, patience=setup.patience)
        # the study judges the drawing at depth K, as the paper: the pyramid does not end on the attractor
        chosen = Pyramid(end_on_attractor=False) if cell.strategy == "pyramid" else cell.strategy
        rows = []
        for seed in seeds:
            start = start_for(cell, seed, setup, target)
            t0 = time.perf_counter()
            result = fit(start, target, steps=setup.steps, lr=setup.lr, loss=cell.loss, seed=seed, progress=False,
                         strategy=chosen, options=RunOptions(gradient=cell.gradient, **stop))
            seconds = time.perf_counter() - t0
            m = evaluate(result.best, target, attractor=False)  # the study judges the depth-K drawing, as the paper
            tried, kept = starts_used(result.history)
            rows.append({**asdict(cell), "seed": seed, "recovered": m["chamfer"] <= setup.success_chamfer,
                         "chamfer": m["chamfer"], "iou": m["iou"], "crossings": self_crossings(result.best),
                         "point_error": point_error(result.best, patterns.koch()),
                         "steps": result.history.cost, "seconds": seconds, "starts_tried": tried, "start": kept,
                         "points": result.best.points.detach().tolist()})
        return rows


def starts_used(history) -> tuple[int, int]:
    """(starts tried, the one kept, from 1) of a fit's history; (1, 1) for a single run (a seed's own start only when 1)."""
    judged = [stage for stage in (history.stages or []) if stage.start is not None and stage.chamfer is not None]
    if not judged:
        return 1, 1
    kept = min(judged, key=lambda stage: stage.chamfer).start + 1
    return history.starts_tried or kept, kept


def _check(cells: list[Cell], seeds: list[int]) -> None:
    if not cells or not seeds:
        raise IFSError("a sweep needs at least one cell and one seed")
    for cell in cells:
        check_strategy(cell.strategy)
        check_gradient_mode(cell.gradient)
        if cell.init not in INITS:
            raise IFSError(f"unknown init {cell.init!r}; known: {', '.join(INITS)}")
        check_loss(cell.loss)  # the same check as RunOptions', before any worker starts


def sweep(cells: list[Cell], seeds: list[int], setup: Setup = Setup(), *, batch: int = 2,
          scheduler: str = "local", workers: int = 2, on_rows: Callable[[list[dict]], None] | None = None) -> list[dict]:
    """Run every cell for every seed: one row per fit, in cell order then seed order; ``on_rows`` gets each task's rows
    as it ends."""
    _check(cells, seeds)
    check_int(batch, "batch", 1)
    tasks = [(cell, seeds[i:i + batch]) for cell in cells for i in range(0, len(seeds), batch)]
    if scheduler == "serial":
        parts = []
        for cell, chunk in tasks:
            parts.append(run_batch(cell, chunk, setup))
            if on_rows is not None:
                on_rows(parts[-1])
        return _joined(parts)
    if scheduler == "local":
        return _joined(_run_pool(tasks, setup, _local_workers(workers), on_rows))
    try:
        import dask.distributed as distributed
    except ImportError:   # a student's environment
        raise IFSError(f"a sweep on the Dask scheduler {scheduler!r} needs dask.distributed: "
                       "pip install 'dask[distributed]' (or use scheduler='local' or 'serial')") from None
    return _joined(_run_dask(distributed, tasks, setup, scheduler, on_rows))


def _joined(parts: list[list[dict]]) -> list[dict]:
    return [row for part in parts for row in part]


def _local_workers(workers: int) -> int:
    """``workers``, cut to the cores with a warning: one thread per worker, never more workers than cores."""
    check_int(workers, "workers", 1)
    n_cores = cores()
    if workers > n_cores:
        warnings.warn(f"sweep: {workers} workers on {n_cores} cores would oversubscribe them; using {n_cores}")
        return n_cores
    return workers


def _show_progress() -> bool:
    return os.environ.get("IFSLIB_PROGRESS", "1") != "0"


def _run_pool(tasks: list[tuple[Cell, list[int]]], setup: Setup, workers: int,
              on_rows: Callable[[list[dict]], None] | None) -> list[list[dict]]:
    """Each task on a `ProcessPoolExecutor` of ``workers`` processes; the parts in task order."""
    # spawn: a forked child would copy this process's threads (torch's OpenMP pool) in whatever state they hold
    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn"))
    try:
        futures = [pool.submit(run_batch, cell, chunk, setup) for cell, chunk in tasks]
        with tqdm(total=len(futures), desc="sweep", disable=not (_show_progress() and draw_bars())) as bar:
            for future in as_completed(futures):
                rows = future.result()  # a task's error is raised here, at once
                bar.update()
                if on_rows is not None:
                    on_rows(rows)
        return [future.result() for future in futures]
    finally:
        # on an error or an interrupt, the tasks not yet started are dropped rather than run to the end
        pool.shutdown(wait=True, cancel_futures=True)


def _run_dask(distributed, tasks: list[tuple[Cell, list[int]]], setup: Setup, scheduler: str,
              on_rows: Callable[[list[dict]], None] | None) -> list[list[dict]]:
    """Each task on the running Dask scheduler at ``scheduler``; the parts in task order."""
    client = distributed.Client(scheduler)
    try:
        futures = [client.submit(run_batch, cell, chunk, setup, pure=False) for cell, chunk in tasks]
        if on_rows is not None:
            for future in distributed.as_completed(futures):
                on_rows(future.result())
        elif _show_progress():
            distributed.progress(futures)
        return client.gather(futures)
    finally:
        client.close()


def summarize(rows: list[dict]) -> list[dict]:
    """One row per cell: recovered / fits, median Chamfer and point error (up to similarity, so no pose is needed),
    the crossings, median steps and seconds per fit."""
    keys = ("strategy", "gradient", "init", "loss")
    cells: dict[tuple, list[dict]] = {}
    for row in rows:
        cells.setdefault(tuple(row[k] for k in keys), []).append(row)
    return [{**dict(zip(keys, key)), "recovered": sum(r["recovered"] for r in mine), "fits": len(mine),
             "median_chamfer": statistics.median(r["chamfer"] for r in mine),
             "median_point_error": statistics.median(r.get("point_error", math.nan) for r in mine),
             "crossing": sum(r["crossings"] > 0 for r in mine),
             "median_steps": statistics.median(r["steps"] for r in mine),
             "median_seconds": statistics.median(r["seconds"] for r in mine)} for key, mine in cells.items()]


def table(summary: list[dict]) -> str:
    """A markdown table of `summarize`'s rows."""
    lines = ["| start | gradient | loss | strategy | recovered | median Chamfer (px) | median point error | "
             "crossing at the end | median steps spent | median s/fit |", "|---|---|---|---|---|---|---|---|---|---|"]
    for s in summary:
        lines.append(f"| {s['init']} | {s['gradient']} | {s['loss']} | {s['strategy']} | {s['recovered']}/{s['fits']} | "
                     f"{s['median_chamfer']:.2f} | {s.get('median_point_error', math.nan):.3f} | "
                     f"{s['crossing']}/{s['fits']} | {s['median_steps']:.0f} | {s['median_seconds']:.1f} |")
    return "\n".join(lines)

