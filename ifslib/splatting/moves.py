"""Where a fit's maps start and where a weak map goes: random maps placed on the figure, and reselection of the map
that covers least of the figure on its own, put anew where the figure is least covered (an escape from the local
minima of many overlapping maps, beside the annealing noise)."""
from __future__ import annotations

import math

import numpy as np
import torch
from scipy import ndimage

from ..core.raster.chaos import CHAINS
from .chains import chain_points
from .parameters import ContractiveMaps, random_raw


def pixel_points(mask: np.ndarray) -> np.ndarray:
    """``(k, 2)`` plane coordinates of the centres of a ``(S, S)`` mask's true pixels (row 0 at the top)."""
    size = mask.shape[0]
    row, col = np.nonzero(mask)
    return np.stack([-0.5 + (col + 0.5) / size, 0.5 - (row + 0.5) / size], 1)


def random_start(mask: np.ndarray, m: int, scales: tuple[float, float], generator: torch.Generator,
                 dtype: torch.dtype = torch.float32) -> ContractiveMaps:
    """``m`` random maps (`random_raw`), each sending the figure's centroid to a random pixel of the figure.

    Parameters
    ----------
    mask : numpy.ndarray
        ``(S, S)`` bool figure (a measure's support), not empty.
    """
    raw = random_raw(m, scales, generator, dtype=torch.float64)
    cloud = pixel_points(mask)
    centre = cloud.mean(0)
    pick = torch.randint(len(cloud), (m,), generator=generator).numpy()
    maps = ContractiveMaps(raw).maps().detach().numpy()
    maps[:, :2, 2] = cloud[pick] - maps[:, :2, :2] @ centre
    return ContractiveMaps.from_maps(maps, dtype=dtype)


def coverage_by_map(maps: torch.Tensor, probabilities: torch.Tensor, size: int, points: int,
                    seed: int) -> np.ndarray:
    """``(m, size, size)`` how many of ``points`` chaos-game points each map put in each pixel (no gradient)."""
    rows = max(2, -(-points // CHAINS))
    xy, picks = chain_points(maps.cpu(), probabilities.cpu(), rows, seed)
    xy, picks = xy[1:].reshape(-1, 2).numpy(), picks[1:].reshape(-1).numpy()
    col, row = np.floor((xy[:, 0] + 0.5) * size), np.floor((0.5 - xy[:, 1]) * size)
    inside = (col >= 0) & (col < size) & (row >= 0) & (row < size)
    flat = picks[inside] * size * size + (row[inside] * size + col[inside]).astype(np.int64)
    return np.bincount(flat, minlength=len(maps) * size * size).reshape(len(maps), size, size)


def reselect(params: ContractiveMaps, probabilities: torch.Tensor, mask: np.ndarray, points: int, seed: int,
             generator: torch.Generator, least_uncovered: float) -> int | None:
    """Move the map that alone covers the fewest figure pixels onto the figure's least covered part, in place.

    Nothing moves while less than ``least_uncovered`` of the figure is uncovered. The new map has the others'
    median largest scale, shrunk to the uncovered part's size when that is smaller, a random rotation, and sends
    the attractor's centre to the uncovered pixel farthest from any covered one.

    Returns
    -------
    int or None
        The index of the map moved, or None.
    """
    size = mask.shape[0]
    maps = params.maps().detach().cpu()
    hits = coverage_by_map(maps, probabilities.detach(), size, points, seed) > 0
    covered = hits.any(0)
    uncovered = mask & ~covered
    if uncovered.sum() < least_uncovered * mask.sum():
        return None
    alone = hits & (hits.sum(0) == 1)[None]
    worst = int(np.argmin((alone & mask[None]).sum((1, 2))))
    depth = ndimage.distance_transform_edt(~covered) * uncovered           # pixels to the nearest covered pixel
    row, col = np.unravel_index(int(np.argmax(depth)), depth.shape)
    goal = np.array([-0.5 + (col + 0.5) / size, 0.5 - (row + 0.5) / size])
    spread = pixel_points(covered).std(0).mean() * 2 if covered.any() else 0.5   # about the attractor's radius
    scales = torch.linalg.svdvals(maps[:, :2, :2].double())[:, 0].numpy()
    scale = min(float(np.median(scales)), max(0.05, float(depth.max()) / size / max(spread, 1e-3)))
    angle = float(torch.rand((), generator=generator)) * 2 * math.pi
    turn = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
    lin = scale * turn
    centre = pixel_points(covered).mean(0) if covered.any() else np.zeros(2)
    new = np.eye(3)
    new[:2, :2], new[:2, 2] = lin, goal - lin @ centre
    params.replace(worst, new)
    return worst
