"""Lazy answers that must not pass (issue 53): the exercises' test cells, run as nbgrader runs them
(visible and hidden tests together), refuse them, and the instructor's answers still pass.

The tricks: the library's own function reached through a container the old switch-off missed (a
``functools.partial`` in a global, a class attribute, a dict, a list, a default argument), library
functions that compute the same answer under another name (``IFS.n_leaves``, ``IFS.scales``,
``ifslib.f1``, ``metrics.scores``, ``landscape.alignment``, ``crossing_pairs``, ``metrics.hausdorff``,
scipy's ``directed_hausdorff``, ``similarity_dimension``, scipy's Wilson interval of ``binomtest``, the
fractal search's ``moment_maps``, ``split_flag_count`` and ``Code.bits``), the target itself as a "fit" (one
tiny map onto each of its pixels), and guesses. Each library trick is first shown to be a real one: with
the switch-off disabled it passes the very same test cell. Answers that only the lesson's size tells apart
are tested at the values nbgrader grades the lesson at (``metadata["ifslib"]["grading"]``).

The harness's own guarantees are tested here too: a switched-off function raises however it is
reached, and everything is restored after, nested, on error and from two threads.
"""
from __future__ import annotations

import ast
import functools
import math
import re
import sys
import threading
import types
from pathlib import Path
from types import SimpleNamespace

import nbformat
import numpy as np
import pytest
import torch

import ifslib
from ifslib.measures import dimension
from ifslib.core.targets.target import foreground_points
from ifslib.teaching.exercises import harness

pytestmark = pytest.mark.slow  # make test-slow: the lazy answers' checks run the lessons' targets at several sizes


ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "course"))
import grading_run  # noqa: E402  the grading values nbgrader runs a lesson at
import targets as course_targets  # noqa: E402  the instructor's truths
from scripts import load_script  # noqa: E402  course/scripts.py
from test_exercises import SOLUTION, cell_of, fails, run  # noqa: E402  one way to run a test cell

def cell(grade_id: str) -> str:
    return cell_of(grade_id).source


def points(grade_id: str) -> int:
    return cell_of(f"{grade_id}-test").metadata["nbgrader"]["points"]


def with_body(grade_id: str, body: str, before: str = "") -> str:
    """The answer cell with ``body`` in place of the worked answer (at its indentation), after ``before``."""
    return before + SOLUTION.sub(lambda m: "".join(f"{m.group(1)}{line}\n" for line in body.splitlines()),
                                 cell(grade_id))


def refused(grade_id: str, answer: str, *words: str, **names) -> str:
    return fails(grade_id, *words, answer_source=answer, **names)


@pytest.fixture
def nothing_switched_off(monkeypatch):
    """The harness as if it switched nothing off: to show that a trick passes the test cell without it."""
    monkeypatch.setattr(harness, "LIBRARY", types.MappingProxyType({k: () for k in harness.LIBRARY}))
    monkeypatch.setattr(harness, "_held_library", lambda answer: None)
    monkeypatch.setattr(harness._Watch, "_allows", lambda self, module: True)


# -- the names each exercise's cells read from its notebook ---------------------------------------

def alignment_names() -> dict:
    rng = np.random.default_rng(0)
    return {"fields": {"pixel": rng.normal(size=(4, 4, 2))}, "true": rng.normal(size=(4, 4, 2))}


def crossing_names() -> dict:
    """``cross`` (the instructor's, as the notebook has it when count_crossings is written) and no stalled run."""
    return {"cross": run("04_local_minima-segments-cross")["cross"], "stalled": []}


def collage_names() -> dict:
    coarse = ifslib.load_target(ifslib.patterns.sierpinski_triangle(), 32)
    maps = ifslib.patterns.sierpinski_triangle().maps().detach().double().numpy()[:, :2]
    return {"coarse": coarse, "found": SimpleNamespace(maps=maps)}


def koch_results(size: int = 32) -> dict:
    ifs = ifslib.patterns.koch()
    return {"size": size, "results": {"koch": (ifslib.load_target(ifs, size), None, SimpleNamespace(best=ifs))}}


def copy_map_names() -> dict:
    """Notebook 07's ``target`` (a figure whose pixels are split in halves) and what its answer cell reads."""
    from ifslib.core.targets import silhouettes

    return {"target": ifslib.load_target(silhouettes.letter("G", 64).astype(float), 64),
            "foreground_points": foreground_points}


@functools.cache
def compressed() -> object:
    """A code of the camera man at 64² and 0.5 bpp, as notebook 10 codes its photograph for exercise 4 (block sizes
    4, 8, 16; fixed-length fields)."""
    from skimage import data, transform

    from ifslib.compression import CodeOptions, encode

    image = transform.resize(data.camera()[:, 64:-64] / 255, (64, 64), anti_aliasing=True)
    return encode(np.clip(image, 0, 1), CodeOptions(coder="fixed", m_bits=7), bpp=0.5)  # file version 1


def bits_names() -> dict:
    from ifslib.compression import to_bytes
    from ifslib.compression.domains import domain_bits

    return {"code": compressed(), "to_bytes": to_bytes, "domain_bits": domain_bits}


NAMES = {"03_gradient_fields-alignment": alignment_names, "04_local_minima-count-crossings": crossing_names,
         "08_real_fractals-collage": collage_names,
         "09_measures_and_dimension-moran-code": lambda: {"dimension": dimension},
         "02_fitting_gallery-chamfer": koch_results,
         "06_convergence_study-wilson": lambda: {"summary": []},
         "07_your_own_image-copy-map": copy_map_names, "10_fractal_compression-bits": bits_names}


def names_of(grade_id: str) -> dict:
    return NAMES.get(grade_id, dict)()


# -- library answers -------------------------------------------------------------------------------

AFFINE = "ifslib.patterns.affine"
CHAOS = "(ifslib.patterns.affine(maps[:, :2]), n, seed=seed)"
LIBRARY_TRICKS = [
    # tutorial 2: IFS.n_leaves, held as a method and in a dict
    ("00_tutorial-carpet-leaves", "",
     f"return {AFFINE}([[[0.3, 0, 0], [0, 0.3, 0]]] * m).n_leaves(depth) * primitives"),
    ("00_tutorial-carpet-leaves", "LEAVES = {'count': ifslib.IFS.n_leaves}\n",
     f"return LEAVES['count']({AFFINE}([[[0.3, 0, 0], [0, 0.3, 0]]] * m), depth) * primitives"),
    # tutorial 3: IFS.scales and dimension.ifs_scales
    ("00_tutorial-contraction", "", "M = np.asarray(M, float)\n"
     f"s = float({AFFINE}(M[None, :2]).scales()[0])\nreturn s, np.linalg.solve(np.eye(2) - M[:2, :2], M[:2, 2])"),
    ("00_tutorial-contraction", "", "M = np.asarray(M, float)\n"
     f"s = float(ifslib.dimension.ifs_scales({AFFINE}(M[None, :2]))[0][0])\n"
     "return s, np.linalg.solve(np.eye(2) - M[:2, :2], M[:2, 2])"),
    # tutorial 4: the chaos game held in containers, and a window of it
    ("00_tutorial-chaos-game", "import functools\nGAME = functools.partial(ifslib.chaos_game)\n",
     f"return GAME{CHAOS}"),
    ("00_tutorial-chaos-game", "class Tools:\n    game = staticmethod(ifslib.chaos_game)\n",
     f"return Tools.game{CHAOS}"),
    ("00_tutorial-chaos-game", "TOOLS = {'game': ifslib.chaos_game}\n", f"return TOOLS['game']{CHAOS}"),
    ("00_tutorial-chaos-game", "TOOLS = [ifslib.chaos_game]\n", f"return TOOLS[0]{CHAOS}"),
    ("00_tutorial-chaos-game", "", "return ifslib.core.raster.chaos.chaos_window(ifslib.patterns.affine(maps[:, :2]), n, "
                                   "(-5, -5, 5, 5), seed)"),
    # tutorial 5: the library's Hausdorff distance in containers, and scipy's
    ("00_tutorial-hausdorff", "import functools\nTOOLS = {'h': functools.partial(ifslib.metrics.hausdorff)}\n",
     "return TOOLS['h'](a, b)"),
    ("00_tutorial-hausdorff", "class T:\n    h = staticmethod(ifslib.metrics.hausdorff)\n", "return T.h(a, b)"),
    ("00_tutorial-hausdorff", "H = [ifslib.core.scoring.metrics.hausdorff]\n", "return H[0](a, b)"),
    ("00_tutorial-hausdorff", "from scipy.spatial.distance import directed_hausdorff\n",
     "return max(directed_hausdorff(a, b)[0], directed_hausdorff(b, a)[0])"),
    ("00_tutorial-hausdorff", "from scipy.spatial._hausdorff import directed_hausdorff as dh\n",
     "rng = np.random.default_rng(0)\n"
     "a, b = np.ascontiguousarray(a, float), np.ascontiguousarray(b, float)\n"
     "return max(dh(a, b, rng)[0], dh(b, a, rng)[0])"),
    # tutorial 7, 8, 9: a list, a class attribute
    ("00_tutorial-collage", "H = [ifslib.metrics.hausdorff]\n",
     "return H[0](points, np.concatenate([points @ M[:2, :2].T + M[:2, 2] for M in maps]))"),
    ("00_tutorial-loss", "class T:\n    loss = staticmethod(ifslib.losses.multiscale_mse)\n",
     "return T.loss(image, target, 5)"),
    ("00_tutorial-best-fit-line", "from ifslib.core.targets.placement import best_fit_line\nLINE = [best_fit_line]\n",
     "centre, direction, lo, hi = LINE[0](target)\n"
     "return centre + np.linspace(lo, hi, pattern.n_points)[:, None] * direction"),
    # 02: IoU from F1 (IoU = F1 / (2 - F1)), or from metrics.scores
    ("02_fitting_gallery-iou", "", "f = ifslib.f1(np.asarray(p, bool), np.asarray(q, bool))\nreturn f / (2 - f)"),
    ("02_fitting_gallery-iou", "", "return ifslib.metrics.scores(np.asarray(p, bool), np.asarray(q, bool))['iou']"),
    ("02_fitting_gallery-chamfer", "",
     "return ifslib.metrics.scores(np.asarray(p, bool), np.asarray(q, bool))['chamfer']"),
    # 03: the landscape's own alignment, called and held
    ("03_gradient_fields-alignment", "", "return ifslib.landscape.alignment(field, true)"),
    ("03_gradient_fields-alignment", "import functools\nTOOLS = {'a': functools.partial(ifslib.landscape.alignment)}\n",
     "return TOOLS['a'](field, true)"),
    # 04: the crossing test of the crossing penalty
    ("04_local_minima-segments-cross", "from ifslib.core.geometry.crossings import crossing_pairs\n",
     "segments = torch.tensor(np.array([[a, b], [c, d]], float))\nreturn len(crossing_pairs(segments)[0]) > 0"),
    ("04_local_minima-count-crossings", "from ifslib.core.geometry.crossings import crossing_pairs\n",
     "p = torch.tensor(np.asarray(points, float))\nreturn len(crossing_pairs(torch.stack([p[:-1], p[1:]], 1))[0])"),
    # 08: the library's Hausdorff distance (ifslib.metrics is ifslib.core.scoring.metrics), and scipy's
    ("08_real_fractals-collage", "",
     "copies = np.concatenate([points @ m[:, :2].T + m[:, 2] for m in np.asarray(maps, float)])\n"
     "return ifslib.metrics.hausdorff(np.asarray(points, float), copies)"),
    ("08_real_fractals-collage", "from scipy.spatial.distance import directed_hausdorff\n",
     "points = np.asarray(points, float)\n"
     "copies = np.concatenate([points @ m[:, :2].T + m[:, 2] for m in np.asarray(maps, float)])\n"
     "return max(directed_hausdorff(points, copies)[0], directed_hausdorff(copies, points)[0])"),
    # 11: the set loss's own matching, called and held in a dict
    ("11_learned_guess-pairing", "from ifslib.learned.set_loss import match\n",
     "rows, cols = match(torch.as_tensor(np.asarray(guessed, float)), torch.as_tensor(np.asarray(true, float)))\n"
     "return [int(r) for _, r in sorted(zip(cols, rows))]"),
    ("11_learned_guess-pairing", "from ifslib.learned import set_loss\nTOOLS = {'m': set_loss.match}\n",
     "rows, cols = TOOLS['m'](torch.as_tensor(np.asarray(guessed, float)), torch.as_tensor(np.asarray(true, float)))\n"
     "return [int(r) for _, r in sorted(zip(cols, rows))]"),
    # 09: Moran's equation solved by the library
    ("09_measures_and_dimension-moran-code", "", "return dimension.similarity_dimension(scales)"),
    ("09_measures_and_dimension-moran-code", "",
     f"return dimension.ifs_similarity_dimension({AFFINE}([[[r, 0, 0], [0, r, 0]] for r in scales]))"),
    # 06: scipy's Wilson interval, from the binomial test or its own helper
    ("06_convergence_study-wilson", "from scipy.stats import binomtest, norm\n",
     "ci = binomtest(k, n).proportion_ci(2 * norm.cdf(z) - 1, method='wilson')\nreturn ci.low, ci.high"),
    ("06_convergence_study-wilson", "import scipy.stats\nfrom scipy.stats._binomtest import _binom_wilson_conf_int\n",
     "return _binom_wilson_conf_int(k, n, 2 * scipy.stats.norm.cdf(z) - 1, 'two-sided', False)"),
    # 07: the fractal search's moment maps (the region's copy of the figure), unclipped
    ("07_your_own_image-copy-map", "from ifslib.automatic.fractal.regions import moment_maps\n",
     "return moment_maps(points, part, angles=1, scales=(0.0, np.inf))[0]"),
    ("07_your_own_image-copy-map", "TOOLS = {'m': ifslib.automatic.fractal.regions.moment_maps}\n",
     "return TOOLS['m'](points, part, 1, 0.0, (0.0, np.inf))[0]"),
    # 10: the library's counts of the flags, and of the flags and maps together
    ("10_fractal_compression-bits", "from ifslib.compression.code import split_flag_count\n",
     "flags, maps = split_flag_count(code), 12 * len(code)\n"
     "isometries = 3 * int((~code.flat).sum())\n"
     "return {'header': 120, 'flags': flags, 's and m': maps, 'isometries': isometries,\n"
     "        'domains': code.bits() - flags - maps - isometries,\n"
     "        'padding': 8 * len(to_bytes(code)) - 120 - code.bits()}"),
    ("10_fractal_compression-bits", "",
     "H, W = code.padded\n"
     "domains = sum(domain_bits(H, W, int(k)) for k in code.size[~code.flat])\n"
     "maps, isometries = 12 * len(code), 3 * int((~code.flat).sum())\n"
     "return {'header': 120, 'flags': code.bits() - maps - isometries - domains, 's and m': maps,\n"
     "        'isometries': isometries, 'domains': domains,\n"
     "        'padding': 8 * len(to_bytes(code)) - 120 - code.bits()}"),
]


def trick_id(trick) -> str:
    grade_id, before, body = trick
    return f"{grade_id.split('-', 1)[1]}:{(before + body).splitlines()[0][:40]}"


@pytest.mark.parametrize("trick", LIBRARY_TRICKS, ids=trick_id)
def test_a_library_answer_passes_without_the_switch_off(trick, nothing_switched_off):
    # so each trick below is a real one: only the switch-off refuses it
    grade_id, before, body = trick
    run(grade_id, with_body(grade_id, body, before), **names_of(grade_id))


@pytest.mark.parametrize("trick", LIBRARY_TRICKS, ids=trick_id)
def test_a_library_answer_is_refused_with_a_hint(trick):
    grade_id, before, body = trick
    message = refused(grade_id, with_body(grade_id, body, before), **names_of(grade_id))
    assert re.search(r"(ifslib|scipy)'s own", message), message


@pytest.mark.parametrize("grade_id", sorted({t[0] for t in LIBRARY_TRICKS} - {"00_tutorial-collage"}))
def test_the_instructors_answer_passes(grade_id):
    run(grade_id, **names_of(grade_id))


def test_the_instructors_collage_answer_passes_with_the_students_hausdorff():
    run("00_tutorial-collage", my_hausdorff=run("00_tutorial-hausdorff")["my_hausdorff"])


def test_a_library_function_handed_in_or_held_as_a_default_is_refused_before_it_runs():
    for grade_id, answer in [
        ("03_gradient_fields-alignment", "alignment = ifslib.landscape.alignment"),
        ("09_measures_and_dimension-moran-code", "solve_moran = dimension.similarity_dimension"),
        ("00_tutorial-chaos-game", "my_chaos_game = lambda maps, n, seed=0, game=ifslib.chaos_game: "
                                   "game(ifslib.patterns.affine(maps[:, :2]), n, seed=seed)"),
        ("00_tutorial-hausdorff", "from scipy.spatial.distance import directed_hausdorff as my_hausdorff"),
    ]:
        message = refused(grade_id, answer, "own function", **names_of(grade_id))
        assert "write the" in message


# -- the target itself as the fit ------------------------------------------------------------------

def pixel_maps(target, scale: float = 0.002) -> ifslib.IFS:
    """One tiny map onto each of the target's pixels: its attractor is the picture."""
    return ifslib.patterns.affine([[[scale, 0, x], [0, scale, y]] for x, y in foreground_points(target)], depth=1)


def test_the_koch_pictures_pixels_as_maps_are_refused():
    picture = ifslib.exercises.koch_target(64)
    cheat = pixel_maps(picture)
    assert ifslib.evaluate(cheat, picture, depth="attractor")["chamfer"] <= 1.0   # it draws the picture
    refused("00_tutorial-koch-fit", "my_fit = cheat", "Koch-like curve: 4 maps", cheat=cheat, koch_target=picture)


def test_a_curve_through_the_koch_pictures_pixels_is_refused():
    # a curve of one map per pixel (koch_like through the pixels, in order along the curve's axis):
    # a curve, so the crossing count runs, but not one of four maps
    picture = ifslib.exercises.koch_target(64)
    pixels = foreground_points(picture)
    centre = pixels.mean(0)
    axis = np.linalg.svd(pixels - centre, full_matrices=False)[2][0]
    chain = pixels[np.argsort((pixels - centre) @ axis)][::3]
    cheat = ifslib.patterns.koch_like(chain.tolist(), depth=1)
    assert len(cheat.rules) > 4
    refused("00_tutorial-koch-fit", "my_fit = cheat", "Koch-like curve: 4 maps", cheat=cheat, koch_target=picture)


def test_the_carpet_pictures_pixels_as_maps_are_refused():
    picture = ifslib.exercises.carpet_target(64)
    cheat = pixel_maps(picture)
    assert ifslib.evaluate(cheat, picture, depth="attractor")["iou"] >= 0.8   # it draws the picture
    refused("05_more_examples-carpet-fit", "my_carpet = cheat", "give 8 maps", cheat=cheat, odd_carpet=picture)


def test_a_carpet_of_8_maps_of_implausible_scales_is_refused_by_the_hidden_test():
    # the truth with one map flattened to a line: 8 maps, but no copy of the carpet is 0.02 across
    maps = course_targets.carpet_truth().maps().detach().double().numpy()[:, :2].copy()
    maps[7, 1, 1] = 0.02
    flat = ifslib.patterns.affine(maps, depth=3)
    refused("05_more_examples-carpet-fit", "my_carpet = flat", "a tenth to four fifths", flat=flat,
            odd_carpet=ifslib.exercises.carpet_target(64))


@pytest.mark.parametrize("size", [64, 128, 256])
def test_the_true_fractals_pass_the_new_checks_at_every_size(size):
    run("00_tutorial-koch-fit", "my_fit = truth", truth=course_targets.koch_truth(),
        koch_target=ifslib.exercises.koch_target(size))
    run("05_more_examples-carpet-fit", "my_carpet = truth", truth=course_targets.carpet_truth(),
        odd_carpet=ifslib.exercises.carpet_target(size))


# the instructor's fits at the notebooks' own values: grading's checks, run by .ci/nbgrader.sh (make test runs the
# quick ones inside the notebooks already)
@pytest.mark.grading
@pytest.mark.parametrize("size, steps", [(64, 100), (128, 200)])   # the quick values, the teaching ones
def test_the_instructors_koch_fit_passes(size, steps):
    run("00_tutorial-koch-fit", koch_target=ifslib.exercises.koch_target(size), steps=steps)


@pytest.mark.grading
def test_the_instructors_carpet_fit_passes():
    # the notebook draws the carpet at 128² and the answer fixes its steps and learning rate: the
    # quick values and the teaching ones run this very fit
    run("05_more_examples-carpet-fit", odd_carpet=ifslib.exercises.carpet_target(128))


# -- guesses ---------------------------------------------------------------------------------------

SLOPE = math.log(318 / 14) / math.log(8)
BOX = "09_measures_and_dimension-box-by-hand"


@pytest.mark.parametrize("guess", ["1.5", "1.50", "round(math.log(318 / 14) / math.log(8), 2)",
                                   "np.polyfit(np.log([4, 8, 16, 32]), np.log([14, 40, 112, 318]), 1)[0]",
                                   "1.495"])
def test_a_guessed_box_dimension_fails(guess):
    value = eval(guess, {"math": math, "np": np})
    assert abs(value - SLOPE) < 0.01   # the old hidden test's tolerance took it
    refused(BOX, f"d_by_hand = {guess}")


def test_a_round_guess_is_told_visibly_and_the_slope_to_three_decimals_passes():
    with pytest.raises(AssertionError, match="round number"):
        run(BOX, "d_by_hand = 1.5", visible_only=True)
    run(BOX, "d_by_hand = 1.502")
    run(BOX)


def test_a_similarity_of_scale_one_third_is_not_t3():
    # T1 (the first third) passes the visible test, a similarity of scale 1/3; the hidden one wants T3
    t1 = "T3 = [[1 / 3, 0, 0], [0, 1 / 3, 0], [0, 0, 1]]"
    run("00_tutorial-koch-t3", t1, visible_only=True)
    refused("00_tutorial-koch-t3", t1, "direction of p2 -> p3")


def test_t3_read_off_the_notebooks_own_koch_curve_is_refused():
    # the notebook's `koch` (ifslib.patterns.koch()) is drawn on another base segment: its T3 has
    # the right linear part but another translation (koch_unit's is right: exercise 1b grades why)
    refused("00_tutorial-koch-t3", "T3 = koch.maps().detach().double().numpy()[2]", "translation",
            koch=ifslib.patterns.koch())


@pytest.mark.parametrize("guess", ["0.5", "0.3", "0.9", "1"])
def test_a_positive_guess_of_the_scaled_distance_fails(guess):
    run("00_tutorial-scaled-distance", f"distance_to_copy = {guess}", visible_only=True)
    refused("00_tutorial-scaled-distance", f"distance_to_copy = {guess}")


# -- graded at the values where right and lazy answers differ ------------------------------------

def lesson_values(name: str, preset: str) -> dict:
    """A lesson's parameters at its ``teaching``, ``quick`` or ``grading`` values (those nbgrader runs it at)."""
    path = ROOT / "notebooks" / f"{name}.ipynb"
    book = nbformat.read(path, as_version=4)
    teaching = load_script("notebooks/run.py", "ifslib_notebooks_run").teaching_parameters(path)
    quick = {**teaching, **book.metadata.get("ifslib", {}).get("quick", {})}
    return {"teaching": teaching, "quick": quick, "grading": grading_run.grading_values(book, teaching)}[preset]


FAR = "03_gradient_fields-further-out"
FAR_LAZY = ['far_share = {kind: scores[kind][1] for kind in ("pixel", "distance")}',   # the near grid's, copied
            'far_share = {"pixel": 1.0, "distance": 1.0}']                              # every arrow toward


@functools.cache
def gradient_names(size: int, grid: int, depth: int, half_width: float) -> dict:
    """What notebook 03's further-out cells read, at these values: the near grid's scores among them."""
    optimum = ifslib.patterns.koch(depth=depth)
    target = ifslib.load_target(optimum, size)
    p2 = optimum.points[2].detach().double().numpy()
    xs, ys = (p2[i] + np.linspace(-half_width, half_width, grid) for i in (0, 1))
    true = ifslib.landscape.toward(xs, ys, p2)
    scores = {kind: ifslib.landscape.alignment(
        ifslib.landscape.gradient_field(optimum, target, 2, xs, ys, kind, progress=False), true)
        for kind in ("pixel", "distance")}
    alignment = run("03_gradient_fields-alignment", **alignment_names())["alignment"]
    return {"optimum": optimum, "target": target, "p2": p2, "scores": scores, "alignment": alignment}


def far_names(preset: str) -> dict:
    v = lesson_values("03_gradient_fields", preset)
    return gradient_names(v["size"], v["grid"], v["depth"], v["half_width"])


@pytest.mark.parametrize("preset", ["grading", pytest.param("teaching", marks=pytest.mark.slow)])
def test_the_far_shares_copied_or_guessed_fail_where_they_are_graded(preset):
    # at 64² both far shares are 1.0, as are the near grid's: notebook 03 is graded at 128², where the
    # pixel loss's far share is 0.75 (as at the teaching 256²) and its near share 0.96
    names = far_names(preset)
    far = run(FAR, **names)["far_share"]
    assert far["pixel"] < 1 and far["pixel"] != names["scores"]["pixel"][1], (far, names["scores"])
    for lazy in FAR_LAZY:
        refused(FAR, with_body(FAR, lazy), "pixel: share is off", **names)


def test_at_the_quick_size_the_far_shares_cannot_tell_a_guess_from_the_answer():
    # why notebook 03 is not graded at its quick values
    names = far_names("quick")
    assert run(FAR, **names)["far_share"] == {"pixel": 1.0, "distance": 1.0}
    for lazy in FAR_LAZY:
        run(FAR, with_body(FAR, lazy), **names)
    sizes = {preset: lesson_values("03_gradient_fields", preset)["size"] for preset in ("quick", "grading")}
    assert sizes["grading"] != sizes["quick"], sizes


KOCH_DEPTH = "01_koch_iterations-koch-depth"


@functools.cache
def koch_distances(size: int) -> list[float]:
    """Notebook 01's distance at depth 0 (its table's first row; the exercise reads no other)."""
    return ifslib.metrics.depth_to_attractor(ifslib.patterns.koch(depth=1), range(1), points=400_000,
                                             spacing=0.25 / size)


def the_tables_depth() -> int:
    """The depth the lesson's stored table gives: its depth-0 distance in pixels, shrunk by 3 to half a pixel."""
    book = nbformat.read(ROOT / "notebooks" / "01_koch_iterations.ipynb", as_version=4)
    [table] = [c for c in book.cells if c.cell_type == "code" and "depth_to_attractor" in c.source]
    printed = "".join(o.get("text", "") for o in table.outputs)
    d0 = float(re.search(r"depth 0:\s+([0-9.]+) px", printed).group(1))
    return next(k for k in range(20) if d0 / 3 ** k <= 0.5)


def test_the_koch_depth_read_off_the_lessons_table_fails_where_it_is_graded():
    # the statement asks for a poster 16 times as wide as the lesson's table (at the teaching size,
    # where nbgrader grades notebook 01): the table's depth is not the answer, 16 = 3^2.5 costs more
    grading, teaching = (lesson_values("01_koch_iterations", preset) for preset in ("grading", "teaching"))
    assert grading["size"] == teaching["size"]
    depth_needed = run("01_koch_iterations-depth-needed")["depth_needed"]
    names = {"distances": koch_distances(grading["size"]), "size": grading["size"], "depth_needed": depth_needed}
    read = the_tables_depth()
    assert read == 5 and run(KOCH_DEPTH, **names)["koch_depth"] == 8
    run(KOCH_DEPTH, "koch_depth = 8", **names)
    for wrong in (read, 7, 9):
        refused(KOCH_DEPTH, f"koch_depth = {wrong}", "half a pixel at depth", **names)


def test_the_instructors_koch_depth_passes_at_the_quick_size_too():
    quick = lesson_values("01_koch_iterations", "quick")["size"]
    depth_needed = run("01_koch_iterations-depth-needed")["depth_needed"]
    names = {"distances": koch_distances(quick), "size": quick, "depth_needed": depth_needed}
    assert run(KOCH_DEPTH, **names)["koch_depth"] == 7   # 16 times the 29.6 px the table reads at 128 px


FERN_STEM = "09_measures_and_dimension-fern-stem"


def fern_names() -> dict:
    """Notebook 09's names that the fern-stem cells read (the drawing of the answer made a no-op)."""
    from ifslib.measures.measure import chaos_measure

    book = nbformat.read(ROOT / "notebooks" / "09_measures_and_dimension.ipynb", as_version=4)
    barnsley = re.search(r"^BARNSLEY = (\([^)]*\))", "\n".join(c.source for c in book.cells), re.M).group(1)
    figure = SimpleNamespace(subplots=lambda **kw: (None, None), show=lambda: None)
    return {"BARNSLEY": ast.literal_eval(barnsley), "fern": ifslib.patterns.fern().to(torch.float64),
            "chaos_measure": chaos_measure, "plt": figure, "show": lambda *args, **kwargs: None}


def test_barnsleys_probabilities_fail_the_fern_stem_exercise():
    # the statement asks for a stem from 2 % to 5 % with the main leaflet the largest: Barnsley's
    # (the lesson's constant, stem 1 %), which a student can copy, are not one, nor are the |det|
    # shares (stem 0.02 %)
    names = fern_names()
    run(FERN_STEM, **names)
    run(FERN_STEM, "my_probabilities = (0.03, 0.83, 0.07, 0.07)", **names)
    refused(FERN_STEM, "my_probabilities = BARNSLEY", "stem's share", **names)
    det = np.abs(np.linalg.det(names["fern"].maps().detach().numpy()[:, :2, :2]))
    refused(FERN_STEM, f"my_probabilities = {tuple((det / det.sum()).tolist())}", "stem's share", **names)


# -- a whole lazy submission -----------------------------------------------------------------------

def test_a_submission_of_the_tricks_scores_nothing_on_their_exercises():
    scored, total = 0, 0
    tricks = {t[0]: t for t in LIBRARY_TRICKS}
    for grade_id, (_, before, body) in tricks.items():
        total += points(grade_id)
        try:
            run(grade_id, with_body(grade_id, body, before), **names_of(grade_id))
            scored += points(grade_id)
        except AssertionError:
            pass
    fits = [("00_tutorial-koch-fit", "my_fit = pixel_maps(koch_target)", "koch_target",
             ifslib.exercises.koch_target(64)),
            ("05_more_examples-carpet-fit", "my_carpet = pixel_maps(odd_carpet)", "odd_carpet",
             ifslib.exercises.carpet_target(64))]
    guesses = [("00_tutorial-koch-t3", "T3 = [[1 / 3, 0, 0], [0, 1 / 3, 0], [0, 0, 1]]"),
               ("00_tutorial-scaled-distance", "distance_to_copy = 0.5"), (BOX, "d_by_hand = 1.5")]
    for grade_id, answer, *target in fits + [(g, a) for g, a in guesses]:
        total += points(grade_id)
        names = {"pixel_maps": pixel_maps, **({target[0]: target[1]} if target else {})}
        try:
            run(grade_id, answer, **names)
            scored += points(grade_id)
        except AssertionError:
            pass
    assert total == 32 and scored == 0, (scored, total)


# -- the harness ---------------------------------------------------------------------------------

def test_every_place_the_library_is_switched_off_exists():
    # a route renamed in the library would silently stay on (the harness skips what it cannot find)
    for exercise, places in harness.LIBRARY.items():
        assert len(harness._originals(exercise)) == len(places), exercise


def test_the_library_list_is_read_only():
    with pytest.raises(TypeError):
        harness.LIBRARY["iou"] = ()
    assert all(isinstance(places, tuple) for places in harness.LIBRARY.values())


def test_a_switched_off_function_raises_however_it_is_reached_and_comes_back():
    hausdorff = ifslib.metrics.hausdorff
    a, b = np.zeros((1, 2)), np.array([[3.0, 4.0]])

    class Holder:
        method = staticmethod(hausdorff)

    routes = [hausdorff, ifslib.core.scoring.metrics.hausdorff, functools.partial(hausdorff), Holder.method,
              {"h": hausdorff}["h"], [hausdorff][0], lambda x, y, f=hausdorff: f(x, y),
              functools.wraps(hausdorff)(lambda x, y: hausdorff(x, y))]
    code = hausdorff.__code__
    with harness.library_off("Hausdorff distance"):
        for route in routes:
            with pytest.raises(harness.WriteItYourself, match="ifslib.core.scoring.metrics.hausdorff"):
                route(a, b)
    assert hausdorff.__code__ is code and all(route(a, b) == 5.0 for route in routes)


def test_methods_are_switched_off_on_every_instance_and_bound_method():
    koch = ifslib.patterns.koch()
    bound = koch.n_leaves
    with harness.library_off("leaf count"):
        for call in (bound, ifslib.patterns.sierpinski_carpet().n_leaves, lambda: ifslib.IFS.n_leaves(koch)):
            with pytest.raises(harness.WriteItYourself, match="IFS.n_leaves"):
                call()
    assert bound() == 4 ** koch.depth


def test_another_ifslib_function_that_uses_a_switched_off_one_raises_too():
    # strict on purpose: IFS.scales calls singular_values, depth_to_attractor calls hausdorff, so the
    # library cannot compute the answer through a side door; no worked answer calls such a function
    # (the helpers they use stay on: the next test)
    with harness.library_off("contraction and fixed point"):
        with pytest.raises(harness.WriteItYourself):
            ifslib.patterns.koch().scales()
    with harness.library_off("collage distance"):   # depth_to_attractor is not listed there
        with pytest.raises(harness.WriteItYourself, match="hausdorff"):
            ifslib.metrics.depth_to_attractor(ifslib.patterns.koch(), [1], points=1000)


def test_the_helpers_the_worked_answers_use_stay_on():
    target = ifslib.load_target(ifslib.patterns.koch(), 32)
    with harness.library_off("best-fit-line start"):
        assert len(ifslib.initialization.foreground_points(target)) > 0
        assert ifslib.patterns.koch().n_points == 5
    with harness.library_off("chamfer"):
        ifslib.load_target(ifslib.patterns.koch(), 32)


def test_a_builtin_is_replaced_where_it_is_kept_and_in_the_answers_globals():
    import scipy.spatial._hausdorff as cython

    original = cython.directed_hausdorff
    namespace = {"dh": original}
    exec("def answer(a, b):\n    return dh(a, b, None)", namespace)
    with harness.library_off("Hausdorff distance", namespace["answer"]):
        assert cython.directed_hausdorff is not original and namespace["dh"] is not original
        with pytest.raises(harness.WriteItYourself):
            namespace["answer"](np.zeros((1, 2)), np.ones((1, 2)))
    assert cython.directed_hausdorff is original and namespace["dh"] is original


def test_everything_is_restored_when_the_answer_raises_and_when_blocks_nest_or_overlap():
    hausdorff, collage = ifslib.metrics.hausdorff, ifslib.core.scoring.collage.collage_distance
    codes = hausdorff.__code__, collage.__code__
    with pytest.raises(ZeroDivisionError):
        with harness.library_off("Hausdorff distance"):
            1 / 0
    assert (hausdorff.__code__, collage.__code__) == codes
    outer = harness.library_off("Hausdorff distance")
    inner = harness.library_off("collage distance")
    outer.__enter__()
    inner.__enter__()
    outer.__exit__(None, None, None)   # the outer block ends first: hausdorff stays off for the inner one
    assert hausdorff.__code__ is not codes[0] and collage.__code__ is not codes[1]
    inner.__exit__(None, None, None)
    assert (hausdorff.__code__, collage.__code__) == codes and not harness._ACTIVE


def test_two_threads_switching_the_same_function_off_leave_it_restored():
    hausdorff = ifslib.metrics.hausdorff
    code = hausdorff.__code__
    barrier = threading.Barrier(4)
    errors = []

    def student():
        try:
            barrier.wait()
            for _ in range(50):
                got = harness.run_answer(lambda a, b: float(np.abs(a - b).max()), "Hausdorff distance",
                                         np.zeros((1, 2)), np.ones((1, 2)))
                assert got == 1.0
        except BaseException as exc:  # noqa: BLE001  reported below
            errors.append(exc)

    threads = [threading.Thread(target=student) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and hausdorff.__code__ is code and not harness._ACTIVE


def test_a_switched_off_closure_keeps_its_closure():
    # a function with free variables takes code with the same free variables (CPython checks their number)
    def make():
        scale = 2.0

        def scaled(x):
            return scale * x
        return scaled

    scaled = make()
    module = types.ModuleType("lazy_closure_probe")
    module.scaled = scaled
    sys.modules[module.__name__] = module
    try:
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr(harness, "LIBRARY", types.MappingProxyType(
                {**harness.LIBRARY, "probe": (("lazy_closure_probe", "scaled"),)}))
            with harness.library_off("probe"):
                with pytest.raises(harness.WriteItYourself):
                    scaled(1.0)
        assert scaled(1.0) == 2.0
    finally:
        del sys.modules[module.__name__]
