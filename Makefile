# Two commands do everything from a fresh clone:
#   make reproduce   run the experiments (progress bars in the terminal), run every notebook,
#                    regenerate every figure in figures/, write the results table into README.md
#   make test        ruff, the unit/browser/Dask/Gymnasium tests, every notebook under nbmake
# Both create (or reuse) the virtual environment .venv and install what they need.
#   make lab         JupyterLab on the project; the notebooks' .py files open as notebooks
#   make benchmark   environment steps per second
# Another interpreter: make test PYTHON=python3.10 VENV=.venv310

PYTHON  ?= python3
VENV    ?= .venv
PY      := $(VENV)/bin/python
STAMP   := $(VENV)/.installed
# JupyterLab reads settings overrides from <sys.prefix>/share/jupyter/lab/settings/overrides.d;
# ours make the jupytext notebook the default viewer of .py files (the user's settings stay
# untouched).
LAB_OVERRIDES := $(VENV)/share/jupyter/lab/settings/overrides.d/docking.json
NOTEBOOK_SOURCES := $(sort $(wildcard notebooks/[0-9]*.py))
NOTEBOOKS := $(NOTEBOOK_SOURCES:.py=.ipynb)

# Headless rendering through Mesa's EGL (llvmpipe on CPU-only machines).
export MUJOCO_GL ?= egl
export PYOPENGL_PLATFORM ?= egl

.PHONY: reproduce experiments test setup system-deps notebooks lab benchmark clean

reproduce: setup notebooks experiments
	$(VENV)/bin/jupyter nbconvert --to notebook --execute --inplace \
	    --ExecutePreprocessor.timeout=-1 $(NOTEBOOKS)
	$(PY) -m docking report --readme README.md

# The experiments through the CLI, so their progress bars reach the terminal; the notebooks
# then load the saved runs from results/.
experiments: setup
	$(PY) -m docking run experiment1
	$(PY) -m docking run experiment2
	$(PY) -m docking calibration
	$(PY) -m docking study
	$(PY) -m docking experiment3

test: setup notebooks
	$(VENV)/bin/ruff format --check .
	$(VENV)/bin/ruff check .
	$(PY) -m pytest tests -q
	$(PY) -m pytest --nbmake --nbmake-timeout=3600 -q $(NOTEBOOKS)

lab: setup notebooks
	$(VENV)/bin/jupyter lab $$([ "$$(id -u)" = 0 ] && echo --allow-root)

benchmark: setup
	$(PY) -m docking benchmark

setup: system-deps $(STAMP) $(LAB_OVERRIDES)

# Mesa's EGL/GL libraries render MuJoCo frames without a display or GPU; Debian's chromium is
# the browser of tests/test_browser.py (playwright drives it; it never downloads a browser).
system-deps:
	@missing=; \
	ldconfig -p | grep -q 'libEGL.so.1' && ls /usr/lib/*/dri/swrast_dri.so >/dev/null 2>&1 \
	    || missing="libegl1 libgl1 libgl1-mesa-dri libglx-mesa0"; \
	command -v chromium >/dev/null 2>&1 || missing="$$missing chromium"; \
	if [ -n "$$missing" ]; then \
	    echo "Installing $$missing"; \
	    if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	    $$SUDO apt-get update -qq && $$SUDO apt-get install -y -qq $$missing; \
	fi

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -e '.[dev]'
	touch $@

$(LAB_OVERRIDES): jupyterlab/overrides.json $(STAMP)
	mkdir -p $(dir $@)
	cp $< $@

# The .ipynb files are generated from the jupytext percent-format sources, never edited by hand.
notebooks: $(NOTEBOOKS)

notebooks/%.ipynb: notebooks/%.py $(STAMP)
	$(VENV)/bin/jupytext --quiet --to ipynb --output $@ $<

clean:
	rm -rf $(VENV) notebooks/*.ipynb results build
