"""Initial control points from a target (paper, "Initial Conditions").

Segment patterns start with their points evenly spaced, in index order, along the best-fit line
of the target's foreground (its principal axis), between the extreme projections of the
foreground pixels; square and grid patterns are stretched onto the foreground's bounding box.
Optional seeded jitter ``U(-jitter, jitter)`` is added to every coordinate.
"""
from __future__ import annotations

import numpy as np
import torch

from ..geometry.ifs import IFS
from ..raster.nearest import pixel_centres
from .targets import Target


def foreground_points(target: Target) -> np.ndarray:
    """Plane coordinates ``(k, 2)`` of the target's foreground pixel centres."""
    x, y = pixel_centres(target.size)
    flat = torch.from_numpy(target.mask.reshape(-1))
    return torch.stack([x[flat], y[flat]], 1).numpy()


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


def is_curve(ifs: IFS) -> bool:
    """Whether the rules replace one segment by a chain of segments, as the Koch curve's do.

    True when every rule is a ``segment`` rule with the same source ``(a, b)`` and the rules' targets,
    in order, form a chain from ``a`` to ``b``.
    """
    rules = ifs.rules
    if not rules or any(r.kind != "segment" or r.source != rules[0].source for r in rules):
        return False
    chain = [rules[0].target[0]] + [r.target[1] for r in rules]
    joined = all(rules[i].target[1] == rules[i + 1].target[0] for i in range(len(rules) - 1))
    return joined and chain[0] == rules[0].source[0] and chain[-1] == rules[0].source[1]


def initialize(ifs: IFS, target: Target, jitter: float = 0.0, seed: int | None = None) -> IFS:
    """A copy of ``ifs`` with initial points fitted to the target.

    Parameters
    ----------
    ifs : IFS
        The pattern. A curve (see `is_curve`, as for the Koch curve) gets
        its points evenly spaced along the target's best-fit line, the paper's advice; any other
        pattern (grids, the carpet, rosettes) is stretched onto the target's bounding box.
    target : Target
    jitter : float
        Half-width of the uniform jitter added to every coordinate (plane units).
    seed : int, optional
        Seed of the jitter.

    Returns
    -------
    IFS
    """
    n = ifs.n_points
    if not is_curve(ifs):
        fg = foreground_points(target)
        lo, hi = fg.min(0), fg.max(0)
        pts = ifs.points.detach().double().numpy()
        plo, phi = pts.min(0), pts.max(0)
        new = lo + (pts - plo) / np.where(phi > plo, phi - plo, 1) * (hi - lo)
    else:
        centre, direction, lo, hi = best_fit_line(target)
        new = centre + np.linspace(lo, hi, n)[:, None] * direction
    if jitter:
        rng = np.random.default_rng(seed)
        new = new + rng.uniform(-jitter, jitter, size=new.shape)
    return ifs.clone(torch.as_tensor(new, dtype=ifs.points.dtype))
