"""Fitting a measure: an IFS's probabilities, and optionally its maps, fitted to a grayscale image of its measure.

Gradient descent (Adam) through the deterministic invariant measure (`ifslib.raster.measure`): the
probabilities live on the simplex as a softmax of free logits; the maps move through the IFS's
control points (its ``fixed`` points stay). The loss compares densities (mass times the number of
pixels) summed over pooled copies of both images, the multiscale squared error of the paper, so a
map's copy that lands a few pixels off still feels a pull. The start's maps are the caller's: from
near the truth (control points moved by 0.015) the fern's gray image is fitted to a density
correlation of 0.98 (docs/results/measures.md); a start read from the image alone is not made here.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from tqdm.auto import tqdm

import numpy as np
import torch
import torch.nn.functional as F

from ..errors import IFSError, check_int, check_positive
from ..geometry.ifs import IFS
from ..progress import draw_bars
from ..raster.measure import MeasureOptions, measure_from_maps


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
    """

    ifs: IFS
    probabilities: tuple[float, ...]
    losses: tuple[float, ...]
    correlation: float


def check_measure_image(image) -> torch.Tensor:
    """A grayscale image of a measure as a ``(S, S)`` float64 tensor summing to 1; `IFSError` if it cannot be one."""
    img = torch.as_tensor(np.asarray(image.detach() if isinstance(image, torch.Tensor) else image, dtype=np.float64))
    if img.ndim != 2 or img.shape[0] != img.shape[1] or img.shape[0] < 2:
        raise IFSError(f"a measure's image must be square (S, S) with S >= 2, got shape {tuple(img.shape)}")
    if not torch.isfinite(img).all() or (img < 0).any() or not img.sum() > 0:
        raise IFSError("a measure's image must be finite and >= 0 with some mass (gray levels, not a mask of 0 and -1)")
    return img / img.sum()


def multiscale_loss(a: torch.Tensor, b: torch.Tensor, scales: int) -> torch.Tensor:
    """Sum over ``scales`` 2x poolings of the mean squared difference of densities (mass times pixels) of ``(S, S)`` images."""
    a, b = a[None, None] * a.numel(), b[None, None] * b.numel()
    total = a.new_zeros(())
    for k in range(scales):
        if k:
            a, b = F.avg_pool2d(a, 2, ceil_mode=True), F.avg_pool2d(b, 2, ceil_mode=True)
        total = total + ((a - b) ** 2).mean()
    return total


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
        histogram, `ifslib.raster.measure.chaos_measure`, or a photograph's gray levels).
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
    optimizer = torch.optim.Adam(params)
    losses = []
    for _ in tqdm(range(options.steps), desc="fit measure", disable=not (options.progress and draw_bars())):
        optimizer.zero_grad()
        maps = work.maps() if options.fit_maps else work.maps().detach()
        loss = multiscale_loss(measure_from_maps(maps, logits.softmax(0), size, options.measure), target,
                               options.scales)
        loss.backward()
        if options.fit_maps:
            work.points.grad *= free
        optimizer.step()
        losses.append(float(loss.detach()))
        if not np.isfinite(losses[-1]):
            raise IFSError("the measure fit's loss is not finite: lower lr, or start nearer (the maps may have "
                           "stopped contracting)")
    p = tuple(float(x) for x in logits.detach().softmax(0))
    p = tuple(x / sum(p) for x in p)
    fitted = work.clone()
    fitted.probabilities = p
    with torch.no_grad():
        final = measure_from_maps(fitted.maps(), p, size, options.measure)
    return MeasureFit(fitted.to(ifs.points.dtype), p, tuple(losses), correlation(final, target))


__all__ = ["MeasureFit", "MeasureFitOptions", "check_measure_image", "correlation", "fit_measure", "multiscale_loss"]
