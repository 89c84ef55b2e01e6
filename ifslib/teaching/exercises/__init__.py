"""What the notebooks' exercise tests may import: the harness that runs a student's function with the library's
own switched off (`run_answer`), and the targets (the truths behind them live in ``course/``)."""
import importlib

from .library import ALLOWED  # a plain table: nbgrader's own process reads it without torch

# The harness and the targets load torch: imported on first use, so that the grader's scan of a
# submission (course/nbgrader_checks.py, with `integrity`) starts without it.
_LAZY = {name: "harness" for name in ("LIBRARY", "WriteItYourself", "as_matrix", "as_number", "library_off",
                                      "plain", "random_maps", "run_answer")}
_LAZY.update({name: "targets" for name in ("SIZES", "koch_target", "carpet_target", "two_map_target")})


def __getattr__(name: str):
    if name not in _LAZY:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    globals()[name] = value
    return value


__all__ = ["LIBRARY", "ALLOWED", "plain", "WriteItYourself", "library_off", "run_answer", "as_matrix", "as_number", "random_maps",
           "SIZES", "koch_target", "carpet_target", "two_map_target"]
