"""Studies: many fits run and summarized (the convergence sweep). Imports from every folder above."""
from .. import threads as _threads  # noqa: F401 - torch's thread count is set before this folder computes
