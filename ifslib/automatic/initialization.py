"""`initialize`: a start for fitting a target, a pattern placed on it or a plan read from it.

A pattern is placed by `ifslib.core.targets.placement` (paper, "Initial Conditions"): segment patterns
along the best-fit line of the target's foreground, square and grid patterns on its bounding box,
with optional seeded jitter. The pattern ``"auto"`` reads one from the image itself
(`ifslib.automatic.plan.discover`): a curve, a shape or a fractal's maps, with the candidates an
automatic fit compares.
"""
from __future__ import annotations

import numpy as np

from ..errors import IFSError
from ..core.geometry.crossings import is_curve
from ..core.geometry.ifs import IFS
from .plan import Plan, discover
from ..core.targets.placement import best_fit_line, check_jitter, place
from ..core.targets.target import Target, foreground_points

__all__ = ["initialize", "best_fit_line", "foreground_points", "is_curve"]


def initialize(pattern: IFS | str, target: Target, jitter: float = 0.0, seed: int | None = None, *,
               maps: int | None = None, depth: int | None = None) -> IFS | Plan:
    """A start for fitting ``target``: a pattern's points placed on the target, or an automatic start.

    Parameters
    ----------
    pattern : IFS or "auto"
        The pattern, placed by `ifslib.core.targets.placement.place`: a curve (see `is_curve`, as for
        the Koch curve) gets its points evenly spaced along the target's best-fit line, the paper's
        advice; any other pattern (grids, the carpet, rosettes) is stretched onto the target's
        bounding box. ``"auto"`` reads the target instead
        (`ifslib.automatic.plan.discover`): curve, shape or fractal, the number of maps, maps whose
        copies cover the target; `ifslib.fit` fits the plan by comparing its candidates.
    target : Target
    jitter : float
        Half-width of the uniform jitter added to every free coordinate (plane units, from 0 to 1).
    seed : int, optional
        Seed of the jitter (and of the automatic start's k-means), from 0 to ``ifslib.errors.MAX_SEED``.
    maps, depth : int, optional
        ``"auto"`` only: fix the number of maps or the depth instead of choosing among candidates
        (`ifslib.automatic.auto.choices`).

    Returns
    -------
    IFS or Plan
        The placed pattern; for ``"auto"`` a `ifslib.automatic.plan.Plan`, whose ``start`` is the
        IFS chosen without fitting (jittered when ``jitter`` is set).
    """
    check_jitter(jitter, seed)
    if isinstance(pattern, str):
        if pattern != "auto":
            raise IFSError(f"initialize takes an IFS or 'auto', got {pattern!r} (patterns by name: ifslib.patterns.by_name)")
        plan = discover(target, maps, depth, seed=seed or 0)
        return plan.with_start(plan.start.jittered(jitter, np.random.default_rng(seed)))
    if maps is not None or depth is not None:
        raise IFSError("maps and depth are for initialize('auto', ...); set a pattern's depth on the pattern")
    return place(pattern, target, jitter, seed)
