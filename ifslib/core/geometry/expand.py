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
    """The attractor's point leaves within ``tolerance`` (plane units): the certified cut (`attractor_leaves`) or,
    with ``samples``, sampled leaves of it (`sample_attractor`)."""
    ifs.validate()
    points = ifs.points.to(device=device, dtype=dtype or ifs.points.dtype)
    maps = rule_maps(points, ifs.rules, gradient)
    if samples is not None:
        return sample_attractor(maps, tolerance, samples, rules=ifs.rules, window=window)
    return attractor_leaves(maps, tolerance, window, max_leaves, ifs.rules)


__all__ = ["expand_attractor"]
