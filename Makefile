# ifslib: the two commands a newcomer needs are `make figures` and `make test`.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
PRESET ?= teaching
# The paper's target images: use the shared copy beside the checkout when there is one.
IFSLIB_DATA ?= $(if $(wildcard ../shared/data/koch.png),$(abspath ../shared/data),)
export IFSLIB_DATA
# pip byte-compiles every module it installs (torch's thousands: a third of the set-up's time), so the
# installs below skip it (--no-compile) and Python compiles a module the first time it is imported and
# keeps it, even where the shell sets PYTHONDONTWRITEBYTECODE (the .pyc files go to .venv and to
# __pycache__ folders that git ignores); the set-up imports what every test worker imports once, so that
# the workers do not each compile it at the same time (about 10 s of CPU a process)
export PYTHONDONTWRITEBYTECODE :=

.PHONY: setup setup-grading test test-slow test-fast test-stored figures book slides student student-binder setup-browser test-browser bench clean

# pyproject.toml declares ranges; constraints.txt pins the versions the tests ran with (torch==2.13.0:
# this machine's local CPU wheel, never a multi-GB CUDA build from the index).
# What the tests and the notebooks need; the book's and the browser's extras come on top, only for
# the commands that use them (make test does not wait for Sphinx and Playwright to install).
$(VENV)/.installed: pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet --no-compile -c constraints.txt -e '.[dev,sweep]'
	$(PY) -c 'import torch, scipy.optimize, matplotlib.pyplot, skimage.metrics, papermill, xdist, ifslib.automatic'
	touch $@

# nbgrader (and the classic notebook server it brings) only for the commands that run it: make student,
# .ci/nbgrader.sh; make test leaves out the tests marked `grading`
$(VENV)/.installed-grading: $(VENV)/.installed
	$(PY) -m pip install --quiet --no-compile -c constraints.txt -e '.[dev,sweep,grading]'
	touch $@

$(VENV)/.installed-docs: $(VENV)/.installed-grading
	$(PY) -m pip install --quiet --no-compile -c constraints.txt -e '.[dev,sweep,grading,docs,browser]'
	touch $@

setup-grading: $(VENV)/.installed-grading  ## nbgrader for make student and .ci/nbgrader.sh

setup: $(VENV)/.installed $(VENV)/.installed-grading $(VENV)/.installed-docs  ## create .venv and install ifslib (editable) with all its extras, at the tested versions (constraints.txt)

# one pytest-xdist worker per core, at one torch thread each (tests/conftest.py); notebooks 00, 01 and 03
# run at their quick values (metadata["ifslib"]["quick"]) in a temporary copy, their figures compared on
# the same worker; the other notebooks' quick runs are in the slow tier
test: $(VENV)/.installed  ## run the test suite (the library, notebooks 00, 01 and 03 at their quick values); the slow tier: make test-slow
	$(PY) -m pytest -q -n auto --dist loadscope -m "not slow and not grading"

# the tests marked `slow` (whole fractal searches, several fits, the sweep's process pool, the literature's
# samplers, the course's own checks, notebooks 02, 04-10 and the glossary at their quick values): about half the suite's CPU, so make test leaves
# them out and .ci/run runs them after it
test-slow: $(VENV)/.installed  ## the slow tier: whole fractal searches and several fits (CI runs it after make test)
	$(PY) -m pytest -q -n auto --dist loadscope -m "slow and not grading"

# The stored notebooks run again at their teaching values, in a fresh kernel each (nbval, strict: every
# checked cell's text compared, sanitized by notebooks/nbval-sanitize.cfg, and its pictures by
# tests/nbval_stored.py), as many at once as the cores hold at one thread each (notebooks/run.py's way).
# NOTEBOOKS: name prefixes or paths, e.g. `make test-stored NOTEBOOKS="00_tutorial 01 03 glossary"`; all by default.
# KERNEL: a Jupyter kernel's name to run them in (CI: the students' venv, .ci/wheel.sh); this venv's Python by default.
NOTEBOOKS ?=
KERNEL ?=
STORED = $(if $(strip $(NOTEBOOKS)),$(foreach n,$(NOTEBOOKS),$(if $(filter %.ipynb,$(n)),$(n),$(wildcard notebooks/$(n)*.ipynb))),$(wildcard notebooks/[0-9][0-9]_*.ipynb) notebooks/glossary.ipynb)
test-stored: $(VENV)/.installed  ## the stored notebooks run again and compared with their outputs, pictures included (nbval; NOTEBOOKS="01 03")
	$(PY) -m pytest -p tests.nbval_stored --nbval $(if $(KERNEL),--nbval-kernel-name $(KERNEL),--nbval-current-env) --nbval-sanitize-with notebooks/nbval-sanitize.cfg \
		-n auto --dist loadfile -q $(sort $(STORED))

# the inner loop of work: the library's quick tests, without the notebooks' runs and the slow searches
test-fast: $(VENV)/.installed  ## the library's quick tests: no notebook, no whole fractal search (under a minute)
	$(PY) -m pytest tests -q -n auto --dist loadscope -m "not notebook and not slow and not grading"

# PRESET=teaching (the default) stores each notebook's run in the notebook itself and writes figures/;
# PRESET=quick runs the quick values into build/quick/ and build/figures-quick/, never over the stored outputs
figures: $(VENV)/.installed  ## run every notebook at its teaching values, store the run in it, write figures/ (PRESET=quick: into build/)
	$(PY) notebooks/run.py --preset $(PRESET)
	$(if $(filter teaching,$(PRESET)),$(PY) -m ifslib render koch --size 512 --depth 6 -o figures/koch.png)

# The book's formulas (MathJax) and the lecture slides (reveal.js) from the npm registry, so both open with
# no network (no CDN). One install for both: `npm install --no-save` removes the packages it is not given.
NPM_PACKAGES := mathjax@3.2.2 reveal.js@4.6.1
MATHJAX := build/npm/node_modules/mathjax/es5/tex-mml-chtml.js
REVEAL := build/npm/node_modules/reveal.js/dist/reveal.js
$(MATHJAX) $(REVEAL) &:
	npm install --no-save --no-audit --no-fund --prefix build/npm $(NPM_PACKAGES)

book: $(VENV)/.installed-docs $(MATHJAX)  ## static HTML book of the notebooks (stored outputs, warnings as errors) in build/book/html
	$(PY) docs/build.py

slides: $(VENV)/.installed-docs $(REVEAL)  ## a reveal.js deck per lecture (docs/slides/lectures.yaml; stored outputs, speaker notes, offline) in build/slides/
	$(PY) docs/slides.py

student: $(VENV)/.installed-grading  ## student edition (nbgrader's release: solutions stubbed, hidden tests out) in build/student, each executed and checked
	$(PY) notebooks/student.py build/student --check

student-binder: $(VENV)/.installed-grading  ## the students' Binder repository in build/student-binder (student edition, ifslib wheel, binder/; no answers); its README says how to publish it
	$(PY) course/student_binder.py build/student-binder

setup-browser: $(VENV)/.installed-docs  ## Debian's chromium (apt-get, as root, only when missing) and playwright, for test-browser
	PY=$(PY) sh browser_tests/setup.sh

test-browser: setup-browser book slides  ## the explorer and the tutorial in JupyterLab in headless Chromium, the book's pages and the lecture slides
	$(PY) -m pytest browser_tests -q -p no:cacheprovider

bench: $(VENV)/.installed  ## print the renderer's speed and memory
	$(PY) benchmarks/render.py

clean:
	rm -rf $(VENV) build .pytest_cache
