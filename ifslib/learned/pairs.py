"""Training pairs: random maps (`random_fractals.random_affine`, the benchmarks' sampler) fitted into the frame, and the
picture of their attractor by the chaos game, as the automatic path sees a target."""
from __future__ import annotations

import numpy as np

from ..core.geometry.patterns import conjugated
from ..core.geometry.random_fractals import random_affine
from . import config


def chaos_points(maps: np.ndarray, rng: np.random.Generator, chains: int = config.CHAINS,
                 steps: int = config.STEPS, burn_in: int = config.BURN_IN) -> np.ndarray:
    """``(chains * steps, 2)`` points of the attractor of ``(m, 2, 3)`` maps, each map drawn with odds by its area
    (with a floor): the copies are then visited about as densely as each other, and a picture covers the set."""
    area = np.abs(np.linalg.det(maps[:, :, :2]))
    odds = np.maximum(area, 0.1 * area.mean())
    p = np.zeros((chains, 2))
    out = np.empty((steps, chains, 2))
    for k in range(burn_in + steps):
        pick = maps[rng.choice(len(maps), chains, p=odds / odds.sum())]
        p = np.einsum("cij,cj->ci", pick[:, :, :2], p) + pick[:, :, 2]
        if k >= burn_in:
            out[k - burn_in] = p
    return out.reshape(-1, 2)


def framed(maps: np.ndarray, points: np.ndarray, extent: float = config.EXTENT) -> tuple[np.ndarray, np.ndarray]:
    """The maps and points conjugated by ``S(x) = k x + b`` so that the points' box is centred, its longer side
    ``extent``."""
    lo, hi = points.min(0), points.max(0)
    k = extent / max(float((hi - lo).max()), 1e-12)
    b = -k * (lo + hi) / 2
    return conjugated(maps, k, b), k * points + b


def picture(points: np.ndarray, size: int = config.SIZE) -> np.ndarray:
    """``(size, size)`` bool: the pixels of the frame ``[-0.5, 0.5]^2`` a point falls in, row 0 at the top
    (`ifslib.pixel_centres`' convention)."""
    col = np.floor((points[:, 0] + 0.5) * size).astype(int)
    row = np.floor((0.5 - points[:, 1]) * size).astype(int)
    keep = (col >= 0) & (col < size) & (row >= 0) & (row < size)
    image = np.zeros((size, size), dtype=bool)
    image[row[keep], col[keep]] = True
    return image


def pair(tag: int, index: int, maps: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Training pair ``index`` of stream ``tag``: ``(SIZE, SIZE)`` bool picture and ``(m, 2, 3)`` maps."""
    rng = np.random.default_rng([tag, index])
    m = maps if maps is not None else int(rng.integers(config.MAPS[0], config.MAPS[1] + 1))
    raw = random_affine(m, rng)
    fitted, points = framed(raw, chaos_points(raw, rng))
    return picture(points), fitted


#: The frame's 8 symmetries: orthogonal matrices ``g`` with ``g^2 = 1`` or rotations by quarter turns.
SYMMETRIES = np.array([[[c, -s], [s, c]] for c, s in ((1, 0), (0, 1), (-1, 0), (0, -1))]
                      + [[[c, s], [s, -c]] for c, s in ((1, 0), (0, 1), (-1, 0), (0, -1))], dtype=float)


def turned(image: np.ndarray, maps: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The pair seen through the symmetry ``g`` of the frame: the picture of ``g(A)`` and the maps
    ``g w g^-1`` whose attractor it is."""
    size = image.shape[0]
    rows, cols = np.nonzero(image)
    centres = np.stack([(cols + 0.5) / size - 0.5, 0.5 - (rows + 0.5) / size], 1)
    linear = g @ maps[:, :, :2] @ g.T
    shifts = maps[:, :, 2] @ g.T
    return picture(centres @ g.T, size), np.concatenate([linear, shifts[:, :, None]], 2)
