#!/usr/bin/env bash
# nbgrader itself: the tests marked `grading` (make test leaves them out), then nbgrader grades the course as
# it is released: lay out build/course from notebooks/ at their teaching values (each with its locked grading
# cell: course/grading_run.py), `nbgrader generate_assignment`, then `nbgrader autograde` the instructor's
# source (every auto-graded point; the written answers left for manual grading) and the blank release
# (0 points), printing how long each student's autograde took.
set -euo pipefail
cd "$(dirname "$0")/.."
make setup-grading
IFSLIB_THREADS=1 .venv/bin/python -m pytest tests -q -p no:cacheprovider -m grading
IFSLIB_THREADS=1 .venv/bin/python course/grading.py build/course --check
