"""The automatic path's tuned numbers, in one frozen `AutoConfig`; `AUTO` is the tuned one.

Four sections, one per stage of ``ifslib fit IMAGE --pattern auto``: `FigureConfig` (how the figure is read:
curve or shape, lace or solid, detailed, limbed, searched or not), `StartConfig` (the curve and shape starts
offered), `SearchConfig` (the fractal search, `ifslib.automatic.fractal.config`) and `AutoFitConfig` (how the
``auto`` strategy fits and compares them). Each field says what it trades; where a value was measured, the docs
page that measured it. Change one with ``dataclasses.replace``.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field, fields

from ..errors import IFSError, check_int
from ..core.scoring.losses import check_loss
from .fractal.config import DEFAULT as SEARCH
from .fractal.config import SearchConfig


def _check(config, skip: tuple[str, ...] = (), may_be_zero: tuple[str, ...] = ()) -> None:
    """Every int at least 1 (a count or a size; 0 allowed for ``may_be_zero``), every float finite and >= 0, every
    tuple of such numbers; the fields ``skip`` are checked by the caller."""
    for f in fields(config):
        if f.name in skip:
            continue
        value = getattr(config, f.name)
        for v in (value if isinstance(value, tuple) else (value,)):
            for x in (v if isinstance(v, tuple) else (v,)):
                if isinstance(x, bool) or not isinstance(x, (int, float)) or not 0 <= x < float("inf"):
                    raise IFSError(f"{f.name} must hold finite numbers >= 0 ({type(config).__name__}), got {value!r}")
                if isinstance(x, int):
                    check_int(x, f.name, 0 if f.name in may_be_zero else 1, f" (a {type(config).__name__} field)")


def _share(config, *names: str) -> None:
    for name in names:
        if not 0 <= getattr(config, name) <= 1:
            raise IFSError(f"{name} is a share: give a number from 0 to 1, got {getattr(config, name)!r}")


@dataclass(frozen=True)
class FigureConfig:
    """How the figure is read (`ifslib.automatic.auto`, `ifslib.automatic.plan`): each threshold's one line."""

    # too few pixels to read a curve or a shape from: below it the figure is refused
    min_pixels: int = 4
    # one-pixel dilations that may join a dotted figure before its skeleton: more joins looser dots, and blurs gaps
    max_join: int = 4
    # a figure of less area than this many pixels per skeleton pixel is thin (a line 1-3 px wide): higher calls
    # wider strokes curves
    curve_width: float = 4.0
    # ... and a curve when its skeleton's longest path holds this share of it: lower takes networks (the carpet's)
    # for paths
    curve_path_share: float = 0.8
    # pixels wide the figure is made before its interior, edge and thin shares are read: a solid figure's interior
    # share rises with size, a fractal's does not
    porous_size: int = 128
    # below this interior share a figure is porous and searched as a fractal: the benchmark's fractals measure at most
    # 0.76, solid silhouettes 0.88 and more (docs/results/fractals.md)
    porous_share: float = 0.8
    # from this interior share a porous figure may be a shape with thin parts (0.78-0.80) as well as a fractal: it is
    # searched only with a rough edge, and fitted both ways unless the search is clear (0.06-0.76 for the fractals)
    ambiguous_share: float = 0.6
    # the search's attractor IoU that makes an ambiguous figure a fractal without a shape rival: higher fits more
    # figures both ways (twice the time)
    clear_fractal_iou: float = 0.93
    # edge box-counting dimension from which a solid figure is searched too: the overlap class 1.05-1.14, drawn
    # silhouettes 0.97-1.03 (docs/results/literature.md)
    rough_edge: float = 1.04
    # box sides (pixels at porous_size) of that count: finer boxes see finer roughness, and more pixel noise
    edge_boxes: tuple[int, ...] = (1, 2, 4, 8)
    # a rough edge made of limbs costs no search when more than this share lies in thin parts (creatures 0.14-0.22,
    # the overlap class 0.02-0.08)
    thin_parts: float = 0.1
    # parts narrower than a disk of this radius (pixels at porous_size) are thin: 7 px, a limb of 4-6 px at 128²
    thin_radius: int = 3
    # a shape is detailed (offered more, smaller copies) from this interior share, a figure and not a lace ...
    detailed_from: float = 0.6
    # ... and below this one: the limbed creatures, thin letters and flower 0.71-0.84, drawn silhouettes 0.88-0.95
    detailed_below: float = 0.85
    # ... in a target of at least this many pixels a side: a smaller one has few pixels for 40 copies
    detailed_min_size: int = 128
    # a figure of fewer pixels is not searched as a fractal: too few to read copies from
    fractal_min_pixels: int = 100
    # nor a target smaller than this: at 64² a fractal's own maps draw IoU 0.77, and a shape fit scores better
    fractal_min_size: int = 128
    # the search's maps are the start when their attractor is within this many pixels (Chamfer) of the target:
    # higher takes rougher fractals over a shape fit
    fractal_chamfer: float = 1.0
    # times an ambiguous figure's search runs again from the next seed (SearchConfig.again for it): it has a shape
    # fit to fall back on, and each run doubles the wait (docs/results/any-shape.md)
    ambiguous_again: int = 0

    def __post_init__(self):
        _check(self, may_be_zero=("ambiguous_again",))
        _share(self, "curve_path_share", "porous_share", "ambiguous_share", "clear_fractal_iou", "thin_parts",
               "detailed_from", "detailed_below")


@dataclass(frozen=True)
class StartConfig:
    """The curve and shape starts offered (`ifslib.automatic.auto.choices`, `shape_maps`)."""

    # (maps, depth) pairs of a shape when neither is given: more, smaller copies at a lower depth fit thin parts far
    # apart (the flower at 128²: IoU 0.83 with 8 maps at depth 3, 0.94 with 24 at depth 2), 256-576 leaves each
    shape_choices: tuple[tuple[int, int], ...] = ((8, 3), (16, 2), (24, 2))
    # ... and of a detailed figure: more, smaller copies keep the spikes a squeezed copy carries short
    # (docs/results/any-shape.md), at more leaves
    shape_choices_detailed: tuple[tuple[int, int], ...] = ((40, 2), (48, 2), (56, 2))
    # numbers of maps of a shape at a given depth: more candidates, each probed
    shape_maps: tuple[int, ...] = (4, 6, 8)
    # numbers of maps (segments) of a curve: more candidates, each probed
    curve_maps: tuple[int, ...] = (2, 3, 4)
    # depth of a curve's start, and of a shape's when its number of maps is given: deeper draws finer, slower
    default_depth: int = 3
    # a limbed figure's thin parts get this many times their share of the maps (at most half): more copies squeezed
    # across limbs, fewer on the body
    limb_maps: float = 2.0
    # every start map's singular values are clipped into this range: contracting, and not flat
    singular_range: tuple[float, float] = (0.05, 0.85)
    # the most maps an automatic start takes: a cap on the cost of a request (each map is a copy of the figure)
    max_start_maps: int = 64

    def __post_init__(self):
        _check(self)
        low, high = self.singular_range
        if not 0 < low < high < 1:
            raise IFSError(f"singular_range must satisfy 0 < low < high < 1, got {self.singular_range!r}")


@dataclass(frozen=True)
class AutoFitConfig:
    """How the ``auto`` strategy fits and compares a plan (`ifslib.automatic.fit_plan`)."""

    # steps each curve or shape candidate gets at the coarsest size before they are compared: surer, slower
    probe_steps: int = 150
    # a shape's last stage's loss: the pixel loss counts every uncovered pixel, where the distance loss hardly sees
    # the slivers between copies (apple at 256²: IoU 0.89 -> 0.97, docs/results/any-shape.md)
    polish_loss: str = "multiscale_pixel"
    # a shape's attractor stage draws the certified cut up to this many leaves, else sampled ones: exact, against
    # 0.55 s a step for the thin letter Y's 228,598 leaves (0.12 s sampled; docs/results/any-shape.md)
    shape_max_leaves: int = 65_536
    # steps of a fractal plan's one attractor stage: its maps are placed within a fraction of a pixel already
    fractal_stage_steps: int = 100
    # that stage's loss: the single-scale pixel loss scores the attractor's IoU better than the multiscale pixel or
    # a soft IoU loss, and quicker (docs/results/fractals.md)
    fractal_loss: str = "pixel"
    # IoU a map costs between the kinds of an ambiguous figure (1 - attractor IoU + this a map, the least kept): the
    # search's map_cost over 40, else a 24-map shape could never beat a fractal
    kind_map_cost: float = 0.001
    # a fractal whose attractor IoU after its stage is below this is polished by the splat fit too (0: never); a fit
    # already recovered (docs/results/fractals.md's 0.85) keeps its time
    splat_below: float = 0.85
    # the splat polish's steps (at most the fit's budget), all at the target's size: every map and probability at
    # once on the chaos game's coverage; about 50 s at 256² on one thread
    splat_steps: int = 200
    # its learning rate for the maps' raw parameters, with no annealing and no reselection: the splat fit's own 0.03
    # with both moves maps off the search's places (many1: attractor IoU 0.798 -> 0.567; 0.005 at full size: 0.840;
    # docs/results/literature.md, "The splat polish")
    splat_lr: float = 0.005
    # offer the learned guess (`ifslib.learned`) beside the search's maps, the one whose attractor scores better
    # (the search's own rule) kept: a fractal of many maps whose search falls short (docs/results/learned-guess.md)
    learned: bool = False

    def __post_init__(self):
        check_loss(self.polish_loss)
        check_loss(self.fractal_loss)
        _check(self, skip=("polish_loss", "fractal_loss", "learned"))
        if not isinstance(self.learned, bool):
            raise IFSError(f"learned must be True or False, got {self.learned!r}")
        _share(self, "splat_below")
        if not self.splat_lr > 0:
            raise IFSError(f"splat_lr must be a learning rate > 0, got {self.splat_lr!r}")


@dataclass(frozen=True)
class AutoConfig:
    """Every tuned number of the automatic path, by stage."""

    figure: FigureConfig = field(default_factory=FigureConfig)
    start: StartConfig = field(default_factory=StartConfig)
    search: SearchConfig = SEARCH
    fit: AutoFitConfig = field(default_factory=AutoFitConfig)

    @property
    def ambiguous_search(self) -> SearchConfig:
        """The search of a figure that may be a shape as well: `search`, run again ``figure.ambiguous_again`` times."""
        return dataclasses.replace(self.search, again=self.figure.ambiguous_again)


#: The tuned settings, which the automatic path reads.
AUTO = AutoConfig()
