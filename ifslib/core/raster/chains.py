"""The chains of the chaos game: one generator that every chaos game of the library walks."""
from __future__ import annotations

from typing import Iterator, NamedTuple

import numpy as np

from ...errors import IFSError, check_int

# Map choices drawn at once: more, fewer calls to the generator; fewer, less memory (about 60 bytes each).
_PICKS_PER_DRAW = 1 << 18

# Above this many maps a binary search beats a pass per map over the cumulative probabilities.
_SEARCH_ABOVE = 32


class Step(NamedTuple):
    """One recorded step of every chain: its points ``x``, ``y`` ``(chains,)`` float64 and ``pick``
    ``(chains,)``, the map that sent each chain's previous point there."""

    x: np.ndarray
    y: np.ndarray
    pick: np.ndarray


def pick_maps(uniform: np.ndarray, cuts: np.ndarray) -> np.ndarray:
    """The map each uniform chooses: how many of the cumulative probabilities ``cuts`` it reaches.

    The inverse of the cumulative distribution, as `numpy.random.Generator.choice` draws it, so that a
    chain fed the same uniforms picks the same maps.
    """
    if len(cuts) > _SEARCH_ABOVE:
        return np.searchsorted(cuts, uniform, side="right")
    pick = np.zeros(uniform.shape, np.uint8)  # searchsorted's count, a pass per map: five times faster for four maps
    for cut in cuts:
        pick += uniform >= cut
    return pick


def walk(maps: np.ndarray, probabilities: np.ndarray, starts: np.ndarray, burn: int, steps: int,
         rng: np.random.Generator) -> Iterator[Step]:
    """Walk chains of the chaos game: ``burn`` steps unrecorded, then yield each of ``steps`` steps.

    Parameters
    ----------
    maps : numpy.ndarray
        ``(m, 3, 3)`` or ``(m, 2, 3)`` float64 maps.
    probabilities : numpy.ndarray
        ``(m,)`` each map's chance at every step, summing to 1.
    starts : numpy.ndarray
        ``(chains, 2)`` where the chains start.
    burn, steps : int
        Steps taken before the points count, and steps recorded.
    rng : numpy.random.Generator
        Draws ``chains`` uniforms a step, in blocks: the stream is that of one
        ``rng.random(chains)`` a step, so the same seed walks the same chains however they are read.

    Yields
    ------
    Step
        The chains' points after each recorded step (fresh arrays: a caller may keep them).
    """
    check_int(burn, "burn-in steps", 0)
    check_int(steps, "steps", 0)
    starts = np.asarray(starts, np.float64)
    if starts.ndim != 2 or starts.shape[1] != 2 or not len(starts):
        raise IFSError(f"starts must be (chains, 2) points, got shape {starts.shape}")
    coef = np.ascontiguousarray(np.asarray(maps, np.float64)[:, :2, :].reshape(-1, 6).T)  # (6, m): a, b, tx, c, d, ty
    cuts = np.cumsum(probabilities)[:-1]
    chains = len(starts)
    x, y = starts[:, 0].copy(), starts[:, 1].copy()
    rows = max(1, _PICKS_PER_DRAW // chains)
    for first in range(0, burn + steps, rows):
        picks = pick_maps(rng.random((min(rows, burn + steps - first), chains)), cuts)
        block = np.take(coef, picks, axis=1)
        for k, (a, b, tx, c, d, ty) in enumerate(block.transpose(1, 0, 2), first):
            x, y = a * x + b * y + tx, c * x + d * y + ty
            if k >= burn:
                yield Step(x, y, picks[k - first])


def fixed_points(maps: np.ndarray) -> np.ndarray:
    """Each map's fixed point ``(m, 2)``: a point of the attractor, where a chain may start."""
    maps = np.asarray(maps, np.float64)
    return np.stack([np.linalg.solve(np.eye(2) - a, t) for a, t in zip(maps[:, :2, :2], maps[:, :2, 2])])


__all__ = ["Step", "fixed_points", "pick_maps", "walk"]
