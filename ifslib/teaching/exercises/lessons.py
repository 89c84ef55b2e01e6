"""The checks of notebooks 01, 05 and 07: a leaf's map from its word, the depth a drawing needs, a carpet of
other proportions, the maps of a two-map fractal."""
from __future__ import annotations

import math

import numpy as np

from ...geometry.ifs import IFS
from ...geometry.patterns import affine
from ...targets.target import Target, load_target
from .harness import as_matrix, call, fit_report, random_maps, report


def word_maps(seed: int = 0) -> np.ndarray:
    """``(3, 3, 3)`` maps on which the leaf-map exercise is checked (they do not commute)."""
    return random_maps(np.random.default_rng(7000 + seed), 3, 0.3, 0.6, shear=0.5)


def check_leaf_map(answer) -> bool:
    """A function ``f(maps, word) -> (3, 3)``: the map ``T_w = T_(i1) o ... o T_(iK)`` of the leaf of word ``w``.

    ``maps[i - 1]`` is ``T_i``; ``word`` is a tuple of map numbers ``(i1, ..., iK)`` from 1 to m.
    """
    name = "leaf map"
    maps = word_maps()
    for word in ((2,), (1, 3), (3, 1, 2), (2, 2, 3, 1)):
        ok, value = call(answer, "leaf map", name, maps.copy(), word)
        value = as_matrix(value, (3, 3), name) if ok else None
        if value is None:
            return False
        truth, backwards = np.eye(3), np.eye(3)
        for i in word:
            truth, backwards = truth @ maps[i - 1], maps[i - 1] @ backwards
        if np.allclose(value, truth, atol=1e-9):
            continue
        if np.allclose(value, backwards, atol=1e-9):
            return report(False, name, "the order is reversed: which map acts on the primitive first, the "
                           "first letter's or the last one's?")
        if len(word) == 1:
            return report(False, name, "maps are numbered from 1: T_i is maps[i - 1].")
        return report(False, name, "a leaf's map composes the maps of its word: a product of 3 x 3 matrices.")
    return report(True, name, "")


def check_depth_needed(answer) -> bool:
    """A function ``f(s, d0, tol) -> int``: the smallest depth K with ``s^K d0 <= tol``."""
    name = "depth needed"
    rng = np.random.default_rng(8000)
    cases = [(1 / 3, 29.6, 0.5), (0.5, 8.3, 1.0), (0.9, 1.0, 1.0)]  # no case on a boundary s^K d0 = tol
    cases += [(float(rng.uniform(0.2, 0.8)), float(rng.uniform(2, 50)), float(rng.uniform(0.1, 1))) for _ in range(20)]
    for s, d0, tol in cases:
        ok, value = call(answer, "depth", name, s, d0, tol)
        if not ok:
            return False
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            return report(False, name, f"return a whole number (an int), got {type(value).__name__}.")
        truth = 0
        while s ** truth * d0 > tol:
            truth += 1
        if int(value) != truth:
            hint = ("off by one: is K the smallest depth that reaches the tolerance, and does yours reach it?"
                    if abs(int(value) - truth) == 1 else "solve s^K d0 <= tol for K: take logarithms (both "
                    "sides' logs are negative or small, mind the direction of the inequality).")
            return report(False, name, hint)
    return report(True, name, "")


def _carpet_truth(seed: int = 0) -> IFS:
    rng = np.random.default_rng(9000 + seed)
    width, height = 0.8, float(rng.uniform(0.55, 0.65))
    fx, fy = rng.uniform(0.2, 0.26, 2)          # the corner cells' share of the width and the height
    xs = np.array([0, fx, 1 - fx, 1]) * width - width / 2
    ys = np.array([0, fy, 1 - fy, 1]) * height - height / 2
    maps = []
    for j in range(3):
        for i in range(3):
            if (i, j) == (1, 1):
                continue
            a, b = (xs[i + 1] - xs[i]) / width, (ys[j + 1] - ys[j]) / height
            maps.append([[a, 0, (xs[i] + xs[i + 1]) / 2], [0, b, (ys[j] + ys[j + 1]) / 2]])
    return affine(maps, depth=3, name="carpet_exercise")


def carpet_target(size: int = 64, seed: int = 0) -> Target:
    """A Sierpinski carpet of other proportions (a rectangle, corner cells narrower than a third), at ``size``.

    The library's `ifslib.patterns.sierpinski_carpet` has square rules: each copy a square scaled by one
    factor, which cannot take these rectangles.
    """
    return load_target(_carpet_truth(seed), size, depth="attractor")


def check_carpet_fit(answer, size: int = 64, min_iou: float = 0.8) -> bool:
    """A fitted IFS whose attractor covers `carpet_target` with IoU at least ``min_iou``."""
    return fit_report(answer, carpet_target(size), "carpet fit", curve=False, min_iou=min_iou)


def _two_map_truth(seed: int = 0) -> IFS:
    # two similarities of scale 0.42-0.5 turned by up to 0.6 rad, far enough apart that their copies of
    # the whole do not touch: a student can tell the two copies apart, as the exercise asks
    rng = np.random.default_rng(10_000 + seed)
    maps = np.zeros((2, 2, 3))
    for i, centre in enumerate(([-0.25, -0.12], [0.25, 0.12])):
        a = rng.uniform(-0.6, 0.6)
        rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        maps[i, :, :2] = rot * rng.uniform(0.42, 0.5)
        maps[i, :, 2] = centre
    return affine(maps, depth=6, name="two_map_exercise")


def two_map_target(size: int = 64, seed: int = 0) -> Target:
    """The attractor of a random two-map affine IFS (seeded; not one the library ships), at ``size``."""
    return load_target(_two_map_truth(seed), size, depth="attractor")


def check_two_maps(answer, size: int = 64, min_iou: float = 0.8) -> bool:
    """A fitted IFS of two maps whose attractor matches `two_map_target` with IoU at least ``min_iou``."""
    return fit_report(answer, two_map_target(size), "two-map fractal", curve=False, maps=2, min_iou=min_iou)
