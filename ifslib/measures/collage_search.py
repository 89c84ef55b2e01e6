"""Maps and probabilities read from a measure's gray image by its collage, then fitted.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import torch
from scipy import ndimage
from scipy.fft import next_fast_len
from scipy.optimize import nnls
from tqdm.auto import tqdm

from ..automatic.fractal.candidates import linear_grid, plane_maps
from ..automatic.fractal.collage import clamp_scales
from ..automatic.fractal.config import DEFAULT as SEARCH
from ..core.fitting.descent import Descent, StepPolicy
from ..core.geometry.ifs import IFS
from ..core.geometry.patterns import affine
from ..core.scoring.losses import multiscale_mse
from ..errors import IFSError, check_int, check_positive
from .measure import push_mass
from .measure_fit import MeasureFit, MeasureFitOptions, check_measure_image, fit_measure, pool_measure


@dataclass(frozen=True)
class CollageSearchOptions:
    """How `collage_search` runs; each default says what it trades.

    Attributes
    ----------
    size : int
        Pixels a side the image is summed to for the search and the fit (must divide the image's):
        larger, finer placements, and each push and FFT costs more.
    turns : int
        Rotations of the grid's linear parts (36: every 10 degrees); the refinement turns a copy the
        rest of the way. More, closer atoms, each step's FFTs grow with them.
    blur : float
        Gaussian blur of the image and its pushes before they are compared, as a share of the frame's side
        (1/64: a pixel at 64², half a pixel at 32²): a copy a pixel off still correlates. Larger, smoother but less
        sharp choices; a blur of the same share draws the same picture at every ``size``.
    atoms : int
        Copies each set may add at a step (those best correlated with its residual): more, more
        least-squares solves.
    first_atoms : int
        At the first step, copies of each of the grid's scales, the best of each scale starting a set
        of its own: more, a better first copy of each size.
    beams : int
        Sets kept after each step, and refined at the end: more, more chances, each fitted.
    refine_steps, refine_lr : int, float
        Adam on the collage error of each kept set (plane units a step for the maps).
    progress : bool
        A progress bar (tqdm.auto) over the steps.
    """

    size: int = 64
    turns: int = 36
    blur: float = 1 / 64
    atoms: int = 40
    first_atoms: int = 6
    beams: int = 3
    refine_steps: int = 1000
    refine_lr: float = 0.002
    progress: bool = False

    def __post_init__(self) -> None:
        check_int(self.size, "size", 8)
        check_int(self.turns, "turns", 1, maximum=720)
        check_positive(self.blur, "blur")
        if not self.blur < 0.25:
            raise IFSError(f"blur is a share of the frame's side below 0.25 (1/64: a pixel at 64²), got {self.blur!r}")
        check_int(self.atoms, "atoms", 1)
        check_int(self.first_atoms, "first_atoms", 1)
        check_int(self.beams, "beams", 1)
        check_int(self.refine_steps, "refine_steps", 0)
        check_positive(self.refine_lr, "refine_lr")
        if not isinstance(self.progress, bool):
            raise IFSError(f"progress must be True or False, got {self.progress!r}")

    @property
    def blur_pixels(self) -> float:
        """The blur's standard deviation in pixels at ``size``."""
        return self.blur * self.size


@dataclass(frozen=True)
class Collage:
    """One set the search kept: ``ifs`` (affine rules with ``probabilities``), its relative residual after the
    pursuit (blurred pushes against the blurred image) and its collage error after the refinement."""

    ifs: IFS
    residual: float
    collage: float


#: The largest singular value a refined map may keep: the measure exists only while every map contracts.
MAX_COLLAGE_SCALE = 0.95


class _Pushes:
    """The image's mass as points about its centre of mass, and the grid's linear parts that push it."""

    def __init__(self, image: torch.Tensor, options: CollageSearchOptions) -> None:
        n = image.shape[0]
        rows, cols = np.nonzero(image.numpy())
        mass = image.numpy()[rows, cols]
        pixel = np.stack([cols, -rows], 1).astype(np.float64)   # pixel units, y up, as the grid's
        self.centre = (pixel * mass[:, None]).sum(0) / mass.sum()
        # float32: the correlations only rank copies, and half the bytes halve the FFTs' time
        self.points, self.mass = torch.as_tensor(pixel - self.centre), torch.as_tensor(mass, dtype=torch.float32)
        self.grid = linear_grid(options.turns, SEARCH.grid_phases, SEARCH.grid_scales, SEARCH.grid_ratios)
        self.scale = np.linalg.svd(self.grid)[1][:, 0].round(3)   # each part's larger singular value
        self.n = n
        # the correlation is circular: wide enough that a push, reaching at most `reach` pixels from its centre of
        # mass (and its blur), wraps round onto the zero padding and never onto the image's n x n corner
        reach = float(np.linalg.norm(self.grid, 2, axis=(1, 2)).max() * self.points.norm(dim=1).max())
        self.side = side = next_fast_len(n + int(np.ceil(reach + 4 * options.blur_pixels)) + 2, real=True)
        kernel = np.zeros((side, side), np.float32)
        kernel[0, 0] = 1.0
        blurred = ndimage.gaussian_filter(kernel, options.blur_pixels, mode="wrap")
        self.kernel = torch.fft.rfft2(torch.as_tensor(blurred))
        # Parseval on a half spectrum: the columns that stand for two (their mirror images) count twice
        twice = torch.full((side // 2 + 1,), 2.0)
        twice[0] = 1.0
        if side % 2 == 0:
            twice[-1] = 1.0
        self.weight = twice / side ** 2

    def best_atoms(self, residuals: list[np.ndarray], count: int, each_scale: bool = False,
                   chunk: int = 512) -> list[np.ndarray]:
        """For each residual ``(n * n,)``: ``(count, 2, 3)`` plane maps, the copies whose blurred push correlates
        best with it (each linear part at its best translation; correlation over the push's norm); with
        ``each_scale``, ``count`` of each of the grid's scales."""
        n, side = self.n, self.side
        spectra = [torch.fft.rfft2(torch.nn.functional.pad(torch.as_tensor(r.reshape(n, n), dtype=torch.float32),
                                                           (0, side - n, 0, side - n))) for r in residuals]
        best = [[] for _ in residuals]
        for start in range(0, len(self.grid), chunk):
            pushed = torch.fft.rfft2(self._canvases(self.grid[start:start + chunk])) * self.kernel
            norm = ((pushed.real ** 2 + pushed.imag ** 2) * self.weight).sum((1, 2)).sqrt()
            for k, spectrum in enumerate(spectra):
                score = torch.fft.irfft2(torch.conj(pushed) * spectrum, s=(side, side))[:, :n, :n].flatten(1)
                value, where = (score / norm[:, None]).max(1)
                best[k].append(torch.stack([value, torch.arange(start, start + len(value)), where], 1))
        out = []
        for rows in best:
            rows = torch.cat(rows).numpy()
            groups = [self.scale == s for s in np.unique(self.scale)] if each_scale else [slice(None)]
            top = np.concatenate([rows[g][np.argsort(-rows[g][:, 0], kind="stable")[:count]] for g in groups])
            part, where = top[:, 1].astype(np.int64), top[:, 2].astype(np.int64)
            cands = np.stack([np.zeros_like(part), part, where // n, where % n], 1)
            out.append(torch.as_tensor(plane_maps(self.grid, cands, self.centre, n)))
        return out

    def _canvases(self, linear: np.ndarray) -> torch.Tensor:
        """``(G, side, side)`` the mass pushed by each linear part, its centre of mass at pixel (0, 0) (bilinear)."""
        side = self.side
        v = torch.einsum("gij,pj->gpi", torch.as_tensor(linear), self.points)
        col, row = v[..., 0], -v[..., 1]
        c0, r0 = col.floor(), row.floor()
        fc, fr = col - c0, row - r0
        canvas = torch.zeros(len(linear), side * side, dtype=torch.float32)
        for dc, dr, w in ((0, 0, (1 - fc) * (1 - fr)), (1, 0, fc * (1 - fr)), (0, 1, (1 - fc) * fr), (1, 1, fc * fr)):
            index = ((r0 + dr).long() % side) * side + (c0 + dc).long() % side
            canvas.scatter_add_(1, index, w.float() * self.mass[None])
        return canvas.view(-1, side, side)


def _blurred_push(image: torch.Tensor, one_map: torch.Tensor, blur: float) -> np.ndarray:
    """``(n * n,)`` the image pushed by one map (all its mass), blurred."""
    pushed = push_mass(image, one_map[None], torch.ones(1, dtype=image.dtype)).numpy()
    return ndimage.gaussian_filter(pushed, blur).ravel()


def _pursuit(image: torch.Tensor, maps: int, options: CollageSearchOptions) -> list[tuple[list, np.ndarray, float]]:
    """Matching pursuit: the `beams` sets of ``maps`` copies of least residual, each as (maps, p, residual)."""
    pushes = _Pushes(image, options)
    wanted = ndimage.gaussian_filter(image.numpy(), options.blur_pixels).ravel()
    scale = float(np.linalg.norm(wanted))
    beams = [([], [], wanted, scale)]   # (maps, their blurred pushes, residual, its norm)
    for step in tqdm(range(maps), desc="collage search", disable=not options.progress, leave=False):
        grown = []
        # the first copy of each size starts a set of its own: the copy that explains most of the image alone
        # (a large one) is often not one of its maps (a triangle's three halves)
        first = step == 0 and maps > 1
        atoms = pushes.best_atoms([b[2] for b in beams], options.first_atoms if first else options.atoms, first)
        for (chosen, columns, _, _), offers in zip(beams, atoms):
            for atom in offers:
                block = np.stack(columns + [_blurred_push(image, atom, options.blur_pixels)], 1)
                p, norm = nnls(block, wanted)
                grown.append((chosen + [atom], [*columns, block[:, -1]], wanted - block @ p, norm))
        grown.sort(key=lambda b: b[3])
        beams = _scale_beams(grown) if first else _distinct(grown, options.beams, scale)
    return [(chosen, nnls(np.stack(columns, 1), wanted)[0], norm / scale) for chosen, columns, _, norm in beams]


def _distinct(grown: list, count: int, scale: float) -> list:
    """The first ``count`` sets of ``grown`` (sorted) that differ: one set is reached in several orders."""
    kept = []
    for b in grown:
        if all(abs(b[3] - k[3]) > 1e-12 * scale for k in kept):
            kept.append(b)
        if len(kept) == count:
            break
    return kept


def _scale_beams(grown: list) -> list:
    """The best one-copy set of each of the grid's scales (``grown`` sorted)."""
    kept = {}
    for b in grown:
        size = round(float(np.linalg.svd(b[0][0][:2, :2].numpy())[1][0]), 2)
        kept.setdefault(size, b)
    return list(kept.values())


def refine_collage(image: torch.Tensor, maps: torch.Tensor, probabilities: np.ndarray, steps: int, lr: float,
                   scales: int = 5) -> tuple[torch.Tensor, torch.Tensor, float]:
    """Adam on the multiscale collage error ``|sum_i p_i T_i# f - f|`` of maps ``(m, 2, 3)`` or ``(m, 3, 3)`` and
    probabilities (softmax of logits) against the image ``f`` ``(n, n)``; returns the maps ``(m, 2, 3)``, the
    probabilities and the error."""
    n = image.shape[0]
    linear = maps[:, :2].clone().requires_grad_(True)
    logits = torch.log(torch.as_tensor(np.maximum(probabilities, 1e-3))).requires_grad_(True)

    def error() -> torch.Tensor:
        collage = push_mass(image, linear, torch.softmax(logits, 0))
        return multiscale_mse(collage * n * n, image * n * n, scales)

    # every map contracts, or the measure does not exist
    keep = StepPolicy(contract=lambda _: clamp_scales(linear, high=MAX_COLLAGE_SCALE),
                      advice="the collage error is not finite: lower refine_lr")
    Descent([{"params": [linear, logits], "lr": lr}], error, keep).run(steps)
    with torch.no_grad():
        return linear.detach(), torch.softmax(logits, 0).detach(), float(error())


def collage_search(image, maps: int, options: CollageSearchOptions = CollageSearchOptions()) -> list[Collage]:
    """Read ``maps`` affine maps and their probabilities from a measure's gray image by its collage.

    Parameters
    ----------
    image : array-like
        ``(S, S)`` gray levels >= 0 of the measure on the frame, row 0 at the top; ``options.size``
        must divide ``S``.
    maps : int
        The number of maps.
    options : CollageSearchOptions

    Returns
    -------
    list of Collage
        The kept sets, least collage error first.
    """
    if not isinstance(options, CollageSearchOptions):
        raise IFSError(f"options must be a CollageSearchOptions, got {type(options).__name__}")
    check_int(maps, "maps", 1, maximum=16)
    small = pool_measure(check_measure_image(image), options.size).double()
    found = []
    for chosen, p, residual in _pursuit(small, maps, options):
        refined, probabilities, collage = refine_collage(small, torch.stack(chosen), p, options.refine_steps,
                                                         options.refine_lr)
        ifs = affine(refined)
        ifs.probabilities = tuple(float(x) for x in probabilities / probabilities.sum())
        found.append(Collage(ifs, float(residual), collage))
    return sorted(found, key=lambda c: c.collage)


def fit_measure_from_collage(image, maps: int, options: MeasureFitOptions = MeasureFitOptions(
        steps=300, map_lr=0.001, fit_maps=True), search: CollageSearchOptions = CollageSearchOptions()) -> MeasureFit:
    """Fit maps and probabilities to a measure's gray image when the maps are unknown, from its collage.

    `collage_search` reads sets of ``maps`` maps and probabilities from the gray levels; `fit_measure`
    fits each on the image summed to ``search.size``; the fit of highest density correlation is kept.

    Parameters
    ----------
    image : array-like
        ``(S, S)`` gray levels >= 0, row 0 at the top; ``search.size`` must divide ``S``.
    maps : int
        The number of maps.
    options : MeasureFitOptions
        The fit of each set the search keeps.
    search : CollageSearchOptions

    Returns
    -------
    MeasureFit
        With ``start``, the search's set the fit began from.
    """
    if not isinstance(options, MeasureFitOptions):
        raise IFSError(f"options must be a MeasureFitOptions, got {type(options).__name__}")
    small = pool_measure(check_measure_image(image), search.size)
    best = None
    for found in collage_search(image, maps, search):
        fitted = fit_measure(found.ifs, small, options)
        if best is None or fitted.correlation > best.correlation:
            best = dataclasses.replace(fitted, start=found.ifs)
    return best
