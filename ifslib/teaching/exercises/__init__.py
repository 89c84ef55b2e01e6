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
from .harness import LIBRARY, WriteItYourself, library_off
from .lessons import (carpet_target, check_carpet_fit, check_depth_needed, check_leaf_map, check_two_maps,
                      two_map_target, word_maps)
from .tutorial import (chaos_maps, check_best_fit_start, check_chaos_game, check_collage_distance, check_contraction,
                       check_hausdorff, check_koch_fit, check_koch_map, check_leaf_count, check_loss,
                       check_scaled_distance, collage_maps, contraction_maps, koch_map, koch_target)

__all__ = ["LIBRARY", "WriteItYourself", "library_off", "koch_map", "check_koch_map", "check_leaf_count",
           "contraction_maps", "check_contraction", "chaos_maps", "check_chaos_game", "check_hausdorff",
           "check_scaled_distance", "collage_maps", "check_collage_distance", "check_loss", "koch_target",
           "check_best_fit_start", "check_koch_fit", "word_maps", "check_leaf_map", "check_depth_needed",
           "carpet_target", "check_carpet_fit", "two_map_target", "check_two_maps"]
