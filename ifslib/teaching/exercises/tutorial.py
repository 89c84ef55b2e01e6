"""The tutorial's checks: the Koch maps, leaf counts, contraction, the chaos game, the Hausdorff and collage
distances, a multiscale loss, the best-fit-line start and a Koch fit."""
from __future__ import annotations

import math

import numpy as np
import torch

from ...geometry.ifs import IFS
from ...geometry.patterns import affine, by_name, koch_like, koch_unit
from ...targets.target import Target, load_target
from .harness import apply_maps, as_matrix, as_number, call, fit_report, hausdorff_pair, one_number, random_maps, report


def koch_map(i: int) -> np.ndarray:
    """The true ``3 x 3`` map ``T_i`` (``i = 1 .. 4``) of the Koch curve on the base ``(0,0) -> (1,0)``."""
    return koch_unit().maps().detach().double().numpy()[i - 1]


def check_koch_map(answer, i: int = 3) -> bool:
    """The Koch curve's map ``T_i`` (``i = 1 .. 4``, onto ``p_(i-1) -> p_i``) as a ``(3, 3)`` matrix.

    For the base segment from ``(0, 0)`` to ``(1, 0)``; the paper prints ``T_3`` with a wrong
    translation, and that printed matrix is answered "not yet".
    """
    name = f"T{i}"
    if callable(answer):
        print(f"{name}: not yet. Hint: give the matrix itself, a 3 x 3 list or array, not a function.")
        return False
    value = as_matrix(answer, (3, 3), name)
    if value is None:
        return False
    truth = koch_map(i)
    if np.allclose(value, truth, atol=1e-6):
        return report(True, name, "")
    if not np.allclose(value[2], [0, 0, 1], atol=1e-9):
        return report(False, name, "a homogeneous matrix's last row is (0, 0, 1).")
    if np.allclose(value[:2, :2], truth[:2, :2], atol=1e-6):
        return report(False, name, "the rotation and scale are right; the translation is where the map "
                       "sends the origin, the start of its copy.")
    if np.allclose(value[:2, :2], truth[:2, :2].T, atol=1e-6):
        return report(False, name, "the copy turns the wrong way: which way does the segment "
                       f"p{i - 1} -> p{i} point?")
    return report(False, name, f"the map shrinks the base to the length of p{i - 1} -> p{i} and turns it to "
                   "that segment's direction: read both off the picture.")


def check_leaf_count(answer, pattern: str = "carpet", depth: int = 4) -> bool:
    """How many leaf shapes does ``pattern`` draw at ``depth``?"""
    ifs = by_name(pattern, depth=depth)
    truth = len(ifs.rules) ** depth * len(ifs.primitives)
    name = f"leaves of {pattern} at depth {depth}"
    if isinstance(answer, bool) or not isinstance(answer, (int, np.integer)):
        return report(False, name, f"give a whole number (an int), got {type(answer).__name__}.")
    value = int(answer)
    if value == truth:
        return report(True, name, "")
    m = len(ifs.rules)
    if value == depth ** m or value == m * depth:
        hint = "count depth 1 and depth 2 by hand: how does the count grow from one depth to the next?"
    else:
        hint = f"depth 0 draws the primitive; what does one step of the Hutchinson operator do to a drawing of N shapes with {m} maps?"
    return report(False, name, hint)


def contraction_maps(seed: int = 0, n: int = 4) -> np.ndarray:
    """``(n, 3, 3)`` affine maps with shear, on which the contraction exercise is checked."""
    return random_maps(np.random.default_rng(1000 + seed), n, 0.3, 0.8, shear=0.8)


def check_contraction(answer) -> bool:
    """A function ``f(M) -> (s, x)``: the contraction factor ``s`` of the ``3 x 3`` map ``M`` and its fixed point ``x``.

    ``s`` is the smallest factor with ``|M(a) - M(b)| <= s |a - b|`` for all points: the largest
    singular value of the linear part. The maps of the check shear, so ``sqrt|det|`` and the largest
    eigenvalue are not it.
    """
    name = "contraction and fixed point"
    for M in contraction_maps():
        ok, value = call(answer, "contraction and fixed point", name, M.copy())
        if not ok:
            return False
        try:
            s, x = value
            s, x = float(s), np.asarray(x, dtype=float).reshape(-1)[:2]
            assert x.shape == (2,)
        except Exception:  # noqa: BLE001
            return report(False, name, f"return a pair (s, x): a number and a point (x, y); got {value!r:.60}.")
        lin, t = M[:2, :2], M[:2, 2]
        s_true = float(np.linalg.svd(lin, compute_uv=False)[0])
        x_true = np.linalg.solve(np.eye(2) - lin, t)
        if not math.isclose(s, s_true, rel_tol=1e-6, abs_tol=1e-9):
            if (math.isclose(s, math.sqrt(abs(np.linalg.det(lin))), rel_tol=1e-6)
                    or math.isclose(s, float(np.abs(np.linalg.eigvals(lin)).max()), rel_tol=1e-6)):
                return report(False, name, "sqrt|det L| and the largest eigenvalue say how areas and "
                               "eigenvectors are stretched; a shear stretches some other direction more: "
                               "what is the longest |L v| for a unit vector v?")
            return report(False, name, "s is the largest factor |M(a) - M(b)| / |a - b|; the translation "
                           "cancels in M(a) - M(b).")
        if not np.allclose(x, x_true, atol=1e-7):
            return report(False, name, "s is right; the fixed point solves M(x) = x, a 2 x 2 linear system.")
    return report(True, name, "")


def chaos_maps(seed: int = 0) -> np.ndarray:
    """``(3, 3, 3)``: the three affine maps on which the chaos-game exercise is checked."""
    return random_maps(np.random.default_rng(2000 + seed), 3, 0.35, 0.55)


_REFERENCE: dict[str, object] = {}


def check_chaos_game(answer, n: int = 20_000) -> bool:
    """A function ``f(maps, n, seed) -> (n, 2)`` points of the attractor of ``maps`` (``(m, 3, 3)``).

    Every point must lie on the attractor (within 0.01 plane units of the reference cloud) and the
    points must cover it (95 % of the reference within 0.02 of a student point).
    """
    from ...raster.chaos import chaos_game as reference_game

    name = "chaos game"
    maps = chaos_maps()
    if "chaos" not in _REFERENCE:  # the same every time: drawn once per session
        _REFERENCE["chaos"] = reference_game(affine(maps), 200_000, seed=1)
    reference = _REFERENCE["chaos"]
    ok, value = call(answer, "chaos game", name, maps.copy(), n, 0)
    points = as_matrix(value, (n, 2), name) if ok else None
    if points is None:
        return False
    from scipy.spatial import cKDTree

    if "chaos tree" not in _REFERENCE:
        _REFERENCE["chaos tree"] = cKDTree(reference)
    off = _REFERENCE["chaos tree"].query(points)[0]
    if off.max() > 0.01:
        return report(False, name, f"{int((off > 0.01).sum())} of your points are off the attractor: where does "
                       "your walk start, and is that point on the attractor?")
    missed = cKDTree(points).query(reference[::10])[0]   # 20,000 reference points judge the cover
    if np.quantile(missed, 0.95) > 0.02:
        return report(False, name, "your points lie on the attractor but miss parts of it: does every step "
                       "choose its map at random, a new choice each step?")
    return report(True, name, "")


def check_hausdorff(answer) -> bool:
    """A function ``f(a, b) -> float``: the Hausdorff distance between point sets ``(N, 2)`` and ``(M, 2)``."""
    name = "Hausdorff distance"
    rng = np.random.default_rng(3000)
    cases = [(rng.uniform(-0.5, 0.5, (60, 2)), rng.uniform(-0.5, 0.5, (85, 2)))]
    a = rng.uniform(-0.5, 0.5, (70, 2))
    cases.append((a, np.vstack([a[:40] + rng.normal(0, 0.01, (40, 2)), [[0.9, 0.9]]])))  # b has an outlier
    cases.append((cases[1][1], cases[1][0]))
    for a, b in cases:
        value, failed = one_number(answer, "Hausdorff distance", name, a.copy(), b.copy())
        if value is None:
            return failed
        ab, ba = hausdorff_pair(a, b)
        if math.isclose(value, max(ab, ba), rel_tol=1e-9, abs_tol=1e-12):
            continue
        if math.isclose(value, ab, rel_tol=1e-9) or math.isclose(value, ba, rel_tol=1e-9):
            return report(False, name, "that is one direction only: a set can lie close to the other "
                           "while the other has points far from it.")
        return report(False, name, "for each point of one set, how far is the nearest point of the other? "
                       "Which of those distances does the definition keep?")
    return report(True, name, "")


def check_scaled_distance(answer, s: float = 1 / 3, d: float = 0.3) -> bool:
    """A point is at distance ``d`` from S, measured after pulling it back by ``T^-1``; its distance to ``T(S)``?"""
    truth = s * d
    name = "distance to T(S)"
    value = as_number(answer)
    if value is None:
        return report(False, name, f"give one number, got {type(answer).__name__}.")
    if math.isclose(value, truth, rel_tol=1e-6):
        return report(True, name, "")
    if math.isclose(value, d / s, rel_tol=1e-6):
        return report(False, name, "that is the paper's printed law: does a map that shrinks every shape "
                       "make distances larger?")
    return report(False, name, "T takes S, and the nearest point of S, to T(S): what does it do to the "
                   "segment between the point and its nearest point?")


def collage_maps(seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Maps ``(3, 3, 3)`` and a point set ``(200, 2)`` on which the collage exercise is checked."""
    rng = np.random.default_rng(4000 + seed)
    return random_maps(rng, 3, 0.3, 0.5), rng.uniform(-0.4, 0.4, (200, 2))


def check_collage_distance(answer) -> bool:
    """A function ``f(maps, points) -> float``: the Hausdorff distance from ``points`` to the union of its copies."""
    name = "collage distance"
    for seed in range(2):
        maps, points = collage_maps(seed)
        value, failed = one_number(answer, "collage distance", name, maps.copy(), points.copy())
        if value is None:
            return failed
        truth = max(hausdorff_pair(points, apply_maps(maps, points)))
        if math.isclose(value, truth, rel_tol=1e-9):
            continue
        each = max(max(hausdorff_pair(points, apply_maps(maps[i:i + 1], points))) for i in range(len(maps)))
        if math.isclose(value, each, rel_tol=1e-9):
            return report(False, name, "compare the points with all the copies together, their union, "
                           "not with each copy in turn.")
        return report(False, name, "make the collage: every map applied to every point, all in one set; "
                       "then measure it against the points.")
    return report(True, name, "")


def _reference_multiscale(a: torch.Tensor, b: torch.Tensor, levels: int = 4) -> torch.Tensor:
    total = (a - b).square().mean()
    x, y = a[None, None], b[None, None]
    for _ in range(levels):
        x, y = torch.nn.functional.avg_pool2d(x, 2), torch.nn.functional.avg_pool2d(y, 2)
        total = total + (x - y).square().mean()
    return total


def check_loss(answer) -> bool:
    """A function ``f(image, target) -> scalar tensor``: the multiscale pixel loss with 4 pooled copies.

    ``image`` and ``target`` are ``(size, size)`` tensors (size a multiple of 16); the loss is the MSE
    of the two images plus the MSE of each of 4 copies, each averaged over 2 x 2 blocks of the one
    before. It must be differentiable in ``image``: the check compares its gradient too.
    """
    name = "multiscale pixel loss"
    rng = np.random.default_rng(5000)
    for size in (32, 48):
        image = torch.tensor(rng.random((size, size)), dtype=torch.float64, requires_grad=True)
        target = torch.tensor(rng.random((size, size)) < 0.3, dtype=torch.float64)
        ok, value = call(answer, "loss", name, image, target.clone())
        if not ok:
            return False
        if not isinstance(value, torch.Tensor) or value.numel() != 1:
            return report(False, name, "return a torch scalar (a tensor with one number), computed with torch "
                           "so that it has a gradient.")
        truth = _reference_multiscale(image, target)
        got = float(value.detach())
        if not math.isclose(got, float(truth.detach()), rel_tol=1e-6):
            if math.isclose(got, float((image - target).square().mean().detach()), rel_tol=1e-6):
                hint = "that is the plain pixel loss; add the pooled copies."
            else:
                hint = ("the first term compares the images themselves; each further term, copies with 2 x 2 "
                        "blocks averaged, one level coarser each time.")
            return report(False, name, hint)
        if not value.requires_grad:
            return report(False, name, "the value is right but it has no gradient: compute it with torch "
                           "operations only (no .numpy(), no float()).")
        grad, = torch.autograd.grad(value, image)
        true_grad, = torch.autograd.grad(truth, image)
        if not torch.allclose(grad, true_grad, rtol=1e-5, atol=1e-12):
            return report(False, name, "the value is right but its gradient is not: is a detached copy in it?")
    return report(True, name, "")


def koch_target(size: int = 64, seed: int = 0) -> Target:
    """A Koch-like curve the library does not ship: its five points drawn at random (seeded), turned, at ``size``.

    The fit exercise's target; the plain `ifslib.patterns.koch` lies more than a pixel from it.
    """
    return load_target(_koch_truth(seed), size, depth="attractor")


def _koch_truth(seed: int = 0) -> IFS:
    rng = np.random.default_rng(6000 + seed)
    knee = rng.uniform(0.3, 0.36)
    peak = [rng.uniform(0.45, 0.55), rng.uniform(0.22, 0.3)]
    shape = np.array([[0, 0], [knee, 0], peak, [1 - rng.uniform(0.3, 0.36), 0], [1, 0]])
    pts = (shape - [0.5, (shape[:, 1].max() + shape[:, 1].min()) / 2]) * 0.8
    turn = math.radians(rng.choice([-1, 1]) * rng.uniform(20, 40))
    c, s = math.cos(turn), math.sin(turn)
    return koch_like(pts @ np.array([[c, s], [-s, c]]), depth=3, name="koch_exercise")


def check_best_fit_start(answer) -> bool:
    """A function ``f(pattern, target) -> (n, 2)``: a curve pattern's points spread along the target's best-fit line.

    Evenly spaced, in index order, between the extreme projections of the target's foreground pixel
    centres on its principal axis (either end first).
    """
    from ...discovery.initialization import _placed
    from ...geometry.patterns import koch

    name = "best-fit-line start"
    for seed, pattern in ((1, koch()), (2, koch_like([[-0.4, 0], [-0.1, 0.1], [0.1, -0.1], [0.4, 0]]))):
        target = koch_target(48, seed)
        truth = _placed(pattern, target)
        ok, value = call(answer, "best-fit-line start", name, pattern.clone(), target)
        if not ok:
            return False
        if isinstance(value, IFS):
            value = value.points.detach()
        try:
            points = np.asarray(value.numpy() if isinstance(value, torch.Tensor) else value, dtype=float)
        except (TypeError, ValueError):
            return report(False, name, f"return the points, an (n, 2) array, got {type(value).__name__}.")
        if points.shape != truth.shape:
            return report(False, name, f"return one point per control point of the pattern, {truth.shape}; "
                           f"got shape {points.shape}.")
        if np.allclose(points, truth, atol=1e-4) or np.allclose(points, truth[::-1], atol=1e-4):
            continue
        gaps = np.linalg.norm(np.diff(points, axis=0), axis=1)
        if gaps.std() > 1e-6 * max(gaps.mean(), 1e-12):
            return report(False, name, "space the points evenly, in the pattern's order.")
        if np.allclose(points.mean(0), truth.mean(0), atol=1e-3):
            return report(False, name, "centred right; the line's direction or length is off: which direction "
                           "do the foreground pixels spread the most along, and how far?")
        return report(False, name, "the line goes through the mean of the foreground pixels' centres.")
    return report(True, name, "")


def check_koch_fit(answer, size: int = 64) -> bool:
    """A fitted IFS whose attractor lies within 1 px (Chamfer) of `koch_target` and does not cross itself."""
    return fit_report(answer, koch_target(size), "Koch fit", curve=True)
