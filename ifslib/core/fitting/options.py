"""The settings of a fit, as frozen dataclasses validated once, where they are built: `RunOptions` (one Adam run),
`StrategyOptions` (how a strategy spends its runs) and `Checkpoint` (a resumable run).

`ifslib.fit` takes them as objects, or their fields by name (``fit(ifs, target, lr=0.01)``), and
hands them down whole; nothing below it pops or refills a setting.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, ClassVar

from ...names import DEFAULT_LR
from ...errors import IFSError, check_int
from ..geometry.attractor import check_depth_or_attractor
from ..geometry.rules import check_gradient_mode
from ..raster.distance import METHODS, resolve_device
from ..scoring.losses import DEFAULT_LOSS, check_loss

#: The largest learning rate a fit takes: Adam's step is about ``lr`` plane units, and the frame is 1 wide.
MAX_LR = 1.0


def _finite(value, allow_zero: bool = False) -> bool:
    return (isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
            and (value >= 0 if allow_zero else value > 0))


def check_stop(tol: float | None, patience: int | None) -> None:
    """Raise `IFSError` unless ``tol`` is None or a finite number >= 0 and ``patience`` None or an int >= 1."""
    if tol is not None and not _finite(tol, allow_zero=True):
        raise IFSError(f"tol must be None or a finite number >= 0, got {tol!r}")
    if patience is not None:
        check_int(patience, "patience", 1)


@dataclass(frozen=True)
class RunOptions:
    """How one Adam run moves the control points (`ifslib.core.fitting.run.run`).

    Attributes
    ----------
    lr : float
        Learning rate at the target's size (the paper used 0.003), above 0 and at most `MAX_LR`.
    stage_lr : float, optional
        The learning rate of a coarser stage, set by the strategies (``lr`` scaled with the stage's
        pixel size); None runs at ``lr``. Not a setting a fit takes by name.
    loss : str or callable
        One of `ifslib.core.scoring.losses.LOSSES` (`DEFAULT_LOSS` when not given) or ``f(distance, target)``.
    depth : int or "attractor", optional
        Render depth (``ifs.depth`` when None); ``"attractor"`` fits the attractor itself.
    sigma, levels
        Passed to the loss.
    method, device, gradient
        Passed to `ifslib.distance_field` (``gradient="paper"`` reproduces the paper's cut gradient).
    max_rollbacks : int
        Stop a run after this many consecutive rolled-back steps.
    keep_every : int, optional
        Keep the control points every ``keep_every`` steps in ``history.snapshots``, for `ifslib.animate`.
    crossing_weight : float
        For curves: add ``crossing_weight * ifslib.crossings.crossing_penalty(ifs)`` to the loss.
    tol, patience : optional
        Early stop once the best loss improved by at most a fraction ``tol`` over the last
        ``patience`` steps. None keeps the strategy's own setting: off for ``plain``, on for
        ``pyramid``; ``patience`` None with ``tol`` set is ``DEFAULT_PATIENCE``.
    """

    #: The window of early stopping (`ifslib.core.fitting.run.converged`) when ``tol`` is set and
    #: ``patience`` is not: longer waits out more of a slow stretch, shorter stops a stalled run sooner.
    DEFAULT_PATIENCE: ClassVar[int] = 50

    lr: float = DEFAULT_LR
    loss: str | Callable = DEFAULT_LOSS
    depth: int | str | None = None
    sigma: float | None = None
    levels: int = 5
    method: str = "fast"
    device: str = "auto"
    gradient: str = "exact"
    max_rollbacks: int = 20
    keep_every: int | None = None
    crossing_weight: float = 0.0
    tol: float | None = None
    patience: int | None = None
    stage_lr: float | None = None

    def __post_init__(self) -> None:
        if not (_finite(self.lr) and self.lr <= MAX_LR):
            raise IFSError(f"lr must be a finite number > 0 and at most {MAX_LR:g} (a step as wide as the frame), "
                           f"got {self.lr!r}")
        if self.stage_lr is not None and not _finite(self.stage_lr):
            raise IFSError(f"stage_lr must be None or a finite number > 0, got {self.stage_lr!r}")
        check_loss(self.loss)
        if self.method not in METHODS:
            raise IFSError(f"unknown method {self.method!r}; known methods: {', '.join(METHODS)}")
        resolve_device(self.device)  # a name torch does not know is refused here; an absent device when used
        check_gradient_mode(self.gradient)
        check_stop(self.tol, self.patience)
        if not _finite(self.crossing_weight, allow_zero=True):
            raise IFSError(f"crossing_weight must be a finite number >= 0, got {self.crossing_weight!r}")
        if self.keep_every is not None:
            check_int(self.keep_every, "keep_every", 1)
        check_int(self.max_rollbacks, "max_rollbacks", 1)
        if self.depth is not None:
            check_depth_or_attractor(self.depth)

    def replace(self, **changes) -> RunOptions:
        """A copy with ``changes`` (validated again)."""
        return dataclasses.replace(self, **changes)

    @property
    def stop_window(self) -> int:
        """The steps over which early stopping looks: ``patience``, or ``DEFAULT_PATIENCE`` when it is None."""
        return self.DEFAULT_PATIENCE if self.patience is None else self.patience

    @property
    def step_lr(self) -> float:
        """The learning rate Adam starts from: ``stage_lr`` when a strategy set one, else ``lr``."""
        return self.lr if self.stage_lr is None else self.stage_lr


@dataclass(frozen=True)
class StrategyOptions:
    """How a strategy spends its runs (`ifslib.core.fitting.strategies`; each setting's strategy in brackets).

    Attributes
    ----------
    n_starts : int
        Starts tried at most [pyramid, multistart].
    keep : int
        Probes that go on to the full budget [multistart].
    probe : float
        A probe's share of ``steps`` [multistart].
    jitter : float
        Half-width of the uniform jitter of a start's points, plane units [pyramid, multistart, restart].
    success : float
        Symmetric Chamfer distance (pixels) at which no more starts are tried [pyramid, restart].
    budget : float
        The most steps, in multiples of ``steps`` [restart].
    coarsest : int
        The pyramid's coarsest size in pixels: below 64 a Koch curve of depth 3 blurs into its own gaps [pyramid, auto].
    pyramid_factor : int
        Each pyramid stage is this many times the size of the one before (4: 64² then 256²; a middle 128²
        stage costs more time than it saves at 256², docs/results/fits-in-seconds.md) [pyramid, auto].
    stage_steps : int
        At most this many steps in one pyramid stage (or ``steps``, when smaller): enough for the stages of
        starts that recover, while a start that crawls on for a thousand steps ends stalled and is better
        replaced [pyramid, auto].
    stage_tol, stage_patience : float, int
        Each pyramid stage's early stop (`ifslib.core.fitting.run.converged`) where the run options set none
        [pyramid, auto].
    attractor_steps : int
        At most this many steps in the last stage, which fits the attractor itself at the target's size
        (what the inverse problem asks for: a drawing at depth K can match the target while its attractor
        does not) [pyramid, auto].
    max_leaves : int
        The attractor stage draws the certified cut (`ifslib.distance_field` with ``depth="attractor"``) when
        it has at most this many leaves, else sampled leaves of it (``method="sampled"``: overlapping copies
        of a shape): more is exact on more figures, and slower and larger per step [pyramid, auto].
    uncross_weight : float
        The crossing barrier's weight when the run options set none: larger pushes crossings apart sooner
        and distorts the curve's fit more [uncross].
    end_on_attractor : bool
        End each start with a stage that fits the attractor itself and judge it; False keeps the
        fit on the drawing at depth K, the paper's question [pyramid, auto].
    """

    n_starts: int = 8
    keep: int = 2
    probe: float = 0.15
    jitter: float = 0.05
    success: float = 1.0
    budget: float = 3.0
    coarsest: int = 64
    pyramid_factor: int = 4
    stage_steps: int = 500
    stage_tol: float = 1e-3
    stage_patience: int = 30
    attractor_steps: int = 300
    max_leaves: int = 300_000
    uncross_weight: float = 0.1
    end_on_attractor: bool = True

    def __post_init__(self) -> None:
        check_int(self.n_starts, "n_starts", 1)
        check_int(self.keep, "keep", 1)
        check_int(self.coarsest, "coarsest", 1)
        check_int(self.pyramid_factor, "pyramid_factor", 2)
        for name in ("stage_steps", "stage_patience", "attractor_steps", "max_leaves"):
            check_int(getattr(self, name), name, 1)
        for name in ("stage_tol", "uncross_weight"):
            if not _finite(getattr(self, name)):
                raise IFSError(f"{name} must be a finite number > 0, got {getattr(self, name)!r}")
        if not (_finite(self.probe) and self.probe < 1):
            raise IFSError(f"probe must be a share of the steps, above 0 and below 1, got {self.probe!r}")
        for name in ("jitter", "success", "budget"):
            if not _finite(getattr(self, name), allow_zero=name != "budget"):
                raise IFSError(f"{name} must be a finite number >= 0, got {getattr(self, name)!r}")
        if not isinstance(self.end_on_attractor, bool):
            raise IFSError(f"end_on_attractor must be True or False, got {self.end_on_attractor!r}")


@dataclass(frozen=True)
class Checkpoint:
    """A resumable run: write the state to ``path`` every ``every`` steps and at the end; continue from ``resume``.

    Either path may be None; a fit with a checkpoint is a single run (strategy ``plain``).
    """

    path: str | Path | None = None
    every: int = 100
    resume: str | Path | None = None

    def __post_init__(self) -> None:
        check_int(self.every, "checkpoint_every", 1)


#: The settings `ifslib.fit` takes by name, and the object each belongs to.
FIELDS = {f.name: RunOptions for f in dataclasses.fields(RunOptions) if f.name != "stage_lr"} | \
         {f.name: StrategyOptions for f in dataclasses.fields(StrategyOptions)}


def split_settings(settings: dict, run: RunOptions | None, strategy: StrategyOptions | None
                   ) -> tuple[RunOptions, StrategyOptions]:
    """``settings`` given by name (fields of `RunOptions` or `StrategyOptions`) applied to the objects given."""
    unknown = sorted(set(settings) - set(FIELDS))
    if unknown:
        raise IFSError(f"unknown setting(s) {', '.join(unknown)}: a fit takes {', '.join(sorted(FIELDS))}")
    run = RunOptions() if run is None else run
    strategy = StrategyOptions() if strategy is None else strategy
    mine = {k: v for k, v in settings.items() if FIELDS[k] is RunOptions}
    theirs = {k: v for k, v in settings.items() if FIELDS[k] is StrategyOptions}
    return (run.replace(**mine) if mine else run,
            dataclasses.replace(strategy, **theirs) if theirs else strategy)
