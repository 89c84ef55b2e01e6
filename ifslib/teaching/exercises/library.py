"""Which library functions each exercise switches off while a student's function runs (`LIBRARY`), and what
it may call (`ALLOWED`); what an answer may not name is the grader's (``course/notebook_scan.py``)."""
from __future__ import annotations

import types

#: For each exercise that asks for a function a library has: where it is kept (module, attribute; a
#: method or property as ``Class.attribute``). Each is switched off however it is reached while the
#: student's function runs (see `library_off`), the ifslib functions that compute the same thing too.
LIBRARY = {
    "chaos game": [("ifslib", "chaos_game"), ("ifslib.core.raster.chaos", "chaos_game"),
                   ("ifslib.core.raster.chaos", "chaos_window"), ("ifslib.core.raster.chaos", "_points"),
                   ("ifslib.core.geometry.sampled", "sample_attractor"),
                   ("ifslib.core.geometry.expand", "sample_attractor"),
                   ("ifslib.core.geometry.attractor", "attractor_leaves")],
    "Hausdorff distance": [("ifslib.core.scoring.metrics", "hausdorff"),
                           ("ifslib.core.scoring.metrics", "depth_to_attractor"),
                           ("scipy.spatial.distance", "directed_hausdorff"),
                           ("scipy.spatial._hausdorff", "directed_hausdorff")],
    "collage distance": [("ifslib.core.scoring.metrics", "hausdorff"), ("ifslib.core.scoring.collage", "collage_distance"),
                         ("scipy.spatial.distance", "directed_hausdorff"),
                         ("scipy.spatial._hausdorff", "directed_hausdorff")],
    "contraction and fixed point": [("ifslib.core.geometry.rules", "singular_values"),
                                    ("ifslib.core.geometry.rules", "map_scales"),
                                    ("ifslib.core.geometry.ifs", "IFS.scales"),
                                    ("ifslib.measures.dimension", "ifs_scales")],
    "loss": [("ifslib", "loss"), ("ifslib.core.scoring.losses", "loss"), ("ifslib.core.scoring.losses", "mse"),
             ("ifslib.core.scoring.losses", "multiscale_mse"), ("ifslib.core.scoring.losses", "pyramid")],
    "best-fit-line start": [("ifslib", "initialize"), ("ifslib", "best_fit_line"),
                            ("ifslib.core.targets.placement", "initialize"),
                            ("ifslib.core.targets.placement", "best_fit_line"),
                            ("ifslib.core.targets.placement", "placed_points")],
    "leaf map": [("ifslib", "expand"), ("ifslib.core.geometry.leaves", "expand"),
                 ("ifslib.core.geometry.leaves", "compose_words"), ("ifslib.core.geometry.attractor", "word_maps")],
    "leaf count": [("ifslib", "expand"), ("ifslib.core.geometry.leaves", "expand"),
                   ("ifslib.core.geometry.ifs", "IFS.n_leaves"), ("ifslib.core.geometry.leaves", "leaf_count_text")],
    "depth": [("ifslib.core.scoring.metrics", "depth_to_attractor")],
    "iou": [("ifslib", "iou"), ("ifslib.core.scoring.metrics", "iou"), ("ifslib.core.scoring.metrics", "f1"),
            ("ifslib.core.scoring.metrics", "scores")],
    "chamfer": [("ifslib", "chamfer"), ("ifslib.core.scoring.metrics", "chamfer"), ("ifslib.core.scoring.metrics", "scores")],
    "alignment": [("ifslib.teaching.landscape", "alignment")],
    "segments cross": [("ifslib.core.geometry.crossings", "crossing_pairs"),
                       ("ifslib.core.geometry.crossings", "crossing_depths"),
                       ("ifslib.core.geometry.crossings", "crossing_penalty"),
                       ("ifslib.core.scoring.metrics", "crossing_points"), ("ifslib.core.scoring.metrics", "self_crossings")],
    "crossing count": [("ifslib.core.geometry.crossings", "crossing_pairs"),
                       ("ifslib.core.geometry.crossings", "crossing_depths"),
                       ("ifslib.core.geometry.crossings", "crossing_penalty"),
                       ("ifslib.core.scoring.metrics", "crossing_points"), ("ifslib.core.scoring.metrics", "self_crossings")],
    "similarity dimension": [("ifslib.measures.dimension", "similarity_dimension"),
                             ("ifslib.measures.dimension", "ifs_similarity_dimension")],
    # scipy's binomial test gives the interval (proportion_ci(method="wilson")); ifslib computes none
    "Wilson interval": [("scipy.stats", "binomtest"), ("scipy.stats._binomtest", "binomtest"),
                        ("scipy.stats._binomtest", "BinomTestResult.proportion_ci"),
                        ("scipy.stats._binomtest", "_binom_wilson_conf_int")],
    # the fractal search's copies matched by moments, and the shape starts' (one per k-means part)
    "copy map": [("ifslib.automatic.fractal.regions", "moment_maps"), ("ifslib.automatic.auto", "shape_maps")],
    # exercises whose library equivalent is only the watch's (no module of ifslib may be called)
    "stalled": [], "choose maps": [], "least squares": [],
    "rotation": [("ifslib.splatting.parameters", "_rotation")],
    "largest changes": [],
    # the set loss's Hungarian matching (scipy's linear_sum_assignment is the tool the exercise asks for)
    "pairing": [("ifslib.learned.set_loss", "match"), ("ifslib.learned.set_loss", "set_loss")],
    # the quadtree's flags, and the flags and maps' bits together
    "bit budget": [("ifslib.compression.code", "split_flag_count"), ("ifslib.compression.code", "Code.bits")],
}
# read-only, so that an answer cell cannot empty an exercise's list (LIBRARY["iou"] = [])
LIBRARY = types.MappingProxyType({exercise: tuple(places) for exercise, places in LIBRARY.items()})

#: The modules of ifslib a student's function may call while its test runs (what its inputs are made of:
#: a target's pixels, a pattern's point count, a compressed code's fields); every other module of ifslib
#: is refused while it runs (`run_answer`), whatever route reaches it.
ALLOWED = types.MappingProxyType({
    "best-fit-line start": frozenset({"ifslib.core.targets", "ifslib.core.geometry.ifs",
                                      "ifslib.core.raster.nearest"}),
    "bit budget": frozenset({"ifslib.compression.code", "ifslib.compression.domains",
                             "ifslib.compression.config", "ifslib.compression.quantize"}),
    # the exercise asks for a loop over the decoder's pass (iterate_offset) and its plan
    "largest changes": frozenset({"ifslib.compression"}),
})
