"""`fit`: the public entry to the inverse problem, on top of the fitting layer.

It checks its arguments, picks a strategy (`ifslib.fitting.strategies`) and hands the work down;
the strategies call the single Adam run (`ifslib.fitting.run.run`). Nothing below calls back up.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from ..errors import MAX_SEED, IFSError, check_int
from ..geometry.attractor import check_depth_or_attractor
from ..geometry.ifs import IFS
from .run import FitResult, check_stop, run
from .strategies import DEFAULT_STRATEGY, check_strategy, run_strategy
from ..targets.target import Target

#: The largest learning rate a fit takes: Adam's step is about ``lr`` plane units, and the frame is 1 wide.
MAX_LR = 1.0


def fit(ifs: IFS, target: Target, steps: int = 1500, lr: float = 0.003, loss: str | Callable = "multiscale_pixel",
        depth: int | None = None, seed: int = 0, callback: Callable | None = None, checkpoint: str | Path | None = None,
        checkpoint_every: int = 100, resume: str | Path | None = None, progress: bool = True,
        sigma: float | None = None, levels: int = 5, method: str = "fast", device: str = "auto",
        gradient: str = "exact", max_rollbacks: int = 20, keep_every: int | None = None,
        strategy: str | None = None, crossing_weight: float = 0.0, tol: float | None = None,
        patience: int | None = None, end_on_attractor: bool = True) -> FitResult:
    """Fit an IFS's control points to a target with Adam.

    Parameters
    ----------
    ifs : IFS
        The starting point (not modified).
    target : Target
        From `ifslib.load_target`; its size sets the render size.
    steps : int
        The step budget of each run (the paper used 1500 steps in one run). With the default
        strategy each stage of each start spends at most ``min(steps, 500)`` and most stop
        long before.
    lr : float
        Learning rate at the target's size (the paper used 0.003), at most `MAX_LR`.
    loss : str or callable
        ``pixel``, ``multiscale_pixel``, ``distance``, ``multiscale_distance`` or ``f(distance, target)``.
    depth : int or "attractor", optional
        Render depth (``ifs.depth`` when None); ``"attractor"`` fits the attractor itself, every
        stage (the default strategies end with an attractor stage anyway: see
        `ifslib.fitting.strategies`).
    seed : int
        Seeds torch and the strategies' jitter, from 0 to ``ifslib.errors.MAX_SEED``; a seeded fit on CPU is
        reproducible.
    callback : callable, optional
        ``callback(step, loss, ifs)`` after every step of every run.
    checkpoint, checkpoint_every, resume
        A resumable single run (see `ifslib.fitting.run.run`); they imply ``strategy="plain"``.
    progress : bool
        Show progress bars naming the stage (start k of n, size) and the current loss.
    sigma, levels
        Passed to the loss.
    method, device, gradient
        Passed to `ifslib.distance_field` (``gradient="paper"`` reproduces the paper's cut gradient).
    max_rollbacks : int
        Stop a run after this many consecutive rolled-back steps.
    keep_every : int, optional
        Keep the control points every ``keep_every`` steps in ``history["snapshots"]`` (of the run
        returned), for `ifslib.animate`.
    strategy : str, optional
        How the steps are spent. None (the default) is `DEFAULT_STRATEGY`, ``"pyramid"``: coarse to
        fine in pixels with early stopping, starts tried until one recovers the target; a fit with
        ``checkpoint`` or ``resume`` is a single run, and an automatic start
        (``ifslib.initialize("auto", target)``) is fitted with ``"auto"``, which compares several
        numbers of maps. ``"plain"`` is one run of ``steps`` steps, the
        paper's procedure; the others are in `ifslib.fitting.strategies`. ``history["cost"]`` counts
        every step of every run.
    crossing_weight : float
        For curves: add ``crossing_weight * ifslib.crossings.crossing_penalty(ifs)`` to the loss.
    tol, patience : optional
        Early stop of each run once its best loss improved by at most a fraction ``tol`` over the
        last ``patience`` steps (`ifslib.fitting.run.converged`). None keeps the strategy's own
        setting: off for ``plain`` and the other single-run strategies, on for ``pyramid``;
        ``tol=0`` stops only when the loss no longer improves at all.

    end_on_attractor : bool
        The default strategies (``pyramid``, ``auto``) end with a stage that fits the attractor
        itself and judge it; False keeps them on the drawing at ``depth`` (the paper's question).

    Returns
    -------
    FitResult
        ``history["stopped"]`` says why the returned run ended; the default strategy adds
        ``history["stages"]`` (each stage's start, size, steps and why it stopped),
        ``history["starts_tried"]`` and ``history["recovered"]``.
    """
    check_int(steps, "steps", 0)
    if patience is not None:
        check_stop(tol, patience)
    else:
        check_stop(tol, 1)
    if not (isinstance(lr, (int, float)) and 0 < lr <= MAX_LR):
        raise IFSError(f"lr must be a finite number > 0 and at most {MAX_LR:g} (a step as wide as the frame), got {lr!r}")
    check_int(seed, "seed", 0, maximum=MAX_SEED)
    if not isinstance(target, Target):
        raise IFSError(f"target must be a Target (see ifslib.load_target), got a {type(target).__name__}")
    if not isinstance(ifs, IFS):
        raise IFSError(f"ifs must be an IFS, got a {type(ifs).__name__}")
    if depth is not None:
        check_depth_or_attractor(depth)
    single = checkpoint is not None or resume is not None
    if strategy is None:
        automatic = isinstance(ifs.meta.get("pattern"), dict) and ifs.meta["pattern"].get("name") == "auto"
        strategy = "plain" if single else "auto" if automatic else DEFAULT_STRATEGY
    check_strategy(strategy)
    kwargs = dict(lr=lr, loss=loss, depth=depth, callback=callback, progress=progress, sigma=sigma, levels=levels,
                  method=method, device=device, gradient=gradient, max_rollbacks=max_rollbacks,
                  keep_every=keep_every, crossing_weight=crossing_weight)
    if tol is not None:
        kwargs["tol"] = tol
    if patience is not None:
        kwargs["patience"] = patience
    if strategy == "plain":
        return run(ifs, target, steps=steps, seed=seed, checkpoint=checkpoint, checkpoint_every=checkpoint_every,
                   resume=resume, **kwargs)
    if single:
        raise IFSError("checkpoint and resume work with strategy='plain' only")
    return run_strategy(strategy, ifs, target, steps, seed, kwargs, end_on_attractor=end_on_attractor)
