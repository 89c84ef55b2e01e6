"""Initial control points from a target (paper, "Initial Conditions").

Segment patterns start with their points evenly spaced, in index order, along the best-fit line
of the target's foreground (its principal axis), between the extreme projections of the
foreground pixels; square and grid patterns are stretched onto the foreground's bounding box.
Optional seeded jitter ``U(-jitter, jitter)`` is added to every coordinate. The pattern
``"auto"`` reads one from the image itself (`ifslib.discovery.plan.discover`): a curve, a shape or a
fractal's maps, with the candidates an automatic fit compares.
"""
from __future__ import annotations

import numpy as np

from ..errors import MAX_SEED, IFSError, check_int
from ..geometry.crossings import is_curve
from ..geometry.ifs import IFS
from .plan import Plan, discover
from ..targets.target import Target, foreground_points

__all__ = ["initialize", "best_fit_line", "foreground_points", "is_curve"]


def best_fit_line(target: Target) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The principal axis of the foreground.

    Returns
    -------
    centre : numpy.ndarray
        ``(2,)`` mean of the foreground.
    direction : numpy.ndarray
        ``(2,)`` unit vector of largest variance (sign chosen so that it points right, or up).
    lo, hi : float
        Extreme projections of the foreground on the axis, relative to ``centre``.
    """
    pts = foreground_points(target)
    centre = pts.mean(0)
    _, _, vt = np.linalg.svd(pts - centre, full_matrices=False)
    direction = vt[0]
    if direction[0] < -1e-12 or (abs(direction[0]) <= 1e-12 and direction[1] < 0):
        direction = -direction
    proj = (pts - centre) @ direction
    return centre, direction, float(proj.min()), float(proj.max())


def initialize(pattern: IFS | str, target: Target, jitter: float = 0.0, seed: int | None = None, *,
               maps: int | None = None, depth: int | None = None) -> IFS | Plan:
    """A start for fitting ``target``: a pattern's points placed on the target, or an automatic start.

    Parameters
    ----------
    pattern : IFS or "auto"
        The pattern. A curve (see `is_curve`, as for the Koch curve) gets its points evenly spaced
        along the target's best-fit line, the paper's advice; any other pattern (grids, the carpet,
        rosettes) is stretched onto the target's bounding box. ``"auto"`` reads the target instead
        (`ifslib.discovery.plan.discover`): curve, shape or fractal, the number of maps, maps whose
        copies cover the target; `ifslib.fit` fits the plan by comparing its candidates.
    target : Target
    jitter : float
        Half-width of the uniform jitter added to every free coordinate (plane units, from 0 to 1).
    seed : int, optional
        Seed of the jitter (and of the automatic start's k-means), from 0 to ``ifslib.errors.MAX_SEED``.
    maps, depth : int, optional
        ``"auto"`` only: fix the number of maps or the depth instead of choosing among candidates
        (`ifslib.discovery.auto.choices`).

    Returns
    -------
    IFS or Plan
        The placed pattern; for ``"auto"`` a `ifslib.discovery.plan.Plan`, whose ``start`` is the
        IFS chosen without fitting (jittered when ``jitter`` is set).
    """
    if isinstance(jitter, bool) or not isinstance(jitter, (int, float)) or not 0 <= jitter <= 1:
        raise IFSError(f"jitter must be a number from 0 to 1 (plane units: the frame is 1 wide), got {jitter!r}")
    if seed is not None:
        check_int(seed, "seed", 0, maximum=MAX_SEED)
    if isinstance(pattern, str):
        if pattern != "auto":
            raise IFSError(f"initialize takes an IFS or 'auto', got {pattern!r} (patterns by name: ifslib.patterns.by_name)")
        plan = discover(target, maps, depth, seed=seed or 0)
        return plan.with_start(plan.start.jittered(jitter, np.random.default_rng(seed)))
    if maps is not None or depth is not None:
        raise IFSError("maps and depth are for initialize('auto', ...); set a pattern's depth on the pattern")
    return pattern.clone(_placed(pattern, target)).jittered(jitter, np.random.default_rng(seed))


def _placed(ifs: IFS, target: Target) -> np.ndarray:
    """The pattern's points on the target: along its best-fit line (curves) or on its bounding box."""
    n = ifs.n_points
    if not is_curve(ifs):
        fg = foreground_points(target)
        lo, hi = fg.min(0), fg.max(0)
        pts = ifs.points.detach().double().numpy()
        plo, phi = pts.min(0), pts.max(0)
        return lo + (pts - plo) / np.where(phi > plo, phi - plo, 1) * (hi - lo)
    centre, direction, lo, hi = best_fit_line(target)
    return centre + np.linspace(lo, hi, n)[:, None] * direction
