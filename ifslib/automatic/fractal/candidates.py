"""Copies that fit inside: the figure's affine copies placed on it by FFT matching, and maps made of them.

`copy_candidates` matches the figure mapped by each linear part of `linear_grid` against the
figure at every translation at once; `candidate_copies` keeps the largest of each scale as the
search's starting copies (`plane_maps`: plane units) and of each shape as `swap`'s pool;
`random_starts` are random maps beside them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import torch
from scipy import ndimage
from scipy.fft import next_fast_len

from ...errors import IFSError
from ...core.targets.target import Target, foreground_points
from .config import DEFAULT, SearchConfig
from .regions import rotation


def linear_grid(turns: int = DEFAULT.grid_turns, phases: int = DEFAULT.grid_phases, scales=DEFAULT.grid_scales,
                ratios=DEFAULT.grid_ratios) -> np.ndarray:
    """Linear parts ``R(theta) diag(s, ±r s) R(phi)`` to try: ``(G, 2, 2)``.

    ``theta`` takes ``turns`` angles of the whole turn, ``phi`` ``phases`` angles of the half turn
    (one when ``r = 1``: a similarity has no second angle), ``s`` the ``scales``, ``r`` the
    ``ratios`` of the smaller singular value to the larger, and both signs (a reflection or not).
    """
    thetas = rotation(np.arange(turns) * 2 * math.pi / turns)
    parts = []
    for s in scales:
        for r in ratios:
            phis = rotation(np.zeros(1) if r == 1.0 else np.arange(phases) * math.pi / phases)
            diag = np.stack([np.diag([s, sign * r * s]) for sign in (1.0, -1.0)])
            # every (phi, theta, sign) product at once, in that order: a Python loop over them took a second
            parts.append((thetas[None, :, None] @ diag[None, None, :] @ phis[:, None, None]).reshape(-1, 2, 2))
    return np.concatenate(parts)


def pixels(mask: np.ndarray) -> np.ndarray:
    """``(P, 2)`` figure pixels as ``(x, y) = (col, -row)``: pixel units, y up like the plane."""
    rows, cols = np.nonzero(mask)
    return np.stack([cols, -rows], 1).astype(np.float64)


def _centred_pixels(mask: np.ndarray) -> torch.Tensor:
    """`pixels` less their centroid (the origin a linear part of `linear_grid` turns about)."""
    points = pixels(mask)
    return torch.as_tensor(points - points.mean(0))


def copy_candidates(mask: np.ndarray, grid: np.ndarray, per_map: int = 2, chunk: int = 512, *,
                    config: SearchConfig = DEFAULT) -> np.ndarray:
    """Placements of the figure's copies ``L(A)`` that lie inside the figure, for every ``L`` of ``grid``.

    Parameters
    ----------
    mask : numpy.ndarray
        ``(n, n)`` bool, the figure.
    grid : numpy.ndarray
        ``(G, 2, 2)`` linear parts in pixel units (``x`` right, ``y`` up), from `linear_grid`.
    per_map : int
        Placements kept for each ``L`` (those covering most).
    config : SearchConfig
        Its ``inside``: the share of a copy's pixels that must land on the figure grown by one pixel.

    Returns
    -------
    numpy.ndarray
        ``(C, 4)`` rows ``(pixels covered, index into grid, row, col)``, most pixels first; the
        copy's centroid (the image of the figure's centroid) sits at pixel ``(row, col)``.
    """
    n = mask.shape[0]
    u = _centred_pixels(mask)
    grown = torch.as_tensor(ndimage.binary_dilation(mask), dtype=torch.float32)
    spectra = {}  # the grown figure's spectrum at each padded size
    rows = []
    for start in range(0, len(grid), chunk):
        linear = torch.as_tensor(grid[start:start + chunk])
        v = torch.einsum("gij,pj->gpi", linear, u)
        col, row = torch.round(v[..., 0]).long(), torch.round(-v[..., 1]).long()
        # Zero padding: the correlation is circular, and a copy reaching ``reach`` pixels from its centroid,
        # placed anywhere in the frame, wraps onto the padding only when the side is at least n + reach.
        # The grid's parts come scale by scale, so a chunk of small copies pads (and transforms) less.
        size = next_fast_len(n + int(max(col.abs().max(), row.abs().max())) + 1, real=True)
        if size not in spectra:
            spectra[size] = torch.fft.rfft2(torch.nn.functional.pad(grown, (0, size - n, 0, size - n)))
        flat = (row % size) * size + col % size
        copies = torch.zeros(len(linear), size * size).scatter_(1, flat, 1.0).view(-1, size, size)
        drawn = copies.sum((1, 2))
        # The correlation counts pixels, so it is an integer up to the FFT's rounding error, whose sign
        # depends on the CPU and the thread count (a one-pixel hit came out 0.99999994 or 1.0000001):
        # every decision below is taken on the rounded count, which is exact.
        hits = torch.fft.irfft2(torch.conj(torch.fft.rfft2(copies)) * spectra[size], s=(size, size))[:, :n, :n]
        hits = torch.round(hits).to(torch.int64).reshape(len(linear), -1)
        enough = hits.double() >= config.inside * drawn.double()[:, None] - 0.5
        # the placements covering most, the first in reading order among equals (an exact key, no tie left to chance)
        key = torch.where(enough, hits, 0) * (n * n) + (n * n - 1 - torch.arange(n * n))
        values = key.topk(per_map, dim=1).values.numpy()  # (G, per_map), each linear part's best first
        count, index = values // (n * n), n * n - 1 - values % (n * n)
        part = np.broadcast_to(start + np.arange(len(linear))[:, None], values.shape)
        rows.append(np.stack([count, part, index // n, index % n], -1).reshape(-1, 4)[count.reshape(-1) >= 1])
    out = np.concatenate(rows).astype(np.int64) if rows else np.empty((0, 4), np.int64)  # an empty grid: none
    return out[np.argsort(-out[:, 0], kind="stable")]


def footprints(mask: np.ndarray, grid: np.ndarray, cands: np.ndarray, chunk: int = 2048) -> torch.Tensor:
    """``(C, n * n)`` float 0/1: the figure pixels each candidate copy of ``cands`` (`copy_candidates`) covers
    (its pixels grown by one)."""
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


def plane_maps(grid: np.ndarray, cands: np.ndarray, centroid: np.ndarray, n: int) -> np.ndarray:
    """``(C, 2, 3)`` maps ``[A | t]`` in plane units of the candidates ``cands`` ``(C, 4)`` (pixel-unit ``L`` of
    ``grid``, ``centroid`` ``(2,)`` in pixel units sent to pixel ``(row, col)``, ``n`` the mask's size)."""
    linear = grid[cands[:, 1]]
    # pixel (x, y) = (col, -row) and plane P = p / n + o, with o = (0.5/n - 0.5, 0.5 - 0.5/n)
    o = np.array([0.5 / n - 0.5, 0.5 - 0.5 / n])
    shift = np.stack([cands[:, 3], -cands[:, 2]], 1) - linear @ centroid
    t = shift / n + o - linear @ o
    return np.concatenate([linear, t[:, :, None]], 2)


def random_starts(count: int, k: int, target: Target, rng: np.random.Generator, *,
                  config: SearchConfig = DEFAULT) -> np.ndarray:
    """``(count, k, 2, 3)`` random maps: singular values in ``config.start_scales``, any rotation (a share
    ``config.start_reflected`` of them reflected), each taking the figure's centroid onto a random figure pixel."""
    fg = foreground_points(target)
    angle = rng.uniform(-math.pi, math.pi, (count, k, 2))
    scale = rng.uniform(*config.start_scales, (count, k, 2))
    scale[..., 1] *= np.where(rng.random((count, k)) < config.start_reflected, -1.0, 1.0)
    rot = rotation(angle)  # (count, k, 2, 2, 2): [..., which, i, j]
    linear = rot[..., 0, :, :] * scale[..., None, :] @ rot[..., 1, :, :]
    t = fg[rng.integers(0, len(fg), (count, k))] - linear @ fg.mean(0)
    return np.concatenate([linear, t[..., None]], -1)


def largest(groups: np.ndarray, per: int) -> np.ndarray:
    """Indices of the first ``per`` rows of each value of ``groups`` (of rows sorted largest copy first), in order."""
    return np.sort(np.concatenate([np.nonzero(groups == g)[0][:per] for g in np.unique(groups)]))



@dataclass(frozen=True)
class Copies:
    """The candidate copies of one search, at the search size.

    Attributes
    ----------
    starts : numpy.ndarray
        ``(C, 2, 3)`` plane maps of the `SearchConfig.per_scale` largest copies of each scale.
    feet : torch.Tensor
        ``(C, n * n)`` the figure pixels each of them covers (`footprints`).
    pool : numpy.ndarray
        ``(P, 2, 3)`` the `SearchConfig.swap_per_shape` largest copies of each scale and ratio of
        singular values: what `swap` may put in place of a map.
    """

    starts: np.ndarray
    feet: torch.Tensor
    pool: np.ndarray


def candidate_copies(coarse: Target, *, config: SearchConfig = DEFAULT) -> Copies:
    """The copies of ``coarse``'s figure that fit inside it (`copy_candidates` on `linear_grid`), as `Copies`."""
    grid = linear_grid(config.grid_turns, config.grid_phases, config.grid_scales, config.grid_ratios)
    cands = copy_candidates(coarse.mask, grid, config=config)
    if len(cands) == 0:
        raise IFSError("no copy of the figure fits inside it: the figure is too small to search for a fractal")
    singular = np.linalg.svd(grid)[1].round(3)[cands[:, 1]]
    centroid = pixels(coarse.mask).mean(0)
    shape = np.unique(np.stack([singular[:, 0], (singular[:, 1] / singular[:, 0]).round(2)], 1), axis=0,
                      return_inverse=True)[1].reshape(-1)
    pool = plane_maps(grid, cands[largest(shape, config.swap_per_shape)], centroid, coarse.size)
    cands = cands[largest(singular[:, 0], config.per_scale)]
    starts = plane_maps(grid, cands, centroid, coarse.size)
    return Copies(starts, footprints(coarse.mask, grid, cands), pool)
