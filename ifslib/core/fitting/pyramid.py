"""Coarse to fine in pixels: the one driver the ``pyramid`` and ``auto`` strategies climb with, and the attractor
stage that ends them (docs/guide/internals.md)."""
from __future__ import annotations

from ...errors import LeafBudgetError
from ..geometry.attractor import ATTRACTOR
from ..geometry.ifs import IFS
from ..raster.distance import attractor_leaves_for
from .frame import Frame
from .options import Pyramid, RunOptions
from .result import FitResult, Stage

def with_early_stop(options: RunOptions, settings: Pyramid) -> RunOptions:
    """``options`` with the pyramid's own early stop (``settings.stage_tol``, ``stage_patience``) where the fit set none."""
    return options.replace(tol=settings.stage_tol if options.tol is None else options.tol,
                           patience=settings.stage_patience if options.patience is None else options.patience)


def climb(frame: Frame, start: IFS, options: RunOptions, label: str, *, sizes: list[int] | None = None
          ) -> tuple[FitResult, list[Stage]]:
    """Fit ``start`` at each size of the pyramid (or of ``sizes``) in turn, each stage from the last one's best points."""
    stages, current, result = [], start, None
    for size in frame.sizes if sizes is None else sizes:
        staged = options.replace(stage_lr=options.lr * frame.target.size / size)
        result = frame.run(current, min(frame.steps, frame.settings.stage_steps), staged, target=frame.levels[size],
                           desc=f"{label} · {size}²")
        stages.append(Stage(size=size, steps=result.history.cost, stopped=result.history.stopped,
                            best_loss=result.best_loss))
        current = result.best
    return result, stages


def attractor_method(ifs: IFS, size: int, max_leaves: int) -> str:
    """``"fast"`` when the certified cut of ``ifs``'s attractor at ``size`` has at most ``max_leaves`` leaves, else ``"sampled"``."""
    try:
        attractor_leaves_for(ifs, size, max_leaves=max_leaves)
    except LeafBudgetError:
        return "sampled"
    return "fast"


def attractor_stage(frame: Frame, ifs: IFS, options: RunOptions, label: str, *, steps: int | None = None,
                    max_leaves: int | None = None) -> tuple[FitResult, Stage]:
    """Fit the attractor of ``ifs`` at the target's size (the last stage of ``pyramid`` and ``auto``): with the
    certified cut when it has at most ``max_leaves`` leaves, else (or once it outgrows them) sampled leaves."""
    target = frame.target
    method = attractor_method(ifs, target.size, frame.settings.max_leaves if max_leaves is None else max_leaves)
    budget = min(frame.steps if steps is None else steps, frame.settings.attractor_steps)
    fallback = None
    try:
        result = frame.run(ifs, budget, options.replace(depth=ATTRACTOR, method=method),
                           desc=f"{label} · {target.size}² · attractor")
    except LeafBudgetError as exc:
        if method != "fast":
            raise
        # the maps grew on the way until the certified cut outgrew the leaf budget: the stage again, from its start,
        # with sampled leaves of the cut (whose number does not grow with the maps)
        method = "sampled"
        fallback = f"the certified cut outgrew the leaf budget during the stage ({exc}); run again with sampled leaves"
        result = frame.run(ifs, budget, options.replace(depth=ATTRACTOR, method=method),
                           desc=f"{label} · {target.size}² · attractor (sampled)")
    loss = options.loss if isinstance(options.loss, str) else "custom"
    return result, Stage(size=target.size, depth=ATTRACTOR, method=method, loss=loss, steps=result.history.cost,
                         stopped=result.history.stopped, best_loss=result.best_loss, fallback=fallback)
