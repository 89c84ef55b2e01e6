"""Initial control points from a target (paper, "Initial Conditions").

Segment patterns start with their points evenly spaced, in index order, along the best-fit line
of the target's foreground (its principal axis), between the extreme projections of the
foreground pixels; square and grid patterns are stretched onto the foreground's bounding box.
Optional seeded jitter ``U(-jitter, jitter)`` is added to every coordinate. The pattern
``"auto"`` builds one from the image itself (`ifslib.discovery.auto`): any curve or shape.
"""
from __future__ import annotations

import numpy as np
import torch

from ..errors import MAX_SEED, IFSError, check_int
from ..geometry.crossings import is_curve
from ..geometry.ifs import IFS
from .auto import auto_start
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
               maps: int | None = None, depth: int | None = None) -> IFS:
    """A start for fitting ``target``: a pattern's points placed on the target, or an automatic start.

    Parameters
    ----------
    pattern : IFS or "auto"
        The pattern. A curve (see `is_curve`, as for the Koch curve) gets its points evenly spaced
        along the target's best-fit line, the paper's advice; any other pattern (grids, the carpet,
        rosettes) is stretched onto the target's bounding box. ``"auto"`` reads the target instead
        (`ifslib.discovery.auto.auto_start`): curve or shape, the number of maps, maps whose copies
        cover the target; fit it with the ``auto`` strategy to compare several numbers of maps.
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
    IFS
    """
    if isinstance(jitter, bool) or not isinstance(jitter, (int, float)) or not 0 <= jitter <= 1:
        raise IFSError(f"jitter must be a number from 0 to 1 (plane units: the frame is 1 wide), got {jitter!r}")
    if seed is not None:
        check_int(seed, "seed", 0, maximum=MAX_SEED)
    if isinstance(pattern, str):
        if pattern != "auto":
            raise IFSError(f"initialize takes an IFS or 'auto', got {pattern!r} (patterns by name: ifslib.patterns.by_name)")
        base = auto_start(target, maps, depth, seed=seed or 0)
        new = base.points.detach().double().numpy()
    else:
        if maps is not None or depth is not None:
            raise IFSError("maps and depth are for initialize('auto', ...); set a pattern's depth on the pattern")
        base, new = pattern, _placed(pattern, target)
    if jitter:
        rng = np.random.default_rng(seed)
        free = [i for i in range(base.n_points) if i not in base.fixed]
        new[free] = new[free] + rng.uniform(-jitter, jitter, size=(len(free), 2))
    return base.clone(torch.as_tensor(new, dtype=base.points.dtype))


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
