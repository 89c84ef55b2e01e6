"""Check functions for the exercises of the notebooks (the tutorial, 01, 05 and 07).

Each check takes the student's answer, prints ``"<name>: correct."`` or ``"<name>: not yet. Hint:
..."`` and returns a bool, so a notebook cell reads ``ifslib.exercises.check_koch_map(T3, 3);``. A
check never raises: an answer of the wrong kind (``None``, a string, a function that returns
nothing or raises) is answered "not yet" with a hint that says what was expected.

Checks that cannot be passed by the library's own answer:

* where the student writes a function the library already has (the chaos game, the Hausdorff and
  collage distances, a loss, the best-fit-line start), the check calls it on inputs of its own
  choosing (random, seeded) and compares with a reference, **with the library's function switched
  off** while the student's runs (`library_off`): calling it then raises `WriteItYourself`, and a
  library function handed in as the answer is refused;
* where the student fits an IFS, the target is one the library does not ship (a Koch curve from
  seeded random control points, a carpet of other proportions, a random two-map fractal), and the
  fit is scored by its attractor (`ifslib.evaluate` with ``depth="attractor"``).

A check prints no number when the answer is right, so its stored output is the same on every
machine.
"""
from __future__ import annotations

import contextlib
import importlib
import math
from typing import Callable, Iterator

import numpy as np
import torch

from ..scoring.metrics import evaluate, self_crossings
from ..geometry.crossings import is_curve
from ..geometry.ifs import IFS
from ..geometry.patterns import affine, by_name, koch_like, koch_unit
from ..targets.target import Target, load_target


# --- reporting -------------------------------------------------------------------------------------

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
    if not np.isfinite(value).all():
        print(f"{name}: not yet. Hint: your array holds values that are not finite numbers.")
        return None
    return value


def _number(answer) -> float | None:
    if isinstance(answer, bool) or not isinstance(answer, (int, float, np.integer, np.floating)):
        return None
    value = float(answer)
    return value if math.isfinite(value) else None


# --- the library switched off while a student's function runs ----------------------------------------

class WriteItYourself(RuntimeError):
    """Raised by a library function that a check has switched off: the exercise asks for your own."""


#: For each exercise that asks for a function the library has: where the library keeps it
#: (module, attribute), every place a student could reach it from.
LIBRARY = {
    "chaos game": [("ifslib", "chaos_game"), ("ifslib.raster.chaos", "chaos_game"),
                   ("ifslib.geometry.sampled", "sample_attractor")],
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


def _call(answer, exercise: str, name: str, *args):
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


def _maps_array(ifs: IFS) -> np.ndarray:
    with torch.no_grad():
        return ifs.to(torch.float64).maps().numpy()


def _random_maps(rng: np.random.Generator, m: int, lo: float = 0.3, hi: float = 0.55,
                 shear: float = 0.0) -> np.ndarray:
    """``(m, 3, 3)`` contractions: a rotation, scales in ``[lo, hi]``, an optional shear, a translation."""
    out = np.zeros((m, 3, 3))
    for i in range(m):
        a = rng.uniform(-math.pi, math.pi)
        rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        lin = rot @ np.diag(rng.uniform(lo, hi, 2)) @ np.array([[1.0, rng.uniform(-shear, shear)], [0.0, 1.0]])
        out[i, :2, :2], out[i, :2, 2], out[i, 2, 2] = lin, rng.uniform(-0.3, 0.3, 2), 1.0
    return out


def _hausdorff(a: np.ndarray, b: np.ndarray) -> tuple[float, float]:
    """The two directed distances ``(sup_a d(a, B), sup_b d(b, A))`` (the reference of the checks)."""
    from scipy.spatial import cKDTree

    return float(cKDTree(b).query(a)[0].max()), float(cKDTree(a).query(b)[0].max())


def _apply(maps: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Every map applied to every point: ``(m * N, 2)``."""
    return (points @ maps[:, :2, :2].transpose(0, 2, 1) + maps[:, None, :2, 2]).reshape(-1, 2)


# --- part 1 of the tutorial: maps, leaves, contraction, the chaos game --------------------------------

def koch_map(i: int) -> np.ndarray:
    """The true ``3 x 3`` map ``T_i`` (``i = 1 .. 4``) of the Koch curve on the base ``(0,0) -> (1,0)``."""
    return koch_unit().maps().detach().double().numpy()[i - 1]


def check_koch_map(answer, i: int = 3) -> bool:
    """The Koch curve's map ``T_i`` (``i = 1 .. 4``, onto ``p_(i-1) -> p_i``) as a ``(3, 3)`` matrix.

    For the base segment from ``(0, 0)`` to ``(1, 0)``; the paper prints ``T_3`` with a wrong
    translation, and that printed matrix is answered "not yet".
    """
    name = f"T{i}"
    if callable(answer):
        print(f"{name}: not yet. Hint: give the matrix itself, a 3 x 3 list or array, not a function.")
        return False
    value = _matrix(answer, (3, 3), name)
    if value is None:
        return False
    truth = koch_map(i)
    if np.allclose(value, truth, atol=1e-6):
        return _report(True, name, "")
    if not np.allclose(value[2], [0, 0, 1], atol=1e-9):
        return _report(False, name, "a homogeneous matrix's last row is (0, 0, 1).")
    if np.allclose(value[:2, :2], truth[:2, :2], atol=1e-6):
        return _report(False, name, "the rotation and scale are right; the translation is where the map "
                       "sends the origin, the start of its copy.")
    if np.allclose(value[:2, :2], truth[:2, :2].T, atol=1e-6):
        return _report(False, name, "the copy turns the wrong way: which way does the segment "
                       f"p{i - 1} -> p{i} point?")
    return _report(False, name, f"the map shrinks the base to the length of p{i - 1} -> p{i} and turns it to "
                   "that segment's direction: read both off the picture.")


def check_leaf_count(answer, pattern: str = "carpet", depth: int = 4) -> bool:
    """How many leaf shapes does ``pattern`` draw at ``depth``?"""
    ifs = by_name(pattern, depth=depth)
    truth = len(ifs.rules) ** depth * len(ifs.primitives)
    name = f"leaves of {pattern} at depth {depth}"
    if isinstance(answer, bool) or not isinstance(answer, (int, np.integer)):
        return _report(False, name, f"give a whole number (an int), got {type(answer).__name__}.")
    value = int(answer)
    if value == truth:
        return _report(True, name, "")
    m = len(ifs.rules)
    if value == depth ** m or value == m * depth:
        hint = "count depth 1 and depth 2 by hand: how does the count grow from one depth to the next?"
    else:
        hint = f"depth 0 draws the primitive; what does one step of the Hutchinson operator do to a drawing of N shapes with {m} maps?"
    return _report(False, name, hint)


def contraction_maps(seed: int = 0, n: int = 4) -> np.ndarray:
    """``(n, 3, 3)`` affine maps with shear, on which the contraction exercise is checked."""
    return _random_maps(np.random.default_rng(1000 + seed), n, 0.3, 0.8, shear=0.8)


def check_contraction(answer) -> bool:
    """A function ``f(M) -> (s, x)``: the contraction factor ``s`` of the ``3 x 3`` map ``M`` and its fixed point ``x``.

    ``s`` is the smallest factor with ``|M(a) - M(b)| <= s |a - b|`` for all points: the largest
    singular value of the linear part. The maps of the check shear, so ``sqrt|det|`` and the largest
    eigenvalue are not it.
    """
    name = "contraction and fixed point"
    for M in contraction_maps():
        ok, value = _call(answer, "contraction and fixed point", name, M.copy())
        if not ok:
            return False
        try:
            s, x = value
            s, x = float(s), np.asarray(x, dtype=float).reshape(-1)[:2]
            assert x.shape == (2,)
        except Exception:  # noqa: BLE001
            return _report(False, name, f"return a pair (s, x): a number and a point (x, y); got {value!r:.60}.")
        lin, t = M[:2, :2], M[:2, 2]
        s_true = float(np.linalg.svd(lin, compute_uv=False)[0])
        x_true = np.linalg.solve(np.eye(2) - lin, t)
        if not math.isclose(s, s_true, rel_tol=1e-6, abs_tol=1e-9):
            if (math.isclose(s, math.sqrt(abs(np.linalg.det(lin))), rel_tol=1e-6)
                    or math.isclose(s, float(np.abs(np.linalg.eigvals(lin)).max()), rel_tol=1e-6)):
                return _report(False, name, "sqrt|det L| and the largest eigenvalue say how areas and "
                               "eigenvectors are stretched; a shear stretches some other direction more: "
                               "what is the longest |L v| for a unit vector v?")
            return _report(False, name, "s is the largest factor |M(a) - M(b)| / |a - b|; the translation "
                           "cancels in M(a) - M(b).")
        if not np.allclose(x, x_true, atol=1e-7):
            return _report(False, name, "s is right; the fixed point solves M(x) = x, a 2 x 2 linear system.")
    return _report(True, name, "")


def chaos_maps(seed: int = 0) -> np.ndarray:
    """``(3, 3, 3)``: the three affine maps on which the chaos-game exercise is checked."""
    return _random_maps(np.random.default_rng(2000 + seed), 3, 0.35, 0.55)


_REFERENCE: dict[str, object] = {}


def check_chaos_game(answer, n: int = 20_000) -> bool:
    """A function ``f(maps, n, seed) -> (n, 2)`` points of the attractor of ``maps`` (``(m, 3, 3)``).

    Every point must lie on the attractor (within 0.01 plane units of the reference cloud) and the
    points must cover it (95 % of the reference within 0.02 of a student point).
    """
    from ..raster.chaos import chaos_game as reference_game

    name = "chaos game"
    maps = chaos_maps()
    if "chaos" not in _REFERENCE:  # the same every time: drawn once per session
        _REFERENCE["chaos"] = reference_game(affine(maps), 200_000, seed=1)
    reference = _REFERENCE["chaos"]
    ok, value = _call(answer, "chaos game", name, maps.copy(), n, 0)
    points = _matrix(value, (n, 2), name) if ok else None
    if points is None:
        return False
    from scipy.spatial import cKDTree

    if "chaos tree" not in _REFERENCE:
        _REFERENCE["chaos tree"] = cKDTree(reference)
    off = _REFERENCE["chaos tree"].query(points)[0]
    if off.max() > 0.01:
        return _report(False, name, f"{int((off > 0.01).sum())} of your points are off the attractor: where does "
                       "your walk start, and is that point on the attractor?")
    missed = cKDTree(points).query(reference[::10])[0]   # 20,000 reference points judge the cover
    if np.quantile(missed, 0.95) > 0.02:
        return _report(False, name, "your points lie on the attractor but miss parts of it: does every step "
                       "choose its map at random, a new choice each step?")
    return _report(True, name, "")


# --- part 2: distances -------------------------------------------------------------------------------

def _one_number(answer, library: str, name: str, *args) -> tuple[float | None, bool]:
    """The student's function called (the library's ``library`` switched off), its result read as one number.

    Returns ``(value, _)``, or ``(None, the check's answer)`` once the call or its result has been reported.
    """
    ok, value = _call(answer, library, name, *args)
    if not ok:
        return None, False
    value = _number(np.asarray(value).item() if np.ndim(value) == 0 and value is not None else value)
    if value is None:
        return None, _report(False, name, "return one number.")
    return value, True


def check_hausdorff(answer) -> bool:
    """A function ``f(a, b) -> float``: the Hausdorff distance between point sets ``(N, 2)`` and ``(M, 2)``."""
    name = "Hausdorff distance"
    rng = np.random.default_rng(3000)
    cases = [(rng.uniform(-0.5, 0.5, (60, 2)), rng.uniform(-0.5, 0.5, (85, 2)))]
    a = rng.uniform(-0.5, 0.5, (70, 2))
    cases.append((a, np.vstack([a[:40] + rng.normal(0, 0.01, (40, 2)), [[0.9, 0.9]]])))  # b has an outlier
    cases.append((cases[1][1], cases[1][0]))
    for a, b in cases:
        value, failed = _one_number(answer, "Hausdorff distance", name, a.copy(), b.copy())
        if value is None:
            return failed
        ab, ba = _hausdorff(a, b)
        if math.isclose(value, max(ab, ba), rel_tol=1e-9, abs_tol=1e-12):
            continue
        if math.isclose(value, ab, rel_tol=1e-9) or math.isclose(value, ba, rel_tol=1e-9):
            return _report(False, name, "that is one direction only: a set can lie close to the other "
                           "while the other has points far from it.")
        return _report(False, name, "for each point of one set, how far is the nearest point of the other? "
                       "Which of those distances does the definition keep?")
    return _report(True, name, "")


def check_scaled_distance(answer, s: float = 1 / 3, d: float = 0.3) -> bool:
    """A point is at distance ``d`` from S, measured after pulling it back by ``T^-1``; its distance to ``T(S)``?"""
    truth = s * d
    name = "distance to T(S)"
    value = _number(answer)
    if value is None:
        return _report(False, name, f"give one number, got {type(answer).__name__}.")
    if math.isclose(value, truth, rel_tol=1e-6):
        return _report(True, name, "")
    if math.isclose(value, d / s, rel_tol=1e-6):
        return _report(False, name, "that is the paper's printed law: does a map that shrinks every shape "
                       "make distances larger?")
    return _report(False, name, "T takes S, and the nearest point of S, to T(S): what does it do to the "
                   "segment between the point and its nearest point?")


def collage_maps(seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Maps ``(3, 3, 3)`` and a point set ``(200, 2)`` on which the collage exercise is checked."""
    rng = np.random.default_rng(4000 + seed)
    return _random_maps(rng, 3, 0.3, 0.5), rng.uniform(-0.4, 0.4, (200, 2))


def check_collage_distance(answer) -> bool:
    """A function ``f(maps, points) -> float``: the Hausdorff distance from ``points`` to the union of its copies."""
    name = "collage distance"
    for seed in range(2):
        maps, points = collage_maps(seed)
        value, failed = _one_number(answer, "collage distance", name, maps.copy(), points.copy())
        if value is None:
            return failed
        truth = max(_hausdorff(points, _apply(maps, points)))
        if math.isclose(value, truth, rel_tol=1e-9):
            continue
        each = max(max(_hausdorff(points, _apply(maps[i:i + 1], points))) for i in range(len(maps)))
        if math.isclose(value, each, rel_tol=1e-9):
            return _report(False, name, "compare the points with all the copies together, their union, "
                           "not with each copy in turn.")
        return _report(False, name, "make the collage: every map applied to every point, all in one set; "
                       "then measure it against the points.")
    return _report(True, name, "")


# --- part 3: a loss ----------------------------------------------------------------------------------

def _reference_multiscale(a: torch.Tensor, b: torch.Tensor, levels: int = 4) -> torch.Tensor:
    total = (a - b).square().mean()
    x, y = a[None, None], b[None, None]
    for _ in range(levels):
        x, y = torch.nn.functional.avg_pool2d(x, 2), torch.nn.functional.avg_pool2d(y, 2)
        total = total + (x - y).square().mean()
    return total


def check_loss(answer) -> bool:
    """A function ``f(image, target) -> scalar tensor``: the multiscale pixel loss with 4 pooled copies.

    ``image`` and ``target`` are ``(size, size)`` tensors (size a multiple of 16); the loss is the MSE
    of the two images plus the MSE of each of 4 copies, each averaged over 2 x 2 blocks of the one
    before. It must be differentiable in ``image``: the check compares its gradient too.
    """
    name = "multiscale pixel loss"
    rng = np.random.default_rng(5000)
    for size in (32, 48):
        image = torch.tensor(rng.random((size, size)), dtype=torch.float64, requires_grad=True)
        target = torch.tensor(rng.random((size, size)) < 0.3, dtype=torch.float64)
        ok, value = _call(answer, "loss", name, image, target.clone())
        if not ok:
            return False
        if not isinstance(value, torch.Tensor) or value.numel() != 1:
            return _report(False, name, "return a torch scalar (a tensor with one number), computed with torch "
                           "so that it has a gradient.")
        truth = _reference_multiscale(image, target)
        got = float(value.detach())
        if not math.isclose(got, float(truth.detach()), rel_tol=1e-6):
            if math.isclose(got, float((image - target).square().mean().detach()), rel_tol=1e-6):
                hint = "that is the plain pixel loss; add the pooled copies."
            else:
                hint = ("the first term compares the images themselves; each further term, copies with 2 x 2 "
                        "blocks averaged, one level coarser each time.")
            return _report(False, name, hint)
        if not value.requires_grad:
            return _report(False, name, "the value is right but it has no gradient: compute it with torch "
                           "operations only (no .numpy(), no float()).")
        grad, = torch.autograd.grad(value, image)
        true_grad, = torch.autograd.grad(truth, image)
        if not torch.allclose(grad, true_grad, rtol=1e-5, atol=1e-12):
            return _report(False, name, "the value is right but its gradient is not: is a detached copy in it?")
    return _report(True, name, "")


# --- part 4: the best-fit-line start and a fit -----------------------------------------------------

def koch_target(size: int = 64, seed: int = 0) -> Target:
    """A Koch-like curve the library does not ship: its five points drawn at random (seeded), turned, at ``size``.

    The fit exercise's target; the plain `ifslib.patterns.koch` lies more than a pixel from it.
    """
    return load_target(_koch_truth(seed), size, depth="attractor")


def _koch_truth(seed: int = 0) -> IFS:
    rng = np.random.default_rng(6000 + seed)
    knee = rng.uniform(0.3, 0.36)
    peak = [rng.uniform(0.45, 0.55), rng.uniform(0.22, 0.3)]
    shape = np.array([[0, 0], [knee, 0], peak, [1 - rng.uniform(0.3, 0.36), 0], [1, 0]])
    pts = (shape - [0.5, (shape[:, 1].max() + shape[:, 1].min()) / 2]) * 0.8
    turn = math.radians(rng.choice([-1, 1]) * rng.uniform(20, 40))
    c, s = math.cos(turn), math.sin(turn)
    return koch_like(pts @ np.array([[c, s], [-s, c]]), depth=3, name="koch_exercise")


def check_best_fit_start(answer) -> bool:
    """A function ``f(pattern, target) -> (n, 2)``: a curve pattern's points spread along the target's best-fit line.

    Evenly spaced, in index order, between the extreme projections of the target's foreground pixel
    centres on its principal axis (either end first).
    """
    from ..discovery.initialization import _placed
    from ..geometry.patterns import koch

    name = "best-fit-line start"
    for seed, pattern in ((1, koch()), (2, koch_like([[-0.4, 0], [-0.1, 0.1], [0.1, -0.1], [0.4, 0]]))):
        target = koch_target(48, seed)
        truth = _placed(pattern, target)
        ok, value = _call(answer, "best-fit-line start", name, pattern.clone(), target)
        if not ok:
            return False
        if isinstance(value, IFS):
            value = value.points.detach()
        try:
            points = np.asarray(value.numpy() if isinstance(value, torch.Tensor) else value, dtype=float)
        except (TypeError, ValueError):
            return _report(False, name, f"return the points, an (n, 2) array, got {type(value).__name__}.")
        if points.shape != truth.shape:
            return _report(False, name, f"return one point per control point of the pattern, {truth.shape}; "
                           f"got shape {points.shape}.")
        if np.allclose(points, truth, atol=1e-4) or np.allclose(points, truth[::-1], atol=1e-4):
            continue
        gaps = np.linalg.norm(np.diff(points, axis=0), axis=1)
        if gaps.std() > 1e-6 * max(gaps.mean(), 1e-12):
            return _report(False, name, "space the points evenly, in the pattern's order.")
        if np.allclose(points.mean(0), truth.mean(0), atol=1e-3):
            return _report(False, name, "centred right; the line's direction or length is off: which direction "
                           "do the foreground pixels spread the most along, and how far?")
        return _report(False, name, "the line goes through the mean of the foreground pixels' centres.")
    return _report(True, name, "")


def _fit_report(answer, target: Target, name: str, *, curve: bool, maps: int | None = None,
                max_chamfer: float = 1.0, min_iou: float = 0.8) -> bool:
    if not isinstance(answer, IFS):
        return _report(False, name, f"give the fitted ifslib.IFS (a FitResult's .best), got {type(answer).__name__}.")
    if maps is not None and len(answer.rules) != maps:
        return _report(False, name, f"the fractal has {maps} maps; your IFS has {len(answer.rules)}.")
    try:
        m = evaluate(answer, target, depth="attractor")
    except Exception as exc:  # noqa: BLE001  an IFS that cannot be drawn gets a hint
        return _report(False, name, f"its attractor cannot be drawn ({exc}).")
    if curve:
        crossings = self_crossings(answer) if is_curve(answer) else 0
        ok = m["chamfer"] <= max_chamfer and crossings == 0
        hint = (f"its attractor lies {m['chamfer']:.1f} px from the target (Chamfer), {crossings} self-crossings; "
                f"aim for {max_chamfer:g} px and none. Where does your start lie, and does the fit cross itself?")
    else:
        ok = m["iou"] >= min_iou
        hint = (f"its attractor's IoU with the target is {m['iou']:.2f}; aim for {min_iou:g}. Can your maps "
                "take the shapes the target's copies have?")
    return _report(ok, name, hint)


def check_koch_fit(answer, size: int = 64) -> bool:
    """A fitted IFS whose attractor lies within 1 px (Chamfer) of `koch_target` and does not cross itself."""
    return _fit_report(answer, koch_target(size), "Koch fit", curve=True)


# --- notebook 01: the word tree and the depth a drawing needs -------------------------------------------

def word_maps(seed: int = 0) -> np.ndarray:
    """``(3, 3, 3)`` maps on which the leaf-map exercise is checked (they do not commute)."""
    return _random_maps(np.random.default_rng(7000 + seed), 3, 0.3, 0.6, shear=0.5)


def check_leaf_map(answer) -> bool:
    """A function ``f(maps, word) -> (3, 3)``: the map ``T_w = T_(i1) o ... o T_(iK)`` of the leaf of word ``w``.

    ``maps[i - 1]`` is ``T_i``; ``word`` is a tuple of map numbers ``(i1, ..., iK)`` from 1 to m.
    """
    name = "leaf map"
    maps = word_maps()
    for word in ((2,), (1, 3), (3, 1, 2), (2, 2, 3, 1)):
        ok, value = _call(answer, "leaf map", name, maps.copy(), word)
        value = _matrix(value, (3, 3), name) if ok else None
        if value is None:
            return False
        truth, backwards = np.eye(3), np.eye(3)
        for i in word:
            truth, backwards = truth @ maps[i - 1], maps[i - 1] @ backwards
        if np.allclose(value, truth, atol=1e-9):
            continue
        if np.allclose(value, backwards, atol=1e-9):
            return _report(False, name, "the order is reversed: which map acts on the primitive first, the "
                           "first letter's or the last one's?")
        if len(word) == 1:
            return _report(False, name, "maps are numbered from 1: T_i is maps[i - 1].")
        return _report(False, name, "a leaf's map composes the maps of its word: a product of 3 x 3 matrices.")
    return _report(True, name, "")


def check_depth_needed(answer) -> bool:
    """A function ``f(s, d0, tol) -> int``: the smallest depth K with ``s^K d0 <= tol``."""
    name = "depth needed"
    rng = np.random.default_rng(8000)
    cases = [(1 / 3, 29.6, 0.5), (0.5, 8.3, 1.0), (0.9, 1.0, 1.0)]  # no case on a boundary s^K d0 = tol
    cases += [(float(rng.uniform(0.2, 0.8)), float(rng.uniform(2, 50)), float(rng.uniform(0.1, 1))) for _ in range(20)]
    for s, d0, tol in cases:
        ok, value = _call(answer, "depth", name, s, d0, tol)
        if not ok:
            return False
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            return _report(False, name, f"return a whole number (an int), got {type(value).__name__}.")
        truth = 0
        while s ** truth * d0 > tol:
            truth += 1
        if int(value) != truth:
            hint = ("off by one: is K the smallest depth that reaches the tolerance, and does yours reach it?"
                    if abs(int(value) - truth) == 1 else "solve s^K d0 <= tol for K: take logarithms (both "
                    "sides' logs are negative or small, mind the direction of the inequality).")
            return _report(False, name, hint)
    return _report(True, name, "")


# --- notebook 05: a carpet of other proportions --------------------------------------------------------

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
    return _fit_report(answer, carpet_target(size), "carpet fit", curve=False, min_iou=min_iou)


# --- notebook 07: a two-map fractal --------------------------------------------------------------------

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
    return _fit_report(answer, two_map_target(size), "two-map fractal", curve=False, maps=2, min_iou=min_iou)
