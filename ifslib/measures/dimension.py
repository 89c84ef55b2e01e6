"""How big a fractal is: the similarity dimension (Moran's equation) and the box-counting dimension.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import torch
from scipy.optimize import brentq
from scipy.stats import linregress

from ..errors import IFSError, check_int
from ..core.geometry.ifs import IFS
from ..core.geometry.rules import singular_values

#: Two singular values within this share of each other make a map a similarity (for `ifs_similarity_dimension`).
SIMILARITY_TOLERANCE = 1e-6


def similarity_dimension(scales) -> float:
    """The root ``D >= 0`` of Moran's equation ``sum_i r_i^D = 1``.

    Parameters
    ----------
    scales : sequence of float
        ``(m,)`` contraction ratios, each in ``(0, 1)``.

    Returns
    -------
    float
        0 for one map; otherwise the unique root (``sum r_i^D`` falls from ``m`` at 0 towards 0).

    Raises
    ------
    IFSError
        For no scales, or a scale outside ``(0, 1)``.
    """
    r = np.asarray(scales.detach() if isinstance(scales, torch.Tensor) else scales, dtype=np.float64).reshape(-1)
    if r.size == 0:
        raise IFSError("Moran's equation needs at least one scale")
    if not (np.isfinite(r).all() and (r > 0).all() and (r < 1).all()):
        raise IFSError(f"every scale must be strictly between 0 and 1 (a contraction), got {r.tolist()}")
    if r.size == 1:
        return 0.0
    high = math.log(r.size) / -math.log(r.max()) + 1  # sum r_i^D <= m r_max^D < 1 there
    return float(brentq(lambda d: np.power(r, d).sum() - 1, 0.0, high, xtol=1e-12))


def ifs_scales(ifs: IFS) -> tuple[np.ndarray, bool]:
    """Each map's scale ``(m,)`` (its largest singular value) and whether every map is a similarity."""
    smallest, largest = singular_values(ifs.maps().detach().double())
    similar = bool(((largest - smallest) <= SIMILARITY_TOLERANCE * largest).all())
    return largest.numpy(), similar


def ifs_similarity_dimension(ifs: IFS) -> float:
    """`similarity_dimension` of an IFS's maps' scales (an upper bound of the box dimension for affine maps)."""
    return similarity_dimension(ifs_scales(ifs)[0])


@dataclass(frozen=True)
class BoxCount:
    """A box-counting estimate: the counts and the line fitted to them.

    Attributes
    ----------
    sizes : numpy.ndarray
        ``(k,)`` box sides ``eps`` in plane units (the frame is 1 wide), largest first.
    counts : numpy.ndarray
        ``(k,)`` boxes of each side that hold part of the figure.
    dimension : float
        The fitted slope of ``log N`` against ``log(1/eps)``.
    stderr : float
        The slope's standard error from the fit (0 for two sizes).
    intercept : float
        The fitted ``log N`` at ``eps = 1``.
    """

    sizes: np.ndarray
    counts: np.ndarray
    dimension: float
    stderr: float
    intercept: float


def fit_box_dimension(sizes, counts) -> BoxCount:
    """Fit ``log N = D log(1/eps) + c`` by least squares to counts ``N`` of boxes of sides ``eps``, each ``(k,)``, k >= 2."""
    sizes, counts = np.asarray(sizes, dtype=np.float64), np.asarray(counts, dtype=np.float64)
    if sizes.shape != counts.shape or sizes.ndim != 1 or sizes.size < 2:
        raise IFSError(f"box counting needs sizes and counts of the same length >= 2, got {sizes.shape} and {counts.shape}")
    if not ((sizes > 0).all() and (counts >= 1).all() and np.isfinite(sizes).all()):
        raise IFSError("every box size must be > 0 and every count >= 1 (a box size with no box lit has no logarithm)")
    if len(np.unique(sizes)) != sizes.size:
        raise IFSError(f"box sizes must differ from one another, got {sizes.tolist()}")
    fit = linregress(np.log(1 / sizes), np.log(counts))
    return BoxCount(sizes, counts.astype(np.int64), float(fit.slope), float(fit.stderr if sizes.size > 2 else 0.0),
                    float(fit.intercept))


#: Box sizes per halving of the side: more sizes average out the wobble of a self-similar set's counts
#: between its own scales (the carpet's 1/3 against boxes of 1/2, 10^6 points, one grid: -0.071 at 1 a
#: halving, -0.064 at 4; docs/results/measures.md).
SIZES_PER_OCTAVE = 4

#: Grids tried at each box size, shifted along the diagonal by ``k / OFFSETS`` of a box; the least count is
#: kept (the cover a box-counting dimension asks for is the smallest): the carpet's error from -0.064 to
#: -0.023 at 4 sizes a halving (x 2.8), and to -0.027 at 1.
OFFSETS = 4


def box_sizes(finest: int = 512, coarsest: int = 8, per_octave: int = SIZES_PER_OCTAVE) -> np.ndarray:
    """Box sides from ``1/coarsest`` down to ``1/finest`` (plane units: the frame is 1 wide), ``per_octave`` a halving.

    Returns
    -------
    numpy.ndarray
        ``(k,)`` sides, largest first, in geometric progression of ratio ``2 ** (-1 / per_octave)``.
    """
    check_int(coarsest, "the coarsest boxes per side", 1)
    check_int(finest, "the finest boxes per side", coarsest * 2)
    check_int(per_octave, "box sizes per octave", 1)
    steps = round(per_octave * math.log2(finest / coarsest))
    return (1.0 / coarsest) * 2.0 ** (-np.arange(steps + 1) / per_octave)


def count_points(points, sizes, offsets: int = OFFSETS) -> np.ndarray:
    """Boxes of each side in ``sizes`` holding a point of ``(n, 2)``: the least count over ``offsets`` shifted grids.

    Grid ``j`` has its corner at ``(-0.5, -0.5) - (j / offsets) eps (1, 1)``.
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) == 0 or not np.isfinite(pts).all():
        raise IFSError(f"points must be a non-empty (n, 2) array of finite numbers, got shape {pts.shape}")
    check_int(offsets, "offsets", 1)
    out = []
    for eps in sizes:
        n = int(math.ceil((np.ptp(pts, 0).max() + 1e-12) / eps)) + 2
        lowest = pts.min(0)
        least = None
        for j in range(offsets):
            corner = np.floor((lowest + 0.5) / eps) * eps - 0.5 - (j / offsets) * eps
            cell = np.floor((pts - corner) / eps).astype(np.int64)
            lit = np.zeros((n, n), bool)
            lit[cell[:, 0], cell[:, 1]] = True
            count = int(lit.sum())
            least = count if least is None else min(least, count)
        out.append(least)
    return np.array(out)


def count_pixels(image, sizes_px) -> np.ndarray:
    """Boxes of ``k x k`` pixels (for each ``k`` in ``sizes_px``) that hold a lit pixel of a ``(H, W)`` bool image."""
    img = np.asarray(image.detach() if isinstance(image, torch.Tensor) else image).astype(bool)
    if img.ndim != 2 or not img.any():
        raise IFSError(f"box counting needs a 2-D image with at least one lit pixel, got shape {img.shape}")
    out = []
    for k in sizes_px:
        h, w = -(-img.shape[0] // k) * k, -(-img.shape[1] // k) * k
        padded = np.zeros((h, w), bool)
        padded[:img.shape[0], :img.shape[1]] = img
        out.append(int(padded.reshape(h // k, k, w // k, k).any((1, 3)).sum()))
    return np.array(out)


def box_counting_points(points, finest: int = 512, coarsest: int = 8, per_octave: int = SIZES_PER_OCTAVE,
                        offsets: int = OFFSETS) -> BoxCount:
    """Box-counting dimension of ``(n, 2)`` points in plane units (chaos-game points of an attractor).

    Parameters
    ----------
    points : array-like
        ``(n, 2)`` points of the figure, in plane units.
    finest, coarsest : int
        Boxes per frame side at the finest and coarsest sizes (`box_sizes`). Too fine for the points
        and the counts saturate (the slope falls): keep ``finest^D`` well below ``n`` (1,000,000 points
        fill the carpet's ~90,000 boxes at 512).
    per_octave, offsets : int
        Box sizes per halving (`SIZES_PER_OCTAVE`) and shifted grids per size (`OFFSETS`).

    Returns
    -------
    BoxCount
    """
    sizes = box_sizes(finest, coarsest, per_octave)
    return fit_box_dimension(sizes, count_points(points, sizes, offsets))


def box_counting_image(image, finest: int | None = None, coarsest: int = 4) -> BoxCount:
    """Box-counting dimension of a drawing: its pixels above 0.5, a ``(S, S)`` image of the frame.

    Boxes of ``S / finest`` .. ``S / coarsest`` pixels, doubling (``finest`` at most and by default ``S``,
    both powers of 2 apart and dividing ``S``): a count a student can redo by hand on a grid.
    """
    data = np.asarray(image.detach() if isinstance(image, torch.Tensor) else image, dtype=np.float64)
    if data.ndim != 2 or data.shape[0] != data.shape[1]:
        raise IFSError(f"box_counting_image takes a square (S, S) image, got shape {data.shape}")
    s = data.shape[0]
    finest = s if finest is None else finest
    sizes = box_sizes(finest, coarsest, 1)
    pixels = s * sizes
    if finest > s or not np.allclose(pixels, np.round(pixels)):
        raise IFSError(f"a {s}-pixel image splits into boxes of whole pixels only for box counts per side that "
                       f"divide {s}; got finest={finest}, coarsest={coarsest}")
    return fit_box_dimension(sizes, count_pixels(data > 0.5, np.round(pixels).astype(int)))


__all__ = ["BoxCount", "OFFSETS", "SIMILARITY_TOLERANCE", "SIZES_PER_OCTAVE", "box_counting_image", "box_counting_points", "box_sizes", "count_pixels", "count_points",
           "fit_box_dimension", "ifs_scales", "ifs_similarity_dimension", "similarity_dimension"]
