"""A pattern placed on a target (paper, "Initial Conditions"), from the target's pixels alone (no search: a
start read from the image itself is the automatic path's, `ifslib.discover`)."""
from __future__ import annotations

import numpy as np

from ...errors import MAX_SEED, IFSError, check_int
from ..geometry.crossings import is_curve
from ..geometry.ifs import IFS
from .target import Target, foreground_points


def best_fit_line(target: Target) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The principal axis of the foreground: its mean ``(2,)``, the unit direction of largest variance (pointing
    right, or up) and the extreme projections ``lo, hi`` on it, relative to the mean."""
    pts = foreground_points(target)
    centre = pts.mean(0)
    _, _, vt = np.linalg.svd(pts - centre, full_matrices=False)
    direction = vt[0]
    if direction[0] < -1e-12 or (abs(direction[0]) <= 1e-12 and direction[1] < 0):
        direction = -direction
    proj = (pts - centre) @ direction
    return centre, direction, float(proj.min()), float(proj.max())


def check_jitter(jitter: float, seed: int | None) -> None:
    """Raise `IFSError` unless ``jitter`` is a number from 0 to 1 and ``seed`` None or an int from 0 to ``MAX_SEED``."""
    if isinstance(jitter, bool) or not isinstance(jitter, (int, float)) or not 0 <= jitter <= 1:
        raise IFSError(f"jitter must be a number from 0 to 1 (plane units: the frame is 1 wide), got {jitter!r}")
    if seed is not None:
        check_int(seed, "seed", 0, maximum=MAX_SEED)


def initialize(pattern: IFS, target: Target, jitter: float = 0.0, seed: int | None = None) -> IFS:
    """A start for fitting ``target`` (paper, "Initial Conditions"): a curve's points evenly spaced along the target's
    best-fit line, any other pattern stretched onto its bounding box, then jittered by ``jitter`` (seeded)."""
    if isinstance(pattern, str):
        hint = ("a start read from the image is ifslib.discover(target) (import ifslib.automatic)"
                if pattern == "auto" else "patterns by name: ifslib.patterns.by_name")
        raise IFSError(f"initialize takes an IFS, got {pattern!r}: {hint}")
    if not isinstance(pattern, IFS):
        raise IFSError(f"initialize takes an IFS (ifslib.patterns), got {type(pattern).__name__}")
    check_jitter(jitter, seed)
    return pattern.clone(placed_points(pattern, target)).jittered(jitter, np.random.default_rng(seed))


def placed_points(ifs: IFS, target: Target) -> np.ndarray:
    """``(n, 2)`` the pattern's points on the target: along its best-fit line (curves) or on its bounding box."""
    n = ifs.n_points
    if not is_curve(ifs):
        fg = foreground_points(target)
        lo, hi = fg.min(0), fg.max(0)
        pts = ifs.points.detach().double().numpy()
        plo, phi = pts.min(0), pts.max(0)
        return lo + (pts - plo) / np.where(phi > plo, phi - plo, 1) * (hi - lo)
    centre, direction, lo, hi = best_fit_line(target)
    return centre + np.linspace(lo, hi, n)[:, None] * direction
