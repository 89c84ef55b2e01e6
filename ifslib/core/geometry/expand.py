"""An IFS's attractor as point leaves: the certified cut or sampled leaves of it, the one entry point for both."""
from __future__ import annotations

import torch

from .attractor import AttractorLeaves, attractor_leaves
from .ifs import IFS
from .rules import rule_maps
from .sampled import sample_attractor


def expand_attractor(ifs: IFS, tolerance: float, window: tuple[float, float, float, float] | None = None, *,
                     max_leaves: int | None = None, device: torch.device | str = "cpu",
                     dtype: torch.dtype | None = None, gradient: str = "exact",
                     samples: int | None = None) -> AttractorLeaves:
    """The attractor's point leaves of an IFS, differentiable through `ifslib.core.geometry.attractor.leaf_points`.

    The certified cut (`ifslib.core.geometry.attractor.attractor_leaves`) or, with ``samples``, sampled
    leaves of it (`ifslib.core.geometry.sampled.sample_attractor`).

    Parameters
    ----------
    ifs : IFS
        Its rules must contract (largest singular value < 1); its primitives play no part.
    tolerance : float
        ``ε`` in plane units.
    window : (x0, y0, x1, y1), optional
        The box whose points matter (see `ifslib.core.geometry.attractor.attractor_leaves`).
    max_leaves : int, optional
        Leaf budget; `ifslib.core.geometry.attractor.DEFAULT_MAX_LEAVES` when None.
    device, dtype, gradient
        As in `ifslib.core.geometry.leaves.expand`.
    samples : int, optional
        Draw this many leaves of the cut at random (confined to ``window`` when given) instead of
        the whole cut (then ``max_leaves`` plays no part).

    Returns
    -------
    AttractorLeaves
    """
    ifs.validate()
    points = ifs.points.to(device=device, dtype=dtype or ifs.points.dtype)
    maps = rule_maps(points, ifs.rules, gradient)
    if samples is not None:
        return sample_attractor(maps, tolerance, samples, rules=ifs.rules, window=window)
    return attractor_leaves(maps, tolerance, window, max_leaves, ifs.rules)


__all__ = ["expand_attractor"]
