"""How the search scores a number of maps: every score and the lower bound each pruning relies on, in one place.

Change a score here and its bound beside it: `board` and `phases` read only these functions (the
thresholds they compare against, ``swap_below``, ``give_up_px``, are `SearchConfig` fields).
"""
from __future__ import annotations

from .config import SearchConfig


def choice_score(iou: float, k: int, config: SearchConfig) -> float:
    """What chooses the number of maps (minimum description length): ``1 - iou + map_cost * k``, the least wins."""
    return 1 - iou + config.map_cost * k


def least_choice_score(k: int, config: SearchConfig) -> float:
    """The least `choice_score` ``k`` maps can reach (an attractor of IoU 1): a move that cannot beat the best
    row's score with it is not tried."""
    return choice_score(1.0, k, config)


def trial_score(chamfer_px: float, k: int, config: SearchConfig) -> float:
    """What decides which numbers of maps are tried and reoriented: the attractor's Chamfer distance (pixels) plus
    ``chamfer_cost`` a map, which forgives a copy turned the wrong way (reorienting mends it) where the IoU does not."""
    return chamfer_px + config.chamfer_cost * k


def least_trial_score(k: int, config: SearchConfig) -> float:
    """The least `trial_score` ``k`` maps can reach (a Chamfer distance of 0): once a row scores no more, ``k`` maps
    are not tried."""
    return trial_score(0.0, k, config)
