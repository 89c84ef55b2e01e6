"""What the notebooks' exercise tests may import: the harness that runs a student's function, and the targets.

The answers, the reference functions and the truths behind the fit targets are not here: they live
in the instructor's notebooks (nbgrader's solution regions and hidden tests) and in
``course/targets.py``. A test cell of a notebook calls `run_answer` to run the student's function
with the library's own one switched off, and raises ``AssertionError`` with a hint on a wrong answer:

* `run_answer` refuses the library's function handed in as the answer (directly, through
  ``functools.partial``, a wrapper, a closure or a default argument) and, while the student's
  function runs, switches the library's functions for that exercise (`LIBRARY`: the function asked
  for and the library's others that compute the same thing) off at their root: each one's code is
  swapped for code that raises `WriteItYourself`, so it raises however it is reached (a global, a
  class attribute, a dict, a ``functools.partial``, another library function that calls it), and
  is restored when the student's function returns or raises;
* `koch_target`, `carpet_target` and `two_map_target` read pictures shipped with the package
  (``targets/*.png``): a student fits the picture; the maps that drew it are not installed.
"""
import importlib

from .library import ALLOWED, BANS  # plain tables: nbgrader's own process reads them without torch

# The harness and the targets load torch: imported on first use, so that the grader's scan of a
# submission (course/nbgrader_checks.py, with `integrity` and `BANS`) starts without it.
_LAZY = {name: "harness" for name in ("LIBRARY", "WriteItYourself", "as_matrix", "as_number", "library_off",
                                      "plain", "random_maps", "run_answer")}
_LAZY.update({name: "targets" for name in ("SIZES", "koch_target", "carpet_target", "two_map_target")})


def __getattr__(name: str):
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    globals()[name] = value
    return value


__all__ = ["LIBRARY", "ALLOWED", "BANS", "plain", "WriteItYourself", "library_off", "run_answer", "as_matrix", "as_number", "random_maps",
           "SIZES", "koch_target", "carpet_target", "two_map_target"]
