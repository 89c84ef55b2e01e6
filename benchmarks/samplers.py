"""Random affine IFSs of the kinds the literature draws: a fern's stem, a dominant spiral, strongly
overlapping copies, and many maps (Anderson and Farrell's sampler), each redrawn until its attractor
is neither dust nor a blob.

`literature_ifs(kind, maps, seed)` draws one; `copy_overlap` and `acceptance` measure what the classes
promise. The attractor is drawn here from sampled leaves (`sample_attractor`: the chaos game on the
word tree, within half a pixel), on the pixel grid `ifslib.render` uses (row 0 at ``y = 0.5``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import torch
from scipy import ndimage

from ifslib.errors import IFSError, LeafBudgetError, check_int, check_positive
from ifslib.core.geometry.attractor import attractor_ball, attractor_leaves
from ifslib.core.geometry.ifs import IFS
from ifslib.core.geometry.patterns import affine
from ifslib.core.geometry.random_fractals import MAX_RANDOM_SCALE, random_ifs
from ifslib.core.geometry.sampled import sample_attractor

#: The classes, and the numbers of maps each draws (inclusive).
MAP_RANGE = {"stem": (3, 6), "spiral": (2, 4), "overlap": (2, 6), "many": (6, 10)}
KINDS = tuple(MAP_RANGE)

#: A stem map's smallest singular value lies in [STEM_FLOOR, STEM_THIN]: a segment to the eye. Not 0, as
#: the fern's stem is not (`FERN_MAPS`): a drawing at a depth K needs every map's inverse.
STEM_FLOOR, STEM_THIN = 0.001, 0.05
#: The spiral's dominant similarity: its scale and the size of its turn (degrees, either sense).
SPIRAL_SCALE, SPIRAL_TURN = (0.75, 0.92), (10.0, 60.0)
#: The overlap class: the copies' areas add up to this many times the attractor's own extent
#: (``sum |det L_i|``; above 1 the copies of a figure with area must overlap) ...
OVERLAP_AREA = (1.2, 1.8)
#: ... and at least this share of the attractor's pixels lies in two copies or more (`copy_overlap`).
OVERLAP_SHARE = 0.3


@dataclass(frozen=True)
class Acceptance:
    """When a drawn IFS is kept: its attractor drawn twice at ``size`` from ``points`` sampled leaves.

    Attributes
    ----------
    size : int
        Pixels per side of the frame ``[-0.5, 0.5]^2``.
    share : (float, float)
        The attractor's share of the frame's pixels: below it is dust, above it a blob.
    agreement : float
        The IoU the two drawings (seeds 0 and 1) must exceed: below it ``points`` do not cover the
        attractor, and a target drawn from it would depend on the seed.
    points : int
        Leaves a drawing.
    attempts : int
        Draws before giving up.
    """

    size: int = 128
    share: tuple[float, float] = (0.02, 0.60)
    agreement: float = 0.9
    points: int = 100_000
    attempts: int = 64


ACCEPT = Acceptance()


def literature_ifs(kind: str, maps: int, seed: int = 0, depth: int = 3, extent: float = 0.8,
                   accept: Acceptance = ACCEPT) -> IFS:
    """A random contractive affine IFS of one class, fitted into the frame, kept by a seeded rule.

    Classes (parameters in this module's constants):

    ``"stem"``
        A tree or a fern: one or two maps of rank one or nearly (smallest singular value in
        [`STEM_FLOOR`, `STEM_THIN`]) squash the whole onto a segment from the base, the *stem*; the
        others hang copies on it: one continues it at its top (scale 0.45-0.8, turned at most 15°),
        the rest branch from points along it (scale 0.25-0.45, turned 25-75° to either side, half
        of them reflected). The stem's length is set from the attractor's box with a first stem, so
        that its top is where the continuation hangs: the copies hang on it, not beside it.
    ``"spiral"``
        A dominant similarity of scale in `SPIRAL_SCALE` turning by 10-60° about a centre, plus 1-3
        small affine maps whose fixed points lie 0.5-1 from it; each small map's scale is 0.45-0.85
        times the spiral's step ``|1 - r e^{i theta}|`` (the gap between successive copies along the
        arm, at distance 1), about what makes successive copies touch: smaller is dust, larger a blob.
    ``"overlap"``
        Maps of scale 0.5-0.9 with singular values in a ratio of 0.5-1, scaled together so that
        ``sum |det L_i|`` is in `OVERLAP_AREA`, their fixed points spread round a circle; kept only
        when at least `OVERLAP_SHARE` of the attractor lies in two copies or more. The attractor is
        solid, with a fractal edge.
    ``"many"``
        `random_ifs` with 6-10 maps (Anderson and Farrell's sampler, as Djeacoumar et al., CGF 2025,
        use), redrawn with seed ``seed * accept.attempts + attempt``.

    Every IFS is then moved and scaled (conjugated by one similarity) so that its attractor's box is
    centred with its longer side ``extent``, and kept when `acceptance` passes (its share of the
    frame within ``accept.share``, two drawings agreeing to IoU above ``accept.agreement``), else
    redrawn from the same generator: the same ``(kind, maps, seed)`` gives the same IFS.

    Parameters
    ----------
    kind : {"stem", "spiral", "overlap", "many"}
    maps : int
        Number of maps, within `MAP_RANGE` of the class.
    seed : int
        Seeds `numpy.random.default_rng` (with the class and the number of maps).
    depth : int
    extent : float
        Longer side of the attractor's box, plane units (0.75 leaves the 12.5 % border that the
        literature's scores crop).
    accept : Acceptance

    Returns
    -------
    IFS
        ``maps`` affine rules (`ifslib.patterns.affine`), named ``<kind><maps>_<seed>``.

    Raises
    ------
    IFSError
        On an unknown class, a number of maps outside the class's range, a bad seed or extent, or
        when no draw passes in ``accept.attempts``.
    """
    if kind not in MAP_RANGE:
        raise IFSError(f"literature_ifs draws one of {', '.join(KINDS)}; got {kind!r}")
    low, high = MAP_RANGE[kind]
    check_int(maps, f"the number of maps of a {kind!r} IFS", low, maximum=high)
    check_int(seed, "seed", 0)
    extent = check_positive(extent, "extent")
    if extent > 1:
        raise IFSError(f"extent is the attractor's longer side in the frame of side 1: at most 1, got {extent}")
    rng = np.random.default_rng([KINDS.index(kind), maps, seed])
    for attempt in range(accept.attempts):
        if kind == "many":
            framed = random_ifs(maps, seed * accept.attempts + attempt, extent=extent).maps().detach().double()
        else:
            framed = fit_to_frame(DRAW[kind](rng, maps), extent)
        share, agreement = acceptance(framed, accept)
        keep = accept.share[0] <= share <= accept.share[1] and agreement > accept.agreement
        if keep and kind == "overlap":
            keep = copy_overlap(framed, accept.size, accept.points) >= OVERLAP_SHARE
        if keep:
            return affine(framed[:, :2].numpy(), depth=depth, name=f"{kind}{maps}_{seed}")
    raise IFSError(f"no {kind!r} IFS of {maps} maps passed in {accept.attempts} draws from seed {seed}: "
                   "try another seed, or loosen the Acceptance")


def _rotations(rng: np.random.Generator, k: int) -> np.ndarray:
    """``(k, 2, 2)`` random rotations, each composed with a random reflection of the axes (as `random_ifs`)."""
    angle = rng.uniform(-math.pi, math.pi, k)
    flip = np.where(rng.random((k, 2)) < 0.5, -1.0, 1.0)
    c, s = np.cos(angle), np.sin(angle)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2) * flip[:, None, :]


def _turn(angle: float) -> np.ndarray:
    """The rotation by ``angle`` radians, ``(2, 2)``."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s], [s, c]])


def _full(linear: np.ndarray, shift: np.ndarray) -> torch.Tensor:
    """``(k, 3, 3)`` float64 maps from ``(k, 2, 2)`` linear parts and ``(k, 2)`` shifts."""
    out = torch.zeros(len(linear), 3, 3, dtype=torch.float64)
    out[:, :2, :2], out[:, :2, 2], out[:, 2, 2] = torch.as_tensor(linear), torch.as_tensor(shift), 1.0
    return out


def _stem(rng: np.random.Generator, maps: int) -> torch.Tensor:
    """A stem's maps in a frame where the stem rises from the origin to ``(0, 1)``, turned at random."""
    stems = 2 if maps >= 4 and rng.random() < 0.5 else 1
    linear, shift = [], []
    for i in range(maps - stems):
        mirror = np.diag([-1.0, 1.0]) if rng.random() < (0.3 if i == 0 else 0.5) else np.eye(2)
        if i == 0:    # the continuation at the stem's top
            r, turn, height = rng.uniform(0.45, 0.8), math.radians(rng.uniform(-15, 15)), 1.0
        else:         # a branch from a point along the stem
            r, height = rng.uniform(0.25, 0.45), rng.uniform(0.2, 1.0)
            turn = math.radians(rng.uniform(25, 75)) * rng.choice([-1.0, 1.0])
        linear.append(_turn(turn) @ np.diag([r * rng.uniform(0.6, 1.0), r]) @ mirror)
        shift.append([0.0, height])
    thin = [rng.uniform(STEM_FLOOR, STEM_THIN) for _ in range(stems)]
    twig = (math.radians(rng.uniform(30, 60)) * rng.choice([-1.0, 1.0]), rng.uniform(0.3, 0.8), rng.uniform(0.4, 0.8))

    def with_stem(length: float) -> tuple[np.ndarray, np.ndarray]:
        stem, at = [np.diag([thin[0], length])], [[0.0, 0.0]]
        if stems == 2:    # a thin twig from a point of the stem
            stem.append(_turn(twig[0]) @ np.diag([thin[1], length * twig[2]]))
            at.append([0.0, twig[1]])
        return np.array(linear + stem), np.array(shift + at)

    # a first stem's attractor sets the stem's length, so that its top is at height 1, where the continuation hangs
    top = float(attractor_box(_full(*with_stem(0.3)))[1][1])
    lin, at = with_stem(min(1.0 / max(top, 1e-9), 0.6))
    rotation = _rotations(rng, 1)[0]
    return _full(rotation @ lin @ rotation.T, at @ rotation.T)


def _spiral(rng: np.random.Generator, maps: int) -> torch.Tensor:
    """A spiral's maps: the dominant similarity about the origin, then the small maps."""
    r = rng.uniform(*SPIRAL_SCALE)
    turn = math.radians(rng.uniform(*SPIRAL_TURN)) * rng.choice([-1.0, 1.0])
    step = abs(1 - r * complex(math.cos(turn), math.sin(turn)))
    linear, shift = [r * _turn(turn)], [[0.0, 0.0]]
    u, v = _rotations(rng, maps - 1), _rotations(rng, maps - 1)
    for i in range(maps - 1):
        s = min(step * rng.uniform(0.45, 0.85), MAX_RANDOM_SCALE / 2)
        lin = u[i] @ np.diag([s, s * rng.uniform(0.3, 1.0)]) @ v[i]
        angle, distance = rng.uniform(-math.pi, math.pi), 1.0 if i == 0 else rng.uniform(0.5, 1.0)
        fixed = distance * np.array([math.cos(angle), math.sin(angle)])
        linear.append(lin)
        shift.append(fixed - lin @ fixed)
    return _full(np.array(linear), np.array(shift))


def _overlap(rng: np.random.Generator, maps: int) -> torch.Tensor:
    """Overlapping maps: areas adding up to `OVERLAP_AREA`, fixed points round the unit circle."""
    for _ in range(1000):
        s1, ratio = rng.uniform(0.5, 1.0, maps), rng.uniform(0.5, 1.0, maps)
        s1 *= math.sqrt(rng.uniform(*OVERLAP_AREA) / float((s1 ** 2 * ratio).sum()))
        if s1.max() < MAX_RANDOM_SCALE and s1.min() >= 0.5:
            break
    else:
        raise IFSError(f"no overlapping scales of {maps} maps reach an area of {OVERLAP_AREA} below {MAX_RANDOM_SCALE}")
    u, v = _rotations(rng, maps), _rotations(rng, maps)
    linear = u @ (np.stack([s1, s1 * ratio], 1)[:, :, None] * v)
    angles = 2 * math.pi * (np.arange(maps) + rng.uniform(-0.25, 0.25, maps)) / maps + rng.uniform(0, 2 * math.pi)
    fixed = np.stack([np.cos(angles), np.sin(angles)], 1) * rng.uniform(0.6, 1.0, (maps, 1))
    return _full(linear, fixed - np.einsum("kij,kj->ki", linear, fixed))


DRAW = {"stem": _stem, "spiral": _spiral, "overlap": _overlap}


def attractor_cloud(maps: torch.Tensor, n: int = 65536, seed: int = 0, tolerance: float | None = None) -> np.ndarray:
    """``(n, 2)`` sampled leaves of the attractor (`sample_attractor`), within ``tolerance`` of it.

    ``tolerance`` in plane units; by default 1/200 of the attractor's radius (`attractor_ball`).
    """
    if tolerance is None:
        tolerance = attractor_ball(maps)[1] / 200
    return sample_attractor(maps, tolerance, n, seed=seed).points.numpy()


def attractor_box(maps: torch.Tensor) -> tuple[np.ndarray, np.ndarray]:
    """The attractor's bounding box ``(lo, hi)``, each ``(2,)``, from its certified leaves as `random_ifs` finds it.

    The finest cut within 1/200 to 1/25 of the attractor's radius that stays under two million leaves
    (`attractor_leaves`); when even the coarsest is over, a million sampled leaves within 1/200 (a
    sample can miss a rare tip: its box may be short by a little).
    """
    radius = attractor_ball(maps)[1]
    for fraction in (200, 100, 50, 25):
        try:
            cloud = attractor_leaves(maps, radius / fraction, max_leaves=2_000_000).points.numpy()
            break
        except LeafBudgetError:
            continue
    else:
        cloud = attractor_cloud(maps, 1_000_000, 0, radius / 200)
    return cloud.min(0), cloud.max(0)


def fit_to_frame(maps: torch.Tensor, extent: float) -> torch.Tensor:
    """The maps conjugated by the similarity ``S(x) = k x + b`` that centres the attractor's box in the frame
    with its longer side ``extent`` (as `random_ifs` does; the box from `attractor_box`).

    ``maps``: ``(k, 3, 3)`` float64; returns the same shape. The linear parts do not change.
    """
    lo, hi = attractor_box(maps)
    k = extent / max(float((hi - lo).max()), 1e-12)
    b = torch.as_tensor(-k * (lo + hi) / 2)
    out = maps.clone()
    out[:, :2, 2] = k * maps[:, :2, 2] + b - maps[:, :2, :2] @ b
    return out


def occupancy(points: np.ndarray, size: int) -> np.ndarray:
    """The pixels of the frame that hold a point, grown by one pixel (a 3 x 3 cross): ``(size, size)`` bool.

    Row 0 is the top of the frame (``y = 0.5``), as in `ifslib.render`.
    """
    hist = np.histogram2d(0.5 - points[:, 1], points[:, 0] + 0.5, bins=size, range=[[0, 1], [0, 1]])[0]
    return ndimage.binary_dilation(hist > 0)


def acceptance(maps: torch.Tensor, accept: Acceptance = ACCEPT) -> tuple[float, float]:
    """The attractor's share of the frame and the IoU of two drawings (seeds 0 and 1), at ``accept.size``.

    ``maps``: ``(k, 3, 3)`` float64 maps in the frame. Leaves within half a pixel.
    """
    tolerance = 0.5 / accept.size
    first, second = (occupancy(attractor_cloud(maps, accept.points, s, tolerance), accept.size) for s in (0, 1))
    union = np.logical_or(first, second).sum()
    return float(first.mean()), float(np.logical_and(first, second).sum() / union) if union else 0.0


def copy_overlap(maps: torch.Tensor, size: int = 128, points: int = 100_000) -> float:
    """The share of the attractor's pixels that lie in two or more of its copies ``T_i(A)``.

    Each copy is drawn from the same sampled leaves of the attractor mapped by ``T_i`` (`occupancy`
    at ``size``): 0 when the copies are apart, near 1 when every copy covers much of the others.
    """
    cloud = attractor_cloud(maps, points, 0, 0.5 / size)
    lin, shift = maps[:, :2, :2].numpy(), maps[:, :2, 2].numpy()
    copies = np.stack([occupancy(cloud @ lin[i].T + shift[i], size) for i in range(len(lin))])
    covered = copies.sum(0)
    return float((covered >= 2).sum() / max(int((covered >= 1).sum()), 1))


__all__ = ["ACCEPT", "Acceptance", "KINDS", "MAP_RANGE", "acceptance", "attractor_box", "attractor_cloud",
           "copy_overlap", "fit_to_frame", "literature_ifs", "occupancy"]
