"""`fit`: the public entry to the inverse problem, on top of the fitting layer.

It checks its arguments once (into `RunOptions`, `StrategyOptions` and a `Checkpoint`), picks a
strategy (`ifslib.core.fitting.strategies`) and hands the work down; nothing below calls back up.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from ...errors import MAX_SEED, IFSError, check_int
from ...names import DEFAULT_STEPS
from ..geometry.ifs import IFS
from ..targets.target import Target
from .options import Checkpoint, RunOptions, StrategyOptions, split_settings
from .result import FitResult
from .run import run
from .strategies import DEFAULT_STRATEGY, Start, check_strategy, run_strategy


def _checkpoint(checkpoint, checkpoint_every: int | None, resume) -> Checkpoint | None:
    """A `Checkpoint` from the arguments: an object, or a path to write (and a path to resume from)."""
    if isinstance(checkpoint, Checkpoint):
        if checkpoint_every is not None or resume is not None:
            raise IFSError("give checkpoint_every and resume inside the Checkpoint, not beside it")
        return checkpoint
    if checkpoint is None and resume is None:
        if checkpoint_every is not None:
            raise IFSError("checkpoint_every goes with a checkpoint path")
        return None
    return Checkpoint(checkpoint, 100 if checkpoint_every is None else checkpoint_every, resume)


def _check(start, target, steps: int, seed: int, options: RunOptions) -> None:
    check_int(steps, "steps", 0)
    check_int(seed, "seed", 0, maximum=MAX_SEED)
    if not isinstance(target, Target):
        raise IFSError(f"target must be a Target (see ifslib.load_target), got a {type(target).__name__}")
    if not isinstance(start, IFS) and not isinstance(getattr(start, "start", None), IFS):
        raise IFSError(f"ifs must be an IFS (or a plan from ifslib.discover(target)), "
                       f"got a {type(start).__name__}")


def fit(ifs: IFS | Start, target: Target, *, steps: int = DEFAULT_STEPS, strategy: str | None = None, seed: int = 0,
        options: RunOptions | StrategyOptions | tuple | None = None, progress: bool = True,
        callback: Callable | None = None, checkpoint: Checkpoint | str | Path | None = None,
        **settings) -> FitResult:
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
    strategy : str, optional
        How the steps are spent. None (the default) is `DEFAULT_STRATEGY`, ``"pyramid"``: coarse to
        fine in pixels with early stopping, starts tried until one recovers the target; a plan is
        fitted with ``"auto"``, and a fit with a checkpoint is a single run, ``"plain"`` (the
        paper's procedure). The others are in `ifslib.core.fitting.strategies`.
    seed : int
        Seeds torch and the strategies' jitter, from 0 to ``ifslib.errors.MAX_SEED``; a seeded fit
        on CPU is reproducible.
    options : RunOptions, StrategyOptions or a pair of them, optional
        The settings as objects (`ifslib.core.fitting.options`); the defaults where not given.
    progress : bool
        Show progress bars naming the stage (start k of n, size) and the current loss.
    callback : callable, optional
        ``callback(step, loss, ifs)`` after every step of every run.
    checkpoint : Checkpoint or path, optional
        A resumable single run (`ifslib.core.fitting.options.Checkpoint`; a path is where to write it).
        With a path, ``checkpoint_every`` and ``resume`` may be given by name too.
    **settings
        Any field of `RunOptions` (``lr``, ``loss``, ``depth``, ``sigma``, ``levels``, ``method``,
        ``device``, ``gradient``, ``max_rollbacks``, ``keep_every``, ``crossing_weight``, ``tol``,
        ``patience``) or of `StrategyOptions` (``n_starts``, ``jitter``, ``success``,
        ``end_on_attractor``, ...) by name, over ``options``: ``fit(ifs, target, lr=0.01)``.

    Returns
    -------
    FitResult
        ``history.stopped`` says why the returned run ended; the default strategy adds
        ``history.stages`` (each stage's start, size, steps and why it stopped),
        ``history.starts_tried`` and ``history.recovered``; ``history.cost`` counts every step
        of every run.
    """
    saved = _checkpoint(checkpoint, settings.pop("checkpoint_every", None), settings.pop("resume", None))
    run_options, strategy_options = split_settings(settings, *_objects(options))
    _check(ifs, target, steps, seed, run_options)
    if strategy is None:
        strategy = "plain" if saved is not None else DEFAULT_STRATEGY if isinstance(ifs, IFS) else ifs.strategy
    check_strategy(strategy)
    if strategy == "plain":
        start = ifs if isinstance(ifs, IFS) else ifs.start
        return run(start, target, steps=steps, options=run_options, seed=seed, callback=callback,
                   checkpoint=saved, progress=progress)
    if saved is not None:
        raise IFSError("checkpoint and resume work with strategy='plain' only")
    return run_strategy(strategy, ifs, target, steps=steps, seed=seed, options=run_options,
                        settings=strategy_options, progress=progress, callback=callback)


def _objects(options) -> tuple[RunOptions | None, StrategyOptions | None]:
    """``options`` as a (run, strategy) pair, each None where not given."""
    given = options if isinstance(options, tuple) else (options,) if options is not None else ()
    run_options = [o for o in given if isinstance(o, RunOptions)]
    strategy_options = [o for o in given if isinstance(o, StrategyOptions)]
    if len(run_options) + len(strategy_options) != len(given) or len(run_options) > 1 or len(strategy_options) > 1:
        raise IFSError("options must be a RunOptions, a StrategyOptions, or one of each in a tuple")
    return (run_options[0] if run_options else None, strategy_options[0] if strategy_options else None)


__all__ = ["FitResult", "fit"]
