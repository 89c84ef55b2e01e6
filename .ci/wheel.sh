#!/usr/bin/env bash
# The student path as a student takes it (docs/guide/start-here.md): build the wheel and write the
# students' folder with it (course/student_binder.py: the student edition, the wheel, binder/) in a
# temporary folder outside the repository; install a fresh venv from that folder as Binder does
# (torch first: constraints.txt's local CPU wheel, PyTorch's index being out of this machine's reach;
# then the folder's binder/requirements.txt from its root: the wheel by relative path and
# requirements-student.txt's packages, no Dask, no pytest, no nbgrader), then in that venv:
#   1. every module the student edition's code cells import, every module of the installed ifslib and
#      every module ifslib imports inside a function (its lazy imports) imports; an import guarded by
#      `except ImportError` is optional and left out (the sweep's Dask);
#   2. every notebook of the student edition runs whole at its quick values with that venv's kernel
#      (course/run_edition.py): no lesson cell needs a missing package or an exercise's answer;
#   3. every stored notebook runs again at its teaching values, the ones a student runs, in that venv's
#      kernel, and strict nbval compares it with what is stored (`make test-stored KERNEL=...`, the same
#      check as on the project's venv): the teaching values take code paths the quick ones do not
#      (notebook 06's "local" scheduler where the quick run's is "serial"). One run at the teaching
#      values (about 1,000 s) serves both checks, the stored outputs' and the students' venv's.
set -euo pipefail
cd "$(dirname "$0")/.."
repo="$(pwd)"
PY=.venv/bin/python
if [ -z "${IFSLIB_DATA:-}" ] && [ -d ../shared/data ]; then export IFSLIB_DATA="$(cd ../shared/data && pwd)"; fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
started=$SECONDS
make setup-grading  # nbgrader writes the student edition
"$PY" -m pip wheel --quiet --no-deps -w "$work/dist" .
"$PY" course/student_binder.py "$work/class" --wheel "$(ls "$work"/dist/ifslib-*.whl)"
"$("$PY" -c 'import sys; print(sys._base_executable)')" -m venv "$work/venv"
cp course/run_edition.py "$work/"
cd "$work/class"
"$work/venv/bin/python" -m pip install --quiet -c "$repo/constraints.txt" "torch==2.13.0"
grep -v '^--extra-index-url' binder/requirements.txt > "$work/requirements.txt"
"$work/venv/bin/python" -m pip install --quiet -c "$repo/constraints.txt" -r "$work/requirements.txt"
echo "wheel.sh: the students' folder written and its venv installed in $((SECONDS - started)) s"
# nothing of the repository on the path: the kernel imports the installed wheel, targets included
export PYTHONPATH= IFSLIB_THREADS=1
unset MPLBACKEND  # the student's inline backend
"$work/venv/bin/python" -c "import ifslib; e = ifslib.exercises; assert 'site-packages' in ifslib.__file__; \
e.koch_target(64); print('ifslib from', ifslib.__file__)"
# no Dask, as a student's pip install has none: notebook 06's "local" sweep takes the standard library's pool
"$work/venv/bin/python" -c "import importlib.util; assert importlib.util.find_spec('dask') is None, \
'dask is in the student venv, so notebook 06 would not run its sweep as a student does'"
step=$SECONDS
"$work/venv/bin/python" - <<'EOF'
"""Step 1: import what the student edition and ifslib import, in the student's venv; name what fails."""
import ast
import importlib
import pkgutil
import sys
from pathlib import Path

import nbformat
from IPython.core.inputtransformer2 import TransformerManager

import ifslib


def imports(tree, skip=frozenset()):
    """(module, name or None) of each absolute import under ``tree``, but those whose node id is in ``skip``."""
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            yield from ((alias.name, None) for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and not node.level:
            yield from ((node.module, None if alias.name == "*" else alias.name) for alias in node.names)


def guarded(tree):
    """Ids of the nodes inside a ``try`` that catches ImportError: imports that may fail by design."""
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Try) and any(h.type is None or "ImportError" in ast.unparse(h.type)
                                             for h in node.handlers):
            ids |= {id(inner) for statement in node.body for inner in ast.walk(statement)}
    return ids


wanted = {}
for path in sorted(Path(".").glob("*.ipynb")):
    for index, cell in enumerate(nbformat.read(path, as_version=4).cells):
        if cell.cell_type == "code":  # IPython's %magics and !shell lines made Python, as the kernel does
            for key in imports(ast.parse(TransformerManager().transform_cell(cell.source))):
                wanted.setdefault(key, f"{path.name}, cell {index}")
package = Path(ifslib.__file__).parent
for info in pkgutil.walk_packages(ifslib.__path__, "ifslib."):
    if not info.name.endswith("__main__"):  # `python -m ifslib` runs the CLI when imported
        wanted.setdefault((info.name, None), "the installed ifslib")
for path in sorted(package.rglob("*.py")):
    tree = ast.parse(path.read_text())
    skip = guarded(tree)
    for function in ast.walk(tree):
        if isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for key in imports(function, skip):
                wanted.setdefault(key, f"ifslib/{path.relative_to(package)}, {function.name}()")
failed = []
for (module, name), where in sorted(wanted.items(), key=str):
    try:
        found = importlib.import_module(module)
        if name is not None and not hasattr(found, name):
            importlib.import_module(f"{module}.{name}")
    except Exception as error:  # noqa: BLE001  every failure is reported, not only ImportError
        failed.append(f"    {module}{'.' + name if name else ''} (imported by {where}): {type(error).__name__}: {error}")
print(f"imports: {len(wanted) - len(failed)} of {len(wanted)} import in the student venv "
      "(the student edition's cells, every module of ifslib and its lazy imports)")
if failed:
    sys.exit("\n".join(failed))
EOF
echo "wheel.sh: imports checked in $((SECONDS - step)) s"
step=$SECONDS
# Step 2: course/run_edition.py: the student edition at its quick values, one notebook per core at a time, at one thread
# each (the venv's own kernel; the copies keep their metadata: the glossary reads notebook 01's quick values).
status=0
"$work/venv/bin/python" "$work/run_edition.py" "$work/class" --timeout 900 || status=$?
echo "wheel.sh: the student edition at its quick values in $((SECONDS - step)) s"
step=$SECONDS
# Step 3: the stored notebooks in the students' venv, compared with nbval. The kernel is registered inside that venv
# (its share/jupyter, found through JUPYTER_PATH); pytest and nbval are the project's, the kernel's Python the venv's,
# started in notebooks/, so the cells import the installed wheel.
"$work/venv/bin/python" -m ipykernel install --prefix "$work/venv" --name ifslib-student --display-name "ifslib (students' venv)" >/dev/null
cd "$repo/notebooks"  # where nbval starts the kernel: the repository's ifslib must not be the one imported
"$work/venv/bin/python" -c "import ifslib; assert 'site-packages' in ifslib.__file__, ifslib.__file__"
cd "$repo"
JUPYTER_PATH="$work/venv/share/jupyter" .venv/bin/jupyter kernelspec list | grep -q "ifslib-student *$work/venv/"
JUPYTER_PATH="$work/venv/share/jupyter" make test-stored KERNEL=ifslib-student || status=$?
echo "wheel.sh: the stored notebooks at their teaching values in the students' venv in $((SECONDS - step)) s; $((SECONDS - started)) s in all"
exit "$status"
