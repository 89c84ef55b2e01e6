"""A lazy student's submission (issue 53): the release with each auto-graded exercise answered the laziest way.

    python course/lazy_submission.py build/course/release/lecture2 build/lazy/lecture2   # one assignment

`write_lazy` copies the released notebooks and puts each code answer of `LAZY` in place of nbgrader's
stub (``...  # YOUR CODE HERE``), at the stub's indentation, its ``before`` lines at the top of the
cell: the library's own function (called, or held in a ``functools.partial``, a list, a dict, a class
attribute), the target picture itself as the fit (one tiny map per pixel), a number guessed or read
off the lesson's printed output, a copy of what the notebook already holds, an answer made to pass
the visible test alone. The written answers (markdown) stay unanswered, and so do the exercises of
`UNANSWERED` (none thought of). ``course/grading.py --check`` autogrades this submission with
nbgrader and fails unless it scores 0.
"""
from __future__ import annotations

import argparse
import shutil
import sys
from pathlib import Path
from typing import NamedTuple

import nbformat

#: nbgrader's stub for a cleared code answer (course/nbgrader_config.py's ``ClearSolutions.code_stub``).
STUB = "...  # YOUR CODE HERE"


class Lazy(NamedTuple):
    """A lazy answer: ``body`` in place of the stub, ``before`` at the top of the answer cell."""

    body: str
    before: str = ""


PIXEL_MAPS = ("from ifslib.core.targets.target import foreground_points\n"
              "{name} = ifslib.patterns.affine([[[0.002, 0, x], [0, 0.002, y]]\n"
              "                                 for x, y in foreground_points({target})], depth=1)")
AFFINE = "ifslib.patterns.affine"

#: grade_id of the answer cell -> the lazy answer, one trick each (the comment above it).
LAZY: dict[str, Lazy] = {
    # -- 00, the tutorial
    # the library's own Koch curve on the unit segment (patterns.koch_unit) holds T3: read it off
    "00_tutorial-koch-t3": Lazy("T3 = ifslib.patterns.koch_unit().maps().detach().double().numpy()[2]"),
    # IFS.n_leaves counts the leaves: an IFS of m dummy maps
    "00_tutorial-carpet-leaves": Lazy(
        f"return {AFFINE}([[[0.3, 0, 0], [0, 0.3, 0]]] * m).n_leaves(depth) * primitives"),
    # IFS.scales gives the contraction factor
    "00_tutorial-contraction": Lazy(
        "M = np.asarray(M, float)\n"
        f"s = float({AFFINE}(M[None, :2]).scales()[0])\n"
        "return s, np.linalg.solve(np.eye(2) - M[:2, :2], M[:2, 2])"),
    # the library's chaos game, held in a functools.partial in a global
    "00_tutorial-chaos-game": Lazy(f"return GAME({AFFINE}(maps[:, :2]), n, seed=seed)",
                                   "import functools\nGAME = functools.partial(ifslib.chaos_game)\n"),
    # scipy's directed Hausdorff distance, both ways
    "00_tutorial-hausdorff": Lazy("return max(directed_hausdorff(a, b)[0], directed_hausdorff(b, a)[0])",
                                  "from scipy.spatial.distance import directed_hausdorff\n"),
    # the number the statement gives, as if T kept distances
    "00_tutorial-scaled-distance": Lazy("distance_to_copy = 0.3"),
    # the library's Hausdorff distance, held in a list
    "00_tutorial-collage": Lazy(
        "return H[0](points, np.concatenate([points @ M[:2, :2].T + M[:2, 2] for M in maps]))",
        "H = [ifslib.metrics.hausdorff]\n"),
    # the library's multiscale MSE, held as a class attribute
    "00_tutorial-loss": Lazy("return T.loss(image, target, 5)",
                             "class T:\n    loss = staticmethod(ifslib.losses.multiscale_mse)\n"),
    # the library's best-fit line, held in a list
    "00_tutorial-best-fit-line": Lazy(
        "centre, direction, lo, hi = LINE[0](target)\n"
        "return centre + np.linspace(lo, hi, pattern.n_points)[:, None] * direction",
        "from ifslib.core.targets.placement import best_fit_line\nLINE = [best_fit_line]\n"),
    # the target picture itself as the fit: one tiny map onto each of its pixels
    "00_tutorial-koch-fit": Lazy(PIXEL_MAPS.format(name="my_fit", target="koch_target")),
    # -- 01, Koch's iterations
    # the library's compositions of every word of the word's length, the word's one picked out
    "01_koch_iterations-leaf-map": Lazy(
        "from ifslib.core.geometry.leaves import compose_words\n"
        "words = compose_words(torch.as_tensor(np.asarray(maps, float)), len(word))\n"
        "return words[int(np.ravel_multi_index([i - 1 for i in word], (len(maps),) * len(word)))].numpy()"),
    # the visible test's two answers, hard-coded
    "01_koch_iterations-depth-needed": Lazy("return 3 if d0 > tol else 0"),
    # read off the lesson's printed table (512 px: 0.49 px at depth 5), though the statement asks for
    # a poster 16 times as wide
    "01_koch_iterations-koch-depth": Lazy("koch_depth = 5"),
    # -- 02, the fitting gallery
    # IoU from the library's F1 (IoU = F1 / (2 - F1))
    "02_fitting_gallery-iou": Lazy("f = ifslib.f1(np.asarray(p, bool), np.asarray(q, bool))\nreturn f / (2 - f)"),
    # guessed: no pixel shared, each pixel's neighbour one away (the line's two ends forgotten)
    "02_fitting_gallery-shifted-line": Lazy("shifted_iou = 0.0\nshifted_chamfer = 1.0\non_the_line = \"chamfer\""),
    # the library's scores hold the Chamfer distance
    "02_fitting_gallery-chamfer": Lazy(
        "return ifslib.metrics.scores(np.asarray(p, bool), np.asarray(q, bool))['chamfer']"),
    # -- 03, gradient fields
    # the landscape's own alignment
    "03_gradient_fields-alignment": Lazy("return ifslib.landscape.alignment(field, true)"),
    # a copy of the near grid's shares, which the notebook already holds (graded at 128 px, where the
    # pixel loss's far share, 0.75, is neither the near one nor 1)
    "03_gradient_fields-further-out": Lazy(
        "far_share = {kind: scores[kind][1] for kind in (\"pixel\", \"distance\")}"),
    # -- 04, local minima
    # the notebook's own test of a stalled run (section "Which runs stalled?"), copied, its factor 10 kept
    "04_local_minima-stalled": Lazy("return loss > 10 * best_loss and chamfer > limit"),
    # the library's crossing test of the crossing penalty
    "04_local_minima-segments-cross": Lazy(
        "segments = torch.tensor(np.array([[a, b], [c, d]], float))\nreturn len(crossing_pairs(segments)[0]) > 0",
        "from ifslib.core.geometry.crossings import crossing_pairs\n"),
    # the library's crossing pairs of the polyline's segments
    "04_local_minima-count-crossings": Lazy(
        "p = torch.tensor(np.asarray(points, float))\nreturn len(crossing_pairs(torch.stack([p[:-1], p[1:]], 1))[0])",
        "from ifslib.core.geometry.crossings import crossing_pairs\n"),
    # -- 05, more examples
    # the target picture itself as the fit
    "05_more_examples-carpet-fit": Lazy(PIXEL_MAPS.format(name="my_carpet", target="odd_carpet")),
    # -- 06, the convergence study
    # the paper's cut rotation, as the statement prints it
    "06_convergence_study-rotation": Lazy(
        "return torch.tensor([[torch.cos(theta), -torch.sin(theta)],\n"
        "                     [torch.sin(theta), torch.cos(theta)]])"),
    # scipy's Wilson interval (binomtest), at the confidence of z (switched off while the test runs it)
    "06_convergence_study-wilson": Lazy(
        "from scipy.stats import binomtest, norm\n\n"
        "ci = binomtest(k, n).proportion_ci(2 * norm.cdf(z) - 1, method=\"wilson\")\n"
        "return ci.low, ci.high"),
    # the textbook rule n = z² p (1 - p) / h² = 42.7, up to the next even number
    "06_convergence_study-seeds-needed": Lazy("seeds_needed = 44"),
    # -- 07, your own image
    # the notebook's automatic start and fit, told to use 2 maps
    "07_your_own_image-two-maps": Lazy(
        "my_two_maps = ifslib.fit(ifslib.initialize(\"auto\", two_maps, maps=2), two_maps, steps=steps,\n"
        "                         progress=False).best"),
    # the search's own moment maps (figure's mean and covariance onto the region's), unclipped (switched off)
    "07_your_own_image-copy-map": Lazy(
        "from ifslib.automatic.fractal.regions import moment_maps\n"
        "return moment_maps(points, part, angles=1, scales=(0.0, np.inf))[0]"),
    # -- 08, real fractals
    # the library's Hausdorff distance
    "08_real_fractals-collage": Lazy(
        "copies = np.concatenate([points @ m[:, :2].T + m[:, 2] for m in np.asarray(maps, float)])\n"
        "return ifslib.metrics.hausdorff(np.asarray(points, float), copies)"),
    # the two answers the statement asks for (0.04 and 0.001), hard-coded
    "08_real_fractals-choose-maps": Lazy("return 3 if cost >= 0.04 else 6"),
    # -- 09, measures and dimension
    # the library's Moran solver
    "09_measures_and_dimension-moran-code": Lazy("return ifslib.dimension.similarity_dimension(scales)"),
    # a guessed dimension
    "09_measures_and_dimension-box-by-hand": Lazy("d_by_hand = 1.5"),
    # Barnsley's probabilities, which the notebook holds (fitted back in its section 3), though the
    # statement asks for a stem at least twice as heavy as theirs
    "09_measures_and_dimension-fern-stem": Lazy("my_probabilities = BARNSLEY"),
    # -- 10, fractal compression
    # numpy's line fit, the visible test's own reference
    "10_fractal_compression-least-squares": Lazy("return tuple(np.polyfit(d, r, 1))"),
    # made to pass the visible test alone: no change when the contrasts contract, 2 otherwise
    "10_fractal_compression-contraction": Lazy(
        "return [0.0 if float(abs(s).max()) < 1 else 2.0] * iterations"),
    # the library's own counts: split_flag_count, and Code.bits for the rest (switched off)
    "10_fractal_compression-bits": Lazy(
        "from ifslib.compression.code import split_flag_count\n\n"
        "flags, maps = split_flag_count(code), 12 * len(code)\n"
        "isometries = 3 * int((~code.flat).sum())\n"
        "return {\"header\": 120, \"flags\": flags, \"s and m\": maps, \"isometries\": isometries,\n"
        "        \"domains\": code.bits() - flags - maps - isometries,\n"
        "        \"padding\": 8 * len(to_bytes(code)) - 120 - code.bits()}"),
    # -- 11, the learned guess
    # the library's own matching (the set loss's)
    "11_learned_guess-pairing": Lazy(
        "rows, cols = match(torch.as_tensor(np.asarray(guessed, float)), torch.as_tensor(np.asarray(true, float)))\n"
        "return [int(r) for _, r in sorted(zip(cols, rows))]"),
}

#: Exercises whose lazy answer no one has thought of: they keep the blank stub.
UNANSWERED: tuple[str, ...] = ()


def grade_id(cell) -> str | None:
    return cell.metadata.get("nbgrader", {}).get("grade_id")


def is_code_answer(cell) -> bool:
    return cell.cell_type == "code" and bool(cell.metadata.get("nbgrader", {}).get("solution"))


def answered(source: str, lazy: Lazy) -> str:
    """``source`` (a released answer cell) with ``lazy`` in place of its one stub line."""
    lines = source.split("\n")
    where = [i for i, line in enumerate(lines) if line.strip() == STUB]
    if len(where) != 1:
        raise ValueError(f"an answer cell holds {len(where)} stub lines ({STUB!r}), not one:\n{source}")
    indent = lines[where[0]][:len(lines[where[0]]) - len(lines[where[0]].lstrip())]
    body = [indent + line if line else line for line in lazy.body.split("\n")]
    return lazy.before + "\n".join(lines[:where[0]] + body + lines[where[0] + 1:])


def lazy_notebook(book, table: dict[str, Lazy] = LAZY) -> list[str]:
    """Fill ``book``'s code answers named in ``table`` (in place); returns their grade ids."""
    filled = []
    for cell in book.cells:
        if is_code_answer(cell) and grade_id(cell) in table:
            cell.source = answered(cell.source, table[grade_id(cell)])
            filled.append(grade_id(cell))
    return filled


def write_lazy(release: Path, out: Path, table: dict[str, Lazy] = LAZY) -> list[str]:
    """Copy the release folder to ``out`` (replaced) with the lazy answers; returns the grade ids filled."""
    if out.exists():
        shutil.rmtree(out)
    shutil.copytree(release, out)
    filled = []
    for path in sorted(out.glob("*.ipynb")):
        book = nbformat.read(path, as_version=4)
        done = lazy_notebook(book, table)
        if done:
            nbformat.write(book, path)
            filled += done
    return filled


def passed_tests(gradebook: Path, assignment: str, student: str) -> list[str]:
    """The test cells (grade ids) that gave ``student`` every one of their points, from nbgrader's gradebook."""
    from nbgrader.api import Gradebook

    with Gradebook(f"sqlite:///{gradebook}") as book:
        return [grade.name for notebook in book.find_submission(assignment, student).notebooks
                for grade in notebook.grades
                if grade.cell_type == "code" and grade.max_score and (grade.auto_score or 0) >= grade.max_score]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("release", type=Path, help="the released assignment folder (course/release/lecture2, ...)")
    parser.add_argument("out", type=Path, help="the submission folder to write (replaced)")
    args = parser.parse_args(argv)
    filled = write_lazy(args.release, args.out)
    print(f"{len(filled)} answers filled lazily in {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
