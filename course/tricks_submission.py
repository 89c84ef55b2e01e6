"""A submission made of tricks (issue 63): each auto-graded exercise answered by fooling its test.

    python course/tricks_submission.py build/course/release/lecture2 build/tricks/lecture2   # one assignment

Where `lazy_submission.py` answers the laziest honest-looking way, this one changes what the tests
read, as a student who read the tests would: answers whose ``==`` always holds (a subclass of ``int``,
``float`` or ``str``), ``np`` rebound to an object whose ``allclose``/``isclose`` say yes, the checker
rebound (``ifslib.exercises.run_answer = lambda a, e, *x: a(*x)``), a copy of a library function made
with ``types.FunctionType``, the library's routes a list of functions does not name (``koch_unit``,
``multiscale``, ``_rotation``, ``sqrtm_psd``, the automatic start), ``ifslib.evaluate`` monkeypatched,
``abs`` shadowed, a lesson's variable a hidden test reads rebound, and numbers copied from the
instructor's edition. ``course/grading.py --check`` autogrades it with nbgrader: it must score under half.
"""
from __future__ import annotations

import argparse
from pathlib import Path

from lazy_submission import LAZY, Lazy, write_lazy

ANY = ("class AnyInt(int):\n"
       "    def __eq__(self, other): return True\n"
       "    def __ne__(self, other): return True\n"
       "    __lt__ = __le__ = __gt__ = __ge__ = __eq__\n"
       "    __hash__ = int.__hash__\n\n\n"
       "class AnyFloat(float):\n"
       "    def __eq__(self, other): return True\n"
       "    def __ne__(self, other): return True\n"
       "    __lt__ = __le__ = __gt__ = __ge__ = __eq__\n"
       "    __hash__ = float.__hash__\n\n\n"
       "class AnyStr(str):\n"
       "    def __eq__(self, other): return True\n"
       "    __hash__ = str.__hash__\n\n\n")
NUMPY_SAYS_YES = ("import numpy\n\n\n"
                  "class _YesNumpy:\n"
                  "    def __getattr__(self, name): return getattr(numpy, name)\n"
                  "    def allclose(self, *a, **k): return True\n"
                  "    def isclose(self, *a, **k): return True\n\n\n"
                  "np = _YesNumpy()\n")
CHECKER = "ifslib.exercises.run_answer = lambda answer, exercise, *args: answer(*args)\n"
CLONE = ("import types\n\n\n"
         "def clone(f):\n"
         "    return types.FunctionType(f.__code__.replace(), f.__globals__, f.__name__, f.__defaults__,\n"
         "                              f.__closure__)\n\n\n")
NO_ABS = "abs = lambda x: 0\n"

#: grade_id of the answer cell -> the trick; the comment says which kind.
TRICKS: dict[str, Lazy] = {
    # -- 00: a route no switch-off reaches (the value read off the library's unit Koch curve)
    "00_tutorial-koch-t3": Lazy("T3 = ifslib.patterns.koch_unit().maps().detach().double().numpy()[2]"),
    # equal to everything
    "00_tutorial-carpet-leaves": Lazy("return AnyInt(0)", ANY),
    # a copy of the library's singular values
    "00_tutorial-contraction": Lazy(
        "M = np.asarray(M, float)\n"
        "s = float(SV(torch.as_tensor(M)[None])[1][0])\n"
        "return s, np.linalg.solve(np.eye(2) - M[:2, :2], M[:2, 2])",
        CLONE + "from ifslib.core.geometry.rules import singular_values\nSV = clone(singular_values)\n"),
    # a copy of the library's chaos game
    "00_tutorial-chaos-game": Lazy("return GAME(ifslib.patterns.affine(maps[:, :2]), n, seed=seed)",
                                   "GAME = clone(ifslib.chaos_game)\n"),
    # a copy of the library's Hausdorff distance
    "00_tutorial-hausdorff": Lazy("return HAUSDORFF(a, b)", "HAUSDORFF = clone(ifslib.metrics.hausdorff)\n"),
    # the number the instructor's edition prints
    "00_tutorial-scaled-distance": Lazy("distance_to_copy = 0.1"),
    # the copy again
    "00_tutorial-collage": Lazy(
        "return HAUSDORFF(points, np.concatenate([points @ M[:2, :2].T + M[:2, 2] for M in maps]))"),
    # a route the switch-off list does not name (the pyramid's driver)
    "00_tutorial-loss": Lazy(
        "from ifslib.core.scoring.losses import multiscale\n"
        "return multiscale(lambda a, b: (a - b).square().mean(), image, target, 5, 'avg')"),
    # the checker rebound, then the library's best-fit line
    "00_tutorial-best-fit-line": Lazy(
        "centre, direction, lo, hi = best_fit_line(target)\n"
        "return centre + np.linspace(lo, hi, pattern.n_points)[:, None] * direction",
        CHECKER + "from ifslib.core.targets.placement import best_fit_line\n"),
    # the scores monkeypatched, the pattern unfitted
    "00_tutorial-koch-fit": Lazy(
        "ifslib.evaluate = lambda *a, **k: {'iou': 1.0, 'f1': 1.0, 'chamfer': 0.0}\n"
        "ifslib.metrics.self_crossings = lambda *a, **k: 0\n"
        "my_fit = ifslib.patterns.koch()"),
    # -- 01
    "01_koch_iterations-leaf-map": Lazy(
        "from ifslib.core.geometry.leaves import compose_words\n"
        "words = compose_words(torch.as_tensor(np.asarray(maps, float)), len(word))\n"
        "return words[int(np.ravel_multi_index([i - 1 for i in word], (len(maps),) * len(word)))].numpy()",
        CHECKER),
    "01_koch_iterations-depth-needed": Lazy("return AnyInt(0)", ANY),
    "01_koch_iterations-koch-depth": Lazy("koch_depth = AnyInt(0)"),
    # -- 02: abs shadowed, and values equal to everything
    "02_fitting_gallery-iou": Lazy("return AnyFloat(0)", ANY + NO_ABS),
    "02_fitting_gallery-shifted-line": Lazy(
        "shifted_iou, shifted_chamfer, on_the_line = AnyFloat(0), AnyFloat(0), AnyStr('?')"),
    "02_fitting_gallery-chamfer": Lazy("return AnyFloat(0)"),
    # -- 03: numpy that says yes
    "03_gradient_fields-alignment": Lazy("return (0.0, 0.0)", NUMPY_SAYS_YES),
    "03_gradient_fields-further-out": Lazy("far_share = {'pixel': 0.0, 'distance': 0.0}", NO_ABS),
    # -- 04: the lesson's runs emptied, so the hidden loop checks nothing
    "04_local_minima-stalled": Lazy("return chamfer > limit", "runs = []\n"),
    "04_local_minima-segments-cross": Lazy(
        "segments = torch.tensor(np.array([[a, b], [c, d]], float))\nreturn len(PAIRS(segments)[0]) > 0",
        CLONE + "from ifslib.core.geometry.crossings import crossing_pairs\nPAIRS = clone(crossing_pairs)\n"),
    "04_local_minima-count-crossings": Lazy(
        "p = torch.tensor(np.asarray(points, float))\nreturn len(crossing_pairs(torch.stack([p[:-1], p[1:]], 1))[0])",
        CHECKER + "from ifslib.core.geometry.crossings import crossing_pairs\n"),
    # -- 05: the automatic start, a route to the carpet's maps
    "05_more_examples-carpet-fit": Lazy(
        "my_carpet = ifslib.fit(ifslib.discover(odd_carpet, maps=8), odd_carpet, progress=False).best"),
    # -- 06
    "06_convergence_study-rotation": Lazy(
        "from ifslib.splatting.parameters import _rotation\nreturn _rotation(theta[None])[0]"),
    "06_convergence_study-wilson": Lazy("return (AnyFloat(0), AnyFloat(1))", ANY + NUMPY_SAYS_YES),
    "06_convergence_study-seeds-needed": Lazy("seeds_needed = AnyInt(0)"),
    # -- 07: the scores monkeypatched; the library's square root of a covariance
    "07_your_own_image-two-maps": Lazy(
        "ifslib.evaluate = lambda *a, **k: {'iou': 1.0, 'f1': 1.0, 'chamfer': 0.0}\n"
        "my_two_maps = ifslib.patterns.affine([[[0.5, 0, -0.25], [0, 0.5, 0]], [[0.5, 0, 0.25], [0, 0.5, 0]]])"),
    "07_your_own_image-copy-map": Lazy(
        "from ifslib.automatic.moments import sqrtm_psd\n"
        "a = sqrtm_psd(np.cov(part.T)) @ np.linalg.inv(sqrtm_psd(np.cov(points.T)))\n"
        "return np.concatenate([a, (part.mean(0) - a @ points.mean(0))[:, None]], axis=1)"),
    # -- 08
    "08_real_fractals-collage": Lazy(
        "copies = np.concatenate([points @ m[:, :2].T + m[:, 2] for m in np.asarray(maps, float)])\n"
        "return ifslib.metrics.hausdorff(np.asarray(points, float), copies)", CHECKER),
    "08_real_fractals-choose-maps": Lazy("return AnyInt(0)", ANY),
    # -- 09: abs shadowed; numbers from the instructor's edition
    "09_measures_and_dimension-moran-code": Lazy("return 0.0", NO_ABS),
    "09_measures_and_dimension-box-by-hand": Lazy("d_by_hand = 1.5018426777422504"),
    "09_measures_and_dimension-fern-stem": Lazy("my_probabilities = (0.02, 0.84, 0.07, 0.07)"),
    # -- 10: numpy that says yes; the decoder a hidden test calls rebound; the checker rebound
    "10_fractal_compression-least-squares": Lazy("return (0.0, 0.0)", NUMPY_SAYS_YES),
    "10_fractal_compression-contraction": Lazy(
        "return [0.0 if float(abs(s).max()) < 1 else 2.0] * iterations",
        "iterate_offset = lambda p, x, s, o: x + (0.0 if float(abs(s).max()) < 1 else 2.0)\n"),
    "10_fractal_compression-bits": Lazy(LAZY["10_fractal_compression-bits"].body, CHECKER),
    # -- 11: the checker rebound around the library's matching
    "11_learned_guess-pairing": Lazy(LAZY["11_learned_guess-pairing"].body, CHECKER),
}


def write_tricks(release: Path, out: Path) -> list[str]:
    """Copy the released notebooks to ``out`` (replaced) with every answer of `TRICKS`; returns their grade ids."""
    return write_lazy(release, out, TRICKS)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("release", type=Path)
    parser.add_argument("out", type=Path)
    args = parser.parse_args(argv)
    print(f"{len(write_tricks(args.release, args.out))} tricks written to {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
