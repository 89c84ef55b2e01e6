"""Attractor coding: improve a collage code for the image the decoder returns, not for the collage.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import torch
from tqdm.auto import tqdm

from ..core.fitting.descent import Descent, StepPolicy
from ..errors import IFSError
from .code import Code
from .config import DECODE_MAX_ITER, DECODE_TOL, RefineOptions
from .decode import Plan, fixed_point, iterate, plan, post_filter, shapes, start_image
from .encode import check_image, pad, search
from .quantize import dequantize_m, dequantize_s, zero_s
from .partitions import partition_of
from .rates import Choice, domain_cost
from .rectangles import isometry_count, rectangle_isometry, rectangle_pool


def implicit_fixed_point(p: Plan, s: torch.Tensor, m: torch.Tensor, start: torch.Tensor,
                         tol: float = DECODE_TOL, max_iter: int = DECODE_MAX_ITER) -> torch.Tensor:
    """The decoder's fixed point ``(H, W)``, differentiable in ``s`` and ``m`` ``(L,)`` by its implicit derivative.

    The forward pass iterates without a graph; the backward pass solves v = g + J^T v by iteration
    (to ``tol`` relative to g, at most ``max_iter`` times), then back-propagates v through one step.
    """
    with torch.no_grad():
        star, _, _ = fixed_point(p, s.detach(), m.detach(), start, tol, max_iter)
    out = iterate(p, star, s, m)
    if not out.requires_grad:
        return out
    x0 = star.clone().requires_grad_()
    with torch.enable_grad():
        f0 = iterate(p, x0, s.detach(), m.detach())

    def adjoint(g: torch.Tensor) -> torch.Tensor:
        v = g
        for _ in range(max_iter):
            new = g + torch.autograd.grad(f0, x0, v, retain_graph=True)[0]
            done = float((new - v).abs().max()) <= tol * max(float(g.abs().max()), 1e-30)
            v = new
            if done:
                break
        return v

    out.register_hook(adjoint)
    return out


def decoded_error(code: Code, target: torch.Tensor, p: Plan | None = None, start=None) -> tuple[float, torch.Tensor]:
    """``(mean squared error of the decoded, post-filtered image against target (h, w), the padded fixed point)``."""
    p = plan(code) if p is None else p
    start = start_image(p, None, target.dtype) if start is None else start
    with torch.no_grad():
        x, _, _ = fixed_point(p, code.s(target.dtype), code.m(target.dtype), start)
    h, w = target.shape
    return float(((post_filter(p, x, code.options.deblock)[:h, :w].clamp(0, 1) - target) ** 2).mean()), x


def search_again(code: Code, target: torch.Tensor, decoded: torch.Tensor, price: Choice | None = None) -> Code:
    """Every non-flat block's domain, isometry, s and m searched with the pool cut from ``decoded`` ``(H, W)``;
    with ``price`` (`rates.Choice`), each domain's coded bits at its price of a bit added to its error."""
    fields = {name: getattr(code, name).clone() for name in ("domain", "iso", "s_idx", "m_idx")}
    H, W = target.shape
    for bh, bw in shapes(code):
        at = torch.nonzero((code.heights == bh) & (code.widths == bw) & ~code.flat)[:, 0]
        if len(at) == 0:
            continue
        rows = (code.y[at, None, None] + torch.arange(bh)[:, None]) * W + code.x[at, None, None] + torch.arange(bw)
        blocks = target.reshape(-1)[rows.reshape(len(at), -1)]
        penalty = None
        if price is not None and price.models is not None and price.lam > 0:  # models: `fields.Models`
            penalty = price.lam * domain_cost(price.models, H, W, bh, code.y[at].numpy(), code.x[at].numpy())
        pool = rectangle_pool(decoded, bh, bw)
        domains = torch.stack([rectangle_isometry(pool, k).reshape(len(pool), -1) for k in range(isometry_count(bh, bw))])
        fit = search(blocks, domains, code.options, torch.ones(len(at), dtype=torch.bool), penalty)
        for name in fields:
            fields[name][at] = getattr(fit, name)
    return code.with_maps(**fields)


def _levels(latent: torch.Tensor, low: int, high: int) -> torch.Tensor:
    """Rounded levels in [low, high] in the forward pass, the identity in the backward pass."""
    return latent + (latent.round().clamp(low, high) - latent).detach()


def descend(code: Code, target: torch.Tensor, steps: int, lr: float, progress: bool = False,
            budget: float = float("inf")) -> Code:
    """Adam (`Descent`) on the blocks' s and m levels through the fixed point; the best quantized code seen
    whose fields fit in ``budget`` bits is returned (``code`` itself if none closer does)."""
    o, p = code.options, plan(code)
    h, w = target.shape
    zero, flat = zero_s(o), code.flat
    s_lat, m_lat = (levels.to(target.dtype).requires_grad_() for levels in (code.s_idx, code.m_idx))
    best_err, x = decoded_error(code, target, p)
    closer = []  # each code closer than all before it: the last that fits in the budget is returned

    def loss() -> torch.Tensor:
        nonlocal best_err, x
        s_level = _levels(s_lat, 0, 2 * zero - 1)
        # a non-flat block keeps a non-zero s (its domain's bits stay in the file); a flat one stays flat
        bump = torch.where(s_lat.detach() >= zero, 1.0, -1.0)
        s_level = torch.where(flat, float(zero), torch.where(s_level.detach() == zero, s_level + bump, s_level))
        m_level = _levels(m_lat, 0, 2**o.m_bits - 1)
        x = implicit_fixed_point(p, dequantize_s(s_level, o, target.dtype), dequantize_m(m_level, o, target.dtype),
                                 x.detach())
        out = post_filter(p, x, o.deblock)[:h, :w]  # the decoder's output: the filter is linear, after the fixed point
        err = float(((out.detach().clamp(0, 1) - target) ** 2).mean())
        if err < best_err:
            best_err = err
            closer.append(code.with_maps(s_idx=s_level.detach().round().long(), m_idx=m_level.detach().round().long()))
        return ((out - target) ** 2).mean()

    policy = StepPolicy(rollback=True, name="attractor descent")  # a step whose gradient is not finite is undone
    with tqdm(total=steps, desc="attractor descent", disable=not progress, leave=False) as bar:
        Descent([{"params": [s_lat, m_lat], "lr": lr}], loss, policy).run(steps, bar=bar)
    # coding a code to count its bits costs as much as a step: only the closest few are coded
    return next((c for c in reversed(closer) if _fits(c, budget)), code)


def _fits(code: Code, budget: float) -> bool:
    """Whether ``code``'s fields take at most ``budget`` bits (coded ones are coded to know)."""
    return budget == float("inf") or code.bits() <= budget


def refine_maps(code: Code, target: torch.Tensor, padded: torch.Tensor, options: RefineOptions,
                progress: bool = False, budget: float = float("inf"),
                price: Choice | None = None) -> tuple[Code, float, torch.Tensor]:
    """Moves 1 and 2 on a fixed partition, each kept only within ``budget`` bits: ``(code, its decoded mean
    squared error, its padded fixed point)``."""
    best_err, x = decoded_error(code, target)
    for _ in range(options.searches):
        candidate = search_again(code, padded, x, price)
        err, new_x = decoded_error(candidate, target)
        if err >= best_err or not _fits(candidate, budget):
            break
        code, best_err, x = candidate, err, new_x
    if options.steps:
        code = descend(code, target, options.steps, options.lr, progress, budget)
        best_err, x = decoded_error(code, target)
    return code, best_err, x


def refine(code: Code, image, options: RefineOptions = RefineOptions(), progress: bool = False,
           price: Choice | None = None, budget_bits: float | None = None) -> Code:
    """Attractor coding: ``code`` improved for its decoded image's distance to ``image``, in no more bits.

    Parameters
    ----------
    code : Code
        A code of ``image`` (from `encode.encode`).
    image : array or torch.Tensor
        ``(h, w)`` gray levels in [0, 1], the code's size.
    options : RefineOptions
    progress : bool
        Show bars over the steps.
    price : rates.Choice, optional
        What chose ``code`` (`encode.collage`): its price of a bit and models price the domains searched
        again; without it they are chosen by error alone (and kept only if the file does not grow).
    budget_bits : float, optional
        The most bits of fields (`Code.bits`) the result may take; default, and at least, ``code.bits()``.

    Returns
    -------
    Code
        No more bits than ``code`` or ``budget_bits``, whichever is more (so no larger a file than the
        rate asked); with ``options.repartitions == 0`` the same partition and flat blocks. Never decodes
        worse.
    """
    target = check_image(image).float()
    if tuple(target.shape) != (code.height, code.width):
        raise IFSError(f"the image is {tuple(target.shape)} but the code is of a {code.height} x {code.width} image")
    padded = pad(target, code.options)
    budget = max(code.bits(), budget_bits or 0)
    code, best_err, x = refine_maps(code, target, padded, options, progress, budget, price)
    for _ in range(options.repartitions):
        chosen = partition_of(code.options).at_rate(padded, x, code.height, code.width, code.options, budget, progress)
        candidate, err, new_x = refine_maps(chosen.code, target, padded, options, progress, budget, chosen)
        if err >= best_err:
            break
        code, best_err, x = candidate, err, new_x
    return code
