# Two commands do everything from a fresh clone:
#   make reproduce   run every notebook, regenerate every figure in figures/, print the results table
#   make test        run the unit tests and execute every notebook under pytest --nbmake
# Both create (or reuse) the virtual environment .venv and install what they need.

PYTHON  ?= python3
VENV    ?= .venv
PY      := $(VENV)/bin/python
STAMP   := $(VENV)/.installed
NOTEBOOK_SOURCES := $(sort $(wildcard notebooks/[0-9]*.py))
NOTEBOOKS := $(NOTEBOOK_SOURCES:.py=.ipynb)

# Headless rendering through Mesa's EGL (llvmpipe on CPU-only machines).
export MUJOCO_GL ?= egl
export PYOPENGL_PLATFORM ?= egl

.PHONY: reproduce test setup system-deps notebooks benchmark clean

reproduce: setup notebooks
	$(VENV)/bin/jupyter nbconvert --to notebook --execute --inplace \
	    --ExecutePreprocessor.timeout=-1 $(NOTEBOOKS)
	$(PY) -m docking.report

test: setup notebooks
	$(VENV)/bin/ruff format --check .
	$(VENV)/bin/ruff check .
	$(PY) -m pytest tests -q
	$(PY) -m pytest --nbmake --nbmake-timeout=3600 -q $(NOTEBOOKS)

benchmark: setup
	$(PY) benchmarks/env_speed.py

setup: system-deps $(STAMP)

# Mesa's EGL/GL libraries render MuJoCo frames without a display or GPU.
system-deps:
	@if ! ldconfig -p | grep -q 'libEGL.so.1' || ! ls /usr/lib/*/dri/swrast_dri.so >/dev/null 2>&1; then \
	    echo "Installing Mesa EGL (libegl1, libgl1-mesa-dri) for headless rendering"; \
	    if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	    $$SUDO apt-get update -qq && $$SUDO apt-get install -y -qq libegl1 libgl1 libgl1-mesa-dri libglx-mesa0; \
	fi

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[dev]'
	touch $@

# The .ipynb files are generated from the jupytext percent-format sources, never edited by hand.
notebooks: $(NOTEBOOKS)

notebooks/%.ipynb: notebooks/%.py $(STAMP)
	$(VENV)/bin/jupytext --quiet --to ipynb --output $@ $<

clean:
	rm -rf $(VENV) notebooks/*.ipynb results build
