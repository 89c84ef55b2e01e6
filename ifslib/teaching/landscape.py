"""The loss landscape around an optimum (the paper's Figure "vecfield"): the descent direction of each loss as
one control point moves over a grid (`gradient_field`), scored against the direction to the optimum (`alignment`)."""
from __future__ import annotations

from typing import Callable

import numpy as np

from .. import threads as _threads  # noqa: F401 - before torch loads (ifslib.threads)
import torch  # noqa: E402
from tqdm.auto import tqdm

from ..core.raster.distance import distance_field
from ..errors import IFSError, check_int
from ..core.geometry.ifs import IFS
from ..core.scoring.losses import loss as loss_fn
from ..core.targets.target import Target


def gradient_field(ifs: IFS, target: Target, index: int, xs: np.ndarray, ys: np.ndarray,
                   loss: str | Callable, *, depth: int | None = None,
                   sigma: float | None = None, levels: int = 5, progress: bool = True) -> np.ndarray:
    """Descent direction ``(ny, nx, 2)`` of a loss for control point ``index`` placed at each grid position, the other
    points as in ``ifs`` (zero where the gradient vanishes)."""
    check_int(index, "index", 0)
    if index >= ifs.n_points:
        raise IFSError(f"index {index} is out of range for an IFS with {ifs.n_points} points")
    xs, ys = np.asarray(xs, dtype=float), np.asarray(ys, dtype=float)
    field = np.zeros((len(ys), len(xs), 2))
    base = ifs.points.detach()
    cells = [(j, i) for j in range(len(ys)) for i in range(len(xs))]
    for j, i in tqdm(cells, desc=f"gradient field ({loss if isinstance(loss, str) else 'custom'})",
                     disable=not progress, leave=False):
        points = base.clone()
        points[index] = torch.tensor([xs[i], ys[j]], dtype=base.dtype)
        moved = ifs.clone(points)
        value = loss_fn(distance_field(moved, target.size, depth), target, loss, sigma=sigma, levels=levels)
        (grad,) = torch.autograd.grad(value, moved.points)
        field[j, i] = -grad[index].double().numpy()
    return field


def toward(xs: np.ndarray, ys: np.ndarray, optimum) -> np.ndarray:
    """Unit vectors from each grid position to ``optimum``: ``(ny, nx, 2)`` (zero at the optimum)."""
    gx, gy = np.meshgrid(np.asarray(xs, float), np.asarray(ys, float))
    vec = np.stack([optimum[0] - gx, optimum[1] - gy], -1)
    norm = np.linalg.norm(vec, axis=-1, keepdims=True)
    return np.divide(vec, norm, out=np.zeros_like(vec), where=norm > 0)


def alignment(vectors: np.ndarray, directions: np.ndarray) -> tuple[float, float]:
    """How well ``(..., 2)`` vectors point along ``directions``: the mean cosine between them and the fraction of
    positions where it is positive, over the positions where both are non-zero."""
    v = np.asarray(vectors, float).reshape(-1, 2)
    d = np.asarray(directions, float).reshape(-1, 2)
    nv, nd = np.linalg.norm(v, axis=1), np.linalg.norm(d, axis=1)
    ok = (nv > 0) & (nd > 0)
    if not ok.any():
        return float("nan"), float("nan")
    cos = (v[ok] * d[ok]).sum(1) / (nv[ok] * nd[ok])
    return float(cos.mean()), float((cos > 0).mean())
