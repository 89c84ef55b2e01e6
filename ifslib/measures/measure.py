"""The invariant measure of an IFS with probabilities, drawn as gray levels on the pixel grid, three ways.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch

from ..errors import IFSError, check_int
from ..core.geometry.attractor import check_contractive_maps
from ..core.geometry.ifs import IFS, check_probabilities
from ..core.geometry.leaves import check_bytes
from ..core.raster.chains import fixed_points, walk

#: Chains of the chaos game run side by side: more chains, fewer Python steps (65,536 x 16 bytes a step).
MEASURE_CHAINS = 65_536

#: Steps each chain takes before its points count: the chains start at fixed points, whose spread is
#: not the measure's; after k steps the start's trace is within ``max scale ** k`` of the frame
#: (0.85 ** 48 < 0.0005, an eighth of a pixel at 256 px for the fern).
BURN_IN = 48

#: Chaos-game points of `chaos_measure` by default: its histogram's L1 noise is about
#: ``sqrt(2 cells / (pi n))`` (0.01 for the fern's ~15,000 lit cells at 256 px needs ~10^8; 3 x 10^7 gives ~0.02).
DEFAULT_MEASURE_POINTS = 30_000_000

#: Bytes a push holds per lit cell and map (its image, four corners' indices and weights), rounded up.
PUSH_BYTES = 96

#: Share of the mass the last push may lose outside the frame before `invariant_measure` refuses:
#: an attractor that leaves the frame has no measure on it.
MAX_LOST_MASS = 1e-3


@dataclass(frozen=True)
class MeasureOptions:
    """How `invariant_measure` pushes mass.

    Attributes
    ----------
    iterations : int
        Pushes through the maps from uniform mass on the output's own grid; the start's trace shrinks
        like ``max scale ** k`` (64 leaves the fern's within 1e-4 of the frame, a fortieth of a pixel at 256 px).
    supersample : int
        Fine cells per output pixel along each side, a power of 2. Each push splits a cell's mass over
        four cells, and a cell lumps the mass it holds: the error of the gray levels falls about in
        proportion to the fine cell's size (L1 to the chaos game at 256 px, fern: 0.31 at 1, 0.15 at 2,
        0.07 at 4; docs/results/measures.md). 1 is cheapest (what a fit's gradient needs).
    refine : int
        Pushes at each finer grid (2, 4, .. ``supersample`` cells a pixel), each started from the
        coarser grid's mass split evenly: the coarse grid's blur shrinks like ``sum p_i s_i^2`` a push
        (0.63 for the fern: 12 pushes leave 0.4 %).
    max_lost : float
        Share of the mass the last push may lose outside the frame before `measure_from_maps` refuses
        (`MAX_LOST_MASS`: an attractor that leaves the frame has no measure on it); a fit, whose maps
        may wander out on the way, passes 1 (the mass kept is renormalised to 1 after every push).
    """

    iterations: int = 64
    supersample: int = 4
    refine: int = 12
    max_lost: float = MAX_LOST_MASS

    def __post_init__(self) -> None:
        check_int(self.iterations, "iterations", 1)
        check_int(self.supersample, "supersample", 1)
        check_int(self.refine, "refine", 1)
        if not (isinstance(self.max_lost, (int, float)) and 0 <= self.max_lost <= 1):
            raise IFSError(f"max_lost must be a share from 0 to 1, got {self.max_lost!r}")
        if self.supersample & (self.supersample - 1):
            raise IFSError(f"supersample must be a power of 2 (1, 2, 4, ..), got {self.supersample}")


def _probabilities(probabilities, m: int, dtype: torch.dtype) -> torch.Tensor:
    """The probabilities as a ``(m,)`` tensor of ``dtype``, checked (a tensor keeps its autograd)."""
    if isinstance(probabilities, torch.Tensor):
        p = probabilities.to(dtype)
        if p.shape != (m,):
            raise IFSError(f"probabilities must have shape ({m},), one per map, got {tuple(p.shape)}")
        check_probabilities(p.detach().double(), m)
        return p
    return torch.tensor(check_probabilities(probabilities, m), dtype=dtype)


def chaos_measure(ifs: IFS, size: int, n: int = DEFAULT_MEASURE_POINTS, seed: int = 0) -> np.ndarray:
    """The chaos game's histogram on the frame: ``(size, size)`` float64 cell masses summing to 1.

    The maps are drawn with `IFS.measure_probabilities` (the IFS's own, or the default). Each of
    `MEASURE_CHAINS` chains starts at a map's fixed point and takes `BURN_IN` steps before its points
    are counted; points outside the frame are not counted (the frame should hold the attractor).

    Parameters
    ----------
    ifs : IFS
        Its maps must contract.
    size : int
        Pixels per side.
    n : int
        Points counted, >= 1 (rounded up to a whole number of steps of all chains).
    seed : int
        Seeds `numpy.random.default_rng`.

    Returns
    -------
    numpy.ndarray
        ``(size, size)`` float64, row 0 at the top.
    """
    check_int(size, "size", 1)
    check_int(n, "the number of chaos-game points", 1)
    check_int(seed, "seed", 0)
    check_bytes(size * size * 8 + MEASURE_CHAINS * 64, f"a {size} x {size} histogram", "draw fewer pixels")
    with torch.no_grad():
        maps_t = ifs.to(torch.float64).maps()
        check_contractive_maps(maps_t, ifs.rules)
        p = ifs.measure_probabilities(maps_t).numpy()
    maps = maps_t.numpy()
    rng = np.random.default_rng(seed)
    chains = min(MEASURE_CHAINS, n)
    starts = fixed_points(maps)[rng.choice(len(p), size=chains, p=p)]
    counts = np.zeros(size * size + 1)
    for step in walk(maps, p, starts, BURN_IN, -(-n // chains), rng):
        counts += _bin(step.x, step.y, size)
    total = counts[:-1].sum()
    if total == 0:
        raise IFSError("no chaos-game point fell in the frame [-0.5, 0.5]^2: the attractor lies outside it")
    return (counts[:-1] / total).reshape(size, size)


def _bin(x: np.ndarray, y: np.ndarray, size: int) -> np.ndarray:
    """Counts of the points ``(x, y)`` per pixel, flat row-major, with one more slot for those outside the frame."""
    col = np.floor((x + 0.5) * size)
    row = np.floor((0.5 - y) * size)
    inside = (col >= 0) & (col < size) & (row >= 0) & (row < size)
    flat = np.where(inside, row * size + col, size * size).astype(np.int64)
    return np.bincount(flat, minlength=size * size + 1)


#: Bytes `cylinder_measure` holds per cylinder of a level and its children (maps, shifts, masses, boxes).
CYLINDER_BYTES = 400


@dataclass(frozen=True)
class CylinderOptions:
    """How `cylinder_measure` splits cylinders.

    Attributes
    ----------
    smallest : float
        A cylinder still crossing a pixel's edge when its bounding box is narrower than this many pixels
        is placed whole at its centre of mass: the share of mass so placed bounds half the L1 error
        (1/64: at 256 px the lopsided triangle places 0.019 of its mass so in 1 s, the fern 0.019 in 31 s).
    max_depth : int
        Levels of words at most (a map of scale near 1 shrinks its cylinders slowly); what is left then
        is placed as above.
    """

    smallest: float = 1 / 64
    max_depth: int = 200

    def __post_init__(self) -> None:
        if not (isinstance(self.smallest, (int, float)) and 0 < self.smallest <= 1):
            raise IFSError(f"smallest must be a width in pixels above 0 and at most 1, got {self.smallest!r}")
        check_int(self.max_depth, "max_depth", 1)


def _invariant_ball(lin: np.ndarray, shift: np.ndarray, centre: np.ndarray) -> float:
    """Radius of a ball about ``centre`` that every map sends into itself: it holds the attractor."""
    scale = np.linalg.norm(lin, ord=2, axis=(1, 2))
    reach = np.linalg.norm(lin @ centre + shift - centre, axis=1)
    return float((reach / (1 - scale)).max())


def cylinder_measure(ifs: IFS, size: int, options: CylinderOptions = CylinderOptions()) -> tuple[np.ndarray, float]:
    """The invariant measure by cylinders: ``(size, size)`` float64 cell masses summing to 1, and the share placed.

    Each cylinder ``T_w(A)`` (mass ``p_w``, centre of mass ``T_w(m)`` with ``m`` the measure's mean) lies in
    ``T_w(B)`` for a ball ``B`` that every map sends into itself; when that ellipse's box lies in one pixel
    the pixel gets ``p_w`` exactly, else the cylinder is split into its ``m`` children. Only cylinders
    narrower than ``options.smallest`` pixels (or at ``options.max_depth``) that still cross an edge are
    placed at their centre of mass. Mass outside the frame is dropped and the rest scaled to 1, as
    `chaos_measure` does.

    Parameters
    ----------
    ifs : IFS
        Its maps must contract; its probabilities are `IFS.measure_probabilities`.
    size : int
        Pixels per side.
    options : CylinderOptions

    Returns
    -------
    numpy.ndarray
        ``(size, size)`` float64, row 0 at the top.
    float
        The share of the mass placed at a centre of mass while crossing an edge (the L1 distance to the
        true measure is at most twice this).
    """
    check_int(size, "size", 1)
    if not isinstance(options, CylinderOptions):
        raise IFSError(f"options must be a CylinderOptions, got {type(options).__name__}")
    with torch.no_grad():
        maps_t = ifs.to(torch.float64).maps()
        check_contractive_maps(maps_t, ifs.rules)
        p = ifs.measure_probabilities(maps_t).numpy()
    lin, shift = maps_t[:, :2, :2].numpy(), maps_t[:, :2, 2].numpy()
    mean = np.linalg.solve(np.eye(2) - np.einsum("i,ijk->jk", p, lin), p @ shift)
    radius = _invariant_ball(lin, shift, mean)
    a, b, mass = np.eye(2)[None], np.zeros((1, 2)), np.ones(1)  # the cylinders' maps x -> a x + b
    counts, placed = np.zeros(size * size + 1), 0.0
    for depth in range(options.max_depth + 1):
        centre = a @ mean + b
        half = radius * np.linalg.norm(a, axis=2)  # (k, 2) half-widths of the ellipse's box, plane units
        lo, hi = _pixel_of(centre, half, size), _pixel_of(centre, -half, size)  # its top-left and bottom-right pixels
        whole = (lo == hi).all(1) | (hi < 0).any(1) | (lo >= size).any(1)  # in one pixel, or wholly outside
        counts += np.bincount(_flat(lo[whole], size), mass[whole], size * size + 1)
        last = (2 * half.max(1) * size < options.smallest) | (depth == options.max_depth)
        settle = ~whole & last
        counts += np.bincount(_flat(_pixel_of(centre[settle], 0 * half[settle], size), size), mass[settle],
                              size * size + 1)
        placed += float(mass[settle].sum())
        split = ~whole & ~last
        if not split.any():
            break
        check_bytes(int(split.sum()) * len(p) * CYLINDER_BYTES, f"{int(split.sum()) * len(p):,} cylinders",
                    "use a larger CylinderOptions.smallest or a smaller size")
        a, b, mass = a[split], b[split], mass[split]
        b = (np.einsum("kab,ib->kia", a, shift) + b[:, None]).reshape(-1, 2)
        a = np.einsum("kab,ibc->kiac", a, lin).reshape(-1, 2, 2)
        mass = (mass[:, None] * p[None]).reshape(-1)
    total = counts[:-1].sum()
    if total == 0:
        raise IFSError("no cylinder fell in the frame [-0.5, 0.5]^2: the attractor lies outside it")
    return (counts[:-1] / total).reshape(size, size), placed / total


def _pixel_of(centre: np.ndarray, half: np.ndarray, size: int) -> np.ndarray:
    """``(k, 2)`` (column, row) of the pixels holding ``centre - half`` in x and ``centre + half`` in y (top-left)."""
    col = np.floor((centre[:, 0] - half[:, 0] + 0.5) * size)
    row = np.floor((0.5 - centre[:, 1] - half[:, 1]) * size)
    return np.stack([col, row], 1)


def _flat(pixel: np.ndarray, size: int) -> np.ndarray:
    """Row-major index of ``(k, 2)`` (column, row) pixels, with ``size * size`` for those outside the frame."""
    col, row = pixel[:, 0], pixel[:, 1]
    inside = (col >= 0) & (col < size) & (row >= 0) & (row < size)
    return np.where(inside, row * size + col, size * size).astype(np.int64)


def push_mass(mass: torch.Tensor, maps: torch.Tensor, probabilities: torch.Tensor) -> torch.Tensor:
    """One push of the Markov operator on the grid: ``sum_i p_i`` times the mass moved by ``T_i``.

    The mass of each cell sits at its centre; its image ``T_i(c)`` is split among the four cells
    whose centres surround it, in proportion to the bilinear weights (differentiable in the maps).
    Mass pushed outside the grid is dropped.

    Parameters
    ----------
    mass : torch.Tensor
        ``(S, S)`` cell masses on the frame, row 0 at the top.
    maps : torch.Tensor
        ``(m, 3, 3)`` (or ``(m, 2, 3)``) maps in plane units.
    probabilities : torch.Tensor
        ``(m,)``.

    Returns
    -------
    torch.Tensor
        ``(S, S)``, of total at most ``mass.sum()``.
    """
    s = mass.shape[0]
    flat = mass.reshape(-1)
    lit = (flat.detach() > 0).nonzero().flatten()  # only cells with mass move any: a fractal lights few
    check_bytes(len(lit) * len(maps) * PUSH_BYTES, f"a push of {len(lit):,} cells through {len(maps)} maps",
                "use a smaller size or supersample")
    row, col = lit // s, lit % s
    centre = torch.stack([(col + 0.5) / s - 0.5, 0.5 - (row + 0.5) / s], 1).to(maps.dtype)   # (k, 2)
    image = centre @ maps[:, :2, :2].transpose(1, 2) + maps[:, None, :2, 2]                  # (m, k, 2)
    u, v = (image[..., 0] + 0.5) * s - 0.5, (0.5 - image[..., 1]) * s - 0.5                  # fine column, row
    u0, v0 = u.detach().floor(), v.detach().floor()
    fu, fv = u - u0, v - v0
    weight = probabilities[:, None] * flat[lit][None]                                         # (m, k)
    out = torch.zeros(s * s + 1, dtype=flat.dtype)
    for du, dv, w in ((0, 0, (1 - fu) * (1 - fv)), (1, 0, fu * (1 - fv)), (0, 1, (1 - fu) * fv), (1, 1, fu * fv)):
        c, r = u0 + du, v0 + dv
        inside = (c >= 0) & (c < s) & (r >= 0) & (r < s)
        index = torch.where(inside, r * s + c, torch.full_like(c, s * s)).long()
        out = out.index_add(0, index.reshape(-1), (w * weight).reshape(-1).to(flat.dtype))
    return out[:-1].view(s, s)


def measure_from_maps(maps: torch.Tensor, probabilities, size: int,
                      options: MeasureOptions = MeasureOptions()) -> torch.Tensor:
    """The invariant measure of ``maps`` with ``probabilities``: ``(size, size)`` cell masses summing to 1.

    Differentiable in ``maps`` and (when a tensor) ``probabilities``. The maps must contract and the
    frame must hold the attractor (refused when the last push loses more than `MAX_LOST_MASS`).

    Parameters
    ----------
    maps : torch.Tensor
        ``(m, 3, 3)`` maps in plane units; their dtype is the computation's.
    probabilities : sequence of float or torch.Tensor
        ``(m,)``, each > 0, summing to 1.
    size : int
        Output pixels per side.
    options : MeasureOptions

    Returns
    -------
    torch.Tensor
        ``(size, size)``, row 0 at the top.
    """
    check_int(size, "size", 1)
    if not isinstance(options, MeasureOptions):
        raise IFSError(f"options must be a MeasureOptions, got {type(options).__name__}")
    if maps.ndim != 3 or maps.shape[1:] not in ((3, 3), (2, 3)) or maps.shape[0] == 0:
        raise IFSError(f"maps must have shape (m, 3, 3) or (m, 2, 3), got {tuple(maps.shape)}")
    check_contractive_maps(maps.detach())
    p = _probabilities(probabilities, maps.shape[0], maps.dtype)
    fine = size * options.supersample
    if torch.is_grad_enabled() and (maps.requires_grad or p.requires_grad):  # every push kept for the backward pass
        pushes = options.iterations + options.refine * (options.supersample.bit_length() - 1)
        check_bytes(fine * fine * maps.shape[0] * PUSH_BYTES * pushes, f"a {fine} x {fine} measure with its gradient",
                    "use a smaller size or supersample, or fewer iterations")
    mass = torch.full((size, size), 1.0 / size ** 2, dtype=maps.dtype)
    mass, lost = _settle(mass, maps, p, options.iterations)
    while mass.shape[0] < fine:  # each finer grid starts from the coarser one's mass, split evenly
        mass = mass.repeat_interleave(2, 0).repeat_interleave(2, 1) / 4
        mass, lost = _settle(mass, maps, p, options.refine)
    if lost > options.max_lost:
        raise IFSError(f"the last push lost {lost:.2%} of the mass outside the frame [-0.5, 0.5]^2: "
                       "the attractor does not fit in the frame; scale the IFS into it")
    k = options.supersample
    return mass.view(size, k, size, k).sum((1, 3))


def _settle(mass: torch.Tensor, maps: torch.Tensor, p: torch.Tensor, pushes: int) -> tuple[torch.Tensor, float]:
    """``pushes`` pushes of `push_mass`, each renormalised to 1; also the share of mass the last one lost."""
    for _ in range(pushes):
        pushed = push_mass(mass, maps, p)
        kept = pushed.sum()
        mass = pushed / kept
    return mass, 1 - float(kept.detach())


def invariant_measure(ifs: IFS, size: int, options: MeasureOptions = MeasureOptions(),
                      probabilities=None) -> torch.Tensor:
    """The invariant measure of ``ifs``, deterministic: ``(size, size)`` cell masses summing to 1.

    Differentiable in ``ifs.points`` (through `IFS.maps`) and in ``probabilities`` when a tensor is
    given; otherwise the IFS's own (`IFS.measure_probabilities`: the default when it has none).
    See `measure_from_maps`.
    """
    maps = ifs.maps()
    p = ifs.measure_probabilities(maps.detach().double()) if probabilities is None else probabilities
    return measure_from_maps(maps, p, size, options)


def l1_distance(a, b) -> float:
    """L1 distance of two images each normalised to sum 1 (0: the same measure; 2: disjoint supports)."""
    a = np.asarray(a.detach() if isinstance(a, torch.Tensor) else a, dtype=np.float64)
    b = np.asarray(b.detach() if isinstance(b, torch.Tensor) else b, dtype=np.float64)
    if a.shape != b.shape:
        raise IFSError(f"the two images differ in shape: {a.shape} and {b.shape}")
    if not (a.sum() > 0 and b.sum() > 0 and (a >= 0).all() and (b >= 0).all()):
        raise IFSError("each image must be >= 0 with a positive sum to be normalised")
    return float(np.abs(a / a.sum() - b / b.sum()).sum())


__all__ = ["BURN_IN", "CylinderOptions", "DEFAULT_MEASURE_POINTS", "MAX_LOST_MASS", "MEASURE_CHAINS", "MeasureOptions",
           "chaos_measure", "cylinder_measure",
           "invariant_measure", "l1_distance", "measure_from_maps", "push_mass"]
