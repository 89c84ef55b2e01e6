"""The settings of a fit, as frozen dataclasses validated where they are built: `RunOptions` (one Adam run),
each strategy's own options and `Checkpoint`."""
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


@dataclass(frozen=True)
class RunOptions:
    """How one Adam run moves the control points (`ifslib.core.fitting.run.run`): the learning rate (the paper's
    0.003), the loss, the depth, the renderer's settings, rollbacks, snapshots, the crossings' penalty, early stop."""

    #: The window of early stopping when ``tol`` is set and ``patience`` is not.
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
        if self.tol is not None and not _finite(self.tol, allow_zero=True):
            raise IFSError(f"tol must be None or a finite number >= 0, got {self.tol!r}")
        if self.patience is not None:
            check_int(self.patience, "patience", 1)
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


def _check_fields(options, ints: tuple[str, ...] = (), positive: tuple[str, ...] = (),
                  non_negative: tuple[str, ...] = ()) -> None:
    """Raise `IFSError` naming the first field of ``options`` out of its range."""
    for name in ints:
        check_int(getattr(options, name), name, 1)
    for name in positive:
        if not _finite(getattr(options, name)):
            raise IFSError(f"{name} must be a finite number > 0, got {getattr(options, name)!r}")
    for name in non_negative:
        if not _finite(getattr(options, name), allow_zero=True):
            raise IFSError(f"{name} must be a finite number >= 0, got {getattr(options, name)!r}")


@dataclass(frozen=True)
class Plain:
    """The paper's procedure: one run, every step spent unless the run options set an early stop."""


@dataclass(frozen=True)
class CoarseToFine:
    """Depth 1, then 2, ... up to the full depth, the steps split evenly."""


@dataclass(frozen=True)
class Anneal:
    """The rendering width (pixel losses) or the pooling levels (distance losses) from coarse to fine in four
    stages, the steps split evenly."""


@dataclass(frozen=True)
class Uncross:
    """One run with a barrier on self-crossings added to the loss (curves only), of ``weight`` when the run options
    set no ``crossing_weight``."""

    weight: float = 0.1

    def __post_init__(self) -> None:
        _check_fields(self, positive=("weight",))


@dataclass(frozen=True)
class Pyramid:
    """The default strategy: coarse to fine in pixels, starts tried until one recovers the target, each ending on
    its attractor (what the inverse problem asks: docs/guide/design.md)."""

    n_starts: int = 8
    jitter: float = 0.05
    success: float = 1.0
    coarsest: int = 64
    pyramid_factor: int = 4
    stage_steps: int = 500
    stage_tol: float = 1e-3
    stage_patience: int = 30
    attractor_steps: int = 300
    max_leaves: int = 300_000
    end_on_attractor: bool = True

    def __post_init__(self) -> None:
        _check_fields(self, ints=("n_starts", "coarsest", "stage_steps", "stage_patience", "attractor_steps",
                                  "max_leaves"),
                      positive=("stage_tol",), non_negative=("jitter", "success"))
        check_int(self.pyramid_factor, "pyramid_factor", 2)
        if not isinstance(self.end_on_attractor, bool):
            raise IFSError(f"end_on_attractor must be True or False, got {self.end_on_attractor!r}")


@dataclass(frozen=True)
class Multistart:
    """Short probes from ``n_starts`` starts (``probe`` of the steps each); the best ``keep`` go on to the full budget."""

    n_starts: int = Pyramid.n_starts
    keep: int = 2
    probe: float = 0.15
    jitter: float = Pyramid.jitter

    def __post_init__(self) -> None:
        _check_fields(self, ints=("n_starts", "keep"), non_negative=("jitter",))
        if not (_finite(self.probe) and self.probe < 1):
            raise IFSError(f"probe must be a share of the steps, above 0 and below 1, got {self.probe!r}")


@dataclass(frozen=True)
class Restart:
    """Runs in windows; a window that ends stalled and off the target (``success``) restarts from jittered best
    points, for at most ``budget`` times ``steps``."""

    jitter: float = Pyramid.jitter
    success: float = Pyramid.success
    budget: float = 3.0

    def __post_init__(self) -> None:
        _check_fields(self, positive=("budget",), non_negative=("jitter", "success"))


@dataclass(frozen=True)
class Checkpoint:
    """A resumable single run: write the state to ``path`` every ``every`` steps and at the end; continue from ``resume``."""

    path: str | Path | None = None
    every: int = 100
    resume: str | Path | None = None

    def __post_init__(self) -> None:
        check_int(self.every, "every", 1)


def with_settings(options: RunOptions | None, settings: dict) -> RunOptions:
    """``options`` (the defaults when None) with fields of `RunOptions` given by name; `IFSError` names any other."""
    fields = {f.name for f in dataclasses.fields(RunOptions)} - {"stage_lr"}
    unknown = sorted(set(settings) - fields)
    if unknown:
        raise IFSError(f"unknown setting(s) {', '.join(unknown)}: the run options are {', '.join(sorted(fields))}")
    options = RunOptions() if options is None else options
    return options.replace(**settings) if settings else options
