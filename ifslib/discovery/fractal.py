"""Self-similar copies: the maps of a fractal read from its image (the inverse IFS problem).

A fractal ``A`` drawn by ``k`` affine maps is the union of ``k`` shrunken copies of itself,
``A = T_1(A) ∪ ... ∪ T_k(A)``, and by the collage theorem (Barnsley) maps whose copies of the
target nearly rebuild the target have an attractor near it. `search` looks for such maps on the
target alone (no depth), then judges them by their attractor:

1. **Copies that fit inside** (`copy_candidates`). For each linear part ``L`` of a grid
   (`linear_grid`: rotations, two singular values down to thin copies, reflections, about 25k of
   them), the figure's pixels mapped by ``L`` are matched against the figure at every translation
   at once, by one FFT correlation (`torch.fft.rfft2`): a placement counts when at least `INSIDE`
   of the copy's pixels land on the figure (grown by one pixel).
2. **Sets of copies** (starts of ``k`` maps). `collage_sets`: the sets with the least collage
   distance, by greedy selection and swaps (a facility-location local search on each copy's
   distances, computed once); `beam_covers` and `greedy_covers`: sets that cover the figure with
   little overlap; `random_starts`: random maps, as Tu et al. start.
3. **The collage, refined** (`refine`). All starts of ``k`` maps go through Adam together, on
   the collage distance in pixels: the copies' distance to the figure (``outside``) and each
   figure pixel's distance to the nearest copy (``cover``, through the maps' inverses: ``d(q,
   T_i(A)) <= s_i d(T_i^-1 q, A)``), read from the target's distance transform
   (`torch.nn.functional.grid_sample`); every map's singular values are kept in
   [`MIN_SCALE`, `MAX_SCALE`] after each step.
4. **Judged by the attractor.** A small collage distance does not make a close attractor (a map
   of scale 0.8 multiplies a collage error by five), so the `SHORTLIST` starts with the least
   collage have their attractors drawn (chaos game at `REFINE_SIZE`), the `KEEP` closest go on at
   `REFINE_SIZE`, and the maps whose attractor is closest are kept; `reorient` turns maps the
   same way.
5. **Matched to uncovered regions** (`region_swap`), when no number of maps reoriented draws an
   attractor of IoU `SWAP_BELOW`, for each of them, the best scoring first: for each map, the
   figure pixels the other maps' copies leave uncovered are matched by the figure's copy with the
   same mean and covariance (`ifslib.discovery.regions`), which places a thin copy as well as a
   round one; one or two maps are replaced by such copies, ranked by a short chaos game, refined,
   and kept when the attractor's IoU rises, round after round.
6. **Grown** (`region_grow`), when still none does: the best scoring number of maps gives the next
   its maps and one more, matched to the region all their copies leave uncovered, when that
   attractor beats the next's own (a search that keeps the right maps but one too few).
7. **Swapped** (`swap`), when still no number of maps reoriented draws an attractor of IoU `SWAP_BELOW`:
   the collage places the large copies well and often misses a thin or small one, so each map in
   turn is replaced by each copy of a pool, every such IFS drawn at once by a short chaos game
   (`ifslib.raster.chaos.chaos_occupancy`), and the best replacements refined and kept when the
   attractor's IoU rises.
8. **Run again**, when after all that no attractor reaches `SWAP_BELOW`: the whole search from the
   next seed (other random starts and pixel samples send the moves down other paths), and the
   search whose chosen maps score least (below) is kept.

**How many maps** (minimum description length): for ``k`` = 2, 3, ... the kept maps' attractor
is drawn (chaos game, `JUDGE_POINTS` points) at `JUDGE_SIZE` (or the target's size when smaller)
and scored by its IoU with the target, the measure a fit is judged by; the number chosen is the
``k`` with the least ``1 - IoU + MAP_COST * k`` (a map must raise the attractor's IoU by
`MAP_COST` to be kept), among the `REORIENT` numbers of maps reoriented. Which numbers are tried and
reoriented goes by the attractor's symmetric Chamfer distance at `REFINE_SIZE` plus `CHAMFER_COST`
pixels a map, a score that forgives a copy turned the wrong way (reorienting mends it) where the
IoU does not: since a distance is never negative, ``k`` maps cannot score below ``CHAMFER_COST * k``,
and once some number scores that little, ``k`` is not tried. Nor are more than `GIVE_UP_MAPS` maps
tried when no attractor came within `GIVE_UP_PX` pixels (the figure is not a fractal of a few
maps). `SearchResult.table` lists every ``k`` tried, and the automatic pattern records it.
"""
from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass, field

import numpy as np
import torch
from scipy import ndimage

from ..errors import IFSError, check_int
from ..geometry import patterns
from ..geometry.attractor import ATTRACTOR
from ..geometry.ifs import IFS
from tqdm.auto import tqdm

from ..progress import draw_bars, note
from ..raster.chaos import chaos_occupancy
from ..raster.render import figure_mask
from ..scoring.metrics import chamfer, iou
from .regions import region_maps, rotation, sqrtm_psd, uncovered_maps
from ..targets.target import Target, foreground_points, resize_target

#: The numbers of maps `search` compares when none is given ...
FRACTAL_MAPS = tuple(range(2, 9))
#: ... and the most it takes when one is.
MAX_MAPS = 16
#: The copies are matched at this size, and refined at it ...
SEARCH_SIZE = 64
#: ... then at this one, where the numbers of maps are compared.
REFINE_SIZE = 128
#: Every map's singular values stay in this range (a map of scale 0.9 or more makes a blob; 0.02 is flat).
MIN_SCALE, MAX_SCALE = 0.02, 0.9
#: A placement of a copy counts when this share of its pixels lies on the figure grown by one pixel.
INSIDE = 0.9
#: The candidate copies of each scale that cover most are kept, this many of them (so that small copies are not
#: crowded out by near-twins of large ones).
PER_SCALE = 800
#: Greedy covers start from each of this many of the largest copies ...
FIRSTS = 16
#: ... and the beam search for covers keeps this many sets of copies at each size, and charges a pixel covered twice this much ...
BEAM, OVERLAP = 32, 0.5
#: ... beside this many random starts for each number of maps ...
RANDOM_STARTS = 16
#: ... and the sets of `collage_sets`, from this many first copies.
RESTARTS = 16
#: Adam steps of the collage at `SEARCH_SIZE` and at `REFINE_SIZE`, and how many starts go on to the latter.
SEARCH_STEPS, REFINE_STEPS, KEEP = 150, 150, 4
#: The starts with the least collage distance whose attractors are drawn to choose the `KEEP` (chaos game, `SCREEN_POINTS` points).
SHORTLIST, SCREEN_POINTS = 16, 50_000
#: `reorient` turns each map by this many rotations (and as many reflections) of the figure's ellipse ...
TURNS = 12
#: ... and refines the variants whose collage starts best, this many of them.
SCREEN = 12
#: The numbers of maps tried, and the `REORIENT` of them whose best start is reoriented before the final comparison,
#: are chosen by the attractor's Chamfer distance at `REFINE_SIZE` plus `CHAMFER_COST` pixels a map.
REORIENT, CHAMFER_COST = 3, 0.1
#: The numbers of maps are compared by their attractors' IoU at this size (or the target's, when smaller),
#: drawn with this many chaos-game points: a quarter of two million, for an IoU within 0.002 of theirs ...
JUDGE_SIZE, JUDGE_POINTS = 256, 500_000
#: ... and a map costs this much IoU: lower keeps maps that add slivers, higher drops true small maps (the choice
#: against a Chamfer cost per map is measured in docs/results/fractals.md).
MAP_COST = 0.04
#: More than `GIVE_UP_MAPS` maps are not tried when no attractor of that many maps or fewer came within `GIVE_UP_PX`
#: pixels: not a fractal of a few maps, so a shape stops paying for the search (49 of the benchmark's 50 fractals come
#: within it by 4 maps, the paper's flower does not: docs/results/fractals.md).
GIVE_UP_MAPS, GIVE_UP_PX = 4, 2.5
#: When no reoriented number of maps draws an attractor of IoU `SWAP_BELOW` or more, `swap` replaces one map at a
#: time by a candidate copy, `SWAP_ROUNDS` rounds in all, each for the reoriented number of maps that scores best:
#: every replacement by the `SWAP_PER_SHAPE` largest copies of each scale and ratio of singular values is ranked by a
#: short chaos game at `SEARCH_SIZE` (`chaos_occupancy`), and the `SWAP_TOP` best are refined and judged by their
#: attractors.
#: (`SWAP_BELOW` is the IoU a fractal counts as recovered at: a higher bar makes searches that already recover pay
#: for moves that change nothing, docs/results/fractals.md.)
SWAP_BELOW, SWAP_ROUNDS, SWAP_PER_SHAPE, SWAP_TOP = 0.85, 8, 100, 8
#: Before `swap`, while no reoriented number of maps draws an attractor of IoU `SWAP_BELOW`, each has a map, or two,
#: replaced by copies matched to the figure's uncovered regions (`region_swap`), at most `REGION_ROUNDS` rounds, each
#: refining and judging the `REGION_TOP` best replacements.
REGION_ROUNDS, REGION_TOP = 4, 8
#: Then, while still none does, the best scoring number of maps gives the next its maps and one more, matched to the
#: region they all leave uncovered (`region_grow`), at most `GROW_ROUNDS` times.
GROW_ROUNDS = 2
#: When, after all that, still no number of maps draws an attractor of IoU `SWAP_BELOW`, the search runs again from the
#: next seed, at most this many times: other random starts send the moves down other paths, at the cost of a whole
#: search each (docs/results/fractals.md).
AGAIN = 1
#: At most this many figure pixels are used for the collage distance at each size.
COLLAGE_POINTS = (600, 2000)
#: The chaos game's points when the attractors of each number of maps are compared.
COMPARE_POINTS = 200_000


def linear_grid(turns: int = 36, phases: int = 8, scales=(0.25, 0.35, 0.45, 0.55, 0.65, 0.75, 0.85),
                ratios=(0.05, 0.1, 0.2, 0.4, 0.6, 0.8, 1.0)) -> np.ndarray:
    """Linear parts ``R(theta) diag(s, ±r s) R(phi)`` to try: ``(G, 2, 2)``.

    ``theta`` takes ``turns`` angles of the whole turn, ``phi`` ``phases`` angles of the half turn
    (one when ``r = 1``: a similarity has no second angle), ``s`` the ``scales``, ``r`` the
    ``ratios`` of the smaller singular value to the larger, and both signs (a reflection or not).
    """
    out = []
    for s in scales:
        for r in ratios:
            for phi in ([0.0] if r == 1.0 else np.arange(phases) * math.pi / phases):
                for theta in np.arange(turns) * 2 * math.pi / turns:
                    for sign in (1.0, -1.0):
                        out.append(rotation(theta) @ np.diag([s, sign * r * s]) @ rotation(phi))
    return np.array(out)


def _pixels(mask: np.ndarray) -> np.ndarray:
    """Figure pixels as ``(x, y) = (col, -row)``: pixel units, y up like the plane."""
    rows, cols = np.nonzero(mask)
    return np.stack([cols, -rows], 1).astype(np.float64)


def _centred_pixels(mask: np.ndarray) -> torch.Tensor:
    """`_pixels` less their centroid (the origin a linear part of `linear_grid` turns about)."""
    pixels = _pixels(mask)
    return torch.as_tensor(pixels - pixels.mean(0))


def copy_candidates(mask: np.ndarray, grid: np.ndarray, inside: float = INSIDE, per_map: int = 2,
                    chunk: int = 512) -> np.ndarray:
    """Placements of the figure's copies ``L(A)`` that lie inside the figure, for every ``L`` of ``grid``.

    Parameters
    ----------
    mask : numpy.ndarray
        ``(n, n)`` bool, the figure.
    grid : numpy.ndarray
        ``(G, 2, 2)`` linear parts in pixel units (``x`` right, ``y`` up), from `linear_grid`.
    inside : float
        Share of a copy's pixels that must land on the figure grown by one pixel.
    per_map : int
        Placements kept for each ``L`` (those covering most).

    Returns
    -------
    numpy.ndarray
        ``(C, 4)`` rows ``(pixels covered, index into grid, row, col)``, most pixels first; the
        copy's centroid (the image of the figure's centroid) sits at pixel ``(row, col)``.
    """
    n = mask.shape[0]
    size = 2 * n  # zero padding: a copy that leaves the frame loses the pixels outside
    u = _centred_pixels(mask)
    grown = torch.zeros(size, size)
    grown[:n, :n] = torch.as_tensor(ndimage.binary_dilation(mask), dtype=torch.float32)
    spectrum = torch.fft.rfft2(grown)
    rows = []
    for start in range(0, len(grid), chunk):
        linear = torch.as_tensor(grid[start:start + chunk])
        v = torch.einsum("gij,pj->gpi", linear, u)
        flat = (torch.round(-v[..., 1]).long() % size) * size + torch.round(v[..., 0]).long() % size
        copies = torch.zeros(len(linear), size * size).scatter_(1, flat, 1.0).view(-1, size, size)
        pixels = copies.sum((1, 2))
        # The correlation counts pixels, so it is an integer up to the FFT's rounding error, whose sign
        # depends on the CPU and the thread count (a one-pixel hit came out 0.99999994 or 1.0000001):
        # every decision below is taken on the rounded count, which is exact.
        hits = torch.fft.irfft2(torch.conj(torch.fft.rfft2(copies)) * spectrum, s=(size, size))[:, :n, :n]
        hits = torch.round(hits).to(torch.int64).reshape(len(linear), -1)
        enough = hits.double() >= inside * pixels.double()[:, None] - 0.5
        # the placements covering most, the first in reading order among equals (an exact key, no tie left to chance)
        key = torch.where(enough, hits, 0) * (n * n) + (n * n - 1 - torch.arange(n * n))
        top = key.topk(per_map, dim=1)
        for g in range(len(linear)):
            for value, index in zip(top.values[g].tolist(), top.indices[g].tolist()):
                index = n * n - 1 - value % (n * n)
                if value // (n * n) >= 1:
                    rows.append((value // (n * n), start + g, index // n, index % n))
    out = np.array(rows, dtype=np.int64).reshape(-1, 4)
    return out[np.argsort(-out[:, 0], kind="stable")]


def footprints(mask: np.ndarray, grid: np.ndarray, cands: np.ndarray, chunk: int = 2048) -> torch.Tensor:
    """``(C, n * n)`` float 0/1: the figure pixels each candidate copy covers (its pixels grown by one)."""
    n = mask.shape[0]
    u = _centred_pixels(mask)
    figure = torch.as_tensor(mask.reshape(-1))
    out = []
    for start in range(0, len(cands), chunk):
        c = torch.as_tensor(cands[start:start + chunk])
        v = torch.einsum("gij,pj->gpi", torch.as_tensor(grid[c[:, 1].numpy()]), u)
        col = torch.round(v[..., 0]).long() + c[:, 3, None]
        row = torch.round(-v[..., 1]).long() + c[:, 2, None]
        flat = torch.where((row >= 0) & (row < n) & (col >= 0) & (col < n), row * n + col, n * n)
        drawn = torch.zeros(len(c), n * n + 1).scatter_(1, flat, 1.0)[:, :-1].view(-1, 1, n, n)
        grown = torch.nn.functional.max_pool2d(drawn, 3, 1, 1).view(len(c), -1) > 0
        out.append((grown & figure).float())
    return torch.cat(out)


def greedy_covers(feet: torch.Tensor, firsts: int, most: int) -> list[list[int]]:
    """Greedy set covers: from each of the first ``firsts`` candidates, ``most - 1`` times the one covering most
    pixels not yet covered (one matrix product a step). The first ``k`` entries of each are a start of ``k`` maps."""
    covers = []
    for first in range(min(firsts, len(feet))):
        covered, chosen = feet[first].clone(), [first]
        for _ in range(most - 1):
            j = int(torch.argmax(feet @ (1 - covered)))
            chosen.append(j)
            covered = torch.maximum(covered, feet[j])
        covers.append(chosen)
    return covers


def beam_covers(feet: torch.Tensor, most: int, width: int = BEAM, overlap: float = OVERLAP) -> dict[int, list[list[int]]]:
    """Sets of candidate copies that cover the figure with little overlap, by beam search: ``{k: covers of k copies}``.

    A set of copies scores the figure pixels it covers minus ``overlap`` times those it covers
    twice or more (the copies of a fractal's maps barely overlap, where the copies of a wrong set
    crowd each other). The ``width`` largest copies start; each step adds to every kept set each
    candidate in turn and keeps the ``width`` best distinct sets.
    """
    sizes = feet.sum(1)
    beams = [[i] for i in range(min(width, len(feet)))]
    covered, total = feet[:len(beams)].clone(), sizes[:len(beams)].clone()
    out = {1: [list(b) for b in beams]}
    for k in range(2, most + 1):
        union = covered.sum(1)[:, None] + (1 - covered) @ feet.T            # (B, C)
        score = union - overlap * (total[:, None] + sizes[None] - union)
        for b, beam in enumerate(beams):
            score[b, beam] = -math.inf
        order = torch.argsort(score.reshape(-1), descending=True)
        kept, seen = [], set()
        for flat in order.tolist():
            b, c = divmod(flat, len(feet))
            key = tuple(sorted(beams[b] + [c]))
            if key in seen:
                continue
            seen.add(key)
            kept.append((b, c))
            if len(kept) == width:
                break
        beams = [beams[b] + [c] for b, c in kept]
        covered = torch.stack([torch.maximum(covered[b], feet[c]) for b, c in kept])
        total = torch.stack([total[b] + sizes[c] for b, c in kept])
        out[k] = [list(b) for b in beams]
    return out


def plane_maps(grid: np.ndarray, cands: np.ndarray, centroid: np.ndarray, n: int) -> np.ndarray:
    """``(C, 2, 3)`` maps ``[A | t]`` in plane units of the candidates (pixel-unit ``L``, centroid sent to pixel ``(row, col)``)."""
    linear = grid[cands[:, 1]]
    # pixel (x, y) = (col, -row) and plane P = p / n + o, with o = (0.5/n - 0.5, 0.5 - 0.5/n)
    o = np.array([0.5 / n - 0.5, 0.5 - 0.5 / n])
    shift = np.stack([cands[:, 3], -cands[:, 2]], 1) - linear @ centroid
    t = shift / n + o - linear @ o
    return np.concatenate([linear, t[:, :, None]], 2)


def random_starts(count: int, k: int, target: Target, rng: np.random.Generator) -> np.ndarray:
    """``(count, k, 2, 3)`` random maps: singular values in [0.25, 0.65], any rotation (reflected one time in three),
    each taking the figure's centroid onto a random figure pixel."""
    fg = foreground_points(target)
    angle = rng.uniform(-math.pi, math.pi, (count, k, 2))
    scale = rng.uniform(0.25, 0.65, (count, k, 2))
    scale[..., 1] *= np.where(rng.random((count, k)) < 1 / 3, -1.0, 1.0)
    rot = rotation(angle)  # (count, k, 2, 2, 2): [..., which, i, j]
    linear = rot[..., 0, :, :] * scale[..., None, :] @ rot[..., 1, :, :]
    t = fg[rng.integers(0, len(fg), (count, k))] - linear @ fg.mean(0)
    return np.concatenate([linear, t[..., None]], -1)


def _lookup(distance: torch.Tensor, points: torch.Tensor) -> torch.Tensor:
    """The target's distance (plane units) at ``points`` (..., 2), bilinear, plus the distance to the frame outside it."""
    n = distance.shape[-1]
    flat = points.reshape(1, 1, -1, 2)
    grid = torch.stack([flat[..., 0] * 2, -flat[..., 1] * 2], -1)
    inside = torch.nn.functional.grid_sample(distance.view(1, 1, n, n), grid, mode="bilinear", padding_mode="border",
                                             align_corners=False).view(points.shape[:-1])
    beyond = (points.abs() - (0.5 - 0.5 / n)).clamp(min=0)
    return inside + beyond.square().sum(-1).add(1e-30).sqrt()


def copy_terms(maps: torch.Tensor, points: torch.Tensor, distance: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Each copy's ``outside`` and ``cover`` distances (plane units), for maps ``(..., 2, 3)``: each ``(..., P)``.

    ``outside``: the copy ``T(p)`` of each figure pixel of ``points`` ``(P, 2)``, to the figure;
    ``cover``: each figure pixel ``q`` to the copy ``T(A)``, bounded by ``s d(T^-1 q, A)`` with ``s``
    the map's largest singular value (the module docstring).
    """
    a, t = maps[..., :2], maps[..., 2]
    copies = torch.einsum("...ij,pj->...pi", a, points) + t[..., None, :]
    outside = _lookup(distance, copies)
    det = a[..., 0, 0] * a[..., 1, 1] - a[..., 0, 1] * a[..., 1, 0]
    inverse = torch.stack([torch.stack([a[..., 1, 1], -a[..., 0, 1]], -1),
                           torch.stack([-a[..., 1, 0], a[..., 0, 0]], -1)], -2) / det[..., None, None]
    back = torch.einsum("...ij,...pj->...pi", inverse, points - t[..., None, :])
    scale = torch.linalg.matrix_norm(a, ord=2)
    return outside, _lookup(distance, back) * scale[..., None]


def collage_terms(maps: torch.Tensor, points: torch.Tensor, distance: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """Mean squared ``outside`` and ``cover`` distances (plane units) of a batch of IFSs: ``maps`` ``(S, k, 2, 3)``.

    ``outside`` is averaged over the copies of every map, ``cover`` takes each figure pixel's
    nearest copy (`copy_terms`). Each ``(S,)``.
    """
    outside, cover = copy_terms(maps, points, distance)
    return outside.square().mean((1, 2)), cover.min(1).values.square().mean(-1)


def collage_sets(maps: np.ndarray, target: Target, ks, restarts: int = RESTARTS, points: int = COLLAGE_POINTS[0],
                 sweeps: int = 4, seed: int = 0) -> dict[int, list[list[int]]]:
    """Sets of ``k`` of the candidate copies ``maps`` ``(C, 2, 3)`` with the least collage distance: ``{k: sets}``.

    Choosing ``k`` copies so that every figure pixel is near one of them, at the least cost of
    copies outside the figure, is a facility-location problem: each copy's ``outside`` and
    ``cover`` distances are computed once (`copy_terms`), then from each of ``restarts`` first
    copies (the best single copies and random ones) the copy that lowers the collage most is
    added until there are ``k`` (greedy), and each map in turn is swapped for the candidate that
    lowers it most, for up to ``sweeps`` sweeps (local search). Distinct sets, best first.
    """
    fg = foreground_points(target)
    rng = np.random.default_rng(seed)
    if len(fg) > points:
        fg = fg[rng.choice(len(fg), points, replace=False)]
    with torch.no_grad():
        outside, cover = copy_terms(torch.as_tensor(maps, dtype=torch.float32), torch.as_tensor(fg, dtype=torch.float32),
                                    target.distance.float())
    out, far = outside.square().mean(1), cover.square()                      # (C,), (C, P)
    single = out + far.mean(1)
    half = restarts // 2
    firsts = torch.cat([torch.argsort(single)[:half],
                        torch.as_tensor(rng.choice(len(maps), restarts - half, replace=False))])

    def best(nearest, fixed, k, taken):
        """For each restart, the candidate whose addition to ``nearest`` (R, P) costs least, and that cost."""
        cost = torch.cat([torch.minimum(nearest[:, None], far[None, c:c + 512]).mean(-1) for c in range(0, len(far), 512)], 1)
        cost = cost + (fixed[:, None] + out[None]) / k
        cost.scatter_(1, taken, math.inf)
        value, index = cost.min(1)
        return index, value

    found = {}
    for k in ks:
        chosen = firsts[:, None].clone()
        for _ in range(k - 1):
            nearest = far[chosen].min(1).values
            index, _ = best(nearest, out[chosen].sum(1), k, chosen)
            chosen = torch.cat([chosen, index[:, None]], 1)
        for _ in range(sweeps):
            changed = False
            for i in range(k):
                others = torch.cat([chosen[:, :i], chosen[:, i + 1:]], 1)
                nearest = far[others].min(1).values if k > 1 else torch.full_like(far[:len(chosen)], math.inf)
                index, value = best(nearest, out[others].sum(1), k, chosen)
                now = (torch.minimum(nearest, far[chosen[:, i]]).mean(-1) + (out[others].sum(1) + out[chosen[:, i]]) / k)
                better = value < now - 1e-12
                if bool(better.any()):
                    changed = True
                    chosen[better, i] = index[better]
            if not changed:
                break
        total = far[chosen].min(1).values.mean(-1) + out[chosen].sum(1) / k
        sets, seen = [], set()
        for r in torch.argsort(total).tolist():
            key = tuple(sorted(chosen[r].tolist()))
            if key not in seen:
                seen.add(key)
                sets.append(list(key))
        found[k] = sets
    return found


def _clip_scales(maps: torch.Tensor) -> None:
    """Keep every map's singular values in [`MIN_SCALE`, `MAX_SCALE`], in place."""
    u, s, vh = torch.linalg.svd(maps[..., :2])
    maps[..., :2] = u @ torch.diag_embed(s.clamp(MIN_SCALE, MAX_SCALE)) @ vh


def refine(maps: np.ndarray | torch.Tensor, target: Target, steps: int, lr: float, points: int,
           seed: int = 0) -> tuple[torch.Tensor, torch.Tensor]:
    """Adam on a batch of IFSs' maps ``(S, k, 2, 3)`` (plane units), minimizing their collage distance to ``target``.

    Returns the maps after ``steps`` steps and each IFS's collage distance, the root of
    ``outside + cover`` in pixels of the target.
    """
    fg = foreground_points(target)
    if len(fg) > points:
        fg = fg[np.random.default_rng(seed).choice(len(fg), points, replace=False)]
    p = torch.as_tensor(fg, dtype=torch.float32)
    distance = target.distance.float()
    work = torch.as_tensor(maps, dtype=torch.float32).clone()
    with torch.no_grad():
        _clip_scales(work)
    work.requires_grad_(True)
    opt = torch.optim.Adam([work], lr=lr)
    pixel2 = float(target.size) ** 2
    for _ in range(steps):
        outside, cover = collage_terms(work, p, distance)
        opt.zero_grad(set_to_none=True)
        ((outside + cover) * pixel2).sum().backward()
        opt.step()
        with torch.no_grad():
            _clip_scales(work)
    with torch.no_grad():
        outside, cover = collage_terms(work, p, distance)
    return work.detach().double(), ((outside + cover) * pixel2).sqrt().double()


def turns(target: Target, count: int = TURNS) -> np.ndarray:
    """``(2 * count - 1, 2, 3)`` maps that keep the figure's mean and covariance: its likely near-symmetries.

    ``S = mu + C^1/2 R C^-1/2 (x - mu)`` for ``R`` each of ``count`` rotations, with and without a
    reflection, the identity left out. A copy ``T_i(A)`` is nearly the same set as ``T_i(S(A))``,
    so at a coarse size a map can lock onto the copy turned the wrong way; `reorient` tries them.
    """
    fg = foreground_points(target)
    mu, root = fg.mean(0), sqrtm_psd(np.cov(fg.T))
    inverse = np.linalg.inv(root)
    out = []
    for angle in np.arange(count) * 2 * math.pi / count:
        for sign in (1.0, -1.0):
            linear = root @ rotation(angle) @ np.diag([1.0, sign]) @ inverse
            out.append(np.concatenate([linear, (mu - linear @ mu)[:, None]], 1))
    return np.array(out[1:])


def reorient(maps: np.ndarray, target: Target, rounds: int = 3, seed: int = 0) -> tuple[np.ndarray, float]:
    """Try each map turned by each of `turns` (``T_i o S``), keep the collage's best, and repeat.

    Every variant (one map turned, the others kept) is scored by its collage distance at once;
    the `SCREEN` best and the maps as given are refined together (`refine`), and the one whose
    attractor is closest to the target (`attractor_chamfer`, `SCREEN_POINTS` points) is kept. Stops
    after ``rounds`` rounds or when the maps as given stay best.

    Returns
    -------
    numpy.ndarray
        ``(k, 2, 3)`` the maps.
    float
        Their collage distance in pixels of ``target``.
    """
    symmetric = turns(target)
    maps = np.asarray(maps, dtype=np.float64)
    error = math.inf
    for _ in range(rounds):
        batch = [maps]
        for i in range(len(maps)):
            for s in symmetric:
                turned = maps.copy()
                turned[i, :, :2] = maps[i, :, :2] @ s[:, :2]
                turned[i, :, 2] = maps[i, :, :2] @ s[:, 2] + maps[i, :, 2]
                batch.append(turned)
        batch = np.array(batch)
        _, first = refine(batch, target, 0, 0.0, COLLAGE_POINTS[1], seed)
        keep = torch.cat([torch.tensor([0]), 1 + torch.argsort(first[1:])[:SCREEN]])
        work, err = refine(batch[keep.numpy()], target, REFINE_STEPS, 0.002, COLLAGE_POINTS[1], seed)
        scores = [attractor_chamfer(m, target, SCREEN_POINTS) for m in work.numpy()]
        best = int(np.argmin(scores))
        maps, error = work[best].numpy(), float(err[best])
        if best == 0:
            break
    return maps, error


def largest(groups: np.ndarray, per: int) -> np.ndarray:
    """Indices of the first ``per`` rows of each value of ``groups`` (of rows sorted largest copy first), in order."""
    return np.sort(np.concatenate([np.nonzero(groups == g)[0][:per] for g in np.unique(groups)]))


def swap(maps: np.ndarray, pool: np.ndarray, coarse: Target, fine: Target, judge: Target, rounds: int = 1,
         top: int = SWAP_TOP, seed: int = 0, value: float | None = None) -> tuple[np.ndarray, float, int]:
    """Replace one map at a time by a copy of ``pool``, ranked by the attractor; keep what raises its IoU.

    The search's sets are made by the collage, which places the large copies well and often
    misses a thin or small one (its copy covers few pixels, and a wrong set covers the coarse
    figure's stray pixels better). The attractor tells them apart: each round, every IFS with one
    map replaced by one copy of the pool (``k * len(pool)`` of them) is drawn by a short chaos
    game at ``coarse``'s size (`chaos_occupancy`) and ranked by its IoU with ``coarse``; the
    ``top`` best are refined on the collage at ``fine``'s size (`refine`), and of them and their
    unrefined selves the one whose attractor (`SCREEN_POINTS` points) overlaps ``fine`` most is
    kept when its attractor IoU at ``judge``'s size beats the maps' by more than 0.001. Stops after
    ``rounds`` rounds or a round that keeps nothing.

    Parameters
    ----------
    maps : numpy.ndarray
        ``(k, 2, 3)`` the maps, plane units.
    pool : numpy.ndarray
        ``(C, 2, 3)`` the copies that may replace a map.
    coarse, fine, judge : Target
        The target at the ranking, refining and judging sizes.
    rounds, top : int
        Rounds at most, and replacements refined a round.
    seed : int
        Seeds the chaos games and the collage's pixel sample.
    value : float, optional
        The maps' attractor IoU at ``judge``'s size (`attractor_iou`), when the caller has it.

    Returns
    -------
    numpy.ndarray
        ``(k, 2, 3)`` the maps.
    float
        Their attractor IoU at ``judge``'s size (`attractor_iou`).
    int
        The rounds that replaced a map.
    """
    maps = np.asarray(maps, dtype=np.float64)
    value, kept = attractor_iou(maps, judge) if value is None else value, 0
    copies = torch.as_tensor(pool, dtype=torch.float32)
    for _ in range(rounds):
        ranks = []
        for i in range(len(maps)):
            batch = torch.as_tensor(maps, dtype=torch.float32).expand(len(copies), -1, -1, -1).clone()
            batch[:, i] = copies
            ranks.append(occupancy_iou(batch, coarse, seed))
        best = torch.argsort(torch.cat(ranks), descending=True)[:top].tolist()
        trials = np.repeat(maps[None], len(best), 0)
        for t, flat in enumerate(best):
            trials[t, flat // len(pool)] = pool[flat % len(pool)]
        replaced, overlap = _best_trial(trials, fine, judge, seed)
        if overlap <= value + 1e-3:
            break
        maps, value, kept = replaced, overlap, kept + 1
    return maps, value, kept


def occupancy_iou(batch: torch.Tensor, target: Target, seed: int = 0, chunk: int = 1024) -> torch.Tensor:
    """``(S,)`` IoU with ``target``'s mask of the short chaos games (`chaos_occupancy`) of IFSs ``(S, k, 2, 3)``: a ranking."""
    figure = torch.as_tensor(target.mask)
    out = []
    for start in range(0, len(batch), chunk):
        drawn = chaos_occupancy(batch[start:start + chunk], target.size, seed=seed)
        out.append((drawn & figure).sum((1, 2)) / (drawn | figure).sum((1, 2)))
    return torch.cat(out)


def _best_trial(trials: np.ndarray, fine: Target, judge: Target, seed: int) -> tuple[np.ndarray, float]:
    """Of ``trials`` ``(S, k, 2, 3)`` and their collage refinements at ``fine``'s size, the one whose attractor
    (`SCREEN_POINTS` points) overlaps ``fine`` most, and its attractor IoU at ``judge``'s size."""
    refined, _ = refine(trials, fine, REFINE_STEPS, 0.002, COLLAGE_POINTS[1], seed)
    variants = np.concatenate([trials, refined.numpy()])
    j = int(np.argmax([iou(_drawn(m, fine, SCREEN_POINTS), fine.mask) for m in variants]))
    return variants[j], attractor_iou(variants[j], judge)


def region_swap(maps: np.ndarray, fine: Target, judge: Target, points: np.ndarray, top: int = REGION_TOP,
                seed: int = 0, value: float | None = None) -> tuple[np.ndarray, float, bool]:
    """One round of replacing a map, or two, by copies matched to the figure's uncovered regions (`ifslib.discovery.regions`).

    For each map, the figure pixels the other maps' copies leave uncovered are matched by moments
    (`region_maps`, a few maps each); every IFS with one map, or two maps, replaced by such maps
    (a pair: two thin maps are often missed together, and one alone does not raise the IoU) is
    drawn by a short chaos game at ``fine``'s size and ranked by its IoU with it; the ``top`` best
    are refined on the collage and the best by their attractor is kept when its IoU at
    ``judge``'s size beats the maps' by more than 0.001.

    Parameters and returns are those of `swap` (``fine`` ranks and refines, ``judge`` judges), but
    for ``points``, ``(P, 2)`` plane points of the figure denser than ``fine`` (its pixels at
    ``judge``'s size) that draw the copies, and the last value returned, a bool: whether a
    replacement was kept.
    """
    maps = np.asarray(maps, dtype=np.float64)
    value = attractor_iou(maps, judge) if value is None else value
    offers = [region_maps(maps, i, fine.mask, points) for i in range(len(maps))]
    trials = [_replaced(maps, {i: m}) for i, ms in enumerate(offers) for m in ms]
    for i, j in itertools.combinations(range(len(maps)), 2):
        trials += [_replaced(maps, {i: a, j: b}) for a in offers[i] for b in offers[j]]
    if not trials:
        return maps, value, False
    trials = np.array(trials)
    ranks = occupancy_iou(torch.as_tensor(trials, dtype=torch.float32), fine, seed)
    best = torch.argsort(ranks, descending=True)[:top].numpy()
    replaced, overlap = _best_trial(trials[best], fine, judge, seed)
    if overlap <= value + 1e-3:
        return maps, value, False
    return replaced, overlap, True


def region_grow(maps: np.ndarray, fine: Target, judge: Target, points: np.ndarray, seed: int = 0
                ) -> tuple[np.ndarray | None, float]:
    """The maps and one more, matched to the region all their copies leave uncovered (`uncovered_maps`).

    Each offer is added to the maps, refined on the collage, and the IFS whose attractor overlaps
    ``fine`` most is returned with its attractor IoU at ``judge``'s size; ``(None, 0.0)`` when the
    copies leave nothing uncovered. Where a search keeps the right maps but one too few (the
    missing copy left bare), this gives the next number of maps those maps rather than a new start.
    """
    maps = np.asarray(maps, dtype=np.float64)
    offers = uncovered_maps(maps, fine.mask, points)
    if not len(offers):
        return None, 0.0
    trials = np.array([np.concatenate([maps, m[None]]) for m in offers])
    return _best_trial(trials, fine, judge, seed)


def _replaced(maps: np.ndarray, new: dict) -> np.ndarray:
    """A copy of ``maps`` with map ``i`` replaced by ``new[i]`` for each key."""
    out = maps.copy()
    for i, m in new.items():
        out[i] = m
    return out


def as_ifs(maps: np.ndarray | torch.Tensor, depth: int = 3) -> IFS:
    """An `ifslib.patterns.affine` IFS of ``maps`` ``(k, 2, 3)``."""
    return patterns.affine(torch.as_tensor(maps).detach().double().numpy(), depth=depth, name="auto")


def _drawn(maps: np.ndarray | torch.Tensor, target: Target, points: int) -> np.ndarray:
    """The maps' attractor drawn by the chaos game (``points`` points) on ``target``'s pixel grid."""
    return figure_mask(as_ifs(maps), target.size, ATTRACTOR, method="chaos", points=points)


def attractor_chamfer(maps: np.ndarray | torch.Tensor, target: Target, points: int = COMPARE_POINTS) -> float:
    """Symmetric Chamfer distance (pixels of ``target``) of the maps' attractor, drawn by the chaos game, to the target."""
    return chamfer(_drawn(maps, target, points), target.mask)


def attractor_iou(maps: np.ndarray | torch.Tensor, target: Target, points: int = JUDGE_POINTS) -> float:
    """IoU of the maps' attractor, drawn by the chaos game at the target's size, with the target's mask."""
    return iou(_drawn(maps, target, points), target.mask)


@dataclass
class SearchResult:
    """What `search` found.

    Attributes
    ----------
    maps : numpy.ndarray
        ``(k, 2, 3)`` the chosen maps ``[A | t]``, plane units.
    table : list of dict
        One row per number of maps tried: ``maps``, ``cover`` (share of the figure the greedy
        copies covered at `SEARCH_SIZE`), ``collage_px`` (at `REFINE_SIZE`), ``chamfer_px`` (the
        attractor's, at `REFINE_SIZE`), ``iou`` (the attractor's, at `JUDGE_SIZE`), ``score``
        (``1 - iou + MAP_COST * maps``), ``seconds``; ``reoriented``, ``regions`` (the rounds of
        `region_swap` that replaced maps), ``grown`` (the maps are the fewer's and one more,
        `region_grow`) and ``swapped`` (the rounds of `swap` that replaced a
        map) where they apply.
    rule : str
        How the number of maps was chosen, in words.
    """

    maps: np.ndarray
    table: list[dict] = field(default_factory=list)
    rule: str = ""

    @property
    def chosen(self) -> dict:
        """The table's row of the chosen number of maps."""
        return next(row for row in self.table if row["maps"] == len(self.maps))


def check_maps(maps) -> tuple[int, ...]:
    """The numbers of maps to compare: `FRACTAL_MAPS` for None, else those given (an int or a sequence, each 1 to `MAX_MAPS`)."""
    if maps is None:
        return FRACTAL_MAPS
    ks = tuple(maps) if isinstance(maps, (list, tuple, range)) else (maps,)
    if not ks:
        raise IFSError("give at least one number of maps to compare")
    for k in ks:
        check_int(k, "number of maps", 1)
        if k > MAX_MAPS:
            raise IFSError(f"a fractal search takes at most {MAX_MAPS} maps, got {k}")
    return tuple(sorted(set(ks)))


def search(target: Target, maps=None, seed: int = 0, progress: bool = True, again: int = AGAIN) -> SearchResult:
    """Find the affine maps of a fractal from its image (see the module docstring).

    When no number of maps draws an attractor of IoU `SWAP_BELOW` or more (and the search did not
    give up), the search runs again from ``seed + 1``, up to ``again`` times (its moves take other
    paths from other random starts and pixel samples), and the search whose chosen maps score
    least is returned.

    Parameters
    ----------
    target : Target
        The fractal's image; it is matched at `SEARCH_SIZE` and refined at `REFINE_SIZE` (or at its
        own size when smaller).
    maps : int or sequence of int, optional
        The numbers of maps to compare (one: fix it); by default each of `FRACTAL_MAPS`.
    seed : int
        Seeds the random starts and the pixel samples.
    progress : bool
        A progress bar over the numbers of maps.
    again : int
        The most times the search runs again from the next seed (0: never); by default `AGAIN`.

    Returns
    -------
    SearchResult
    """
    ks = check_maps(maps)
    check_int(again, "the times a search runs again", 0)
    found = _search(target, ks, seed, progress, "fractal search")
    tries = [found]
    for run in range(1, again + 1):
        if max(r["iou"] for r in found.table) >= SWAP_BELOW or not any(r.get("reoriented") for r in found.table):
            break  # an attractor fits, or the search gave up (not a fractal of a few maps: nothing reoriented)
        tries.append(_search(target, ks, seed + run, progress, f"fractal search again (seed {seed + run})"))
        found = min(tries, key=lambda r: (r.chosen["score"], len(r.maps)))
    if len(tries) > 1:
        scores = ", ".join(f"{r.chosen['score']:.3f}" for r in tries)
        found.rule += (f"; no attractor reached IoU {SWAP_BELOW}, so the search ran from seeds "
                       f"{seed}-{seed + len(tries) - 1}, whose chosen maps scored {scores}: the least was kept")
    return found


def _search(target: Target, ks: tuple[int, ...], seed: int, progress: bool, title: str) -> SearchResult:
    """One search from ``seed`` (`search` without its runs again), ``title`` on its progress bar."""
    rng = np.random.default_rng(seed)
    coarse = resize_target(target, min(SEARCH_SIZE, target.size))
    fine = resize_target(target, min(REFINE_SIZE, target.size))
    judge = resize_target(target, min(JUDGE_SIZE, target.size))
    grid = linear_grid()
    cands = copy_candidates(coarse.mask, grid)
    if len(cands) == 0:
        raise IFSError("no copy of the figure fits inside it: the figure is too small to search for a fractal")
    singular = np.linalg.svd(grid)[1].round(3)[cands[:, 1]]
    centroid = _pixels(coarse.mask).mean(0)
    shape = np.unique(np.stack([singular[:, 0], (singular[:, 1] / singular[:, 0]).round(2)], 1), axis=0,
                      return_inverse=True)[1].reshape(-1)
    pool = plane_maps(grid, cands[largest(shape, SWAP_PER_SHAPE)], centroid, coarse.size)
    cands = cands[largest(singular[:, 0], PER_SCALE)]
    starts = plane_maps(grid, cands, centroid, coarse.size)
    feet = footprints(coarse.mask, grid, cands)
    covers = beam_covers(feet, max(ks))
    for cover in greedy_covers(feet, FIRSTS, max(ks)):
        for k in ks:
            covers[k].append(cover[:k])
    feet_total = float(coarse.mask.sum())
    table, found, skipped, hopeless = [], {}, [], []

    def chamfer_score(row):  # which numbers of maps are tried and reoriented (see the module docstring)
        return row["chamfer_px"] + CHAMFER_COST * row["maps"]

    overlaps = {}  # each number of maps' attractor IoU at the judging size, unrounded (what `swap` starts from)

    def judged(maps, overlap=None):  # a row's attractor scores: Chamfer distance at the refining size, IoU at the
        # judging size (``overlap`` when already drawn)
        overlaps[len(maps)] = attractor_iou(maps, judge) if overlap is None else overlap
        overlap = round(overlaps[len(maps)], 4)
        return {"chamfer_px": round(attractor_chamfer(maps, fine), 4), "iou": overlap,
                "score": round(1 - overlap + MAP_COST * len(maps), 4)}

    for k in tqdm(ks, desc=f"{title} · {fine.size}² · maps", disable=not (progress and draw_bars())):
        if table and min(map(chamfer_score, table)) <= CHAMFER_COST * k:
            skipped.append(k)  # k maps score at least CHAMFER_COST * k: they cannot win by the Chamfer distance
            continue
        if k > GIVE_UP_MAPS and table and min(r["chamfer_px"] for r in table) > GIVE_UP_PX:
            hopeless.append(k)
            continue
        t0 = time.perf_counter()
        covers[k] = collage_sets(starts, coarse, [k], seed=seed)[k] + covers[k]
        covered = max(float(feet[c].amax(0).sum()) / feet_total for c in covers[k])
        batch = np.concatenate([starts[np.array(covers[k])], random_starts(RANDOM_STARTS, k, coarse, rng)])
        work, err = refine(batch, coarse, SEARCH_STEPS, 0.005, COLLAGE_POINTS[0], seed)
        best = torch.argsort(err)[:SHORTLIST]
        drawn = np.array([attractor_chamfer(m, fine, SCREEN_POINTS) for m in work[best].numpy()])
        best = best[np.argsort(drawn, kind="stable")[:KEEP]]
        if fine.size > coarse.size:  # a target no larger than the search size is refined once
            work, err = refine(work[best], fine, REFINE_STEPS, 0.002, COLLAGE_POINTS[1], seed)
        else:
            work, err = work[best], err[best]
        j = int(np.argmin([attractor_chamfer(m, fine, SCREEN_POINTS) for m in work.numpy()]))
        found[k] = work[j].numpy()
        table.append({"maps": k, "cover": round(covered, 4), "collage_px": round(float(err[j]), 4), **judged(found[k]),
                      "seconds": round(time.perf_counter() - t0, 2)})
    # the best few numbers of maps, each with its maps turned where that helps (`reorient`), then compared again
    # reoriented: the numbers of maps with the least Chamfer distance plus a cost per map, which forgives a copy turned
    # the wrong way (what reorienting mends) where the IoU does not
    turned = [] if hopeless else sorted(table, key=lambda r: (chamfer_score(r), r["maps"]))[:REORIENT]
    for row in turned:
        t0 = time.perf_counter()
        found[row["maps"]], error = reorient(found[row["maps"]], fine, seed=seed)
        row["reoriented"] = True
        row["collage_px"] = round(error, 4)
        row.update(judged(found[row["maps"]]))
        row["seconds"] = round(row["seconds"] + time.perf_counter() - t0, 2)
    # while no reoriented number of maps fits well, each (the best scoring first) has a map or two replaced by copies
    # matched to the regions the other maps leave uncovered (`region_swap`), round after round while a round raises its
    # attractor's IoU; then, for the number of maps that scores best, one map at a time by a copy of the pool (`swap`),
    # one round at a time, each round that keeps a map followed by region rounds again, until a round keeps nothing
    # for it or the rounds run out
    dense = foreground_points(judge)

    def none_fits():  # some number of maps is reoriented (or grown), and none of them draws IoU SWAP_BELOW yet
        return bool(turned) and max(r["iou"] for r in turned) < SWAP_BELOW

    def regions_for(row):
        k = row["maps"]
        for _ in range(REGION_ROUNDS):
            if not none_fits():
                return
            t0 = time.perf_counter()
            found[k], overlap, kept = region_swap(found[k], fine, judge, dense, seed=seed, value=overlaps[k])
            row["seconds"] = round(row["seconds"] + time.perf_counter() - t0, 2)
            if not kept:
                return
            row["regions"] = row.get("regions", 0) + 1
            row.update(judged(found[k], overlap))

    for row in sorted(turned, key=lambda r: (r["score"], r["maps"])):
        regions_for(row)
    grew = set()  # the numbers of maps grown from
    for _ in range(GROW_ROUNDS):  # the best scoring maps and one more, matched to what they leave uncovered
        if not none_fits():
            break
        row = min(turned, key=lambda r: (r["score"], r["maps"]))
        after = next((r for r in table if r["maps"] == row["maps"] + 1), None)
        if after is None or row["maps"] in grew:
            break  # no next number of maps tried, or the best has grown already (nothing changed since)
        grew.add(row["maps"])
        t0 = time.perf_counter()
        grown, overlap = region_grow(found[row["maps"]], fine, judge, dense, seed=seed)
        after["seconds"] = round(after["seconds"] + time.perf_counter() - t0, 2)
        if grown is None or overlap <= overlaps[after["maps"]] + 1e-3:
            break
        found[after["maps"]] = grown
        after["grown"] = True
        after.update(judged(grown, overlap))
        if after not in turned:
            turned.append(after)
        regions_for(after)
    open_rows, rounds = list(turned), SWAP_ROUNDS
    while rounds and open_rows and none_fits():
        row = min(open_rows, key=lambda r: (r["score"], r["maps"]))
        if MAP_COST * row["maps"] >= min(r["score"] for r in turned):
            open_rows.remove(row)  # even an attractor of IoU 1 would not score below the best
            continue
        t0, rounds = time.perf_counter(), rounds - 1
        found[row["maps"]], overlap, kept = swap(found[row["maps"]], pool, coarse, fine, judge, rounds=1, seed=seed,
                                                 value=overlaps[row["maps"]])
        row["seconds"] = round(row["seconds"] + time.perf_counter() - t0, 2)
        if kept:
            row["swapped"] = row.get("swapped", 0) + 1
            row.update(judged(found[row["maps"]], overlap))
            regions_for(row)
        else:
            open_rows.remove(row)
    if progress and not draw_bars():
        note(f"{title}: " + ", ".join(f"{r['maps']} maps IoU {r['iou']:.3f}, {r['chamfer_px']:.2f} px" for r in table))
    chosen = min(turned or table, key=lambda r: (r["score"], r["maps"]))
    rule = (f"fewest maps for the fit: least 1 - attractor IoU at {judge.size}² plus {MAP_COST} a map "
            f"(minimum description length), among the {REORIENT} reoriented (the least attractor Chamfer distance at "
            f"{fine.size}² plus {CHAMFER_COST} px a map); {chosen['maps']} maps scored {chosen['score']:.3f}")
    regions = [r for r in table if r.get("regions")]
    if regions:
        rule += "; " + ", ".join(f"{r['maps']} maps had {r['regions']} round(s) of maps matched to uncovered regions"
                                 for r in regions) + f" (the reoriented attractor's IoU was below {SWAP_BELOW})"
    swapped = [r for r in table if r.get("swapped")]
    if swapped:
        rule += "; " + ", ".join(f"{r['maps']} maps had {r['swapped']} map(s) swapped" for r in swapped) + \
                f" (no reoriented attractor reached IoU {SWAP_BELOW})"
    if hopeless:
        rule += (f"; {', '.join(map(str, hopeless))} maps not tried, and none reoriented: up to {GIVE_UP_MAPS} maps no "
                 f"attractor came within {GIVE_UP_PX} px of the target")
    if skipped:
        rule += (f"; {', '.join(map(str, skipped))} maps not tried: with {CHAMFER_COST} px a map their Chamfer distance "
                 f"scores at least {CHAMFER_COST * skipped[0]:.1f}, no less than the best already found")
    return SearchResult(found[chosen["maps"]], table, rule)
