"""The exercises' checks (`ifslib.exercises`): for each, the right answer passes; a typical wrong
answer, an answer of the wrong kind, the student edition's stub (None, or a function returning None)
and the library's own answer each answer "not yet" with a hint, without raising."""
import numpy as np
import pytest
import torch

import ifslib
from ifslib import exercises

STUB = lambda *args: None  # noqa: E731  a function whose body the student edition emptied


def not_yet(capsys, ok, *words):
    out = capsys.readouterr().out
    assert ok is False and "not yet. Hint:" in out, out
    for word in words:
        assert word in out, out
    return out


def correct(capsys, ok):
    out = capsys.readouterr().out
    assert ok is True and out.strip().endswith("correct."), out
    assert not any(c.isdigit() for c in out.split(":")[-1]), out  # no number in a stored "correct." line


# --- answers as the notebooks' solutions write them -------------------------------------------------

def contraction_and_fixed_point(M):
    L, t = M[:2, :2], M[:2, 2]
    return np.linalg.svd(L, compute_uv=False)[0], np.linalg.solve(np.eye(2) - L, t)


def my_chaos_game(maps, n, seed=0, start=None, choose=True):
    rng = np.random.default_rng(seed)
    L, t = maps[:, :2, :2], maps[:, :2, 2]
    point = np.linalg.solve(np.eye(2) - L[0], t[0]) if start is None else np.asarray(start, float)
    points = np.empty((n, 2))
    for k, i in enumerate(rng.integers(len(maps), size=n) if choose else np.zeros(n, int)):
        point = L[i] @ point + t[i]
        points[k] = point
    return points


def my_hausdorff(a, b):
    gaps = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=-1)
    return max(gaps.min(1).max(), gaps.min(0).max())


def my_collage(maps, points):
    return my_hausdorff(points, np.concatenate([points @ M[:2, :2].T + M[:2, 2] for M in maps]))


def my_loss(image, target, levels=4):
    a, b = image[None, None], target[None, None]
    total = (a - b).square().mean()
    for _ in range(levels):
        a, b = torch.nn.functional.avg_pool2d(a, 2), torch.nn.functional.avg_pool2d(b, 2)
        total = total + (a - b).square().mean()
    return total


def my_start(pattern, target):
    pixels = ifslib.initialization.foreground_points(target)
    centre = pixels.mean(0)
    direction = np.linalg.svd(pixels - centre, full_matrices=False)[2][0]
    along = (pixels - centre) @ direction
    return centre + np.linspace(along.min(), along.max(), pattern.n_points)[:, None] * direction


def leaf_map(maps, word):
    out = np.eye(3)
    for i in word:
        out = out @ maps[i - 1]
    return out


def depth_needed(s, d0, tol):
    k = 0
    while s ** k * d0 > tol:
        k += 1
    return k


# --- part 1 ------------------------------------------------------------------------------------------

def test_koch_map(capsys):
    r3 = np.sqrt(3)
    correct(capsys, exercises.check_koch_map([[1 / 6, r3 / 6, 1 / 2], [-r3 / 6, 1 / 6, r3 / 6], [0, 0, 1]], 3))
    paper = [[1 / 6, r3 / 6, 1 / 3], [-r3 / 6, 1 / 6, 0], [0, 0, 1]]   # the paper's printed T3
    not_yet(capsys, exercises.check_koch_map(paper, 3), "translation")
    not_yet(capsys, exercises.check_koch_map([[1 / 6, -r3 / 6, 1 / 2], [r3 / 6, 1 / 6, r3 / 6], [0, 0, 1]], 3),
            "wrong way")
    not_yet(capsys, exercises.check_koch_map(None, 3), "(3, 3)")
    not_yet(capsys, exercises.check_koch_map("T3", 3))
    not_yet(capsys, exercises.check_koch_map(exercises.koch_map, 3), "not a function")


def test_leaf_count(capsys):
    correct(capsys, exercises.check_leaf_count(8 ** 4, "carpet", 4))
    out = not_yet(capsys, exercises.check_leaf_count(4 ** 8, "carpet", 4))
    assert "4096" not in out and "8 **" not in out       # the hint does not give the answer
    not_yet(capsys, exercises.check_leaf_count(None, "carpet", 4), "whole number")
    not_yet(capsys, exercises.check_leaf_count(4096.0, "carpet", 4))
    not_yet(capsys, exercises.check_leaf_count(ifslib.expand, "carpet", 4))


def test_contraction(capsys):
    correct(capsys, exercises.check_contraction(contraction_and_fixed_point))
    sqrt_det = lambda M: (np.sqrt(abs(np.linalg.det(M[:2, :2]))), contraction_and_fixed_point(M)[1])  # noqa: E731
    not_yet(capsys, exercises.check_contraction(sqrt_det), "det")
    eigen = lambda M: (np.abs(np.linalg.eigvals(M[:2, :2])).max(), contraction_and_fixed_point(M)[1])  # noqa: E731
    not_yet(capsys, exercises.check_contraction(eigen), "eigenvalue", "unit vector")
    no_fix = lambda M: (contraction_and_fixed_point(M)[0], M[:2, 2])  # noqa: E731
    not_yet(capsys, exercises.check_contraction(no_fix), "fixed point")
    not_yet(capsys, exercises.check_contraction(STUB), "pair")
    not_yet(capsys, exercises.check_contraction(None), "function")
    library = lambda M: (float(ifslib.geometry.rules.map_scales(torch.as_tensor(M)[None])[0]), M[:2, 2])  # noqa: E731
    not_yet(capsys, exercises.check_contraction(library), "write it yourself")


def test_chaos_game(capsys):
    correct(capsys, exercises.check_chaos_game(my_chaos_game))
    from_origin = lambda maps, n, seed=0: my_chaos_game(maps, n, seed, start=(0.9, 0.9))  # noqa: E731
    not_yet(capsys, exercises.check_chaos_game(from_origin), "start")
    one_map = lambda maps, n, seed=0: my_chaos_game(maps, n, seed, choose=False)  # noqa: E731
    not_yet(capsys, exercises.check_chaos_game(one_map), "random")
    not_yet(capsys, exercises.check_chaos_game(STUB))
    not_yet(capsys, exercises.check_chaos_game("chaos"), "function")
    not_yet(capsys, exercises.check_chaos_game(ifslib.chaos_game), "ifslib's own")
    wrapped = lambda maps, n, seed=0: ifslib.chaos_game(ifslib.patterns.affine(maps), n, seed)  # noqa: E731
    not_yet(capsys, exercises.check_chaos_game(wrapped), "write it yourself")
    assert ifslib.chaos_game is ifslib.raster.chaos.chaos_game   # switched back on after the check
    assert ifslib.chaos_game(ifslib.patterns.koch(), 10).shape == (10, 2)


def test_library_off_reaches_names_imported_into_the_notebook(capsys):
    from ifslib import chaos_game

    namespace = {"chaos_game": chaos_game, "ifslib": ifslib}
    exec("def imported(maps, n, seed=0):\n    return chaos_game(ifslib.patterns.affine(maps), n, seed)", namespace)
    not_yet(capsys, exercises.check_chaos_game(namespace["imported"]), "write it yourself")
    assert namespace["chaos_game"] is chaos_game


# --- part 2 ------------------------------------------------------------------------------------------

def test_hausdorff(capsys):
    correct(capsys, exercises.check_hausdorff(my_hausdorff))
    one_way = lambda a, b: np.linalg.norm(a[:, None] - b[None], axis=-1).min(1).max()  # noqa: E731
    not_yet(capsys, exercises.check_hausdorff(one_way), "one direction")
    mean = lambda a, b: np.linalg.norm(a[:, None] - b[None], axis=-1).min(1).mean()  # noqa: E731
    not_yet(capsys, exercises.check_hausdorff(mean))
    not_yet(capsys, exercises.check_hausdorff(STUB), "one number")
    not_yet(capsys, exercises.check_hausdorff(0.5), "function")
    not_yet(capsys, exercises.check_hausdorff(ifslib.metrics.hausdorff), "ifslib's own")
    not_yet(capsys, exercises.check_hausdorff(lambda a, b: ifslib.metrics.hausdorff(a, b)), "write it yourself")


def test_scaled_distance(capsys):
    correct(capsys, exercises.check_scaled_distance(0.1, 1 / 3, 0.3))
    out = not_yet(capsys, exercises.check_scaled_distance(0.9, 1 / 3, 0.3), "printed law")
    assert "0.1" not in out
    not_yet(capsys, exercises.check_scaled_distance(0.3, 1 / 3, 0.3))
    not_yet(capsys, exercises.check_scaled_distance(None, 1 / 3, 0.3), "number")
    not_yet(capsys, exercises.check_scaled_distance("0.1", 1 / 3, 0.3))


def test_collage(capsys):
    correct(capsys, exercises.check_collage_distance(my_collage))
    each = lambda maps, p: max(my_hausdorff(p, p @ M[:2, :2].T + M[:2, 2]) for M in maps)  # noqa: E731
    not_yet(capsys, exercises.check_collage_distance(each), "union")
    not_yet(capsys, exercises.check_collage_distance(lambda maps, p: my_hausdorff(p, p)))
    not_yet(capsys, exercises.check_collage_distance(STUB), "one number")
    not_yet(capsys, exercises.check_collage_distance([1, 2]), "function")
    library = lambda maps, p: ifslib.metrics.hausdorff(p, np.concatenate([p @ M[:2, :2].T + M[:2, 2] for M in maps]))  # noqa: E731
    not_yet(capsys, exercises.check_collage_distance(library), "write it yourself")
    not_yet(capsys, exercises.check_collage_distance(ifslib.scoring.collage.collage_distance), "ifslib's own")


# --- part 3 ------------------------------------------------------------------------------------------

def test_loss(capsys):
    correct(capsys, exercises.check_loss(my_loss))
    not_yet(capsys, exercises.check_loss(lambda a, b: (a - b).square().mean()), "plain pixel loss")
    not_yet(capsys, exercises.check_loss(lambda a, b: my_loss(a, b, levels=5)))
    not_yet(capsys, exercises.check_loss(lambda a, b: my_loss(a.detach(), b)), "gradient")
    not_yet(capsys, exercises.check_loss(lambda a, b: float(my_loss(a, b).detach())), "torch scalar")
    not_yet(capsys, exercises.check_loss(STUB), "torch scalar")
    not_yet(capsys, exercises.check_loss("multiscale_pixel"), "function")
    not_yet(capsys, exercises.check_loss(ifslib.losses.multiscale_mse), "ifslib's own")
    not_yet(capsys, exercises.check_loss(lambda a, b: ifslib.losses.multiscale_mse(a, b, 4)), "write it yourself")


# --- part 4 ------------------------------------------------------------------------------------------

def test_best_fit_start(capsys):
    correct(capsys, exercises.check_best_fit_start(my_start))
    correct(capsys, exercises.check_best_fit_start(lambda p, t: my_start(p, t)[::-1]))   # either end first
    box = lambda p, t: np.linspace(*ifslib.initialization.foreground_points(t)[[0, -1]], p.n_points)  # noqa: E731
    not_yet(capsys, exercises.check_best_fit_start(box))
    uneven = lambda p, t: my_start(p, t)[[0, 1, 3, 2, 4][:p.n_points]] if p.n_points == 5 else my_start(p, t)  # noqa: E731
    not_yet(capsys, exercises.check_best_fit_start(uneven), "evenly")
    not_yet(capsys, exercises.check_best_fit_start(STUB), "control point")
    not_yet(capsys, exercises.check_best_fit_start(ifslib.patterns.koch()), "function")
    not_yet(capsys, exercises.check_best_fit_start(lambda p, t: ifslib.initialize(p, t).points), "write it yourself")
    not_yet(capsys, exercises.check_best_fit_start(ifslib.initialize), "ifslib's own")


def test_koch_fit(capsys):
    correct(capsys, exercises.check_koch_fit(exercises.tutorial._koch_truth()))
    not_yet(capsys, exercises.check_koch_fit(ifslib.patterns.koch()), "px")   # the library's own curve
    not_yet(capsys, exercises.check_koch_fit(ifslib.patterns.koch_paper(1)))
    not_yet(capsys, exercises.check_koch_fit(None), "IFS")
    not_yet(capsys, exercises.check_koch_fit("koch"), "IFS")


def test_koch_target_is_not_the_librarys():
    target = exercises.koch_target(64)
    assert ifslib.evaluate(ifslib.patterns.koch(), target, depth="attractor")["chamfer"] > 2


# --- notebook 01 -------------------------------------------------------------------------------------

def test_leaf_map(capsys):
    correct(capsys, exercises.check_leaf_map(leaf_map))
    backwards = lambda maps, word: leaf_map(maps, word[::-1])  # noqa: E731
    not_yet(capsys, exercises.check_leaf_map(backwards), "reversed")
    zero_based = lambda maps, word: leaf_map(maps, [i + 1 if i < len(maps) else 1 for i in word])  # noqa: E731
    not_yet(capsys, exercises.check_leaf_map(zero_based))
    not_yet(capsys, exercises.check_leaf_map(STUB), "(3, 3)")
    not_yet(capsys, exercises.check_leaf_map(np.eye(3)), "function")
    not_yet(capsys, exercises.check_leaf_map(ifslib.expand), "ifslib's own")


def test_depth_needed(capsys):
    correct(capsys, exercises.check_depth_needed(depth_needed))
    import math
    by_logs = lambda s, d0, tol: max(0, math.ceil(math.log(tol / d0) / math.log(s)))  # noqa: E731
    correct(capsys, exercises.check_depth_needed(by_logs))
    not_yet(capsys, exercises.check_depth_needed(lambda s, d0, tol: depth_needed(s, d0, tol) + 1), "off by one")
    not_yet(capsys, exercises.check_depth_needed(lambda s, d0, tol: math.log(tol / d0) / math.log(s)), "whole number")
    not_yet(capsys, exercises.check_depth_needed(STUB), "whole number")
    not_yet(capsys, exercises.check_depth_needed(4), "function")
    not_yet(capsys, exercises.check_depth_needed(ifslib.metrics.depth_to_attractor), "ifslib's own")


# --- notebooks 05 and 07 -------------------------------------------------------------------------------

def test_carpet_fit(capsys):
    correct(capsys, exercises.check_carpet_fit(exercises.lessons._carpet_truth()))
    carpet = ifslib.patterns.sierpinski_carpet()
    not_yet(capsys, exercises.check_carpet_fit(carpet), "IoU")     # the library's own carpet
    not_yet(capsys, exercises.check_carpet_fit(ifslib.initialize(carpet, exercises.carpet_target(64))), "IoU")
    not_yet(capsys, exercises.check_carpet_fit(None), "IFS")
    not_yet(capsys, exercises.check_carpet_fit(carpet.maps()), "IFS")


def test_two_maps(capsys):
    correct(capsys, exercises.check_two_maps(exercises.lessons._two_map_truth()))
    not_yet(capsys, exercises.check_two_maps(ifslib.patterns.random_ifs(2, seed=0)), "IoU")
    not_yet(capsys, exercises.check_two_maps(ifslib.patterns.random_ifs(3, seed=0)), "2 maps")
    not_yet(capsys, exercises.check_two_maps(None), "IFS")


@pytest.mark.parametrize("check", [exercises.check_chaos_game, exercises.check_hausdorff,
                                   exercises.check_collage_distance, exercises.check_loss,
                                   exercises.check_best_fit_start, exercises.check_leaf_map,
                                   exercises.check_depth_needed, exercises.check_contraction])
def test_a_raising_function_gets_a_hint_not_a_traceback(check, capsys):
    def broken(*args):
        raise ZeroDivisionError("oops")

    not_yet(capsys, check(broken), "ZeroDivisionError")
