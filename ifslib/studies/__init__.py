"""Studies: many fits run and summarized (the convergence sweep). Imports from every folder above."""
