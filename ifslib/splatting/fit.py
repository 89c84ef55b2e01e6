"""A fit of many maps and their probabilities to an image through the splatting renderer, as the literature fits.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass

import numpy as np
import torch
import torch.nn.functional as F
from tqdm.auto import tqdm

from ..errors import IFSError, check_int
from ..names import DEFAULT_STEPS
from ..core.fitting.descent import Descent, StepPolicy
from ..core.geometry import patterns
from ..core.geometry.ifs import IFS
from ..core.scoring.losses import multiscale_mse
from ..core.targets.target import Target
from ..progress import draw_bars
from . import config
from .moves import random_start, reselect
from .parameters import ContractiveMaps
from .render import SplatOptions, coverage, splat_measure

KINDS = ("auto", "support", "measure")


@dataclass(frozen=True)
class SplatFitOptions:
    """How `fit_splat` runs (defaults from `ifslib.splatting.config`, which says what each trades).

    Attributes
    ----------
    steps : int
        Adam steps over all levels, split by `config.LEVEL_STEPS`.
    points_per_pixel : float
        Points splatted a step per pixel of a level's frame (`config.POINTS_PER_PIXEL`).
    kind : {"auto", "support", "measure"}
        Fit the image as a figure's mask (coverage) or as a measure's gray levels (density); "auto": a boolean
        image or a `Target` is a figure, anything else a measure.
    map_lr, probability_lr : float
        Adam's learning rates.
    anneal_share, anneal_noise : float
        Annealing noise's share of the steps and its scale in learning rates.
    reseed_every, reseed_share : int, float
        Reselection every this many steps within this share of the steps (``reseed_every=0``: never).
    depth : int
        Chain steps the gradient runs through (`SplatOptions.depth`).
    seed : int
        Seeds the start, the noise and the chains.
    starts, screen_steps : int
        From a random start: this many random starts are each fitted ``screen_steps`` steps on the image pooled to a
        quarter of its size, and the fit goes on from the one of least loss (a reselection of whole starts: one
        random start of ten maps often lands in a local minimum that no step leaves).
    device : str
        Where the replay, the splat and Adam run ("cpu", or "cuda" where torch has it); the chains are drawn on the
        CPU either way.
    progress : bool
        A progress bar (tqdm.auto) where someone watches.
    snapshots : tuple of int
        Steps after which the fit's maps and probabilities are kept (`SplatFit.snapshots`): 0 is the start (after
        the screening), ``steps`` the result. A picture of the fit as it goes, at the cost of one IFS a snapshot.
    coarse_to_fine : bool
        Run the steps over `config.LEVELS` (a quarter, half and the whole size); False: every step at the image's
        own size, to polish maps already placed to a pixel (a coarse level blurs their detail away).
    """

    steps: int = DEFAULT_STEPS
    points_per_pixel: float = config.POINTS_PER_PIXEL
    kind: str = "auto"
    map_lr: float = config.MAP_LR
    probability_lr: float = config.PROBABILITY_LR
    anneal_share: float = config.ANNEAL_SHARE
    anneal_noise: float = config.ANNEAL_NOISE
    reseed_every: int = config.RESEED_EVERY
    reseed_share: float = config.RESEED_SHARE
    depth: int = config.GRADIENT_DEPTH
    seed: int = 0
    starts: int = config.STARTS
    screen_steps: int = config.SCREEN_STEPS
    device: str = "cpu"
    progress: bool = False
    snapshots: tuple[int, ...] = ()
    coarse_to_fine: bool = True

    def __post_init__(self) -> None:
        check_int(self.steps, "steps", 1)
        if not isinstance(self.snapshots, (tuple, list)):
            raise IFSError(f"snapshots must be a tuple of steps, got {self.snapshots!r}")
        for step in self.snapshots:
            check_int(step, "snapshots' step", 0, maximum=self.steps)
        # a list from the caller becomes a sorted tuple without repeats, so that options stay hashable
        object.__setattr__(self, "snapshots", tuple(sorted(set(self.snapshots))))
        if isinstance(self.points_per_pixel, bool) or not isinstance(self.points_per_pixel, (int, float)) \
                or not 0 < self.points_per_pixel <= 1e4:
            raise IFSError(f"points_per_pixel must be a number in (0, 10000], got {self.points_per_pixel!r}")
        check_int(self.reseed_every, "reseed_every", 0)
        check_int(self.depth, "depth", 1, maximum=256)
        check_int(self.seed, "seed", 0)
        check_int(self.starts, "starts", 1, maximum=1000)
        check_int(self.screen_steps, "screen_steps", 1)
        if self.kind not in KINDS:
            raise IFSError(f"kind must be one of {KINDS}, got {self.kind!r}")
        for name in ("map_lr", "probability_lr"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value < 10:
                raise IFSError(f"{name} must be a number in (0, 10), got {value!r}")
        for name in ("anneal_share", "reseed_share"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 <= value <= 1:
                raise IFSError(f"{name} must be a share in [0, 1], got {value!r}")
        if isinstance(self.anneal_noise, bool) or not isinstance(self.anneal_noise, (int, float)) \
                or not 0 <= self.anneal_noise < 1e3:
            raise IFSError(f"anneal_noise must be a number >= 0, got {self.anneal_noise!r}")
        if self.device not in ("cpu", "cuda") or (self.device == "cuda" and not torch.cuda.is_available()):
            raise IFSError(f"device must be 'cpu', or 'cuda' where torch has CUDA, got {self.device!r}")
        for name in ("progress", "coarse_to_fine"):
            if not isinstance(getattr(self, name), bool):
                raise IFSError(f"{name} must be True or False, got {getattr(self, name)!r}")


@dataclass(frozen=True)
class SplatFit:
    """What `fit_splat` found.

    Attributes
    ----------
    ifs : IFS
        Affine rules (`ifslib.core.geometry.patterns.affine`) with the fitted ``probabilities``.
    losses : tuple of float
        The loss at each step (levels differ in scale).
    reseeds : int
        Maps moved by reselection.
    seconds : float
        Wall time of the fit.
    snapshots : tuple of (int, IFS)
        For each step of `SplatFitOptions.snapshots`, in order, the step and the fit's maps after it (as `ifs`).
    """

    ifs: IFS
    losses: tuple[float, ...]
    reseeds: int
    seconds: float
    snapshots: tuple[tuple[int, IFS], ...] = ()


def read_image(image, kind: str) -> tuple[np.ndarray, str]:
    """``(S, S)`` float64 image and its kind: a figure's mask of 0 and 1, or a measure's gray levels summing to 1."""
    if isinstance(image, Target):
        image = image.mask
    array = np.asarray(image.detach().cpu() if isinstance(image, torch.Tensor) else image)
    if array.ndim != 2 or array.shape[0] != array.shape[1] or array.shape[0] < 8:
        raise IFSError(f"the image must be square (S, S) with S >= 8, got shape {array.shape}")
    if kind == "auto":
        kind = "support" if array.dtype == bool else "measure"
    if not np.issubdtype(array.dtype, np.number) and array.dtype != bool:
        raise IFSError(f"the image must hold numbers or booleans, got dtype {array.dtype}")
    array = array.astype(np.float64)
    if not np.isfinite(array).all() or (array < 0).any():
        raise IFSError("the image must be finite and >= 0 (gray levels or a mask)")
    if kind == "support":
        array = (array > 0).astype(np.float64)
        if not 0 < array.sum() < array.size:
            raise IFSError("the figure is empty or fills the frame: nothing to fit")
        return array, kind
    if not array.sum() > 0:
        raise IFSError("the measure's image has no mass")
    return array / array.sum(), kind


def level_image(image: np.ndarray, factor: int, kind: str) -> torch.Tensor:
    """The image at ``1 / factor`` of its size: a figure max-pooled (a block is on where any pixel is), a measure
    sum-pooled."""
    t = torch.as_tensor(image)[None, None]
    if factor == 1:
        return t[0, 0]
    pooled = F.max_pool2d(t, factor, ceil_mode=True) if kind == "support" else \
        F.avg_pool2d(t, factor, ceil_mode=True) * factor ** 2
    return pooled[0, 0]


def image_loss(density: torch.Tensor, target: torch.Tensor, kind: str) -> torch.Tensor:
    """The multiscale MSE of a splat's mass per pixel against a level's target (coverage or density)."""
    if kind == "support":
        scale = config.COVERAGE / float(target.sum())   # COVERAGE of the figure's mean mass a pixel
        return multiscale_mse(coverage(density, scale), target.to(density.dtype), config.LOSS_LEVELS)
    pixels = target.numel()
    return multiscale_mse(density * pixels, target.to(density.dtype) * pixels, config.LOSS_LEVELS)


def start_maps(start, m: int | None, mask: np.ndarray, generator: torch.Generator) -> ContractiveMaps:
    """The start's maps: ``start`` (an IFS or ``(k, 3, 3)`` maps) topped up to ``m`` with random ones, or ``m``
    random maps."""
    if start is None:
        if m is None:
            raise IFSError("give the number of maps, or start maps to fit from")
        return random_start(mask, check_int(m, "maps", 1, maximum=64), config.START_SCALES, generator)
    maps = start.to(torch.float64).maps().detach() if isinstance(start, IFS) else torch.as_tensor(start).double()
    given = ContractiveMaps.from_maps(maps)
    if m is None or m <= len(given):
        return given
    extra = random_start(mask, m - len(given), config.START_SCALES, generator)
    return ContractiveMaps(torch.cat([given.raw.detach(), extra.raw.detach()]))


def fit_splat(image, maps: int | None = None, start=None, options: SplatFitOptions = SplatFitOptions()) -> SplatFit:
    """Fit ``maps`` affine maps and their probabilities to a figure or a measure's gray image by the splat renderer.

    Parameters
    ----------
    image : Target or array-like
        ``(S, S)``: a figure (a `Target`, or a boolean mask) or a measure's gray levels >= 0, row 0 at the top.
    maps : int, optional
        The number of maps (at least the start's; needed without ``start``).
    start : IFS or array-like, optional
        ``(k, 3, 3)`` maps (or an IFS: its maps and probabilities) to start from; random maps placed on the
        figure when None.
    options : SplatFitOptions

    Returns
    -------
    SplatFit
    """
    if not isinstance(options, SplatFitOptions):
        raise IFSError(f"options must be a SplatFitOptions, got {type(options).__name__}")
    t0 = time.perf_counter()
    array, kind = read_image(image, options.kind)
    if start is None and options.starts > 1:
        start = _screen(array, kind, maps, options)
    generator = torch.Generator().manual_seed(options.seed)
    params = start_maps(start, maps, array > 0, generator)
    params.raw = params.raw.detach().to(options.device).requires_grad_(True)
    p0 = start.measure_probabilities() if isinstance(start, IFS) and len(start.rules) == len(params) else \
        torch.full((len(params),), 1.0 / len(params), dtype=torch.float64)
    logits = p0.log().float().to(options.device).requires_grad_(True)
    reseeds = 0
    kept = [(0, _result(params, logits))] if 0 in options.snapshots else []
    size = array.shape[0]
    levels = zip(config.LEVELS, config.LEVEL_STEPS) if options.coarse_to_fine else [(1, 1.0)]
    plan = [(f, share) for f, share in levels if size // f >= 16]
    total_share = sum(share for _, share in plan)
    bar = tqdm(total=options.steps, desc="fit splat", disable=not (options.progress and draw_bars()))
    policy = StepPolicy(schedule=lambda index: _decay(index / options.steps),
                        advice="the splat fit's loss is not finite: lower map_lr")
    descent = Descent([{"params": [params.raw], "lr": options.map_lr},
                       {"params": [logits], "lr": options.probability_lr}], None, policy)
    for index, (factor, share) in enumerate(plan):
        target = level_image(array, factor, kind).to(options.device)
        level_size = target.shape[0]
        count = options.steps - descent.index if index == len(plan) - 1 else round(options.steps * share / total_share)
        points = max(CHAIN_FLOOR, round(options.points_per_pixel * level_size ** 2))
        mask = target.cpu().numpy() > 0

        def loss() -> torch.Tensor:  # this level's (each level's closures run before the next level's are made)
            density = splat_measure(params.maps(), logits.softmax(0), level_size,
                                    SplatOptions(points, options.depth, seed=options.seed * 100_003 + descent.index))
            return image_loss(density, target, kind)

        def after(*_) -> None:
            nonlocal reseeds
            step = descent.index
            _anneal(params, options, step, generator)
            due = options.reseed_every and step % options.reseed_every == 0
            if due and step < options.reseed_share * options.steps:
                moved = reselect(params, logits.detach().cpu().softmax(0), mask, points * config.RESEED_POINTS,
                                 options.seed * 100_003 + step, generator, config.RESEED_UNCOVERED)
                if moved is not None:
                    reseeds += 1
                    descent.forget(params.raw, moved)
            if step in options.snapshots:
                kept.append((step, _result(params, logits)))

        descent.loss = loss
        descent.run(descent.index + count, after, bar)
    losses = descent.losses
    bar.close()
    return SplatFit(_result(params, logits), tuple(losses), reseeds, time.perf_counter() - t0, tuple(kept))


def _screen(array: np.ndarray, kind: str, maps: int | None, options: SplatFitOptions) -> IFS:
    """The best of ``options.starts`` random starts, each fitted ``screen_steps`` steps at a quarter of the size."""
    small = level_image(array, 4, kind).numpy() if array.shape[0] >= 64 else array
    fits = [fit_splat(small > 0 if kind == "support" else small, maps, None,
                      dataclasses.replace(options, steps=options.screen_steps, starts=1, seed=options.seed * 1000 + k,
                                          progress=False, kind=kind, snapshots=()))
            for k in range(options.starts)]
    return min(fits, key=lambda f: float(np.mean(f.losses[-config.SCREEN_TAIL:]))).ifs


#: The fewest points a level splats (one step of every chain).
CHAIN_FLOOR = 2048


def _decay(progress: float) -> float:
    """The learning rate's share at ``progress`` (0 to 1) of the steps: a cosine from 1 to `config.FINAL_LR_SHARE`,
    so the last steps settle the maps to a pixel's precision instead of jittering by the first steps' size."""
    low = config.FINAL_LR_SHARE
    return low + (1 - low) * 0.5 * (1 + math.cos(math.pi * min(1.0, progress)))


def _anneal(params: ContractiveMaps, options: SplatFitOptions, step: int, generator: torch.Generator) -> None:
    """Gaussian noise on the raw parameters, its scale falling linearly to 0 at ``anneal_share`` of the steps."""
    end = options.anneal_share * options.steps
    if step >= end or options.anneal_noise == 0:
        return
    scale = options.anneal_noise * options.map_lr * (1 - step / end)
    with torch.no_grad():
        params.raw += scale * torch.randn(params.raw.shape, generator=generator).to(params.raw)


def _result(params: ContractiveMaps, logits: torch.Tensor) -> IFS:
    """The fitted maps as affine rules with their probabilities (float64, summing to 1)."""
    maps = params.maps().detach().double().cpu()
    ifs = patterns.affine(maps, depth=2, name="splat", dtype=torch.float64)
    p = logits.detach().double().cpu().softmax(0)
    ifs.probabilities = tuple((p / p.sum()).tolist())
    return ifs
