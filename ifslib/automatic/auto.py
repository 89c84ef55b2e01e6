"""An automatic start for any image: curve or shape, how many maps, and where they go.

Maps whose copies of the target cover the target (the collage theorem): k-means parts for a shape, a skeleton's
polyline for a curve, the fractal search for a lace (docs/guide/design.md). Thresholds: `AUTO` (`FIGURE`, `START`).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch

from ..errors import IFSError, check_int
from ..core.geometry import patterns
from ..core.geometry.ifs import IFS, check_depth
from ..core.raster.nearest import pixel_centres
from .config import AUTO
from .moments import sqrtm_psd
from ..core.targets.target import Target, foreground_points, resize_target

#: The primitives a shape's start may draw (names, not tuned numbers).
PRIMITIVES = ("box", "disk")
#: The sections of `ifslib.automatic.config.AUTO` this module reads.
FIGURE, START = AUTO.figure, AUTO.start


def _skeleton(target: Target) -> np.ndarray:
    """The skeleton of the figure, grown first by the fewest one-pixel dilations (up to `FIGURE.max_join`) that
    leave it in as few pieces as it gets: a thin anti-aliased line thresholded at mid-range breaks into
    dots (the paper's koch.png at 256² is 115 pieces, one piece after three dilations)."""
    from scipy import ndimage
    from skimage.morphology import skeletonize

    grown = np.asarray(target.mask, dtype=bool)
    best, pieces = grown, ndimage.label(grown, np.ones((3, 3)))[1]
    for _ in range(FIGURE.max_join):
        if pieces == 1:
            break
        grown = ndimage.binary_dilation(grown)
        count = ndimage.label(grown, np.ones((3, 3)))[1]
        if count < pieces:
            best, pieces = grown, count
    return skeletonize(best)


def thickness(target: Target, skeleton: np.ndarray | None = None) -> float:
    """The figure's mean width in pixels: its area over the length of its skeleton (`_skeleton`, computed unless given)."""
    skeleton = _skeleton(target) if skeleton is None else skeleton
    return int(target.mask.sum()) / max(int(skeleton.sum()), 1)  # never empty: load_target refuses an empty mask


def classify(target: Target) -> str:
    """``"curve"`` for a thin figure (`thickness` below `FIGURE.curve_width`) whose skeleton is one path
    (its longest path holds `FIGURE.curve_path_share` of it), else ``"shape"`` (`curve_path`)."""
    return "shape" if curve_path(target) is None else "curve"


def curve_path(target: Target) -> np.ndarray | None:
    """The skeleton's longest path ``(L, 2)`` (`skeleton_path`) when the figure is a curve (see `classify`), else
    None: what `classify` decides on, kept for the curve's starts (`candidates` takes it as ``path``)."""
    pixels = int(target.mask.sum())
    if pixels < FIGURE.min_pixels:
        raise IFSError(f"the figure has {pixels} pixel(s): too few to read a curve or a shape from (at least "
                       f"{FIGURE.min_pixels})")
    skeleton = _skeleton(target)
    if thickness(target, skeleton) >= FIGURE.curve_width:
        return None
    path = skeleton_path(target, skeleton)
    return path if len(path) >= FIGURE.curve_path_share * skeleton.sum() else None


def interior_share(target: Target, size: int = FIGURE.porous_size) -> float:
    """The share of the figure's pixels whose eight neighbours are all on the figure, with the target made
    ``size`` pixels wide (`resize_target`): near 1 for a silhouette, low for a fractal's lace."""
    mask = resize_target(target, size).mask
    return float(_interior(mask).sum()) / max(int(mask.sum()), 1)


def _interior(mask: np.ndarray) -> np.ndarray:
    """The figure's pixels whose eight neighbours are all on it (off the frame counts as off the figure)."""
    from scipy import ndimage

    return ndimage.binary_erosion(mask, np.ones((3, 3)), border_value=0)


def edge_dimension(target: Target, size: int = FIGURE.porous_size) -> float:
    """The box-counting dimension of the figure's edge: its pixels with a neighbour off the figure (those
    `interior_share` does not count), with the target made ``size`` pixels wide, counted in boxes of
    `FIGURE.edge_boxes` pixels; the slope of log(boxes) against log(1 / side), by least squares.

    A straight or smooth edge measures about 1 (a square's and a disk's 0.99-1.00 at 128²); a fractal edge more
    (the Koch snowflake's is log 4 / log 3 = 1.26; its filled figure measures 1.22 at 128²).
    """
    mask = resize_target(target, size).mask
    edge = mask & ~_interior(mask)
    counts = []
    for side in FIGURE.edge_boxes:
        n = size // side
        counts.append(max(int(edge[:n * side, :n * side].reshape(n, side, n, side).any((1, 3)).sum()), 1))
    return float(-np.polyfit(np.log(FIGURE.edge_boxes), np.log(counts), 1)[0])


def thin_share(target: Target, size: int = FIGURE.porous_size) -> float:
    """The share of the figure's pixels in parts thinner than a disk of radius `FIGURE.thin_radius` (with the target made
    ``size`` pixels wide): those that a morphological opening by that disk removes."""
    from scipy import ndimage
    from skimage.morphology import disk

    mask = resize_target(target, size).mask
    opened = ndimage.binary_opening(mask, disk(FIGURE.thin_radius))
    return 1.0 - float(opened.sum()) / max(int(mask.sum()), 1)


def thin_parts(target: Target) -> np.ndarray:
    """``(size, size)`` bool: the figure's pixels in parts thinner than `thin_share`'s disk, at the target's own
    size (the disk's radius scaled from `FIGURE.porous_size`, at least one pixel)."""
    from scipy import ndimage
    from skimage.morphology import disk

    radius = max(1, round(FIGURE.thin_radius * target.size / FIGURE.porous_size))
    return target.mask & ~ndimage.binary_opening(target.mask, disk(radius))


def detailed(share: float, size: int) -> bool:
    """Whether a shape of interior share ``share`` (`interior_share`) in a target ``size`` pixels wide is detailed:
    `FIGURE.detailed_from` to `FIGURE.detailed_below`, at `FIGURE.detailed_min_size` or more, so that it is offered
    `START.shape_choices_detailed`."""
    return FIGURE.detailed_from <= share < FIGURE.detailed_below and size >= FIGURE.detailed_min_size


def limbed(share: float, thin: float, size: int) -> bool:
    """Whether a shape of interior share ``share`` and thin share ``thin`` (`thin_share`) in a target ``size``
    pixels wide has limbs: it is `detailed` and more than `FIGURE.thin_parts` of it lies in thin parts (the creatures:
    0.14-0.22; the thin letters and the flower at most 0.05), so `shape_maps` places some maps on them apart."""
    return detailed(share, size) and thin > FIGURE.thin_parts


@dataclass(frozen=True)
class Measures:
    """The measures that decide a shape's path, read once with the figure made `FIGURE.porous_size` wide (`measure`).

    Attributes
    ----------
    share, thin : float
        `interior_share` and `thin_share`.
    edge : float or None
        `edge_dimension` where it decides whether the figure is searched as a fractal: a porous figure of interior
        share at least `FIGURE.ambiguous_share`, or a solid one without thin parts (``thin`` at most
        `FIGURE.thin_parts`: a solid figure's limbs make its edge rough, not copies). None elsewhere: a lace is
        searched whatever its edge, and a solid figure with limbs never is.
    detailed, limbed : bool
        `detailed` and `limbed` at the target's own size: what `choices` takes as ``detail`` and `candidates` as
        ``limbs``.
    """

    share: float
    thin: float
    edge: float | None
    detailed: bool
    limbed: bool


def measure(target: Target) -> Measures:
    """The figure's `Measures`, the target resized once for all of them."""
    small = resize_target(target, FIGURE.porous_size)
    share, thin = interior_share(small), thin_share(small)
    lace = share < FIGURE.ambiguous_share
    edge = None if lace or (share >= FIGURE.porous_share and thin > FIGURE.thin_parts) else edge_dimension(small)
    return Measures(share, thin, edge, detailed(share, target.size), limbed(share, thin, target.size))


def shape_detail(target: Target) -> tuple[bool, bool]:
    """Whether a shape target is `detailed` and whether it is `limbed` (`measure`, as
    `ifslib.automatic.plan.discover` reads them): what to pass `choices` as ``detail`` and `candidates` as
    ``limbs``."""
    m = measure(target)
    return m.detailed, m.limbed


def shape_maps(target: Target, k: int, seed: int = 0, *, limbs: bool = False,
               thin: np.ndarray | None = None) -> np.ndarray:
    """``(k, 2, 3)`` affine maps, each taking the figure's mean and covariance onto one of its ``k`` k-means parts.

    With ``limbs`` (a `limbed` figure), `limb_maps` of the ``k`` parts are drawn among the pixels of its
    thin parts (`thin_parts`) and the rest among the body's, so that a limb is covered by copies squeezed across
    it rather than by parts of body and limb together. Each matrix's singular values are clipped into
    `START.singular_range`, so every map contracts. ``thin`` is the figure's `thin_parts`, computed (with
    ``limbs``) unless the caller has it.
    """
    from scipy.cluster.vq import kmeans2

    fg = foreground_points(target)
    if len(fg) < 3 * k:
        raise IFSError(f"the target has {len(fg)} foreground pixels: too few for {k} maps")
    mu, inv_root = fg.mean(0), np.linalg.inv(sqrtm_psd(np.cov(fg.T)))
    groups = [(fg, k)]
    if limbs:
        thin = thin_parts(target) if thin is None else thin
        if n_thin := limb_maps(target, k, thin):
            on_thin = thin[target.mask]  # foreground_points' order
            groups = [(fg[~on_thin], k - n_thin), (fg[on_thin], n_thin)]
    maps = []
    for points, n in groups:
        _, label = kmeans2(points, n, seed=seed, minit="++")
        for i in range(n):
            part = points[label == i]
            if len(part) < 3:  # an empty or tiny cluster: a small copy at a random pixel of the group
                part = points[np.random.default_rng(seed + i).choice(len(points), 3, replace=False)]
            a = sqrtm_psd(np.cov(part.T)) @ inv_root
            u, s, vt = np.linalg.svd(a)
            a = u @ np.diag(np.clip(s, *START.singular_range)) @ vt
            maps.append(np.concatenate([a, (part.mean(0) - a @ mu)[:, None]], 1))
    return np.array(maps)


def limb_maps(target: Target, k: int, thin: np.ndarray | None = None) -> int:
    """How many of ``k`` maps `shape_maps` places on the thin parts of a limbed figure: `START.limb_maps` times their
    share of its pixels, rounded, at most half of ``k``, and none where fewer than 3 pixels a map are thin.
    ``thin`` is the figure's `thin_parts`, computed unless the caller has it."""
    pixels = int((thin_parts(target) if thin is None else thin).sum())
    n = min(k // 2, round(START.limb_maps * k * pixels / int(target.mask.sum())))
    return n if pixels >= 3 * n else 0


def shape_start(target: Target, k: int, depth: int = 3, primitive: str = "box", seed: int = 0, *,
                limbs: bool = False) -> IFS:
    """A start of ``k`` affine maps for a filled figure (see the module docstring; ``limbs``: `shape_maps`).

    The primitive sits on the figure: ``"box"``, its bounding box; ``"disk"``, a disk at its mean
    with the radius of a disk of the same second moment. Its points are trainable.
    """
    if primitive not in PRIMITIVES:
        raise IFSError(f"unknown primitive {primitive!r} for an automatic start; known: {', '.join(PRIMITIVES)}")
    thin = thin_parts(target) if limbs else None  # read once, for the maps and the pattern's count
    frame = patterns.affine(shape_maps(target, k, seed, limbs=limbs, thin=thin), depth=depth)
    fg = foreground_points(target)
    pts = frame.points.detach().double()
    n = pts.shape[0]
    if primitive == "box":
        extra, prim = np.array([fg.min(0), fg.max(0)]), {"kind": "box", "points": [n, n + 1]}
    else:
        radius = 2 * float(np.linalg.det(np.cov(fg.T))) ** 0.25  # a uniform disk of radius r has variance r^2 / 4
        extra, prim = fg.mean(0)[None], {"kind": "disk", "points": [n], "radius": radius}
    points = torch.cat([pts, torch.as_tensor(extra, dtype=torch.float64)])
    pattern = {"name": "auto", "kind": "shape", "maps": k, "depth": depth, "primitive": primitive}
    if limbs:
        pattern["limb_maps"] = limb_maps(target, k, thin)
    return IFS(points, frame.rules, [prim], depth=depth, name="auto", fixed=frame.fixed, meta={"pattern": pattern})


def skeleton_path(target: Target, skeleton: np.ndarray | None = None) -> np.ndarray:
    """Plane coordinates ``(L, 2)`` of the skeleton's longest path, from one end to the other (skeleton computed unless given)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import shortest_path

    skel = _skeleton(target) if skeleton is None else skeleton
    rows, cols = np.nonzero(skel)
    if len(rows) < 2:
        raise IFSError("the target's skeleton is a single pixel: no curve to follow")
    index = -np.ones(skel.shape, dtype=int)
    index[rows, cols] = np.arange(len(rows))
    src, dst, weight = [], [], []
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):  # 8-connected pixel graph, each edge once
        r2, c2 = rows + dr, cols + dc
        ok = (r2 < skel.shape[0]) & (c2 >= 0) & (c2 < skel.shape[1])
        j = np.where(ok, index[np.minimum(r2, skel.shape[0] - 1), np.clip(c2, 0, skel.shape[1] - 1)], -1)
        hit = ok & (j >= 0)
        src += list(np.nonzero(hit)[0])
        dst += list(j[hit])
        weight += [np.hypot(dr, dc)] * int(hit.sum())
    n = len(rows)
    graph = coo_matrix((weight, (src, dst)), shape=(n, n)).tocsr()
    # the longest shortest path: farthest from any pixel, then farthest from that one (exact on a tree)
    far = np.nan_to_num(shortest_path(graph, directed=False, indices=0), posinf=-1).argmax()
    dist, pred = shortest_path(graph, directed=False, indices=far, return_predecessors=True)
    end = int(np.nan_to_num(dist, posinf=-1).argmax())
    path = [end]
    while path[-1] != far:
        path.append(int(pred[path[-1]]))
    x, y = pixel_centres(target.size, dtype=torch.float64)
    flat = rows[path] * target.size + cols[path]
    return np.stack([x.numpy()[flat], y.numpy()[flat]], 1)


def curve_start(target: Target, k: int, depth: int = 3, *, path: np.ndarray | None = None) -> IFS:
    """A Koch-like start of ``k`` segment rules on ``k + 1`` points spaced evenly along the skeleton (its
    `skeleton_path` ``path``, computed unless given)."""
    path = skeleton_path(target) if path is None else path
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(path, axis=0), axis=1))])
    at = np.linspace(0, arc[-1], k + 1)
    polyline = np.stack([np.interp(at, arc, path[:, 0]), np.interp(at, arc, path[:, 1])], 1)
    ifs = patterns.koch_like(polyline.tolist(), depth=depth, name="auto")
    ifs.meta["pattern"] = {"name": "auto", "kind": "curve", "maps": k, "depth": depth}
    return ifs


def choices(kind: str, maps: int | None = None, depth: int | None = None, *,
            detail: bool = False) -> list[tuple[int, int]]:
    """The (maps, depth) pairs an automatic start is chosen among.

    Both given: that one. ``maps`` given: it, at ``depth`` or `START.default_depth`. ``depth`` given:
    `START.shape_maps` or `START.curve_maps` at that depth. Neither: `START.shape_choices` for a shape
    (`START.shape_choices_detailed` with ``detail``, a `detailed` figure), `START.curve_maps` at
    `START.default_depth` for a curve.
    """
    if depth is not None:
        check_depth(depth)
    if maps is not None:
        check_int(maps, "number of maps", 1 if kind == "shape" else 2)
        if maps > START.max_start_maps:
            raise IFSError(f"number of maps must be at most {START.max_start_maps}, got {maps}")
        return [(maps, START.default_depth if depth is None else depth)]
    if kind == "shape" and depth is None:
        return list(START.shape_choices_detailed if detail else START.shape_choices)
    numbers = START.curve_maps if kind == "curve" else START.shape_maps
    return [(k, START.default_depth if depth is None else depth) for k in numbers]


def candidates(target: Target, options: list[tuple[int, int]], primitive: str = "box", seed: int = 0,
               kind: str | None = None, *, limbs: bool = False, path: np.ndarray | None = None) -> list[IFS]:
    """One automatic start for each ``(maps, depth)`` of ``options`` (see `choices`). ``kind`` (``"curve"``
    or ``"shape"``) is `classify`'s answer, computed unless the caller has it; ``limbs``: a shape's maps are
    placed on its thin parts apart (`shape_maps`); ``path``: a curve's `curve_path`, walked unless given."""
    kind = classify(target) if kind is None else kind
    if kind == "curve" and path is None:
        path = skeleton_path(target)  # one walk of the skeleton for every curve start
    return [curve_start(target, k, d, path=path) if kind == "curve"
            else shape_start(target, k, d, primitive, seed, limbs=limbs) for k, d in options]
