# Tiers, quickest first (each creates or reuses the virtual environment .venv):
#   make check       ruff, the import contracts + the unit tests (no notebooks, no slow
#                    tests): a few minutes
#   make test        check + every notebook under nbmake, reading the committed ledger + the
#                    slow tests and the docs site's + `verify --sample` (recomputes Experiments
#                    1 and 2, a few ledger runs and derived entries, fails unless they equal
#                    the ledger's) (what CI runs)
#   make paper       Experiments 1 and 2 from scratch, Figs. 2-5 and the results table
#   make reproduce   recompute every run (resumable), execute every notebook, write the
#                    ledger, every figure and the README tables
#   make lab         JupyterLab on the project; the notebooks' .py files open as notebooks
#   make benchmark   environment steps per second
# Another interpreter: make test PYTHON=python3.12 VENV=.venv312 (3.11 and 3.12 are supported)

PYTHON  ?= python3
VENV    ?= .venv
PY      := $(VENV)/bin/python
STAMP   := $(VENV)/.installed
# JupyterLab reads settings overrides from <sys.prefix>/share/jupyter/lab/settings/overrides.d;
# ours make the jupytext notebook the default viewer of .py files (the user's settings stay
# untouched). The server's config in <sys.prefix>/etc/jupyter hides the generated .ipynb files
# (ContentsManager.hide_globs: [0-9]*.ipynb) from the file browser, so each notebook is listed
# once, as its .py; jupytext still reads the outputs from the hidden .ipynb.
LAB_OVERRIDES := $(VENV)/share/jupyter/lab/settings/overrides.d/docking.json
LAB_SERVER_CONFIG := $(VENV)/etc/jupyter/jupyter_server_config.json
NOTEBOOK_SOURCES := $(sort $(wildcard notebooks/[0-9]*.py))
NOTEBOOKS := $(NOTEBOOK_SOURCES:.py=.ipynb)

# Headless rendering through Mesa's EGL (llvmpipe on CPU-only machines).
export MUJOCO_GL ?= egl
export PYOPENGL_PLATFORM ?= egl

.PHONY: reproduce experiments lint check test test-site test-verify paper setup system-deps notebooks lab benchmark docs clean

# Everything from the runs up: computed into results/ (never from the ledger), the notebooks
# and the README report executed on them, then the ledger written from the results store
# (a results table per design, and the runs the designs keep whole).
reproduce: setup notebooks experiments
	DOCKING_LEDGER=off $(VENV)/bin/jupyter nbconvert --to notebook \
	    --execute --inplace --ExecutePreprocessor.timeout=-1 $(NOTEBOOKS)
	DOCKING_LEDGER=off $(PY) -m docking report --readme README.md
	$(PY) -m docking ledger update
	$(PY) -m docking ledger derive

# The experiments through the CLI, so their progress bars reach the terminal; computed, not
# read from the ledger.
experiments: setup
	DOCKING_LEDGER=off $(PY) -m docking run experiment1
	DOCKING_LEDGER=off $(PY) -m docking run experiment2
	DOCKING_LEDGER=off $(PY) -m docking design run calibration-experiment1 calibration-experiment2
	DOCKING_LEDGER=off $(PY) -m docking design run experiment3 experiment3-oracle
	DOCKING_LEDGER=off $(PY) -m docking design run third-edition untested

# ruff and the import contracts (import-linter): what check and test both run first.
lint: setup
	$(VENV)/bin/ruff format --check .
	$(VENV)/bin/ruff check .
	$(VENV)/bin/lint-imports

check: lint
	$(PY) -m pytest tests -q -n 2 -m "not slow and not docs"

# make test runs what check does and more, in one pytest session: every notebook under nbmake
# with --overwrite (their outputs land in notebooks/*.ipynb, from which `make docs` builds the
# site), the unit tests and the slow tests, on two processes that steal each other's queued
# items, so that neither waits while the other executes the longest notebook, and the many
# short unit tests fill the time the slow tests spend waiting (on a scheduler that never
# answers, a server starting). Then two jobs side by side (make -j2): the site is built and
# the docs tests check it in Chromium (test-site), while verify recomputes runs and derived
# entries, niced (test-verify). The docs tests leave part of the CPU idle while pages load
# (97 s of CPU machine-wide, Chromium's included, in 63 s), and verify takes it; it writes its
# lines to build/verify.log, printed when it ends, so that they do not break into pytest's.
# (Beside the CPU-bound notebook session, a niced verify made make test slower: 647 s against
# 609 s.) The docs tests run under --dist loadscope: the tests of test_docs.py's class
# TestEveryPageAsLoaded, which share one visit of every page, in one process.
test: lint notebooks
	$(PY) -m pytest --nbmake --nbmake-timeout=1800 --overwrite -n 2 --dist worksteal -q \
	    -m "not docs" $(NOTEBOOKS) tests
	$(MAKE) --no-print-directory -j2 test-site test-verify

test-site: setup
	$(MAKE) --no-print-directory docs
	$(PY) -m pytest tests -q -n 2 --dist loadscope -m docs

test-verify: setup
	@mkdir -p build
	@echo "verify --sample 3: running beside the site's tests (niced); its lines follow when it ends"
	@nice -n 10 $(PY) -m docking verify --sample 3 > build/verify.log 2>&1; \
	    status=$$?; cat build/verify.log; exit $$status

# The documentation site in build/site (open build/site/index.html): the README, the
# executed notebooks (make test writes their outputs; docs/build.py executes, from the ledger,
# any that has none or is older than its source), CONTRIBUTING, the API reference.
docs: setup
	NO_MKDOCS_2_WARNING=1 $(PY) docs/build.py

# The paper's two experiments from an empty store, Figs. 2-5, the learning curves and the
# results table (printed; `make reproduce` writes it into the README).
paper: setup
	DOCKING_LEDGER=off $(PY) -m docking report --compute --figures --no-experiment3 --no-third-edition

lab: setup notebooks
	$(VENV)/bin/jupyter lab $$([ "$$(id -u)" = 0 ] && echo --allow-root)

benchmark: setup
	$(PY) -m docking benchmark

setup: system-deps $(STAMP) $(LAB_OVERRIDES) $(LAB_SERVER_CONFIG)

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

# constraints.txt is the lock: the exact versions of every library (those of numpy, MuJoCo,
# dm-control and OpenCV enter every run's key).
$(STAMP): pyproject.toml constraints.txt
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -c constraints.txt -e '.[dev]'
	touch $@

$(LAB_OVERRIDES): jupyterlab/overrides.json $(STAMP)
	mkdir -p $(dir $@)
	cp $< $@

$(LAB_SERVER_CONFIG): jupyterlab/jupyter_server_config.json $(STAMP)
	mkdir -p $(dir $@)
	cp $< $@

# The .ipynb files are generated from the jupytext percent-format sources, never edited by hand.
# They carry the language_info this environment's kernel reports (jupytext writes none), which
# JupyterLab would otherwise write into a notebook as its kernel starts, marking it modified.
# One jupytext call converts every notebook whose .ipynb is missing or older than its source
# or the environment (the kernel's metadata asked once): a call per notebook took 16 s.
notebooks: $(STAMP)
	@stale=""; for py in $(NOTEBOOK_SOURCES); do nb="$${py%.py}.ipynb"; \
	    if [ ! -e "$$nb" ] || [ "$$py" -nt "$$nb" ] || [ $(STAMP) -nt "$$nb" ]; then \
	        stale="$$stale $$py"; fi; done; \
	if [ -n "$$stale" ]; then echo "jupytext --to ipynb$$stale"; \
	    $(VENV)/bin/jupytext --quiet --to ipynb \
	        --update-metadata "$$($(PY) jupyterlab/kernel_metadata.py)" $$stale; fi

clean:
	rm -rf $(VENV) notebooks/*.ipynb results build
