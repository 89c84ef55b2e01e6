"""The exercises' harness: run a student's function with the library's own one switched off
(`run_answer`, `library_off`), and read an answer as a matrix or a number. Each raises
``AssertionError`` with a hint, as an nbgrader test cell expects."""
from __future__ import annotations

import contextlib
import functools
import importlib
import math
from typing import Callable, Iterator

import numpy as np
import torch

from ...errors import IFSError


class WriteItYourself(RuntimeError):
    """Raised by a library function that a test has switched off: the exercise asks for your own."""


#: For each exercise that asks for a function the library has: where the library keeps it
#: (module, attribute), every place a student could reach it from.
LIBRARY = {
    "chaos game": [("ifslib", "chaos_game"), ("ifslib.raster.chaos", "chaos_game"),
                   ("ifslib.geometry.sampled", "sample_attractor"),
                   ("ifslib.geometry.expand", "sample_attractor")],
    "Hausdorff distance": [("ifslib.scoring.metrics", "hausdorff")],
    "collage distance": [("ifslib.scoring.metrics", "hausdorff"), ("ifslib.scoring.collage", "collage_distance")],
    "contraction and fixed point": [("ifslib.geometry.rules", "singular_values"),
                                    ("ifslib.geometry.rules", "map_scales")],
    "loss": [("ifslib", "loss"), ("ifslib.scoring.losses", "loss"), ("ifslib.scoring.losses", "mse"),
             ("ifslib.scoring.losses", "multiscale_mse"), ("ifslib.scoring.losses", "pyramid")],
    "best-fit-line start": [("ifslib", "initialize"), ("ifslib", "best_fit_line"),
                            ("ifslib.discovery.initialization", "initialize"),
                            ("ifslib.discovery.initialization", "best_fit_line"),
                            ("ifslib.targets.placement", "best_fit_line"), ("ifslib.targets.placement", "place"),
                            ("ifslib.targets.placement", "placed_points")],
    "leaf map": [("ifslib", "expand"), ("ifslib.geometry.leaves", "expand")],
    "leaf count": [("ifslib", "expand"), ("ifslib.geometry.leaves", "expand")],
    "depth": [("ifslib.scoring.metrics", "depth_to_attractor")],
    "iou": [("ifslib", "iou"), ("ifslib.scoring.metrics", "iou")],
    "chamfer": [("ifslib", "chamfer"), ("ifslib.scoring.metrics", "chamfer")],
}


def _switched_off(name: str) -> Callable:
    def off(*args, **kwargs):
        raise WriteItYourself(f"ifslib's own {name} is switched off while this test runs: write it yourself")
    off.__name__ = f"{name.replace(' ', '_')}_switched_off"
    return off


def _originals(exercise: str) -> list[tuple[object, str, object]]:
    if exercise not in LIBRARY:
        raise KeyError(f"no exercise {exercise!r}; one of {sorted(LIBRARY)}")
    out = []
    for module_name, attr in LIBRARY[exercise]:
        module = importlib.import_module(module_name)
        out.append((module, attr, getattr(module, attr)))
    return out


@contextlib.contextmanager
def library_off(exercise: str, answer: Callable | None = None) -> Iterator[None]:
    """Within the block, the library's functions for ``exercise`` (a key of `LIBRARY`) raise `WriteItYourself`.

    They are replaced where the library keeps them and, when ``answer`` is a function, in its
    globals (a name the notebook imported with ``from ifslib... import ...``).
    """
    saved = _originals(exercise)
    ids = {id(value) for _, _, value in saved}
    namespace = getattr(_unwrapped(answer), "__globals__", None)
    shadowed = {k: v for k, v in namespace.items() if id(v) in ids} if isinstance(namespace, dict) else {}
    try:
        for module, attr, _ in saved:
            setattr(module, attr, _switched_off(f"{module.__name__}.{attr}"))
        for key in shadowed:
            namespace[key] = _switched_off(key)
        yield
    finally:
        for module, attr, value in saved:
            setattr(module, attr, value)
        for key, value in shadowed.items():
            namespace[key] = value


def _unwrapped(answer):
    """The function under ``functools.partial``, ``functools.wraps`` wrappers and bound methods."""
    seen = set()
    while id(answer) not in seen:
        seen.add(id(answer))
        if isinstance(answer, (functools.partial, functools.partialmethod)):
            answer = answer.func
        elif hasattr(answer, "__wrapped__"):
            answer = answer.__wrapped__
        elif hasattr(answer, "__func__"):
            answer = answer.__func__
    return answer


def _library_functions() -> set[int]:
    return {id(value) for exercise in LIBRARY for _, _, value in _originals(exercise)}


def _holds_library(answer) -> bool:
    """Whether ``answer`` is, wraps, or closes over one of the library's functions of `LIBRARY`."""
    library = _library_functions()
    inner = _unwrapped(answer)
    if id(answer) in library or id(inner) in library:
        return True
    if str(getattr(inner, "__module__", "") or "").startswith("ifslib"):
        return True
    cells = getattr(inner, "__closure__", None) or ()
    frozen = [getattr(answer, "args", ()), tuple(getattr(answer, "keywords", {}).values())]
    held = [cell.cell_contents for cell in cells if _filled(cell)] + [v for group in frozen for v in group]
    return any(id(value) in library or id(_unwrapped(value)) in library for value in held)


def _filled(cell) -> bool:
    try:
        cell.cell_contents
    except ValueError:
        return False
    return True


def run_answer(answer, exercise: str, *args):
    """The student's function called on ``args`` while the library's own ``exercise`` functions are off.

    Parameters
    ----------
    answer : callable
        The student's function.
    exercise : str
        A key of `LIBRARY`.
    *args
        Passed to ``answer``.

    Returns
    -------
    object
        What ``answer`` returned.

    Raises
    ------
    AssertionError
        With a hint: ``answer`` is not a function, is (or wraps) the library's own, calls it, or raises.
    """
    assert answer is not None and answer is not Ellipsis, f"write your {exercise} first (the cell above)."
    assert callable(answer), (f"give your function itself (its name, without brackets), "
                              f"got {type(answer).__name__}.")
    assert not _holds_library(answer), f"that is ifslib's own function; write the {exercise} yourself."
    try:
        with library_off(exercise, answer):
            return answer(*args)
    except WriteItYourself:
        raise AssertionError(f"your function calls ifslib's own {exercise}; write it yourself "
                             "(numpy and scipy are fine).") from None
    except AssertionError:
        raise
    except Exception as exc:  # noqa: BLE001  a student's bug is answered with a hint, not torch's traceback
        raise AssertionError(f"your function raised {type(exc).__name__}: {exc}") from None


def as_matrix(answer, shape: tuple[int, ...], name: str) -> np.ndarray:
    """``answer`` (a list, array or tensor) as a float64 array of ``shape``; ``AssertionError`` with a hint otherwise."""
    assert answer is not None and answer is not Ellipsis, f"{name}: write your answer first."
    assert not callable(answer), f"{name}: give the numbers themselves, not a function."
    try:
        value = np.asarray(answer.detach().numpy() if isinstance(answer, torch.Tensor) else answer, dtype=float)
    except (TypeError, ValueError):
        raise AssertionError(f"{name}: give a {shape} array of numbers, got {type(answer).__name__}.") from None
    assert value.shape == tuple(shape), f"{name}: give a {tuple(shape)} array, got shape {value.shape}."
    assert np.isfinite(value).all(), f"{name}: your array holds values that are not finite numbers."
    return value


def as_number(answer, name: str) -> float:
    """``answer`` (an int, a float or a one-number array or tensor) as a finite float; ``AssertionError`` otherwise."""
    if isinstance(answer, torch.Tensor) and answer.numel() == 1:
        answer = answer.item()
    elif isinstance(answer, np.ndarray) and answer.size == 1:
        answer = answer.item()
    assert not isinstance(answer, bool) and isinstance(answer, (int, float, np.integer, np.floating)), \
        f"{name}: give one number, got {type(answer).__name__}."
    assert math.isfinite(float(answer)), f"{name}: give a finite number, got {answer}."
    return float(answer)


def random_maps(rng: np.random.Generator, m: int, lo: float = 0.3, hi: float = 0.55,
                shear: float = 0.0) -> np.ndarray:
    """Random affine contractions for a test's inputs: a rotation, scales in ``[lo, hi]``, a shear, a translation.

    Parameters
    ----------
    rng : numpy.random.Generator
    m : int
        Number of maps.
    lo, hi : float
        Range of the two scales drawn; ``hi < 1``.
    shear : float
        Largest shear factor drawn (0: none).

    Returns
    -------
    numpy.ndarray
        ``(m, 3, 3)`` homogeneous matrices whose linear parts have largest singular value at most ``hi``:
        a shear stretches some direction beyond the scales drawn, so a linear part stretched beyond ``hi``
        is scaled down to it (``hi / sigma_max``), and every map is a contraction as the tests say.
    """
    if not 0 < lo <= hi < 1:
        raise IFSError(f"random_maps needs 0 < lo <= hi < 1 for contractions, got lo={lo}, hi={hi}")
    out = np.zeros((m, 3, 3))
    for i in range(m):
        a = rng.uniform(-math.pi, math.pi)
        rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        lin = rot @ np.diag(rng.uniform(lo, hi, 2)) @ np.array([[1.0, rng.uniform(-shear, shear)], [0.0, 1.0]])
        largest = np.linalg.svd(lin, compute_uv=False)[0]
        if largest > hi:
            lin = lin * (hi / largest)
        out[i, :2, :2], out[i, :2, 2], out[i, 2, 2] = lin, rng.uniform(-0.3, 0.3, 2), 1.0
    return out
