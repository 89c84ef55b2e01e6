"""The exercises' harness: how a check reports, reads an answer of any kind, and switches the library's own
function off while the student's runs (`library_off`)."""
from __future__ import annotations

import contextlib
import importlib
import math
from typing import Callable, Iterator

import numpy as np
import torch

from ...scoring.metrics import evaluate, self_crossings
from ...geometry.crossings import is_curve
from ...geometry.ifs import IFS
from ...targets.target import Target


# --- reporting -------------------------------------------------------------------------------------


def report(ok: bool, name: str, hint: str) -> bool:
    print(f"{name}: correct." if ok else f"{name}: not yet. Hint: {hint}")
    return ok


def as_matrix(answer, shape: tuple[int, ...], name: str) -> np.ndarray | None:
    try:
        value = np.asarray(answer.detach().numpy() if isinstance(answer, torch.Tensor) else answer, dtype=float)
    except (TypeError, ValueError):
        print(f"{name}: not yet. Hint: give a {shape} array of numbers, got {type(answer).__name__}.")
        return None
    if value.shape != shape:
        print(f"{name}: not yet. Hint: give a {shape} array, got shape {value.shape}.")
        return None
    if not np.isfinite(value).all():
        print(f"{name}: not yet. Hint: your array holds values that are not finite numbers.")
        return None
    return value


def as_number(answer) -> float | None:
    if isinstance(answer, bool) or not isinstance(answer, (int, float, np.integer, np.floating)):
        return None
    value = float(answer)
    return value if math.isfinite(value) else None


class WriteItYourself(RuntimeError):
    """Raised by a library function that a check has switched off: the exercise asks for your own."""


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
                            ("ifslib.discovery.initialization", "_placed")],
    "leaf map": [("ifslib", "expand"), ("ifslib.geometry.leaves", "expand")],
    "depth": [("ifslib.scoring.metrics", "depth_to_attractor")],
}


def _switched_off(name: str) -> Callable:
    def off(*args, **kwargs):
        raise WriteItYourself(f"ifslib's own {name} is switched off while this check runs: write it yourself")
    off.__name__ = f"{name.replace(' ', '_')}_switched_off"
    return off


def _originals(exercise: str) -> list[tuple[object, str, object]]:
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
    namespace = getattr(answer, "__globals__", None)
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


def call(answer, exercise: str, name: str, *args):
    """``(True, value)`` of the student's function on ``args`` with the library off, else ``(False, None)`` after a hint."""
    if not callable(answer):
        print(f"{name}: not yet. Hint: give your function itself (its name, without brackets), "
              f"got {type(answer).__name__}.")
        return False, None
    if getattr(answer, "__module__", "") and str(getattr(answer, "__module__", "")).startswith("ifslib"):
        print(f"{name}: not yet. Hint: that is ifslib's own function; write the {exercise} yourself.")
        return False, None
    try:
        with library_off(exercise, answer):
            return True, answer(*args)
    except WriteItYourself:
        print(f"{name}: not yet. Hint: your function calls ifslib's own {exercise}; write it yourself "
              "(numpy and scipy are fine).")
    except Exception as exc:  # noqa: BLE001  a student's bug is answered with a hint, not a traceback
        print(f"{name}: not yet. Hint: your function raised {type(exc).__name__}: {exc}")
    return False, None


def maps_array(ifs: IFS) -> np.ndarray:
    with torch.no_grad():
        return ifs.to(torch.float64).maps().numpy()


def random_maps(rng: np.random.Generator, m: int, lo: float = 0.3, hi: float = 0.55,
                 shear: float = 0.0) -> np.ndarray:
    """``(m, 3, 3)`` contractions: a rotation, scales in ``[lo, hi]``, an optional shear, a translation."""
    out = np.zeros((m, 3, 3))
    for i in range(m):
        a = rng.uniform(-math.pi, math.pi)
        rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        lin = rot @ np.diag(rng.uniform(lo, hi, 2)) @ np.array([[1.0, rng.uniform(-shear, shear)], [0.0, 1.0]])
        out[i, :2, :2], out[i, :2, 2], out[i, 2, 2] = lin, rng.uniform(-0.3, 0.3, 2), 1.0
    return out


def hausdorff_pair(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """The two directed distances ``(sup_a d(a, B), sup_b d(b, A))`` (the reference of the checks)."""
    from scipy.spatial import cKDTree

    return float(cKDTree(b).query(a)[0].max()), float(cKDTree(a).query(b)[0].max())


def apply_maps(maps: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Every map applied to every point: ``(m * N, 2)``."""
    return (points @ maps[:, :2, :2].transpose(0, 2, 1) + maps[:, None, :2, 2]).reshape(-1, 2)


def one_number(answer, library: str, name: str, *args) -> tuple[float | None, bool]:
    """The student's function called (the library's ``library`` switched off), its result read as one number.

    Returns ``(value, _)``, or ``(None, the check's answer)`` once the call or its result has been reported.
    """
    ok, value = call(answer, library, name, *args)
    if not ok:
        return None, False
    value = as_number(np.asarray(value).item() if np.ndim(value) == 0 and value is not None else value)
    if value is None:
        return None, report(False, name, "return one number.")
    return value, True


def fit_report(answer, target: Target, name: str, *, curve: bool, maps: int | None = None,
                max_chamfer: float = 1.0, min_iou: float = 0.8) -> bool:
    if not isinstance(answer, IFS):
        return report(False, name, f"give the fitted ifslib.IFS (a FitResult's .best), got {type(answer).__name__}.")
    if maps is not None and len(answer.rules) != maps:
        return report(False, name, f"the fractal has {maps} maps; your IFS has {len(answer.rules)}.")
    try:
        m = evaluate(answer, target, depth="attractor")
    except Exception as exc:  # noqa: BLE001  an IFS that cannot be drawn gets a hint
        return report(False, name, f"its attractor cannot be drawn ({exc}).")
    if curve:
        crossings = self_crossings(answer) if is_curve(answer) else 0
        ok = m["chamfer"] <= max_chamfer and crossings == 0
        hint = (f"its attractor lies {m['chamfer']:.1f} px from the target (Chamfer), {crossings} self-crossings; "
                f"aim for {max_chamfer:g} px and none. Where does your start lie, and does the fit cross itself?")
    else:
        ok = m["iou"] >= min_iou
        hint = (f"its attractor's IoU with the target is {m['iou']:.2f}; aim for {min_iou:g}. Can your maps "
                "take the shapes the target's copies have?")
    return report(ok, name, hint)
