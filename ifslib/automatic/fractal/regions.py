"""Copies matched to what the other maps leave uncovered: a new map for a fractal, by moments.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from ...errors import IFSError
from ...core.raster.nearest import pixel_centres
from ..moments import sqrtm_psd
from .config import DEFAULT, SearchConfig


def rotation(angle) -> np.ndarray:
    """``(..., 2, 2)`` rotation matrices by ``angle`` (radians; a number or an array)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)


def _pixel_points(mask: np.ndarray) -> np.ndarray:
    """Plane coordinates ``(P, 2)`` of a mask's pixel centres (`pixel_centres`, docs/guide/conventions.md)."""
    x, y = pixel_centres(mask.shape[0])
    flat = mask.reshape(-1)
    return np.stack([x.numpy()[flat], y.numpy()[flat]], 1)


def copy_masks(maps: np.ndarray, points: np.ndarray, size: int) -> np.ndarray:
    """``(k, size, size)`` bool: each map's copy of ``points`` ``(P, 2)`` (plane units), grown by one pixel.

    ``points`` should be denser than ``size`` (the figure's pixels at twice the size, say), so that
    a copy is drawn without holes.
    """
    out = np.zeros((len(maps), size, size), bool)
    for j, m in enumerate(np.asarray(maps, dtype=np.float64)):
        q = points @ m[:, :2].T + m[:, 2]
        col = np.floor((q[:, 0] + 0.5) * size).astype(np.int64)
        row = np.floor((0.5 - q[:, 1]) * size).astype(np.int64)
        inside = (col >= 0) & (col < size) & (row >= 0) & (row < size)
        out[j, row[inside], col[inside]] = True
        out[j] = ndimage.binary_dilation(out[j])
    return out


def moment_maps(figure: np.ndarray, region: np.ndarray, angles: int = DEFAULT.angles, pixel: float = 0.0,
                scales: tuple[float, float] = (DEFAULT.min_scale, DEFAULT.max_scale)) -> np.ndarray:
    """``(2 * angles, 2, 3)`` maps sending the mean and covariance of ``figure`` onto those of ``region``.

    Parameters
    ----------
    figure, region : numpy.ndarray
        ``(P, 2)`` and ``(R, 2)`` plane points (``R`` >= 1; a region of one pixel has the
        covariance of a pixel).
    angles : int
        Rotations ``Q`` of the whole turn, each with and without a reflection.
    pixel : float
        The side of the region's pixels (plane units): their own spread, ``pixel² / 12`` a
        direction, is added to the region's covariance, so a region one pixel wide keeps that width.
    scales : (float, float)
        Every map's singular values are clipped into this range, so each map contracts.
    """
    inverse = np.linalg.inv(sqrtm_psd(np.cov(figure.T)))
    spread = np.cov(region.T) if len(region) > 1 else np.zeros((2, 2))
    root = sqrtm_psd(spread + np.eye(2) * pixel ** 2 / 12)
    rotations = rotation(np.arange(angles) * 2 * math.pi / angles)
    q = np.concatenate([rotations, rotations @ np.diag([1.0, -1.0])])
    linear = root @ q @ inverse
    u, sv, vh = np.linalg.svd(linear)
    linear = u @ (np.clip(sv, *scales)[..., None] * vh)
    shift = region.mean(0) - linear @ figure.mean(0)
    return np.concatenate([linear, shift[..., None]], -1)


def region_maps(maps: np.ndarray, i: int, mask: np.ndarray, points: np.ndarray, *,
                config: SearchConfig = DEFAULT) -> np.ndarray:
    """Maps to put in place of map ``i``: the figure's copies matched to the region the other maps leave uncovered.

    Parameters
    ----------
    maps : numpy.ndarray
        ``(k, 2, 3)`` the maps, plane units.
    i : int
        The map to replace.
    mask, points, config
        As for `uncovered_maps`.

    Returns
    -------
    numpy.ndarray
        `uncovered_maps` of the maps but ``i``.
    """
    maps = np.asarray(maps, dtype=np.float64)
    if not 0 <= i < len(maps):
        raise IFSError(f"there is no map {i} to replace among {len(maps)} maps")
    return uncovered_maps(np.delete(maps, i, 0), mask, points, config=config)


def uncovered_maps(others: np.ndarray, mask: np.ndarray, points: np.ndarray, *,
                   config: SearchConfig = DEFAULT) -> np.ndarray:
    """The figure's copies matched to the region that the copies of ``others`` leave uncovered: maps to add to them.

    Parameters
    ----------
    others : numpy.ndarray
        ``(k, 2, 3)`` maps, plane units (``k`` may be 0: the region is then the whole figure).
    mask : numpy.ndarray
        ``(n, n)`` bool, the figure at the size the regions are drawn.
    points : numpy.ndarray
        ``(P, 2)`` plane points of the figure, denser than ``mask`` (`copy_masks`).
    config : SearchConfig
        Its ``angles`` (rotations tried, `moment_maps`), ``per_region`` (copies kept a region),
        ``parts`` (connected parts matched besides the whole region, the largest) and scales.

    Returns
    -------
    numpy.ndarray
        ``(M, 2, 3)`` maps, ``M <= per_region * (1 + parts)`` (none when ``others`` cover the
        whole figure), the copies overlapping their region most first within each region.
    """
    others = np.asarray(others, dtype=np.float64).reshape(-1, 2, 3)
    n = mask.shape[0]
    region = mask & ~copy_masks(others, points, n).any(0)
    labels, count = ndimage.label(region)
    regions = [region]
    if count > 1:
        sizes = np.bincount(labels.ravel())[1:]
        regions += [labels == 1 + j for j in np.argsort(-sizes, kind="stable")[:config.parts]]
    figure = _pixel_points(mask)
    out = []
    for part in regions:
        if part.sum() < 2:
            continue
        trials = moment_maps(figure, _pixel_points(part), config.angles, pixel=1 / n,
                             scales=(config.min_scale, config.max_scale))
        drawn = copy_masks(trials, points, n)
        overlap = (drawn & part).sum((1, 2)) / np.maximum((drawn | part).sum((1, 2)), 1)
        out.extend(trials[np.argsort(-overlap, kind="stable")[:config.per_region]])
    return np.array(out).reshape(-1, 2, 3)
