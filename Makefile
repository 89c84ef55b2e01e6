# ifslib: the two commands a newcomer needs are `make figures` and `make test`.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
PRESET ?= paper
# The paper's target images: use the shared copy beside the checkout when there is one.
IFSLIB_DATA ?= $(if $(wildcard ../shared/data/koch.png),$(abspath ../shared/data),)
export IFSLIB_DATA

.PHONY: setup test figures bench clean

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet torch==2.13.0
	$(PY) -m pip install --quiet -e '.[dev,sweep]'
	touch $@

setup: $(VENV)/.installed  ## create .venv and install ifslib (editable) with its dev extras

test: $(VENV)/.installed  ## run the whole test suite
	$(PY) -m pytest -q

figures: $(VENV)/.installed  ## run every notebook with papermill (paper preset; PRESET=ci for the quick run)
	$(PY) notebooks/run.py --preset $(PRESET)
	$(PY) -m ifslib render koch --size 512 --depth 6 -o figures/koch.png

bench: $(VENV)/.installed  ## print the renderer's speed and memory
	$(PY) benchmarks/render.py

clean:
	rm -rf $(VENV) build .pytest_cache
