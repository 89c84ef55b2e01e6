"""Fitting a measure: an IFS's probabilities, and optionally its maps, fitted to a grayscale image of its measure.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Callable

from tqdm.auto import tqdm

import numpy as np
import torch
from scipy import ndimage

from ..automatic.auto import FIGURE
from ..automatic.plan import discover
from ..errors import IFSError, check_int, check_positive
from ..core.fitting.descent import Descent, StepPolicy
from ..core.geometry.rules import singular_values
from ..core.geometry.ifs import IFS
from ..core.scoring.losses import multiscale_mse
from ..core.geometry import patterns
from ..core.targets.target import Target, foreground_points, target_from_mask
from ..progress import draw_bars
from .measure import MeasureOptions, measure_from_maps


#: A step of the maps that leaves a map's scale (largest singular value) at or above this is halved until none
#: does (`MAX_HALVINGS` times at most, then not taken): the measure exists only while every map contracts, and a
#: start read from the support alone has maps of scale 0.9 that a full step pushes past 1.
MAX_FIT_SCALE = 0.98
MAX_HALVINGS = 8


def halve_step(points: torch.Tensor, before: torch.Tensor, contracts: Callable[[], bool], times: int) -> None:
    """Halve the step just taken from ``before`` to ``points`` until ``contracts()`` (``times`` halvings at most, then
    undo the step), in place."""
    step = points - before
    for _ in range(times):
        if contracts():
            return
        step /= 2
        points.copy_(before + step)
    points.copy_(before)


#: A copy is known from the support only up to the figure's symmetries: ``T_i S`` draws the same set as
#: ``T_i`` when ``S`` keeps the figure, but not the same measure. The turns tried as ``S``: this many
#: rotations about the support's mean, in the frame where its covariance is round, each with and
#: without a reflection (24: every 15 degrees, so a square's and an equilateral triangle's hold).
SYMMETRY_TURNS = 24
#: ... a turn is a symmetry when this share of the support's pixels land on the support grown by a pixel.
SYMMETRY_OVERLAP = 0.9
#: Rounds of turning one map at a time, each followed by a fit of the probabilities (`SYMMETRY_STEPS` steps).
SYMMETRY_ROUNDS = 3
SYMMETRY_STEPS = 40
#: ... a map is turned when that lowers the loss by at least this share (turns that draw the same measure tie).
SYMMETRY_GAIN = 0.01


@dataclass(frozen=True)
class MeasureFitOptions:
    """How `fit_measure` runs.

    Attributes
    ----------
    steps : int
        Adam steps.
    lr : float
        Adam's learning rate for the probabilities' logits (0.05: they settle in ~100 steps).
    map_lr : float
        Adam's learning rate for the control points, in plane units a step (0.002: an eighth of a
        pixel at 64 px; the measure moves with every map at once, so larger steps oscillate).
    fit_maps : bool
        Move the IFS's free control points too (False: the maps are given, only probabilities move).
    measure : MeasureOptions
        The deterministic measure inside the loss (the target's size is the output size): fewer
        pushes than a picture needs, as the gradient of each step only has to point the right way.
    scales : int
        Pooled copies in the loss (each halving the size): 4 reaches 8-pixel blocks.
    progress : bool
        A progress bar (tqdm.auto) over the steps, where someone watches (`ifslib.progress.draw_bars`).
    """

    steps: int = 150
    lr: float = 0.05
    map_lr: float = 0.002
    fit_maps: bool = False
    measure: MeasureOptions = field(default_factory=lambda: MeasureOptions(iterations=32, supersample=2, refine=8,
                                                                                      max_lost=1.0))
    scales: int = 4
    progress: bool = False

    def __post_init__(self) -> None:
        check_int(self.steps, "steps", 1)
        check_positive(self.lr, "lr")
        check_positive(self.map_lr, "map_lr")
        check_int(self.scales, "scales", 1)
        if not isinstance(self.measure, MeasureOptions):
            raise IFSError(f"measure must be a MeasureOptions, got {type(self.measure).__name__}")
        if not isinstance(self.fit_maps, bool):
            raise IFSError(f"fit_maps must be True or False, got {self.fit_maps!r}")


@dataclass(frozen=True)
class MeasureFit:
    """What `fit_measure` found.

    Attributes
    ----------
    ifs : IFS
        A copy of the start with the fitted points and ``probabilities``.
    probabilities : tuple of float
        ``(m,)`` the fitted probabilities.
    losses : tuple of float
        The loss at each step.
    correlation : float
        Pearson correlation of the fitted measure's densities with the target's, at the target's size.
    start : IFS or None
        The maps the search read from the image's support (`fit_measure_from_support`), before `reorient`;
        None when the caller gave them.
    """

    ifs: IFS
    probabilities: tuple[float, ...]
    losses: tuple[float, ...]
    correlation: float
    start: IFS | None = None


def check_measure_image(image) -> torch.Tensor:
    """A grayscale image of a measure as a ``(S, S)`` float64 tensor summing to 1; `IFSError` if it cannot be one."""
    img = torch.as_tensor(np.asarray(image.detach() if isinstance(image, torch.Tensor) else image, dtype=np.float64))
    if img.ndim != 2 or img.shape[0] != img.shape[1] or img.shape[0] < 2:
        raise IFSError(f"a measure's image must be square (S, S) with S >= 2, got shape {tuple(img.shape)}")
    if not torch.isfinite(img).all() or (img < 0).any() or not img.sum() > 0:
        raise IFSError("a measure's image must be finite and >= 0 with some mass (gray levels, not a mask of 0 and -1)")
    return img / img.sum()


def multiscale_loss(a: torch.Tensor, b: torch.Tensor, scales: int) -> torch.Tensor:
    """The core's multiscale MSE (`ifslib.core.scoring.losses.multiscale_mse`, average pooling) of the densities
    (mass times pixels) of two ``(S, S)`` measures, over ``scales`` sizes (the image and ``scales - 1`` pooled copies)."""
    return multiscale_mse(a * a.numel(), b * b.numel(), levels=scales - 1, mode="avg")


def correlation(a, b) -> float:
    """Pearson correlation of two images' pixel values."""
    x = np.asarray(a.detach() if isinstance(a, torch.Tensor) else a, dtype=np.float64).ravel()
    y = np.asarray(b.detach() if isinstance(b, torch.Tensor) else b, dtype=np.float64).ravel()
    return float(np.corrcoef(x, y)[0, 1])


def fit_measure(ifs: IFS, image, options: MeasureFitOptions = MeasureFitOptions()) -> MeasureFit:
    """Fit the probabilities (and, with ``options.fit_maps``, the maps) of ``ifs`` to a measure's image.

    Parameters
    ----------
    ifs : IFS
        The start: its maps (and its probabilities, or the default) are where descent begins.
    image : array-like
        ``(S, S)`` gray levels >= 0 of the measure on the frame, row 0 at the top (a chaos game's
        histogram, `ifslib.measures.measure.chaos_measure`, or a photograph's gray levels).
    options : MeasureFitOptions

    Returns
    -------
    MeasureFit
    """
    if not isinstance(options, MeasureFitOptions):
        raise IFSError(f"options must be a MeasureFitOptions, got {type(options).__name__}")
    target = check_measure_image(image)
    size = target.shape[0]
    work = ifs.to(torch.float64)
    logits = work.measure_probabilities().log().clone().requires_grad_(True)
    params = [{"params": [logits], "lr": options.lr}] + (
        [{"params": [work.points], "lr": options.map_lr}] if options.fit_maps else [])
    free = torch.ones(work.n_points, 1, dtype=torch.float64)
    free[list(work.fixed)] = 0

    def loss() -> torch.Tensor:
        maps = work.maps() if options.fit_maps else work.maps().detach()
        density = measure_from_maps(maps, logits.softmax(0), size, options.measure)
        return multiscale_loss(density, target, options.scales)

    def hold() -> None:  # the fixed points do not move
        work.points.grad *= free

    def contract(before: list[torch.Tensor]) -> None:  # before: every parameter's value, the points last
        halve_step(work.points, before[-1], lambda: float(singular_values(work.maps())[1].max()) < MAX_FIT_SCALE,
                   MAX_HALVINGS)

    policy = StepPolicy(gradient=hold if options.fit_maps else None, contract=contract if options.fit_maps else None,
                        advice="the measure fit's loss is not finite: lower lr, or start nearer (the maps may have "
                               "stopped contracting)")
    descent = Descent(params, loss, policy)
    with tqdm(total=options.steps, desc="fit measure", disable=not (options.progress and draw_bars())) as bar:
        descent.run(options.steps, bar=bar)
    losses = descent.losses
    p = tuple(float(x) for x in logits.detach().softmax(0))
    p = tuple(x / sum(p) for x in p)
    fitted = work.clone()
    fitted.probabilities = p
    with torch.no_grad():
        final = measure_from_maps(fitted.maps(), p, size, options.measure)
    return MeasureFit(fitted.to(ifs.points.dtype), p, tuple(losses), correlation(final, target))


def support_target(image, threshold: float = 0.0) -> Target:
    """The support of a measure's image as a binary `Target`: the pixels above ``threshold`` of its largest gray level.

    Parameters
    ----------
    image : array-like
        ``(S, S)`` gray levels >= 0 (`check_measure_image`), row 0 at the top.
    threshold : float
        Share of the largest gray level, from 0 (every pixel with mass, right for a chaos game's histogram,
        whose faintest parts, a fern's stem, hold a few points a pixel) to below 1 (a photograph's dark
        background left out).

    Returns
    -------
    Target
        ``(S, S)`` mask, named ``"support"``.
    """
    if not (isinstance(threshold, (int, float)) and 0 <= threshold < 1):
        raise IFSError(f"threshold must be a share of the largest gray level, from 0 to below 1, got {threshold!r}")
    img = check_measure_image(image).numpy()
    mask = img > threshold * img.max()
    if mask.all():
        raise IFSError(f"every pixel is above {threshold} of the largest gray level, so the support fills the frame: "
                       "raise threshold to leave the background out")
    return target_from_mask(mask, "support", gray=img / img.max(), polarity="the measure's support (pixels with mass)")


def pool_measure(image, size: int) -> torch.Tensor:
    """A measure's ``(S, S)`` image summed into ``(size, size)`` cells (``size`` must divide ``S``), summing to 1."""
    img = check_measure_image(image)
    check_int(size, "size", 2)
    if img.shape[0] % size:
        raise IFSError(f"the fit's size {size} must divide the image's {img.shape[0]} pixels a side")
    k = img.shape[0] // size
    return img.view(size, k, size, k).sum((1, 3))


def fit_measure_from_support(image, maps: int | None = None, options: MeasureFitOptions = MeasureFitOptions(
        steps=200, map_lr=0.001, fit_maps=True), *, fit_size: int = 64, threshold: float = 0.0,
        turn: bool = True, seed: int = 0) -> MeasureFit:
    """Fit maps and probabilities to a measure's gray image when the maps are unknown.

    The image's support (`support_target`) is a binary figure; the library's fractal search reads maps
    whose attractor covers it (`ifslib.discover`, no fit: the search refines its maps on
    the collage and judges them by their attractor), each turned by the support's symmetry that matches
    the gray levels best (`reorient`); `fit_measure` then moves those maps and the
    probabilities (from the default, proportional to ``|det|``) towards the gray levels, on the image
    summed to ``fit_size`` pixels a side.

    Parameters
    ----------
    image : array-like
        ``(S, S)`` gray levels >= 0 of the measure on the frame, row 0 at the top, with ``S`` at least
        the fractal search's 128 (`ifslib.automatic.config.AUTO.figure.fractal_min_size`).
    maps : int, optional
        The number of maps, when known (the search chooses otherwise).
    options : MeasureFitOptions
        The measure fit (``fit_maps=False`` keeps the search's maps and fits the probabilities alone).
    fit_size : int
        Pixels a side of the measure fit; must divide ``S`` (its cost grows with the pixels lit).
    threshold : float
        Of `support_target`.
    turn : bool
        Compose the search's maps with the support's symmetries that match the gray levels best
        (`reorient`) before the fit: the support cannot tell a copy from its turned twin.
    seed : int
        The search's seed.

    Returns
    -------
    MeasureFit
        With ``start``, the search's maps.

    Raises
    ------
    IFSError
        An image below 128 px, or a support that the search does not read as a fractal (a solid shape,
        or no maps whose attractor lies within a pixel of it).
    """
    if not isinstance(options, MeasureFitOptions):
        raise IFSError(f"options must be a MeasureFitOptions, got {type(options).__name__}")
    small = pool_measure(image, fit_size)
    size = check_measure_image(image).shape[0]
    if size < FIGURE.fractal_min_size:
        raise IFSError(f"the fractal search reads the support at {FIGURE.fractal_min_size} px a side or more, got "
                       f"{size}: give the gray image at that size (the measure is fitted at fit_size)")
    target = support_target(image, threshold)
    plan = discover(target, maps, seed=seed)
    if plan.kind != "fractal":
        raise IFSError(f"the search found no fractal's maps for the image's support (read as a {plan.kind}: "
                       f"{plan.pattern.get('fractal_search', {}).get('verdict', 'not searched')}); give the maps "
                       "and call fit_measure")
    start = reorient(plan.start, small, support_symmetries(target), options) if turn else plan.start
    fitted = fit_measure(start, small, options)
    return dataclasses.replace(fitted, start=plan.start)


def support_symmetries(target: Target) -> np.ndarray:
    """The affine maps that keep the support: ``(k, 3, 3)`` in plane units, the identity first.

    Each keeps the support's mean and covariance (`SYMMETRY_TURNS` rotations in its whitened frame,
    with and without a reflection) and sends at least `SYMMETRY_OVERLAP` of its pixels onto it.
    """
    points = foreground_points(target)
    mean, cov = points.mean(0), np.cov(points.T, bias=True)
    vals, vecs = np.linalg.eigh(cov)
    if not vals.min() > 1e-9 * vals.max():  # a support on a line (or a pixel) has no round frame: only the identity
        return np.eye(3)[None]
    root, inverse = vecs @ np.diag(np.sqrt(vals)) @ vecs.T, vecs @ np.diag(1 / np.sqrt(vals)) @ vecs.T
    grown = ndimage.binary_dilation(target.mask)
    found = []
    for k in range(SYMMETRY_TURNS):
        a = 2 * np.pi * k / SYMMETRY_TURNS
        turn = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        for q in (turn, turn @ np.diag([1.0, -1.0])):
            lin = root @ q @ inverse
            image = (points - mean) @ lin.T + mean
            col, row = np.floor((image[:, 0] + 0.5) * target.size), np.floor((0.5 - image[:, 1]) * target.size)
            inside = (col >= 0) & (col < target.size) & (row >= 0) & (row < target.size)
            on = grown[row[inside].astype(int), col[inside].astype(int)].sum()
            if on >= SYMMETRY_OVERLAP * len(points):
                found.append(np.block([[lin, (mean - lin @ mean)[:, None]], [np.zeros((1, 2)), np.ones((1, 1))]]))
    return np.stack(found)


def reorient(ifs: IFS, image, symmetries: np.ndarray, options: MeasureFitOptions = MeasureFitOptions(),
             steps: int = SYMMETRY_STEPS) -> IFS:
    """Each map composed with the support's symmetry whose measure matches ``image`` best, one map at a time.

    Rounds (`SYMMETRY_ROUNDS`): the probabilities fitted to ``image`` with the maps given (``steps``
    steps of `fit_measure` with ``options``' rates and measure), then every map ``T_i`` replaced by
    ``T_i S`` for the ``S`` of ``symmetries`` (``(k, 3, 3)``, `support_symmetries`) that lowers the loss
    most, by `SYMMETRY_GAIN` at least; until no map turns.

    Returns
    -------
    IFS
        Affine maps (`ifslib.core.geometry.patterns.affine`) with the fitted probabilities.
    """
    target = check_measure_image(image)
    maps = ifs.to(torch.float64).maps().detach()
    p = ifs.measure_probabilities(maps)
    sym = torch.as_tensor(symmetries, dtype=torch.float64)
    check_int(steps, "steps", 1)
    quick = dataclasses.replace(options, steps=steps, fit_maps=False)
    for _ in range(SYMMETRY_ROUNDS):
        start = patterns.affine(maps, depth=ifs.depth, name=ifs.name, dtype=torch.float64)
        start.probabilities = tuple(p.tolist())
        p = torch.tensor(fit_measure(start, target, quick).probabilities, dtype=torch.float64)
        turned = False
        for i in range(len(maps)):
            trials = maps[None].repeat(len(sym), 1, 1, 1)
            trials[:, i] = maps[i] @ sym
            with torch.no_grad():  # a turn that stretches (a long figure's) may stop the map contracting: not tried
                loss = [float(multiscale_loss(measure_from_maps(t, p, target.shape[0], options.measure), target,
                                              options.scales)) if singular_values(t)[1].max() < MAX_FIT_SCALE
                        else np.inf for t in trials]
            best = int(np.argmin(loss))
            if loss[best] < (1 - SYMMETRY_GAIN) * loss[0]:
                maps, turned = trials[best], True
        if not turned:
            break
    out = patterns.affine(maps, depth=ifs.depth, name=ifs.name, dtype=ifs.points.dtype)
    out.probabilities = tuple(float(x) / float(p.sum()) for x in p)
    return out


__all__ = ["MAX_FIT_SCALE", "MeasureFit", "MeasureFitOptions", "check_measure_image", "correlation", "fit_measure",
           "fit_measure_from_support", "multiscale_loss", "pool_measure", "reorient", "support_symmetries",
           "support_target"]
