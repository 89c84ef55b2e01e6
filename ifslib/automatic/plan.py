"""What discovery hands fitting: a `Plan`, the start read from the image and the candidates an
automatic fit compares, made by `discover`.

How it works: docs/guide/internals.md.
"""
from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..errors import IFSError
from ..core.geometry import patterns
from ..core.geometry.ifs import IFS
from ..core.scoring.metrics import evaluate
from ..core.targets.target import Target, resize_target
from . import fractal
from .auto import candidates, choices, curve_path, measure
from .config import AUTO
from ..core.targets.placement import check_jitter

#: The section of `ifslib.automatic.config.AUTO` this module reads (with ``AUTO.search``).
FIGURE = AUTO.figure


@dataclass(frozen=True)
class Plan:
    """A start read from an image, and what an automatic fit chooses among.

    Attributes
    ----------
    start : IFS
        The start chosen without fitting (the nearest candidate, or the fractal search's maps).
    candidates : tuple of IFS
        The starts the ``auto`` strategy probes and compares, ``start`` among them (a fractal's
        plan has the start alone: its number of maps was chosen by the search).
    kind : str
        ``"curve"``, ``"shape"`` or ``"fractal"``.
    pattern : dict
        What ``start.meta["pattern"]`` records for the JSON file (kind, maps, depth; for a fractal
        the search's table, rule and verdict; for a shape whose search failed, ``fractal_search``).
    rivals : tuple of Plan
        Plans of another kind for the same image, when the image could not tell which kind it is
        (`ambiguous`): the ``auto`` strategy fits each and keeps the one whose attractor scores best
        for its number of maps. Empty when the kind is clear.
    search : tuple of Row
        A fractal plan's search rows (`ifslib.automatic.fractal.SearchResult.rows`), full precision: what
        the automatic fit reports as its candidates. Empty for a curve or a shape.
    why : str, optional
        With ``rivals``: why the figure is fitted as both kinds (`ambiguous`).
    """

    #: The strategy that fits a plan (`ifslib.fit` picks it when given one; `ifslib.automatic.fit_plan` registers it).
    strategy: ClassVar[str] = "auto"

    start: IFS
    candidates: tuple[IFS, ...]
    kind: str
    pattern: dict
    rivals: tuple[Plan, ...] = ()
    search: tuple[fractal.Row, ...] = ()
    why: str | None = None

    def with_start(self, start: IFS) -> Plan:
        """The plan with ``start`` (the same pattern, moved: a jittered start) in place of its start."""
        swapped = tuple(start if c is self.start else c for c in self.candidates)
        return dataclasses.replace(self, start=start, candidates=swapped)

    @property
    def depth(self) -> int:
        return self.start.depth


def fractal_start(target: Target, maps: int | None = None, depth: int = AUTO.start.default_depth, seed: int = 0,
                  progress: bool = True, *, config: fractal.SearchConfig = AUTO.search, learned: bool = AUTO.fit.learned
                  ) -> tuple[IFS | None, dict, fractal.SearchResult]:
    """The maps of `ifslib.automatic.fractal.search` (with ``config``) as a start, or None when their attractor
    does not fit; with ``learned``, the learned guess's maps instead when they score less by the search's rule
    (`with_learned`).

    Returns
    -------
    IFS or None
        ``kind="fractal"`` affine maps, when the chosen attractor's Chamfer distance is at most
        `FIGURE.fractal_chamfer` pixels.
    dict
        What the search compared, for the file: ``search`` (one row per number of maps), ``rule``, ``verdict``.
    SearchResult
        What the search found, its rows at full precision (what a later decision reads).
    """
    found = fractal.search(target, maps, seed=seed, progress=progress, config=config)
    if learned and maps is None:
        found = with_learned(target, found, config)
    chamfer_px = found.choice.chamfer_px
    record = {"search": found.table, "rule": found.rule}
    if chamfer_px > FIGURE.fractal_chamfer:
        record["verdict"] = (f"not a fractal of at most {max(r.maps for r in found.rows)} maps: the best attractor is "
                             f"{chamfer_px:.2f} px from the target (> {FIGURE.fractal_chamfer:g})")
        return None, record, found
    record["verdict"] = f"a fractal: {len(found.maps)} maps whose attractor is {chamfer_px:.2f} px from the target"
    ifs = patterns.affine(found.maps, depth=depth, name="auto")
    ifs.meta["pattern"] = {"name": "auto", "kind": "fractal", "maps": len(found.maps), "depth": depth, **record}
    return ifs, record, found


def with_learned(target: Target, found: fractal.SearchResult, config: fractal.SearchConfig) -> fractal.SearchResult:
    """The search's result with the learned guess's row (`ifslib.learned.guess_maps`) last, scored as the search
    scores its own (``1 - attractor IoU at judge_size + map_cost a map``); its maps chosen when they score less."""
    from ..learned.estimator import guess_maps

    t0 = time.perf_counter()
    guessed = guess_maps(target.mask)
    judge = resize_target(target, min(config.judge_size, target.size))
    fine = resize_target(target, min(config.refine_size, target.size))
    iou = fractal.attractor_iou(guessed, judge, config=config)
    row = fractal.Row(len(guessed), float("nan"), float("nan"), fractal.attractor_chamfer(guessed, fine, config=config),
                      iou, 1 - iou + config.map_cost * len(guessed), time.perf_counter() - t0, learned=True)
    won = row.score < found.choice.score
    rule = (f"{found.rule}; the learned guess's {row.maps} maps scored {row.score:.3f} against the search's "
            f"{found.choice.score:.3f}: {'the guess' if won else 'the search'} kept")
    return dataclasses.replace(found, maps=guessed if won else found.maps, rows=found.rows + (row,), rule=rule,
                               learned=won)


def _searchable(target: Target, share: float, edge: float | None, maps: int | None) -> bool:
    """Whether a shape of interior share ``share`` (and edge dimension ``edge``, `ifslib.automatic.auto.Measures`) is
    searched as a fractal first, when it is large enough: a lace (interior share below `FIGURE.ambiguous_share`), or
    a figure of more interior whose edge is rough (at least `FIGURE.rough_edge`). A porous figure with a smooth edge
    is a shape with thin strokes (the thin letter Y of `ifslib.core.targets.silhouettes.thin_gallery`: 1.01), not a
    fractal's lace (those of the random benchmark and the literature's classes with as much interior measure
    1.17-1.24; docs/results/any-shape.md)."""
    figure = share < FIGURE.ambiguous_share or (edge is not None and edge >= FIGURE.rough_edge)
    return (target.size >= FIGURE.fractal_min_size and target.mask.sum() >= FIGURE.fractal_min_pixels and figure
            and (maps is None or maps <= AUTO.search.max_maps))


def ambiguous(share: float, maps: int, iou: float, edge: float | None = None) -> str | None:
    """Why a figure (of interior share ``share``, `ifslib.automatic.auto.interior_share`) whose search found a
    fractal of ``maps`` maps may be a shape as well, or None when it is clearly a fractal: its interior share is
    at least `FIGURE.ambiguous_share` and the search's chosen attractor's IoU ``iou`` (full precision,
    `ifslib.automatic.fractal.SearchResult.choice`) is below `FIGURE.clear_fractal_iou`. ``edge`` is the edge dimension
    of a solid figure searched for its rough edge (`ifslib.automatic.auto.edge_dimension`)."""
    if share < FIGURE.ambiguous_share or iou >= FIGURE.clear_fractal_iou:
        return None
    figure = (f"the figure is solid (interior share {share:.2f}) with a rough edge (dimension {edge:.2f} >= "
              f"{FIGURE.rough_edge:g}: overlapping copies draw one, and so may a shape's)"
              if share >= FIGURE.porous_share and edge is not None else
              f"the figure's interior share {share:.2f} is at least {FIGURE.ambiguous_share:g} (a solid shape with thin "
              f"parts has as much)")
    return (f"{figure} and the search's {maps} maps draw an attractor of IoU {iou:.3f} < {FIGURE.clear_fractal_iou:g}: "
            "fitted as a fractal and as a shape")


def discover(target: Target, maps: int | None = None, depth: int | None = None, *, jitter: float = 0.0,
             seed: int | None = 0, primitive: str = "box", learned: bool = AUTO.fit.learned) -> Plan:
    """A start read from ``target`` itself: a curve, a shape or a fractal's maps, with the candidates an
    automatic fit compares (`ifslib.fit` fits the plan by comparing them).

    Parameters
    ----------
    target : Target
    maps, depth : int, optional
        Fix the number of maps or the depth instead of choosing among candidates
        (`ifslib.automatic.auto.choices`).
    jitter : float
        Half-width of the uniform jitter added to the start's free coordinates (plane units, 0 to 1).
    seed : int
        Seed of the jitter and of the start's k-means, from 0 to ``ifslib.errors.MAX_SEED``.
    primitive : str
        The shapes' primitive.
    learned : bool
        Offer the learned guess (`ifslib.learned.guess`) beside the fractal search's maps (`with_learned`).

    Returns
    -------
    Plan
        Its ``start`` is the IFS chosen without fitting (`plan_for`), jittered when ``jitter`` is set.
    """
    check_jitter(jitter, seed)
    if not isinstance(learned, bool):
        raise IFSError(f"learned must be True or False, got {learned!r}")
    plan = plan_for(target, maps, depth, primitive, seed or 0, learned=learned)
    return plan.with_start(plan.start.jittered(jitter, np.random.default_rng(seed)))


def plan_for(target: Target, maps: int | None = None, depth: int | None = None, primitive: str = "box",
             seed: int = 0, *, learned: bool = AUTO.fit.learned) -> Plan:
    """The plan for ``target``: a fractal's maps when the figure is porous (or solid with a rough edge) and the
    search finds them
    (`fractal_start`), else the curve or shape starts of the (maps, depth)
    pairs of `ifslib.automatic.auto.choices`, the nearest one the start. A fractal plan whose figure
    may be a shape as well (`ambiguous`) carries the shape plan as its rival. A detailed shape
    (`ifslib.automatic.auto.detailed`) is offered more maps, and one with limbs (`ifslib.automatic.auto.limbed`)
    has some of them placed on its thin parts.

    Without fitting, "nearest" is the collage theorem's measure: the start drawn at the target's
    size with the best IoU (shapes) or the smallest Chamfer distance (curves). The ``auto``
    strategy compares the same candidates by fitting them instead.
    """
    path = curve_path(target)  # the skeleton walked once: to classify, and for a curve's starts
    kind = "shape" if path is None else "curve"
    searched = None
    share = edge = None
    detail = limbs = False
    if kind == "shape":  # a curve is never searched as a fractal
        measures = measure(target)
        share, edge, detail, limbs = measures.share, measures.edge, measures.detailed, measures.limbed
    wanted = choices(kind, maps, depth, detail=detail)  # checks maps and depth before any search
    if share is not None and _searchable(target, share, edge, maps):
        config = AUTO.ambiguous_search if share >= FIGURE.ambiguous_share else AUTO.search
        start, searched, found = fractal_start(target, maps, AUTO.start.default_depth if depth is None else depth, seed,
                                                config=config, learned=learned)
        if edge is not None:  # why a figure with interior was searched, for the file
            searched["edge_dimension"] = round(edge, 3)
            if start is not None:
                start.meta["pattern"]["edge_dimension"] = searched["edge_dimension"]
        if start is not None:
            fractal_plan = Plan(start, (start,), "fractal", dict(start.meta["pattern"]), search=found.rows)
            why = ambiguous(share, found.choice.maps, found.choice.iou, edge)
            if why is None:
                return fractal_plan
            rival = _nearest(target, kind, candidates(target, wanted, primitive, seed, kind=kind, limbs=limbs))
            return dataclasses.replace(fractal_plan, pattern={**fractal_plan.pattern, "ambiguous": why},
                                       rivals=(rival,), why=why)
    options = candidates(target, wanted, primitive, seed, kind=kind, limbs=limbs, path=path)
    record = {}  # for the file: what the search found, or why a porous figure was not searched
    if searched is not None:
        record["fractal_search"] = searched
    elif edge is not None and edge < FIGURE.rough_edge and share < FIGURE.porous_share:
        record["not_searched"] = (f"interior share {share:.2f} (porous, at least {FIGURE.ambiguous_share:g}) with a smooth "
                                  f"edge (dimension {edge:.2f} < {FIGURE.rough_edge:g}): a shape with thin strokes, not a "
                                  "fractal's lace")
    for o in options:
        o.meta["pattern"].update(record)
    return _nearest(target, kind, options)


def _nearest(target: Target, kind: str, options: list[IFS]) -> Plan:
    """The curve or shape plan of ``options``, its start the one nearest the target drawn at its depth."""
    if len(options) == 1:
        start = options[0]
    else:
        scores = [evaluate(o, target, attractor=False) for o in options]
        best = (np.argmin([s["chamfer"] for s in scores]) if kind == "curve"
                else np.argmax([s["iou"] for s in scores]))
        start = options[int(best)]
    return Plan(start, tuple(options), kind, dict(start.meta["pattern"]))
