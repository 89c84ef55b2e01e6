"""Self-similar copies: the maps of a fractal read from its image (the inverse IFS problem).

A fractal ``A`` drawn by ``k`` affine maps is the union of ``k`` shrunken copies of itself,
``A = T_1(A) ∪ ... ∪ T_k(A)``, and by the collage theorem (Barnsley) maps whose copies of the
target nearly rebuild the target have an attractor near it. `search` looks for such maps on the
target alone (no depth), then judges them by their attractor. Every setting named below is a
field of `SearchConfig` (`DEFAULT`: the tuned ones), read as ``fractal.DEFAULT.map_cost``.

1. **Copies that fit inside** (`candidates`: `copy_candidates`). For each linear part ``L`` of a
   grid (`linear_grid`: rotations, two singular values down to thin copies, reflections, about
   25k of them), the figure's pixels mapped by ``L`` are matched against the figure at every
   translation at once, by one FFT correlation (`torch.fft.rfft2`): a placement counts when at
   least ``inside`` of the copy's pixels land on the figure (grown by one pixel).
2. **Sets of copies** (starts of ``k`` maps, `covers`). `collage_sets`: the sets with the least
   collage distance, by greedy selection and swaps (a facility-location local search on each
   copy's distances, computed once); `beam_covers` and `greedy_covers`: sets that cover the
   figure with little overlap; `random_starts`: random maps, as Tu et al. start.
3. **The collage, refined** (`collage`: `refine`). All starts of ``k`` maps go through Adam
   together, on the collage distance in pixels: the copies' distance to the figure (``outside``)
   and each figure pixel's distance to the nearest copy (``cover``, through the maps' inverses:
   ``d(q, T_i(A)) <= s_i d(T_i^-1 q, A)``), read from the target's distance transform
   (`torch.nn.functional.grid_sample`); every map's singular values are kept in
   [``min_scale``, ``max_scale``] after each step.
4. **Judged by the attractor** (`judge`, `phases.try_maps`). A small collage distance does not
   make a close attractor (a map of scale 0.8 multiplies a collage error by five), so the
   ``shortlist`` starts with the least collage have their attractors drawn (chaos game at
   ``refine_size``), the ``keep`` closest go on at ``refine_size``, and the maps whose attractor
   is closest are kept; `reorient` (`moves`, `phases.reorient_best`) turns maps the same way.
5. **Matched to uncovered regions** (`region_swap`, `phases.regions`), when no number of maps
   reoriented draws an attractor of IoU ``swap_below``, for each of them, the best scoring first:
   for each map, the figure pixels the other maps' copies leave uncovered are matched by the
   figure's copy with the same mean and covariance (`regions`), which places a thin copy as well
   as a round one; one or two maps are replaced by such copies, ranked by a short chaos game,
   refined, and kept when the attractor's IoU rises, round after round.
6. **Grown** (`region_grow`, `phases.grow`), when still none does: the best scoring number of
   maps gives the next its maps and one more, matched to the region all their copies leave
   uncovered, when that attractor beats the next's own (a search that keeps the right maps but
   one too few).
7. **Swapped** (`swap`, `phases.swaps`), when still no number of maps reoriented draws an
   attractor of IoU ``swap_below``: the collage places the large copies well and often misses a
   thin or small one, so each map in turn is replaced by each copy of a pool, every such IFS
   drawn at once by a short chaos game (`ifslib.automatic.fractal.judge.chaos_occupancy`), and the best
   replacements refined and kept when the attractor's IoU rises.
8. **Run again** (`driver.search`), when after all that no attractor reaches ``swap_below``: the
   whole search from the next seed (other random starts and pixel samples send the moves down
   other paths), and the search whose chosen maps score least (below) is kept.

**How many maps** (minimum description length, `board` and `driver`): for ``k`` = 2, 3, ... the
kept maps' attractor is drawn (chaos game, ``judge_points`` points) at ``judge_size`` (or the
target's size when smaller) and scored by its IoU with the target, the measure a fit is judged
by; the number chosen is the ``k`` with the least ``1 - IoU + map_cost * k`` (a map must raise
the attractor's IoU by ``map_cost`` to be kept), among the ``reorient`` numbers of maps
reoriented. Which numbers are tried and reoriented goes by the attractor's symmetric Chamfer
distance at ``refine_size`` plus ``chamfer_cost`` pixels a map, a score that forgives a copy
turned the wrong way (reorienting mends it) where the IoU does not: since a distance is never
negative, ``k`` maps cannot score below ``chamfer_cost * k``, and once some number scores that
little, ``k`` is not tried. Nor are more than ``give_up_maps`` maps tried when no attractor came
within ``give_up_px`` pixels (the figure is not a fractal of a few maps). `SearchResult.table`
lists every ``k`` tried, and the automatic pattern records it.
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
