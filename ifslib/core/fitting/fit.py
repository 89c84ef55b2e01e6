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
        The start (not modified), or a plan read from the image (``ifslib.discover(target)``).
    steps : int
        The budget of each run (the paper: 1500 in one run); the default strategy's stages spend at most 500.
    strategy : str or a strategy's options, optional
        A name of `ifslib.names.STRATEGIES` or its options (``ifslib.strategies.Pyramid(n_starts=2)``); None:
        ``"pyramid"``, ``"auto"`` for a plan, ``"plain"`` (the paper's single run) with a checkpoint.
    seed : int
        Seeds torch and the strategies' jitter; a seeded fit on CPU is reproducible.
    lr, loss, depth, options
        How each Adam run moves the points (`RunOptions`); the named ones over ``options``.
    checkpoint : Checkpoint or path, optional
        A resumable single run (a path: written every 100 steps).

    Returns
    -------
    FitResult
        ``history.stopped`` says why the returned run ended, ``history.cost`` counts every step of every run."""
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
