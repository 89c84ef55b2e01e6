"""Check functions for the tutorial's exercises (`notebooks/00_tutorial.ipynb`).

Each check takes the student's answer, prints whether it is right (with a hint when it is not) and
returns a bool, so a notebook cell reads ``ifslib.exercises.check_koch_map(T2)``. A check never
raises on a wrong answer, only on an answer of the wrong kind (with a message that says which).
"""
from __future__ import annotations

import math

import numpy as np
import torch

from ..geometry.ifs import IFS
from ..fitting.initialization import is_curve
from ..fitting.metrics import evaluate, self_crossings
from ..geometry.patterns import by_name, koch_unit
from ..fitting.targets import Target


def _report(ok: bool, name: str, hint: str) -> bool:
    print(f"{name}: correct." if ok else f"{name}: not yet. Hint: {hint}")
    return ok


def _matrix(answer, shape: tuple[int, ...], name: str) -> np.ndarray | None:
    try:
        value = np.asarray(answer.detach().numpy() if isinstance(answer, torch.Tensor) else answer, dtype=float)
    except (TypeError, ValueError):
        print(f"{name}: not yet. Hint: give a {shape} array of numbers, got {type(answer).__name__}.")
        return None
    if value.shape != shape:
        print(f"{name}: not yet. Hint: give a {shape} array, got shape {value.shape}.")
        return None
    return value


def koch_map(i: int) -> np.ndarray:
    """The true ``3 x 3`` map ``T_i`` (1-based) of the Koch curve on the base ``(0,0) -> (1,0)``."""
    return koch_unit().maps().detach().double().numpy()[i - 1]


def check_koch_map(answer, i: int = 3) -> bool:
    """Exercise 1: write the Koch curve's map ``T_i`` (the paper prints ``T_3`` wrongly).

    Parameters
    ----------
    answer : array-like
        ``(3, 3)`` homogeneous matrix, for the base segment from ``(0, 0)`` to ``(1, 0)``.
    i : int
        Which map, 1 to 4.
    """
    name = f"T{i}"
    value = _matrix(answer, (3, 3), name)
    if value is None:
        return False
    truth = koch_map(i)
    if np.allclose(value, truth, atol=1e-6):
        return _report(True, name, "")
    if np.allclose(value[:2, :2], truth[:2, :2], atol=1e-6):
        return _report(False, name, "the rotation and scale are right; the translation is where the map "
                       "sends the origin, the start of the copy (for T3 that is the peak).")
    return _report(False, name, "the linear part is (1/3) times a rotation by the angle of the copy's "
                   "segment: 0, +60, -60 and 0 degrees for T1 to T4.")


def check_leaf_count(answer, pattern: str = "carpet", depth: int = 4) -> bool:
    """Exercise 2: how many leaf shapes does ``pattern`` draw at ``depth``? (``m^K x |D|``)."""
    ifs = by_name(pattern, depth=depth)
    truth = len(ifs.rules) ** depth * len(ifs.primitives)
    ok = isinstance(answer, (int, np.integer)) and int(answer) == truth
    return _report(ok, f"leaves of {pattern} at depth {depth}",
                   f"each Hutchinson step replaces every shape by {len(ifs.rules)} copies; "
                   f"there are {len(ifs.primitives)} primitive(s) to start with.")


def check_scaled_distance(answer, s: float = 1 / 3, d: float = 0.3) -> bool:
    """Exercise 3: a point is at distance ``d`` from S, measured after pulling it back by ``T^-1``.

    What is its distance to ``T(S)`` when ``T`` is a similarity of scale ``s``?
    """
    truth = s * d
    ok = isinstance(answer, (int, float, np.floating)) and math.isclose(float(answer), truth, rel_tol=1e-6)
    hint = ("that is the paper's printed law (1/s), an erratum: a map of scale s shrinks every distance by s."
            if isinstance(answer, (int, float)) and math.isclose(float(answer), d / s, rel_tol=1e-6)
            else "distances scale with the map: shrink the picture by s and every distance shrinks by s.")
    return _report(ok, "distance to T(S)", hint)


def check_pixel_value(answer, distance_in_sigmas: float = 1.0) -> bool:
    """Exercise 4: the value of a pixel whose centre lies ``distance_in_sigmas`` sigma from the figure."""
    truth = math.exp(-distance_in_sigmas ** 2)
    ok = isinstance(answer, (int, float, np.floating)) and math.isclose(float(answer), truth, rel_tol=1e-4)
    return _report(ok, "pixel value", "a pixel is exp(-relu(d)^2 / sigma^2).")


def check_initialization(answer: IFS, target: Target, max_chamfer: float = 3.0) -> bool:
    """Exercise 5: a starting IFS close enough to the target that a fit can take it the rest of the way.

    Passes when the start's figure lies within ``max_chamfer`` pixels (symmetric Chamfer) of the target.
    """
    if not isinstance(answer, IFS):
        print(f"initialization: not yet. Hint: give an ifslib.IFS, got {type(answer).__name__}.")
        return False
    try:
        chamfer = evaluate(answer, target, attractor=False)["chamfer"]
    except ValueError as exc:
        print(f"initialization: not yet. Hint: the IFS cannot be drawn ({exc}).")
        return False
    hint = ("spread the points along the target's best-fit line (ifslib.initialize does that)"
            if is_curve(answer) else "stretch the pattern over the target's bounding box (ifslib.initialize)")
    return _report(chamfer <= max_chamfer, f"initialization (Chamfer {chamfer:.2f} px)", hint + ".")


def check_fit(answer: IFS, target: Target, max_chamfer: float = 1.0) -> bool:
    """Exercise 6: a fitted IFS whose figure lies within ``max_chamfer`` pixels of the target.

    A curve (see `ifslib.initialization.is_curve`) must also not cross itself: the mean Chamfer
    distance alone forgives a tangle lying over the target.
    """
    if not isinstance(answer, IFS):
        print(f"fit: not yet. Hint: give the fitted ifslib.IFS (result.best), got {type(answer).__name__}.")
        return False
    chamfer = evaluate(answer, target, attractor=False)["chamfer"]
    crossings = self_crossings(answer) if is_curve(answer) else 0
    return _report(chamfer <= max_chamfer and crossings == 0,
                   f"fit (Chamfer {chamfer:.2f} px, {crossings} self-crossings)",
                   "start from a good initialization and use the multiscale distance loss; "
                   "more steps help only once the curve no longer crosses itself.")
