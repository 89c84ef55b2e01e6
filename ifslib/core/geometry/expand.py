"""An IFS's attractor as point leaves: the certified cut of its word tree (`ifslib.core.geometry.attractor`)
or sampled leaves of it (`ifslib.core.geometry.sampled`), the one entry point for both.
"""
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
    """The attractor's point leaves of an IFS within ``tolerance`` (plane units): the certified cut
    (`attractor_leaves`, up to ``max_leaves``) or, with ``samples``, that many sampled leaves of it
    (`sample_attractor`); ``window``, ``device``, ``dtype`` and ``gradient`` as theirs and `expand`'s."""
    ifs.validate()
    points = ifs.points.to(device=device, dtype=dtype or ifs.points.dtype)
    maps = rule_maps(points, ifs.rules, gradient)
    if samples is not None:
        return sample_attractor(maps, tolerance, samples, rules=ifs.rules, window=window)
    return attractor_leaves(maps, tolerance, window, max_leaves, ifs.rules)


__all__ = ["expand_attractor"]
