"""`fit`: the public entry to the inverse problem. It checks its arguments once, picks a strategy and hands the
work down; nothing below calls back up."""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from ...errors import MAX_SEED, IFSError, check_int
from ...names import DEFAULT_STEPS
from ..geometry.ifs import IFS
from ..targets.target import Target
from .options import Checkpoint, RunOptions, with_settings
from .result import FitResult
from .run import run
from .strategies import DEFAULT_STRATEGY, Start, resolve, run_strategy


def _checkpoint(checkpoint) -> Checkpoint | None:
    """A `Checkpoint` from the argument: an object, a path to write every 100 steps, or None."""
    if checkpoint is None or isinstance(checkpoint, Checkpoint):
        return checkpoint
    if isinstance(checkpoint, (str, Path)):
        return Checkpoint(checkpoint)
    raise IFSError(f"checkpoint must be a Checkpoint or a path, got {type(checkpoint).__name__}")


def _check(start, target, steps: int, seed: int, options: RunOptions) -> None:
    check_int(steps, "steps", 0)
    check_int(seed, "seed", 0, maximum=MAX_SEED)
    if not isinstance(target, Target):
        raise IFSError(f"target must be a Target (see ifslib.load_target), got a {type(target).__name__}")
    if not isinstance(start, IFS) and not isinstance(getattr(start, "start", None), IFS):
        raise IFSError(f"ifs must be an IFS (or a plan from ifslib.discover(target)), "
                       f"got a {type(start).__name__}")


def fit(ifs: IFS | Start, target: Target, *, steps: int = DEFAULT_STEPS, strategy=None, seed: int = 0,
        lr: float | None = None, loss: str | Callable | None = None, depth: int | str | None = None,
        options: RunOptions | None = None, progress: bool = True, callback: Callable | None = None,
        checkpoint: Checkpoint | str | Path | None = None) -> FitResult:
    """Fit an IFS's control points to a target with Adam.

    Parameters
    ----------
    ifs : IFS or Plan
        The starting point (not modified), or a plan read from the image
        (``ifslib.discover(target)``), which is fitted by comparing its candidates.
    target : Target
        From `ifslib.load_target`; its size sets the render size.
    steps : int
        The step budget of each run (the paper used 1500 steps in one run). With the default
        strategy each stage of each start spends at most ``min(steps, 500)`` and most stop
        long before.
    strategy : str or a strategy's options, optional
        How the steps are spent: a name of `ifslib.names.STRATEGIES` (with its defaults) or the strategy's
        options object, ``strategy=ifslib.strategies.Pyramid(n_starts=2)``. None (the default) is
        ``"pyramid"``: coarse to fine in pixels with early stopping, starts tried until one recovers the
        target; a plan is fitted with ``"auto"``, and a fit with a checkpoint is a single run, ``"plain"``
        (the paper's procedure). The others are in `ifslib.core.fitting.strategies`.
    seed : int
        Seeds torch and the strategies' jitter, from 0 to ``ifslib.errors.MAX_SEED``; a seeded fit
        on CPU is reproducible.
    lr, loss, depth : optional
        The learning rate, the loss and the render depth of every run (`RunOptions`), over ``options``.
    options : RunOptions, optional
        How each Adam run moves the points (early stop, rendering method, device, ...); the defaults where
        not given.
    progress : bool
        Show progress bars naming the stage (start k of n, size) and the current loss.
    callback : callable, optional
        ``callback(step, loss, ifs)`` after every step of every run.
    checkpoint : Checkpoint or path, optional
        A resumable single run (`ifslib.core.fitting.options.Checkpoint`; a path is where to write it,
        every 100 steps).

    Returns
    -------
    FitResult
        ``history.stopped`` says why the returned run ended; the default strategy adds
        ``history.stages`` (each stage's start, size, steps and why it stopped),
        ``history.starts_tried`` and ``history.recovered``; ``history.cost`` counts every step
        of every run.
    """
    saved = _checkpoint(checkpoint)
    run_options = _run_options(options, lr=lr, loss=loss, depth=depth)
    _check(ifs, target, steps, seed, run_options)
    if strategy is None:
        strategy = "plain" if saved is not None else DEFAULT_STRATEGY if isinstance(ifs, IFS) else ifs.strategy
    name, settings = resolve(strategy)
    if name == "plain":
        start = ifs if isinstance(ifs, IFS) else ifs.start
        return run(start, target, steps=steps, options=run_options, seed=seed, callback=callback,
                   checkpoint=saved, progress=progress)
    if saved is not None:
        raise IFSError("checkpoint and resume work with strategy='plain' only")
    return run_strategy(name, ifs, target, steps=steps, seed=seed, options=run_options,
                        settings=settings, progress=progress, callback=callback)


def _run_options(options: RunOptions | None, **named) -> RunOptions:
    """``options`` (the defaults when None) with the settings given by name, those not None."""
    if options is not None and not isinstance(options, RunOptions):
        raise IFSError(f"options must be a RunOptions, got {type(options).__name__}")
    return with_settings(options, {k: v for k, v in named.items() if v is not None})


__all__ = ["FitResult", "fit"]
