"""The fractal search's settings, in one frozen `SearchConfig`; `DEFAULT` is the tuned one.

Each field says what it trades; where a value was measured, the docs page that measured it.
Change one with ``dataclasses.replace(DEFAULT, again=0)``.
"""
from __future__ import annotations

from dataclasses import dataclass, fields

from ...errors import IFSError, check_int

#: Fields that are counts of at least 0 (the rest of the ints must be at least 1).
_MAY_BE_ZERO = {"firsts", "random_starts", "search_steps", "refine_steps", "screen", "reorient", "swap_rounds",
                "region_rounds", "grow_rounds", "again", "parts"}
#: Fields that are sizes in pixels: at least 2.
_SIZES = {"search_size", "refine_size", "judge_size"}


@dataclass(frozen=True)
class SearchConfig:
    """Every tuning setting of `ifslib.automatic.fractal.search` (the package docstring says where each acts)."""

    # the numbers of maps compared when none is given: more finds larger fractals, each costs a search
    fractal_maps: tuple[int, ...] = tuple(range(2, 9))
    # the most maps a search takes when they are given: a cap on the time a request may cost
    max_maps: int = 16
    # the copies are matched (and first refined) at this size: larger places copies finer, the FFTs cost its square
    search_size: int = 64
    # the starts are refined, and the numbers of maps compared, at this size: finer detail against slower steps
    refine_size: int = 128
    # the least singular value of a map: lower allows thinner copies, and flat maps that draw nothing
    min_scale: float = 0.02
    # the largest singular value of a map: 0.9 or more lets a single map draw a blob
    max_scale: float = 0.9
    # share of a copy's pixels that must land on the figure grown by one pixel: lower admits copies that spill out
    inside: float = 0.9
    # candidate copies kept of each scale: more keeps small copies beside near-twins of large ones, at more cost
    per_scale: int = 800
    # greedy covers start from this many of the largest copies: more starts, more collage refinements
    firsts: int = 16
    # sets of copies the beam search for covers keeps at each size: wider finds more covers, slower
    beam: int = 32
    # what the beam search charges a pixel covered twice: higher favours copies that barely overlap
    overlap: float = 0.5
    # random starts for each number of maps (as Tu et al. start): more variety, more refinement
    random_starts: int = 16
    # first copies of the collage's facility-location search (`collage_sets`): more sets, more time
    restarts: int = 16
    # Adam steps of the collage at `search_size`: more converges further, each step refines every start
    search_steps: int = 150
    # Adam steps of the collage at `refine_size` (and in every move): as `search_steps`, at the finer size
    refine_steps: int = 150
    # Adam's learning rate of the collage at `search_size`, plane units a step: faster moves copies further, less steadily
    search_lr: float = 0.005
    # Adam's learning rate of the collage at `refine_size` and in every move: as `search_lr`, for finer placements
    refine_lr: float = 0.002
    # IoU by which a move's attractor must beat the maps it replaces to be kept: higher ignores chaos-game noise,
    # lower keeps smaller gains
    accept_margin: float = 1e-3
    # starts that go on from `search_size` to `refine_size`: more keeps more chances, each refined again
    keep: int = 4
    # starts with the least collage whose attractors are drawn to choose the `keep`: more judged, more chaos games
    shortlist: int = 16
    # chaos-game points of every screening drawing: more is steadier, slower
    screen_points: int = 50_000
    # rotations of the figure's ellipse (as many reflections) `reorient` turns each map by: finer turns cost more
    turns: int = 12
    # variants `reorient` refines, those whose collage starts best: more tries, more refinement
    screen: int = 12
    # numbers of maps reoriented and compared at the end (least Chamfer score): more is surer, each one costs moves
    reorient: int = 3
    # pixels of Chamfer distance a map costs when choosing which numbers of maps to try and reorient
    chamfer_cost: float = 0.1
    # the numbers of maps are compared by their attractors' IoU at this size (or the target's, when smaller)
    judge_size: int = 256
    # chaos-game points of that comparison: a quarter of two million, for an IoU within 0.002 of theirs
    judge_points: int = 500_000
    # IoU a map costs: lower keeps maps that add slivers, higher drops true small maps (docs/results/fractals.md)
    map_cost: float = 0.04
    # more maps than this are not tried when none came within `give_up_px`: a shape stops paying for the search
    give_up_maps: int = 4
    # pixels of Chamfer distance a fractal of a few maps comes within (49 of 50 by 4 maps, docs/results/fractals.md)
    give_up_px: float = 2.5
    # IoU a fractal counts as recovered at: higher makes found ones pay for idle moves (docs/results/fractals.md)
    swap_below: float = 0.85
    # rounds of `swap` in all: more mends more maps, each round ranks and refines replacements
    swap_rounds: int = 8
    # largest copies of each scale and ratio of singular values in `swap`'s pool: a wider pool, slower rankings
    swap_per_shape: int = 100
    # replacements `swap` refines and judges each round: more tries, more refinement
    swap_top: int = 8
    # rounds of `region_swap` for each number of maps: more mends more maps, each round refines replacements
    region_rounds: int = 4
    # replacements `region_swap` refines and judges each round: more tries, more refinement
    region_top: int = 8
    # times `region_grow` gives the next number of maps the best one's maps and one more: each a refinement
    grow_rounds: int = 2
    # times the search runs again from the next seed while no attractor fits, each in full (docs/results/fractals.md)
    again: int = 1
    # figure pixels of the collage distance at `search_size` and at `refine_size`: steadier, slower steps
    collage_points: tuple[int, int] = (600, 2000)
    # chaos-game points of `attractor_chamfer`: steadier distances, slower drawings
    compare_points: int = 200_000
    # rotations (each with and without a reflection) a region's copy tries (`regions.moment_maps`): finer, slower
    angles: int = 72
    # angles of the whole turn the linear parts of the copies' grid take (`linear_grid`): finer turns, more FFTs
    grid_turns: int = 36
    # second angles (of the half turn) of a non-similar linear part: finer shears, more FFTs
    grid_phases: int = 8
    # larger singular values of the grid's linear parts: more sizes of copy, more FFTs
    grid_scales: tuple[float, ...] = (0.25, 0.35, 0.45, 0.55, 0.65, 0.75, 0.85)
    # ratios of the smaller singular value to the larger (1: a similarity): thinner copies, more FFTs
    grid_ratios: tuple[float, ...] = (0.05, 0.1, 0.2, 0.4, 0.6, 0.8, 1.0)
    # singular values of a random start's maps are drawn in this range: wider tries more sizes, more starts wasted
    start_scales: tuple[float, float] = (0.25, 0.65)
    # share of a random start's maps that are reflected: a figure's mirrored copies, against turned ones
    start_reflected: float = 1 / 3
    # sweeps of the collage sets' local search (each map swapped for the best candidate): better sets, slower
    collage_sweeps: int = 4
    # copies kept for each uncovered region, those overlapping it most: more offers, more trials to rank
    per_region: int = 3
    # largest connected parts of a region matched besides the whole: more offers, more trials to rank
    parts: int = 2

    def __post_init__(self):
        for f in fields(self):  # each annotation is a string (postponed annotations): "int", "float", ...
            value = getattr(self, f.name)
            if f.type == "int":
                check_int(value, f.name, 2 if f.name in _SIZES else 0 if f.name in _MAY_BE_ZERO else 1,
                          " (a SearchConfig field)")
            elif f.type == "float" and (isinstance(value, bool) or not isinstance(value, (int, float))
                                        or not value >= 0 or value == float("inf")):
                raise IFSError(f"{f.name} must be a finite number >= 0 (a SearchConfig field), got {value!r}")
        self._check_ranges()

    def _check_ranges(self):
        """The checks that tie fields together or bound them above."""
        if not 0 < self.min_scale < self.max_scale < 1:
            raise IFSError(f"the scales must satisfy 0 < min_scale < max_scale < 1 (every map contracts), "
                           f"got {self.min_scale!r} and {self.max_scale!r}")
        if not self.inside <= 1:
            raise IFSError(f"inside is a share of a copy's pixels: give a number from 0 to 1, got {self.inside!r}")
        if not 0 < self.swap_below <= 1:
            raise IFSError(f"swap_below is an IoU: give a number above 0 and at most 1, got {self.swap_below!r}")
        ks = self.fractal_maps
        if not isinstance(ks, tuple) or not ks:
            raise IFSError(f"fractal_maps must be a non-empty tuple of increasing numbers of maps, got {ks!r}")
        for k in ks:
            check_int(k, "each of fractal_maps (at most max_maps)", 1, maximum=self.max_maps)
        if list(ks) != sorted(set(ks)):
            raise IFSError(f"fractal_maps must be increasing numbers of maps, each once, got {ks!r}")
        for name in ("grid_scales", "grid_ratios", "start_scales"):
            values = getattr(self, name)
            if not isinstance(values, tuple) or not values or not all(0 < v <= 1 for v in values):
                raise IFSError(f"{name} must be a non-empty tuple of numbers above 0 and at most 1, got {values!r}")
        if not 0 <= self.start_reflected <= 1:
            raise IFSError(f"start_reflected is a share: give a number from 0 to 1, got {self.start_reflected!r}")
        points = self.collage_points
        if not isinstance(points, tuple) or len(points) != 2:
            raise IFSError(f"collage_points must be a pair (at search_size, at refine_size), got {points!r}")
        for p in points:
            check_int(p, "each of collage_points", 1)


#: The tuned settings, which every function of the search takes by default.
DEFAULT = SearchConfig()
