#!/usr/bin/env bash
# The wheel a student installs runs every notebook of the student edition from a folder outside the
# repository: build the wheel, install it into a fresh venv with torch (constraints.txt: this machine's
# local CPU wheel) and requirements-student.txt, copy build/student (make student) to a temporary folder
# and run each notebook there with that venv's kernel (course/run_edition.py).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=.venv/bin/python
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
[ -d build/student ] || { make setup-grading && "$PY" notebooks/student.py build/student; }  # nbgrader writes it
"$PY" -m pip wheel --quiet --no-deps -w "$work/dist" .
"$("$PY" -c 'import sys; print(sys._base_executable)')" -m venv "$work/venv"
"$work/venv/bin/python" -m pip install --quiet -c constraints.txt "torch==2.13.0" "$work"/dist/ifslib-*.whl \
    -r requirements-student.txt
mkdir "$work/class"
cp -r build/student/. "$work/class/"
cp course/run_edition.py "$work/"
cd "$work/class"
# nothing of the repository on the path: the kernel imports the installed wheel, targets included
export PYTHONPATH= IFSLIB_THREADS=1
"$work/venv/bin/python" -c "import ifslib; e = ifslib.exercises; assert 'site-packages' in ifslib.__file__; \
e.koch_target(64); print('ifslib from', ifslib.__file__)"
"$work/venv/bin/python" "$work/run_edition.py" "$work/class"
