"""Self-similar copies: the maps of a fractal read from its image (the inverse IFS problem).

`search` looks for maps whose copies of the target nearly rebuild it (the collage theorem), then judges them by
their attractor; every setting is a field of `SearchConfig` (`DEFAULT`). The steps: docs/guide/design.md.
"""
from . import regions
from .candidates import copy_candidates, footprints, largest, linear_grid, plane_maps, random_starts
from ...core.scoring.collage import collage_terms, copy_terms
from .collage import refine
from .config import DEFAULT, SearchConfig
from .covers import beam_covers, collage_sets, greedy_covers
from .board import Row
from .driver import SearchResult, check_maps, search
from .judge import as_ifs, attractor_chamfer, attractor_iou, occupancy_iou
from .moves import region_grow, region_swap, reorient, swap, turns
from ..moments import sqrtm_psd
from .regions import rotation

__all__ = ["search", "SearchResult", "Row", "SearchConfig", "DEFAULT", "check_maps", "attractor_iou", "attractor_chamfer",
           "copy_candidates", "linear_grid", "footprints", "collage_sets", "beam_covers", "greedy_covers", "refine",
           "reorient", "swap", "region_swap", "region_grow", "as_ifs", "plane_maps", "largest", "sqrtm_psd",
           "rotation", "random_starts", "copy_terms", "collage_terms", "occupancy_iou", "turns", "regions"]
