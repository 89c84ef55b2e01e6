"""The chaos game: points of an IFS's attractor by random iteration, in float64, burnt in until every recorded
point is a draw of the invariant measure."""
from __future__ import annotations

import math
import warnings
from typing import Iterator

import numpy as np
import torch

from ...errors import IFSError, check_int
from ..geometry.attractor import attractor_ball, check_contractive_maps, check_window
from ..geometry.ifs import IFS
from ..geometry.reach import to_window
from ..geometry.rules import singular_values
from ..geometry.leaves import check_bytes
from .chains import Step, fixed_points, walk
from .nearest import nearest_point, pixel_centres

#: Chains of `chaos_game` run side by side, at most: each pays the burn-in, so more cost more for few points.
CHAINS = 2048

#: The most steps a chain of `chaos_game` takes to forget its start (enough for a largest scale up to about 0.993).
MAX_BURN_IN = 5_000

#: Points of the chaos game a picture uses by default.
DEFAULT_POINTS = 1_000_000

#: A window's chaos game keeps the points of the window grown by this share of its size on each side.
WINDOW_MARGIN = 0.25

#: A window's chaos game maps its points into copies whose balls are this share of the window's half-diagonal.
COPY_SHARE = 0.25

#: A window's chaos game draws at most this many rounds of points before it returns what it has.
MAX_ROUNDS = 64

# Rough bytes per point (points, their KD-tree copy, the tree) and per pixel, rounded up.
_BYTES_PER_POINT = 64
_BYTES_PER_PIXEL = 64


def _check_memory(n_points: int, n_pixels: int = 0) -> None:
    check_bytes(n_points * _BYTES_PER_POINT + n_pixels * _BYTES_PER_PIXEL,
                f"a chaos game of {n_points:,} points drawn on {n_pixels:,} pixels", "draw fewer points or pixels")


def burn_in_steps(maps: torch.Tensor, rules=None, dtype=np.float64) -> int:
    """Steps after which a chain of the chaos game has forgotten its start to the precision of ``dtype``.

    Two chains that apply the same ``k`` maps end at most ``s_max ** k`` times their starts' distance
    apart (``s_max`` the largest scale, each map's largest singular value). A chain started on the
    attractor is within its diameter of any other point of it, so after the least ``k`` with
    ``s_max ** k * diameter`` below ``dtype``'s resolution at the attractor (its epsilon times the
    largest coordinate) its points are draws of the invariant measure, whatever the start.

    Parameters
    ----------
    maps : torch.Tensor
        ``(m, 3, 3)`` (or ``(m, 2, 3)``) maps in plane units.
    rules : sequence, optional
        The IFS's rules, to name the one that does not contract.
    dtype : numpy dtype
        The chains' float type.

    Returns
    -------
    int
        ``k >= 0`` (0 when the attractor is one point); `chaos_game` takes at most `MAX_BURN_IN` of them.

    Raises
    ------
    IFSError
        For a map that does not contract.
    """
    with torch.no_grad():
        maps = maps.detach().double()
        largest = float(check_contractive_maps(maps, rules).max())
        centre, radius = attractor_ball(maps)
    diameter = 2 * radius
    resolution = float(np.finfo(dtype).eps) * (float(centre.abs().max()) + radius)
    if not diameter > resolution:
        return 0
    if largest == 0:  # every map sends the plane to one point: one step forgets the start
        return 1
    return math.ceil(math.log(resolution / diameter) / math.log(largest))


def chaos_game(ifs: IFS, n: int, seed: int = 0) -> np.ndarray:
    """``n`` points of the attractor by the chaos game, in float64: ``n`` draws of the invariant measure.

    ``min(n, CHAINS)`` chains start at the first map's fixed point and take `burn_in_steps` steps, so
    that they have forgotten it; then each records its next ``ceil(n / chains)`` points. The maps are
    drawn with `IFS.measure_probabilities`.

    Parameters
    ----------
    ifs : IFS
        Its rules must contract (largest singular value < 1); primitives and depth play no part.
    n : int
        Number of points, >= 1.
    seed : int
        Seeds `numpy.random.default_rng`: the same seed gives the same points (at any thread count).

    Returns
    -------
    numpy.ndarray
        ``(n, 2)`` float64 points on the attractor (plane units), step by step: row ``i`` is chain
        ``i % chains``'s point ``i // chains``, so the first ``min(n, CHAINS)`` rows are independent draws.

    Raises
    ------
    IFSError
        For ``n < 1``, more points than the memory budget holds, or a map that does not contract.

    Warns
    -----
    UserWarning
        When the maps contract so slowly that a chain would need more than `MAX_BURN_IN` steps to forget
        its start: the points still lie on the attractor, but lean towards the first map's fixed point.
    """
    return _points(ifs, n, seed, warn=True)


def chaos_chains(maps: torch.Tensor, probabilities: np.ndarray, chains: int, steps: int, seed: int,
                 rules=None, warn: bool = False) -> Iterator[Step]:
    """The chaos game's chains as every caller walks them: ``chains`` chains from the first map's fixed point,
    `burn_in_steps` unrecorded (at most `MAX_BURN_IN`), then ``steps`` recorded steps, seeded by ``seed``.

    ``maps`` are ``(m, 3, 3)`` float64; ``rules`` the IFS's, for the burn-in's contraction. ``warn``: say when
    the burn-in is cut, for callers that sample the measure (a picture of the set lies on it whatever the cut).
    """
    burn = burn_in_steps(maps, rules)
    if burn > MAX_BURN_IN:
        if warn:
            warnings.warn(f"chaos_game: the maps contract slowly (a chain needs {burn:,} steps to forget its "
                          f"start, it takes {MAX_BURN_IN:,}): the points lie on the attractor, but are not a "
                          "fair sample of its measure", stacklevel=4)
        burn = MAX_BURN_IN
    maps = maps.numpy()
    starts = np.repeat(fixed_points(maps[:1]), chains, axis=0)
    return walk(maps, probabilities, starts, burn, steps, np.random.default_rng(seed))


def _points(ifs: IFS, n: int, seed: int, warn: bool) -> np.ndarray:
    """`chaos_game`'s points; a picture of the set (``warn=False``) lies on it whatever the burn-in."""
    check_int(n, "the number of chaos-game points", 1)
    check_int(seed, "seed", 0)
    _check_memory(n)
    with torch.no_grad():
        maps = ifs.to(torch.float64).maps()
    chains = min(CHAINS, n)
    steps = math.ceil(n / chains)
    out = np.empty((2, steps, chains))
    walked = chaos_chains(maps, ifs.measure_probabilities(maps).numpy(), chains, steps, seed, ifs.rules, warn)
    for k, step in enumerate(walked):
        out[0, k], out[1, k] = step.x, step.y
    return np.ascontiguousarray(out.reshape(2, -1).T[:n])


def window_copies(ifs: IFS, window) -> tuple[np.ndarray, np.ndarray]:
    """The copies ``T_w(A)`` of the attractor that may meet ``window``, each a small share of its size.

    The words are expanded from the root while their ball ``B(T_w(c), ||L_w|| R)`` (which holds
    ``T_w(A)``; `ifslib.core.geometry.attractor.attractor_ball`) meets the window and is wider than
    `COPY_SHARE` of the window's half-diagonal (small copies waste fewer points outside the window):
    a branch whose ball misses the window holds no point of it. The words kept form
    a cut of every branch that meets the window, so the invariant measure restricted to the window
    is that of the mixture of ``T_w`` applied to chaos-game points, ``T_w`` chosen with the word's
    probability.

    Returns
    -------
    maps : numpy.ndarray
        ``(K, 2, 3)`` float64 composed maps ``T_w`` (K may be 0: the window misses the attractor).
    weight : numpy.ndarray
        ``(K,)`` each word's probability under `ifslib.IFS.measure_probabilities`.
    """
    window = check_window(window)
    with torch.no_grad():
        maps = ifs.to(torch.float64).maps()
        check_contractive_maps(maps, ifs.rules)
        centre, radius = attractor_ball(maps)
        p = ifs.measure_probabilities(maps)
        scale = COPY_SHARE * math.hypot(window[2] - window[0], window[3] - window[1]) / 2
        nodes, weight = torch.eye(3, dtype=torch.float64)[None, :2], torch.ones(1, dtype=torch.float64)
        done_maps, done_weight = [], []
        while nodes.shape[0]:
            err = singular_values(nodes)[1] * radius
            meets = to_window((nodes[..., :2] @ centre) + nodes[..., 2], window) <= err
            small = meets & (err <= scale)
            done_maps.append(nodes[small]), done_weight.append(weight[small])
            grow = meets & ~small
            nodes = (nodes[grow][:, None] @ maps[None]).reshape(-1, 2, 3)
            weight = (weight[grow][:, None] * p[None]).reshape(-1)
        return torch.cat(done_maps).numpy(), torch.cat(done_weight).numpy()


def chaos_window(ifs: IFS, n: int, window, seed: int = 0) -> np.ndarray:
    """Up to ``n`` points of the attractor inside ``window``, by the chaos game mapped into the copies that meet it.

    Each round maps chaos-game points (`chaos_game`) by copies ``T_w`` of `window_copies`, chosen
    with their words' probabilities, and keeps those inside the window: points of the attractor
    (up to float64 rounding), spread as the chaos game's own points are, however small the window.
    Stops at ``n`` points or after `MAX_ROUNDS` rounds (a window that barely meets the attractor).

    Returns
    -------
    numpy.ndarray
        ``(k, 2)`` float64 points, ``k <= n`` (0 when the window misses the attractor).
    """
    check_int(n, "the number of chaos-game points", 1)
    _check_memory(n)
    window = check_window(window)
    maps, weight = window_copies(ifs, window)
    if not len(maps):
        return np.empty((0, 2))
    rng = np.random.default_rng(seed)
    out, count = [], 0
    for k in range(MAX_ROUNDS):
        points = _points(ifs, n, seed + 1 + k, warn=False)
        pick = maps[rng.choice(len(maps), size=n, p=weight / weight.sum())]
        mapped = np.einsum("nij,nj->ni", pick[:, :, :2], points) + pick[:, :, 2]
        inside = ((mapped >= window[:2]) & (mapped <= window[2:])).all(1)
        out.append(mapped[inside])
        count += int(inside.sum())
        if count >= n:
            break
    return np.concatenate(out)[:n]


def _grown(window, share: float) -> tuple[float, float, float, float]:
    x0, y0, x1, y1 = check_window(window)
    dx, dy = share * (x1 - x0), share * (y1 - y0)
    return x0 - dx, y0 - dy, x1 + dx, y1 + dy


def chaos_field(ifs: IFS, size: int, n: int = DEFAULT_POINTS, seed: int = 0, window=None) -> torch.Tensor:
    """Distance from every pixel centre to the nearest of ``n`` chaos-game points: ``(size, size)`` float64.

    Every chaos-game point lies on the attractor, so this is never below the distance to the
    attractor; it exceeds it only where the points have not yet come near (rarely visited parts).

    Parameters
    ----------
    ifs : IFS
    size : int
    n, seed
        As in `chaos_game`.
    window : (x0, y0, x1, y1), optional
        The box of the plane the picture covers (the frame when None). Its ``n`` points are those
        of the window grown by `WINDOW_MARGIN` (`chaos_window`), so that a deep zoom gets as many
        as the frame; where the window misses the attractor, the whole attractor's.
    """
    check_int(n, "the number of chaos-game points", 1)
    _check_memory(n, check_int(size, "size", 1) ** 2)
    found = np.empty((0, 2)) if window is None else chaos_window(ifs, n, _grown(window, WINDOW_MARGIN), seed)
    points = torch.from_numpy(found if len(found) else _points(ifs, n, seed, warn=False))
    x, y = pixel_centres(size, dtype=torch.float64, window=window)
    return nearest_point(points, x, y)[1].view(size, size)


def chaos_reach(ifs: IFS, size: int, radius: float, n: int = DEFAULT_POINTS,
                seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Every (pixel, chaos-game point) pair closer than ``radius``, without a KD-tree: each pixel's least distance is
    `chaos_field`'s wherever that is at most ``radius``."""
    check_int(n, "the number of chaos-game points", 1)
    check_int(size, "size", 1)
    if not (isinstance(radius, (int, float)) and 0 <= radius < math.inf):
        raise IFSError(f"radius must be a finite number >= 0, got {radius!r}")
    _check_memory(n)
    points = _points(ifs, n, seed, warn=False)
    # each point's column and row as real numbers (column c's centre at c), then the columns and rows in reach
    u, v = (points[:, 0] + 0.5) * size - 0.5, (0.5 - points[:, 1]) * size - 0.5
    reach = radius * size
    offsets = np.arange(math.floor(2 * reach) + 1)  # the centres ceil(u - reach) .. floor(u + reach), at most
    col = np.ceil(u - reach).astype(np.int64)[:, None] + offsets
    row = np.ceil(v - reach).astype(np.int64)[:, None] + offsets
    # the centres as `pixel_centres` computes them, (c + 0.5) / size, so the float64 distances are the KD-tree's
    dx = (col + 0.5) / size - 0.5 - points[:, :1]
    dy = 0.5 - (row + 0.5) / size - points[:, 1:]
    distance = np.sqrt(dx[:, None, :] ** 2 + dy[:, :, None] ** 2)  # (n, rows, cols)
    keep = ((distance <= radius) & ((col >= 0) & (col < size))[:, None, :]
            & ((row >= 0) & (row < size))[:, :, None])
    return (row[:, :, None] * size + col[:, None, :])[keep], distance[keep]


__all__ = ["CHAINS", "DEFAULT_POINTS", "MAX_BURN_IN", "MAX_ROUNDS", "WINDOW_MARGIN", "burn_in_steps", "chaos_chains", "chaos_field",
           "chaos_game", "chaos_window", "window_copies"]
