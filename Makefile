# probrob — build the book, run the tests.
#   make book    execute every notebook, build the HTML book into _build/html (offline, -W)
#   make test    ruff + pytest (tests/) + nbval strict over every notebook, then nbval and the
#                exercise solutions again on numpy's baseline floating-point path
# The first run of either creates .venv from requirements.txt (a few minutes).

SHELL := bash
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := help
MAKEFLAGS += --no-builtin-rules

PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
# Re-install only when the requirements or the package metadata change.
STAMP := $(VENV)/.installed-stamp
NOTEBOOKS := $(sort $(wildcard notebooks/*.ipynb))
HTML := _build/html

# Kernels started by jupyter-book, nbval and `jupyter execute` must be this venv's python, even if
# the user has a "python3" kernelspec of their own in ~/.local/share/jupyter.
export JUPYTER_PATH := $(CURDIR)/$(VENV)/share/jupyter
export PIP_DISABLE_PIP_VERSION_CHECK := 1
export PYTHONHASHSEED := 0
# A stalled kernel (idle, its cell never run) fails fast, naming the notebook and the cell: every
# runner of the notebooks (jupyter execute, nbval, and the book: execute.timeout in _config.yml,
# kept equal by tests/test_tooling.py) gives a cell CELL_TIMEOUT seconds and a kernel
# KERNEL_STARTUP_TIMEOUT seconds to start. Over 94 measured executions on a loaded 2-core machine
# (load average 6-7) the slowest real cell took 24.7 s (trabalho3, cell 43) and a kernel at most
# 2.7 s to start.
CELL_TIMEOUT := 120
KERNEL_STARTUP_TIMEOUT := 60
# NB: MPLBACKEND=Agg is set only for plain Python runs (unit tests, benchmarks). Exported to a
# Jupyter kernel it would replace the inline backend and the notebooks would show no figures.

.PHONY: help venv book test lint format pytest nbval nbval-fp execute lab lab-check bench \
        browser-check \
        check-offline \
        clean distclean

help:
	@echo "make book          execute the notebooks and build the HTML book into $(HTML)/"
	@echo "make test          ruff check + ruff format --check + pytest tests/ + nbval notebooks/,"
	@echo "                   then nbval and the exercise solutions on another floating-point path"
	@echo "make execute       re-execute every notebook and store its outputs in place"
	@echo "make bench         run the speed benchmarks (benchmarks/bench_*.py)"
	@echo "make lab           JupyterLab on notebooks/ (live sliders; installs it into .venv once)"
	@echo "make lab-check     open every notebook in JupyterLab (headless Chromium), Run All, check"
	@echo "make format        ruff format + ruff check --fix (code and notebooks)"
	@echo "make browser-check open every page of the built book in headless Chromium and check it"
	@echo "make venv          create/update .venv only; make clean / make distclean (also .venv)"

$(STAMP): requirements.txt pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --no-input -r requirements.txt
	$(BIN)/python -m pip check
	@# Build matplotlib's font cache now: its one-time notice on stderr would otherwise land in
	@# the first notebook cell that imports matplotlib (a build warning under -W).
	MPLBACKEND=Agg $(BIN)/python -c "import matplotlib.pyplot"
	@touch $@

venv: $(STAMP)

# ---- the book ----------------------------------------------------------------------------
# --all: re-read (and so re-execute) every page on every build, so the HTML always reflects the
# current library code even when a notebook itself did not change; it also re-emits warnings of
# unchanged pages, which -W turns into failures.
book: $(STAMP)
	$(BIN)/jupyter-book build . --all -W -n --keep-going
	$(BIN)/python .ci/check_offline.py $(HTML)
	@echo "The book: $(HTML)/index.html"

check-offline:
	$(BIN)/python .ci/check_offline.py $(HTML)

# The browser check's axe-core comes from npm, pinned in .ci/package.json and .ci/package-lock.json;
# `npm ci` runs only when .ci/node_modules is missing or older than the lock file (the stamp).
# The check first proves it can fail: the fixture .ci/fixtures/browser/defects.html plants one
# defect of each class it checks, and the run fails unless each is reported.
NPM_STAMP := .ci/node_modules/.installed-stamp
$(NPM_STAMP): .ci/package.json .ci/package-lock.json
	@command -v npm >/dev/null 2>&1 || { echo "make browser-check: npm is not installed;" \
	  "it installs axe-core from .ci/package-lock.json (Debian: apt-get install -y npm)" >&2; exit 1; }
	npm ci --prefix .ci --no-audit --no-fund
	@touch $@

browser-check: $(STAMP) $(NPM_STAMP)
	$(BIN)/python .ci/browser_check.py --self-test $(BROWSER_CHECK_ARGS)

# ---- tests -------------------------------------------------------------------------------
test: lint pytest nbval nbval-fp

lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .

pytest: $(STAMP)
	MPLBACKEND=Agg $(BIN)/python -m pytest tests/

# nbval compares only cells that were executed when saved (execution_count set); a notebook
# committed without outputs would pass unchecked, so that is refused first (fix: make execute).
define CHECK_EXECUTED
import sys, nbformat
bad = [
    f"{path}: code cell {i} has no stored execution"
    for path in sys.argv[1:]
    for i, cell in enumerate(nbformat.read(path, as_version=4).cells)
    if cell.cell_type == "code" and cell.source.strip() and cell.execution_count is None
]
print(*bad, sep="\n", file=sys.stderr)
sys.exit(f"{len(bad)} unexecuted code cells: run `make execute` and commit the outputs" if bad else 0)
endef
export CHECK_EXECUTED

NBVAL := $(BIN)/python -m pytest --nbval --nbval-sanitize-with tests/nbval_sanitize.cfg \
  --nbval-cell-timeout=$(CELL_TIMEOUT) --nbval-kernel-startup-timeout=$(KERNEL_STARTUP_TIMEOUT)

nbval: $(STAMP)
	$(BIN)/python -c "$$CHECK_EXECUTED" $(NOTEBOOKS)
	$(NBVAL) notebooks/

# The same notebooks (and every exercise's solution, tests/test_exercise_solutions.py) once more
# on other floating-point paths: numpy's SIMD kernels above its baseline switched off
# (NPY_DISABLE_CPU_FEATURES, the features .ci/fp_features.py reads from numpy), so exp, log, sin,
# cos and arctan2 round differently in their last bits, and OpenBLAS's oldest kernels forced
# (OPENBLAS_CORETYPE, .ci/fp_features.py --blas), so matrix products sum in another order, as on
# a reader's machine of another kind (AVX2, AVX-512, arm64). A particle filter turns such a bit
# into another run: every claim about random runs must hold here too, and every stored output
# that nbval compares must be the same. A variable the caller set (this workplace's machines set
# OPENBLAS_CORETYPE=Haswell) chose the first run's path: if it is already what this run would
# set, this run takes the default instead, so that the two runs differ either way.
nbval-fp: $(STAMP)
	@features="$$($(BIN)/python .ci/fp_features.py)"; \
	blas="$$($(BIN)/python .ci/fp_features.py --blas)"; \
	if [ -n "$${NPY_DISABLE_CPU_FEATURES:-}" ]; then features=""; fi; \
	if [ "$${OPENBLAS_CORETYPE:-}" = "$$blas" ]; then blas=""; fi; \
	echo "nbval-fp: NPY_DISABLE_CPU_FEATURES=\"$$features\" OPENBLAS_CORETYPE=\"$$blas\"" \
	  "(nbval ran with \"$${NPY_DISABLE_CPU_FEATURES:-}\" and \"$${OPENBLAS_CORETYPE:-}\";" \
	  "empty: numpy's and OpenBLAS's defaults)"; \
	export NPY_DISABLE_CPU_FEATURES="$$features" OPENBLAS_CORETYPE="$$blas"; \
	$(BIN)/python .ci/fp_features.py --check; \
	start=$$SECONDS; \
	$(NBVAL) notebooks/ tests/test_exercise_solutions.py; \
	echo "nbval-fp: $$((SECONDS - start)) s with $${features:-nothing} disabled" \
	  "and OpenBLAS's $${blas:-default} kernels"

format: $(STAMP)
	$(BIN)/ruff format .
	$(BIN)/ruff check --fix .

# ---- notebooks and benchmarks ------------------------------------------------------------
# Executes each notebook in its own folder and stores the outputs (what nbval compares against),
# then stores it as JupyterLab writes it, without the metadata that changes on every run
# (.ci/normalize_notebooks.py: the venv's kernelspec, no widget state, no execution timestamps,
# no stored {eval} values). `python -c "$STRIP_VOLATILE" NB...` runs that script.
define STRIP_VOLATILE
import runpy, sys
runpy.run_path(".ci/normalize_notebooks.py", run_name="__main__")
endef
export STRIP_VOLATILE

# `jupyter execute` with _ext/probrob_zmq_wakeup.py installed (see there: without it a kernel
# reply can sit unread in the client's socket until the cell timeout).
JUPYTER_EXECUTE := $(BIN)/python -c 'import sys; sys.path.insert(0, "_ext"); \
  import probrob_zmq_wakeup; probrob_zmq_wakeup.install(); \
  from nbclient.cli import main; sys.argv[0] = "jupyter-execute"; main()'

execute: $(STAMP)
	@for nb in $(NOTEBOOKS); do \
	  echo "jupyter execute --inplace $$nb  (with _ext/probrob_zmq_wakeup.py)"; \
	  $(JUPYTER_EXECUTE) --inplace --timeout $(CELL_TIMEOUT) \
	    --startup_timeout $(KERNEL_STARTUP_TIMEOUT) "$$nb"; \
	done
	$(BIN)/python -c "$$STRIP_VOLATILE" $(NOTEBOOKS)

# JupyterLab and jupyterlab-myst (which renders the chapters' MyST: {eval}, {math}, {eq},
# admonitions) are not part of requirements.txt (the book and the tests do not need them);
# JupyterLab's settings for this book (_ext/jupyterlab_overrides.json, installed as the venv's
# overrides.json): the notebook attaches every cell (windowingMode "none"). With the default,
# "contentVisibility", Chromium 156 left players of off-screen cells laid out at 0x0 after they
# were scrolled to (blank until a slider moved; measured: both Trabalho 5 players, every run).
# `make lab` adds requirements-lab.txt to .venv on first use (a version pair that
# `jupyter labextension list` calls compatible; see that file).
LAB_STAMP := $(VENV)/.lab-installed-stamp
$(LAB_STAMP): requirements-lab.txt _ext/jupyterlab_overrides.json $(STAMP)
	$(BIN)/python -m pip install --quiet --no-input -r requirements.txt -r requirements-lab.txt
	mkdir -p $(VENV)/share/jupyter/lab/settings
	cp _ext/jupyterlab_overrides.json $(VENV)/share/jupyter/lab/settings/overrides.json
	$(BIN)/python -m pip check
	$(BIN)/jupyter labextension list
	@touch $@

lab: $(LAB_STAMP)
	$(BIN)/jupyter lab $(if $(filter 0,$(shell id -u)),--allow-root) notebooks/

# A real client: JupyterLab (headless, token-less, on a free port) driven by Chromium opens each
# notebook, checks it is not marked modified on opening, runs all cells and fails on raw MyST,
# an {eval} without a value, a cell error, a blank player or a console error. The fixture
# (.ci/fixtures/myst_roles.ipynb) shows every MyST construct the chapters use.
lab-check: $(LAB_STAMP)
	$(BIN)/python .ci/jupyterlab_check.py --self-test .ci/fixtures/myst_roles.ipynb $(NOTEBOOKS)

bench: $(STAMP)
	MPLBACKEND=Agg $(BIN)/python benchmarks/bench_motion.py
	MPLBACKEND=Agg $(BIN)/python benchmarks/bench_sensors.py
	MPLBACKEND=Agg $(BIN)/python benchmarks/bench_filters.py
	MPLBACKEND=Agg $(BIN)/python benchmarks/bench_kinematics.py
	MPLBACKEND=Agg $(BIN)/python benchmarks/bench_mcl.py
	MPLBACKEND=Agg $(BIN)/python benchmarks/bench_grid.py

# ---- cleaning ----------------------------------------------------------------------------
clean:
	rm -rf _build jupyter_execute .pytest_cache .ruff_cache .hypothesis
	find . -path ./$(VENV) -prune -o -name __pycache__ -type d -print0 | xargs -0 rm -rf
	find . -path ./$(VENV) -prune -o -name .ipynb_checkpoints -type d -print0 | xargs -0 rm -rf

distclean: clean
	rm -rf $(VENV) src/*.egg-info
