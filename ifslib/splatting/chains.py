"""The chains behind the splat: the library's chaos game with the map that made each point, and the last steps
of each chain replayed differentiably (a hand-written backward pass: one bincount per coefficient a step, where
autograd's gather would scatter-add into the few maps point by point, three times slower)."""
from __future__ import annotations

import numpy as np
import torch

from ..core.raster.chaos import CHAINS, chaos_chains


def chain_points(maps: torch.Tensor, probabilities: torch.Tensor, rows: int,
                 seed: int) -> tuple[torch.Tensor, torch.Tensor]:
    """``rows`` consecutive points of each of `CHAINS` chains, and the map that made each from the one before.

    The chains are `chaos_game`'s (the same starts, burn-in and seeded draws, through the library's one chain
    generator, walked by `ifslib.core.raster.chaos.chaos_chains`), kept with their picks.

    Returns
    -------
    points : torch.Tensor
        ``(rows, CHAINS, 2)`` float64 on ``maps``' device (burned in: each point a draw of the measure).
    picks : torch.Tensor
        ``(rows, CHAINS)`` int64: ``picks[k]`` sent ``points[k - 1]`` to ``points[k]`` (row 0's from the last
        burn-in point).
    """
    work = maps.detach().double().cpu()
    p = probabilities.detach().double().cpu()
    points = np.empty((rows, CHAINS, 2))
    picks = np.empty((rows, CHAINS), np.int64)
    for k, step in enumerate(chaos_chains(work, (p / p.sum()).numpy(), CHAINS, rows, seed)):
        points[k, :, 0], points[k, :, 1], picks[k] = step.x, step.y, step.pick
    return torch.from_numpy(points).to(maps.device), torch.from_numpy(picks).to(maps.device)


class Replay(torch.autograd.Function):
    """``depth`` steps of the chains from fixed starts, differentiable in the maps' coefficients and log-probabilities.

    forward(coef ``(m, 6)``, log_p ``(m,)``, x ``(n,)``, y ``(n,)``, picks ``(depth, n)``) ->
    (xy ``(n, 2)``, score ``(n,)`` the sum of ``log_p`` over each point's picks).
    """

    @staticmethod
    def forward(ctx, coef, log_p, x, y, picks):
        xs, ys = [x], [y]
        score = torch.zeros_like(x, dtype=log_p.dtype)
        for s in picks:
            a, b, tx, c, d, ty = coef.t()[:, s]
            x, y = torch.addcmul(torch.addcmul(tx, a, x), b, y), torch.addcmul(torch.addcmul(ty, c, x), d, y)
            xs.append(x), ys.append(y)
            score = score + log_p[s]
        ctx.save_for_backward(coef, picks, torch.stack(xs[:-1]), torch.stack(ys[:-1]))
        ctx.m = coef.shape[0]
        return torch.stack([x, y], 1), score

    @staticmethod
    def backward(ctx, grad_xy, grad_score):
        coef, picks, xs, ys = ctx.saved_tensors
        m = ctx.m
        gx, gy = grad_xy[:, 0].contiguous(), grad_xy[:, 1].contiguous()
        gcoef = torch.zeros(6, m, dtype=torch.float64, device=coef.device)
        glog = torch.zeros(m, dtype=torch.float64, device=coef.device)
        # bincount sums serially: the same bits at any thread count
        count = lambda s, w: torch.bincount(s, w, minlength=m).double()  # noqa: E731
        for j in range(len(picks) - 1, -1, -1):
            s, x, y = picks[j], xs[j], ys[j]
            for k, w in enumerate((gx * x, gx * y, gx, gy * x, gy * y, gy)):
                gcoef[k] += count(s, w)
            if grad_score is not None:
                glog += count(s, grad_score)
            a, b, _, c, d, _ = coef.t()[:, s]
            gx, gy = a * gx + c * gy, b * gx + d * gy
        return gcoef.t().to(coef.dtype), glog.to(coef.dtype), None, None, None


def replay(maps: torch.Tensor, probabilities: torch.Tensor, points: torch.Tensor, picks: torch.Tensor,
           depth: int) -> tuple[torch.Tensor, torch.Tensor]:
    """The chains' last ``rows - depth`` points rebuilt from their points ``depth`` steps before, with their weights.

    Parameters
    ----------
    maps : torch.Tensor
        ``(m, 3, 3)`` maps; the points are computed in their dtype and on their device.
    probabilities : torch.Tensor
        ``(m,)``.
    points, picks
        Of `chain_points`, with ``rows > depth``.

    Returns
    -------
    xy : torch.Tensor
        ``(n, 2)`` points, differentiable in ``maps`` (the pathwise gradient through ``depth`` steps).
    weight : torch.Tensor
        ``(n,)`` ones, whose gradient in ``probabilities`` is the score of each point's ``depth`` picks.
    """
    kept = points.shape[0] - depth
    dtype = maps.dtype
    start = points[:kept].reshape(-1, 2).to(dtype)
    steps = torch.stack([picks[j:j + kept].reshape(-1) for j in range(1, depth + 1)])
    coef = maps[:, :2, :].reshape(-1, 6)
    xy, score = Replay.apply(coef, probabilities.to(dtype).log(), start[:, 0].contiguous(),
                             start[:, 1].contiguous(), steps)
    return xy, (score - score.detach()).exp()
