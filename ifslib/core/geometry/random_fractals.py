"""Random IFSs: the sigma-factor sampler of Anderson and Farrell (WACV 2022) and its framing, for the random
fractals of the automatic path's benchmarks and the learned guess's training pairs (not the paper's patterns)."""
from __future__ import annotations

import math

import numpy as np
import torch

from ...errors import IFSError, LeafBudgetError, check_int
from .attractor import attractor_ball, attractor_leaves
from .ifs import IFS
from .patterns import affine, conjugated


def _singular_pairs(n: int, sigma: float, rng: np.random.Generator) -> np.ndarray:
    """``(n, 2)`` singular values ``s1 >= s2`` in (0, 1) with ``sum(s1 + 2 s2) = sigma``, by rejection."""
    for _ in range(10_000):
        pairs = np.sort(rng.uniform(0.0, 1.0, (n, 2)), axis=1)[:, ::-1]
        pairs *= sigma / (pairs[:, 0] + 2 * pairs[:, 1]).sum()
        if pairs.max() < MAX_RANDOM_SCALE and pairs.min() > 0:
            return pairs
    raise IFSError(f"no singular values of {n} maps reach a sigma-factor of {sigma:.3g} below {MAX_RANDOM_SCALE}")


#: `random_ifs` keeps every singular value below this: a map of scale 0.9 or more makes a blob.
MAX_RANDOM_SCALE = 0.9


def random_affine(maps: int, rng: np.random.Generator) -> np.ndarray:
    """``(maps, 2, 3)`` contractive affine maps drawn by the sigma-factor sampler of Anderson and Farrell (WACV 2022),
    not yet fitted to the frame (`random_ifs` does that)."""
    sigma = rng.uniform((5 + maps) / 2, (6 + maps) / 2)
    pairs = _singular_pairs(maps, sigma, rng)

    def rotations(k):
        angle = rng.uniform(-math.pi, math.pi, k)
        flip = np.where(rng.random((k, 2)) < 0.5, -1.0, 1.0)
        c, s_ = np.cos(angle), np.sin(angle)
        return np.stack([np.stack([c, -s_], -1), np.stack([s_, c], -1)], -2) * flip[:, None, :]

    u, v = rotations(maps), rotations(maps)
    matrices = u @ (pairs[:, :, None] * v)
    return np.concatenate([matrices, rng.uniform(-1.0, 1.0, (maps, 2))[:, :, None]], 2)


def random_ifs(maps: int, seed: int = 0, depth: int = 3, extent: float = 0.8) -> IFS:
    """A random contractive affine IFS whose attractor is neither dust nor a blob (`random_affine`), conjugated so
    that the attractor's box fills ``extent`` of the frame."""
    check_int(maps, "number of maps", 1)
    if maps > 64:
        raise IFSError(f"random_ifs draws at most 64 maps, got {maps}")
    check_int(seed, "seed", 0)
    drawn = random_affine(maps, np.random.default_rng(seed))
    matrices, shifts = drawn[:, :, :2], drawn[:, :, 2]
    full = torch.zeros(maps, 3, 3, dtype=torch.float64)
    full[:, :2, :2], full[:, :2, 2], full[:, 2, 2] = torch.as_tensor(matrices), torch.as_tensor(shifts), 1.0
    radius = attractor_ball(full)[1]
    for fraction in (200, 100, 50, 25):  # the finest cut within the leaf budget: leaves within radius / fraction
        try:
            cloud = attractor_leaves(full, radius / fraction, max_leaves=2_000_000).points.numpy()
            break
        except LeafBudgetError:
            continue
    lo, hi = cloud.min(0), cloud.max(0)
    k = extent / max(float((hi - lo).max()), 1e-12)
    b = -k * (lo + hi) / 2  # S(x) = k x + b puts the box's centre at the origin
    return affine(conjugated(drawn, k, b), depth=depth, name=f"random{maps}_{seed}")

