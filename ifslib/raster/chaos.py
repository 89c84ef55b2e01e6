"""The chaos game: points of an IFS's attractor by random iteration, in float64 (Barnsley).

Every map's fixed point lies on the attractor, and so does the image of any point of it under any
map: a chain that starts at a fixed point and applies randomly chosen maps never leaves the
attractor (up to float64 rounding). Many chains run side by side, each from the fixed point of a
randomly chosen map. The maps are chosen with probabilities in proportion to the area they keep
(``|det L_i|``), with a floor so that a map that flattens (a fern's stem) is still visited.

This is the independent reference of the tests (no leaves, no bound, no search of ours) and the
classic way to draw an attractor: `chaos_field` turns the points into a distance field of the same
pixel grid, which `ifslib.render` shades with ``method="chaos"``.
"""
from __future__ import annotations

import math

import numpy as np
import torch

from ..errors import IFSError, check_int
from ..geometry.attractor import chaos_probabilities, check_contractive_maps
from ..geometry.ifs import IFS
from ..geometry.leaves import check_bytes
from .nearest import nearest_point, pixel_centres

#: Chains run side by side (each a vectorised row).
CHAINS = 1024

#: Points of the chaos game a picture uses by default.
DEFAULT_POINTS = 1_000_000

# Rough bytes per point (the float64 points, their copy for the KD-tree, the tree) and per pixel
# (its centre, its nearest point's index and distance), rounded up.
_BYTES_PER_POINT = 64
_BYTES_PER_PIXEL = 64


def _check_memory(n_points: int, n_pixels: int = 0) -> None:
    check_bytes(n_points * _BYTES_PER_POINT + n_pixels * _BYTES_PER_PIXEL,
                f"a chaos game of {n_points:,} points drawn on {n_pixels:,} pixels", "draw fewer points or pixels")


def chaos_game(ifs: IFS, n: int, seed: int = 0) -> np.ndarray:
    """``n`` points of the attractor by the chaos game, in float64.

    Parameters
    ----------
    ifs : IFS
        Its rules must contract (largest singular value < 1); primitives and depth play no part.
    n : int
        Number of points, >= 1.
    seed : int
        Seeds `numpy.random.default_rng`: the same seed gives the same points.

    Returns
    -------
    numpy.ndarray
        ``(n, 2)`` float64 points on the attractor (plane units).

    Raises
    ------
    IFSError
        For ``n < 1``, more points than the memory budget holds, or a map that does not contract.
    """
    check_int(n, "the number of chaos-game points", 1)
    check_int(seed, "seed", 0)
    _check_memory(n)
    with torch.no_grad():
        maps_t = ifs.to(torch.float64).maps()
    check_contractive_maps(maps_t, ifs.rules)
    maps = maps_t.numpy()
    lin, shift = maps[:, :2, :2], maps[:, :2, 2]
    m = len(maps)
    fixed = np.stack([np.linalg.solve(np.eye(2) - lin[i], shift[i]) for i in range(m)])
    rng = np.random.default_rng(seed)
    chains = min(CHAINS, n)
    steps = math.ceil(n / chains)
    p = chaos_probabilities(maps_t).numpy()
    current = fixed[rng.choice(m, size=chains, p=p)]
    out = np.empty((steps, chains, 2))
    for k in range(steps):
        pick = rng.choice(m, size=chains, p=p)
        current = np.einsum("nij,nj->ni", lin[pick], current) + shift[pick]
        out[k] = current
    return out.reshape(-1, 2)[:n]


def chaos_field(ifs: IFS, size: int, n: int = DEFAULT_POINTS, seed: int = 0, window=None) -> torch.Tensor:
    """Distance from every pixel centre to the nearest of ``n`` chaos-game points: ``(size, size)`` float64, no gradient.

    Every chaos-game point lies on the attractor, so this is never below the distance to the
    attractor; it exceeds it only where the points have not yet come near (rarely visited parts).

    Parameters
    ----------
    ifs : IFS
    size : int
    n, seed
        As in `chaos_game`.
    window : (x0, y0, x1, y1), optional
        The box of the plane the picture covers (the frame when None).
    """
    check_int(n, "the number of chaos-game points", 1)
    _check_memory(n, check_int(size, "size", 1) ** 2)
    points = torch.from_numpy(chaos_game(ifs, n, seed))
    x, y = pixel_centres(size, dtype=torch.float64, window=window)
    return nearest_point(points, x, y)[1].view(size, size)


def chaos_occupancy(maps: torch.Tensor, size: int, chains: int = 48, steps: int = 48, burn: int = 8,
                    seed: int = 0) -> torch.Tensor:
    """The pixels a short chaos game visits, for a batch of IFSs at once: a cheap, noisy picture of each attractor.

    Each IFS runs ``chains`` chains from the fixed point of its first map (a point of the
    attractor) for ``burn + steps`` steps in float32, and the pixels of the last ``steps`` points
    are marked: ``chains * steps`` points an IFS. Far fewer points than `chaos_game` draws, so a
    rarely visited part of an attractor may be missed: it ranks many IFSs against one another
    (`ifslib.discovery.fractal.swap`), it does not score one.

    Parameters
    ----------
    maps : torch.Tensor
        ``(S, k, 2, 3)`` (or ``(S, k, 3, 3)``) maps ``[L | t]`` of ``S`` IFSs of ``k`` maps each,
        plane units; each must contract (not checked: a map that does not contract sends its
        chains out of the frame, where they mark nothing).
    size : int
        Pixels per side of the frame ``[-0.5, 0.5]²``.
    chains, steps, burn : int
        Chains per IFS, the steps whose points are marked, and the steps before them.
    seed : int
        Seeds the choice of maps (`torch.Generator`).

    Returns
    -------
    torch.Tensor
        ``(S, size, size)`` bool, row 0 at the top (``y = 0.5``).
    """
    check_int(size, "size", 1)
    for value, name in [(chains, "chains"), (steps, "steps")]:
        check_int(value, name, 1)
    check_int(burn, "burn", 0)
    maps = torch.as_tensor(maps, dtype=torch.float32)
    if maps.dim() != 4 or maps.shape[-1] != 3 or maps.shape[-2] not in (2, 3):
        raise IFSError(f"chaos_occupancy takes maps of shape (S, k, 2, 3), got {tuple(maps.shape)}")
    count, k = maps.shape[:2]
    generator = torch.Generator().manual_seed(seed)
    cdf = chaos_probabilities(maps).float().cumsum(-1)
    coef = maps[..., :2, :].reshape(count, k, 6)                 # a, b, tx, c, d, ty
    first = maps[:, 0, :2, :]
    start = torch.linalg.solve(torch.eye(2) - first[..., :2], first[..., 2])
    x = start[:, :1].expand(count, chains).contiguous()
    y = start[:, 1:].expand(count, chains).contiguous()
    picks = torch.searchsorted(cdf, torch.rand(count, (burn + steps) * chains, generator=generator)).clamp_(max=k - 1)
    step = torch.gather(coef, 1, picks[..., None].expand(-1, -1, 6)).view(count, burn + steps, chains, 6)
    marked = torch.zeros(count, size * size + 1)
    for s in range(burn + steps):
        a = step[:, s]
        x, y = a[..., 0] * x + a[..., 1] * y + a[..., 2], a[..., 3] * x + a[..., 4] * y + a[..., 5]
        if s >= burn:
            col, row = ((x + 0.5) * size).floor(), ((0.5 - y) * size).floor()
            inside = (col >= 0) & (col < size) & (row >= 0) & (row < size)
            flat = torch.where(inside, row * size + col, torch.full_like(col, size * size)).long()
            marked.scatter_(1, flat, 1.0)
    return marked[:, :-1].view(count, size, size) > 0


__all__ = ["CHAINS", "DEFAULT_POINTS", "chaos_field", "chaos_game", "chaos_occupancy", "chaos_probabilities"]
