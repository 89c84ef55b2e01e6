"""A fit's frame: what every run of one strategy shares, and the target's pyramid, built once when climbed."""
from __future__ import annotations

from dataclasses import KW_ONLY, dataclass
from functools import cached_property
from typing import Callable

from ..geometry.ifs import IFS
from ..targets.target import Target, pyramid_sizes, resize_target
from .options import Pyramid, RunOptions
from .result import FitResult
from .run import run


@dataclass(frozen=True)
class Frame:
    """What every run of one fit shares: the target, the step budget, the seed, the run ``options`` (unless a run
    is given its own), progress and callback, and the strategy's own options (``settings``)."""

    target: Target
    steps: int
    seed: int
    _: KW_ONLY
    options: RunOptions = RunOptions()
    progress: bool = True
    callback: Callable | None = None
    settings: object = Pyramid()

    @cached_property
    def levels(self) -> dict[int, Target]:
        """The target's pyramid, coarsest first: size -> the target resized; built on first use only."""
        sizes = pyramid_sizes(self.target.size, self.settings.coarsest, self.settings.pyramid_factor)
        return {size: resize_target(self.target, size) for size in sizes}

    @property
    def sizes(self) -> list[int]:
        """The pyramid's sizes, coarsest first."""
        return list(self.levels)

    def run(self, start: IFS, steps: int, options: RunOptions | None = None, *, target: Target | None = None,
            desc: str | None = None, **changes) -> FitResult:
        """One run of ``start`` with the frame's seed, callback and progress, at ``target`` (the frame's when None), with
        ``options`` (the frame's when None) changed by ``changes``."""
        options = self.options if options is None else options
        options = options.replace(**changes) if changes else options
        target = self.target if target is None else target
        return run(start, target, steps=steps, options=options, seed=self.seed, callback=self.callback,
                   progress=self.progress, desc=desc)
