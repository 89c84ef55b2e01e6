"""How good a fit is: IoU, F1, Chamfer distance, control-point error and self-crossings (docs/guide/conventions.md)."""
from __future__ import annotations

import numpy as np
import torch
from scipy import ndimage

from ...errors import LeafBudgetError
from ..geometry.attractor import ATTRACTOR, is_attractor
from ..geometry.crossings import crossing_pairs, is_curve, leaf_segments
from ..geometry.ifs import IFS
from ..raster.distance import Budget
from ..raster.render import figure_mask
from ..targets.target import Target

#: Tolerance in pixels of the attractor's distance when it is scored.
EVAL_TOLERANCE = 0.25
#: Above this many leaves in the certified cut, the attractor is scored by the chaos game ...
EVAL_MAX_LEAVES = 1_000_000
#: ... with this many float64 points.
EVAL_POINTS = 2_000_000


def iou(pred: np.ndarray, true: np.ndarray) -> float:
    """Intersection over union of two boolean masks (1.0 when both are empty)."""
    union = np.logical_or(pred, true).sum()
    return float(np.logical_and(pred, true).sum() / union) if union else 1.0


def f1(pred: np.ndarray, true: np.ndarray) -> float:
    """F1 score (Dice) of a predicted mask against the true one."""
    total = pred.sum() + true.sum()
    return float(2 * np.logical_and(pred, true).sum() / total) if total else 1.0


def chamfer(pred: np.ndarray, true: np.ndarray) -> float:
    """Symmetric Chamfer distance in pixels: the mean of the two directed mean distances (``inf`` if a mask is empty)."""
    if not pred.any() or not true.any():
        return float("inf")
    to_true = ndimage.distance_transform_edt(~true)
    to_pred = ndimage.distance_transform_edt(~pred)
    return float(0.5 * (to_true[pred].mean() + to_pred[true].mean()))


def scores(pred: np.ndarray, true: np.ndarray) -> dict[str, float]:
    """IoU, F1 and Chamfer (pixels) of a predicted mask against the true one."""
    return {"iou": iou(pred, true), "f1": f1(pred, true), "chamfer": chamfer(pred, true)}


def attractor_mask(ifs: IFS, size: int, sigma: float | None = None, tolerance: float = EVAL_TOLERANCE) -> np.ndarray:
    """The attractor's pixels at ``size`` (its render >= 0.5): from the certified field within ``tolerance`` pixels, or by
    the chaos game (`EVAL_POINTS` points, seed 0) when the cut has more than `EVAL_MAX_LEAVES` leaves."""
    try:
        return figure_mask(ifs, size, ATTRACTOR, sigma, tolerance=tolerance, budget=Budget(leaves=EVAL_MAX_LEAVES))
    except LeafBudgetError:
        return figure_mask(ifs, size, ATTRACTOR, sigma, method="chaos", points=EVAL_POINTS)


def evaluate(ifs: IFS, target: Target, depth: int | str | None = None, sigma: float | None = None,
             attractor: bool = True) -> dict[str, float]:
    """IoU, F1 and Chamfer (pixels) of an IFS against a target: its drawing at ``depth`` (``ifs.depth`` when None)
    and, with ``attractor``, its attractor (``attractor_iou``, ...); ``depth="attractor"`` scores only the attractor."""
    if is_attractor(depth):
        return scores(attractor_mask(ifs, target.size, sigma), target.mask)
    out = scores(figure_mask(ifs, target.size, depth, sigma), target.mask)
    if attractor:
        out.update({f"attractor_{k}": v for k, v in scores(attractor_mask(ifs, target.size, sigma), target.mask).items()})
    return out


def caption(ifs: IFS, target: Target) -> str:
    """The one number that judges a fit: Chamfer (pixels) for a curve, on which IoU is harsh, IoU for a figure."""
    m = evaluate(ifs, target, attractor=False)
    return f"Chamfer {m['chamfer']:.2f} px" if is_curve(ifs) else f"IoU {m['iou']:.2f}"


def _normalize(points: np.ndarray, a: int, b: int) -> np.ndarray:
    """Points under the similarity taking point a to (0, 0) and point b to (1, 0)."""
    z = points[:, 0] + 1j * points[:, 1]
    w = (z - z[a]) / (z[b] - z[a])
    return np.stack([w.real, w.imag], 1)


def point_error(ifs: IFS, reference: IFS) -> float:
    """Control-point error against a known IFS, up to similarity and reflection: the RMS distance after mapping
    the first rule's source segment onto ``(0, 0) -> (1, 0)``, the smaller of the direct and the reflected comparison."""
    a, b = reference.rules[0].source
    p = _normalize(ifs.points.detach().cpu().double().numpy(), a, b)
    q = _normalize(reference.points.detach().cpu().double().numpy(), a, b)
    flipped = p * np.array([1.0, -1.0])
    return float(min(np.sqrt(((p - q) ** 2).sum(1).mean()), np.sqrt(((flipped - q) ** 2).sum(1).mean())))


def curve_segments(ifs: IFS, depth: int | None = None) -> np.ndarray:
    """The depth-K copies ``(W * p, 2, 2)`` of a curve's segment primitives, in drawing order."""
    with torch.no_grad():
        return leaf_segments(ifs.to(torch.float64), depth).numpy()


def crossing_points(ifs: IFS, depth: int | None = None) -> np.ndarray:
    """Where a curve's depth-K segments properly cross each other: ``(k, 2)`` points, one per pair (touching
    or collinear segments do not cross)."""
    with torch.no_grad():
        segments = leaf_segments(ifs.to(torch.float64), depth)
        i, j, (_, _, cda, cdb) = crossing_pairs(segments)  # the predicate the crossing penalty uses
    i, j = i.numpy(), j.numpy()
    seg = segments.numpy()
    # The crossing lies on segment i at the fraction |cd x ca| / (|cd x ca| + |cd x cb|).
    za, zb = np.abs(cda[i, j].numpy()), np.abs(cdb[i, j].numpy())
    t = (za / (za + zb))[:, None]
    return seg[i, 0] + t * (seg[i, 1] - seg[i, 0])


def self_crossings(ifs: IFS, depth: int | None = None) -> int:
    """How many pairs of a curve's depth-K segments properly cross each other (see `crossing_points`)."""
    return len(crossing_points(ifs, depth))


def hausdorff(a: np.ndarray, b: np.ndarray) -> float:
    """Hausdorff distance between two point sets ``(N, 2)`` and ``(M, 2)`` (plane units), by KD-trees."""
    from scipy.spatial import cKDTree

    if len(a) == 0 or len(b) == 0:
        return float("inf")
    return float(max(cKDTree(b).query(a)[0].max(), cKDTree(a).query(b)[0].max()))


def curve_points(ifs: IFS, depth: int | None = None, spacing: float = 1e-3) -> np.ndarray:
    """Points along a curve's depth-K segments, at most ``spacing`` apart: ``(N, 2)`` float64."""
    seg = curve_segments(ifs, depth)
    out = []
    for a, b in seg:
        n = max(2, int(np.ceil(np.linalg.norm(b - a) / spacing)) + 1)
        out.append(a + np.linspace(0, 1, n)[:, None] * (b - a))
    return np.concatenate(out)


def depth_to_attractor(ifs: IFS, depths, points: int = 1_000_000, spacing: float = 1e-3, seed: int = 0) -> list[float]:
    """The Hausdorff distance between a curve's drawing at each depth (sampled every ``spacing``) and its attractor
    (``points`` of the chaos game); it shrinks like ``s^K`` for maps of contraction at most ``s``."""
    from ..raster.chaos import chaos_game

    limit = chaos_game(ifs, points, seed)
    return [hausdorff(curve_points(ifs, k, spacing), limit) for k in depths]
