# probrob — build the book, run the tests.
#   make book    execute every notebook, build the HTML book into _build/html (offline, -W)
#   make test    ruff + pytest (tests/) + nbval strict over every notebook
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
# NB: MPLBACKEND=Agg is set only for plain Python runs (unit tests, benchmarks). Exported to a
# Jupyter kernel it would replace the inline backend and the notebooks would show no figures.

.PHONY: help venv book test lint format pytest nbval execute lab bench browser-check check-offline \
        clean distclean

help:
	@echo "make book          execute the notebooks and build the HTML book into $(HTML)/"
	@echo "make test          ruff check + ruff format --check + pytest tests/ + nbval notebooks/"
	@echo "make execute       re-execute every notebook and store its outputs in place"
	@echo "make bench         run the speed benchmarks (benchmarks/bench_*.py)"
	@echo "make lab           JupyterLab on notebooks/ (live sliders; installs it into .venv once)"
	@echo "make format        ruff format + ruff check --fix (code and notebooks)"
	@echo "make browser-check open the built chapters in headless Chromium and check them"
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

browser-check: $(STAMP)
	$(BIN)/python .ci/browser_check.py

# ---- tests -------------------------------------------------------------------------------
test: lint pytest nbval

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

nbval: $(STAMP)
	$(BIN)/python -c "$$CHECK_EXECUTED" $(NOTEBOOKS)
	$(BIN)/python -m pytest --nbval --nbval-sanitize-with tests/nbval_sanitize.cfg notebooks/

format: $(STAMP)
	$(BIN)/ruff format .
	$(BIN)/ruff check --fix .

# ---- notebooks and benchmarks ------------------------------------------------------------
# Executes each notebook in its own folder and stores the outputs (what nbval compares against),
# then drops the volatile metadata that would change on every run: per-cell execution timestamps
# and the widget state (fresh model ids each run; the live sliders are re-created on "Run all").
define STRIP_VOLATILE
import sys, nbformat
for path in sys.argv[1:]:
    nb = nbformat.read(path, as_version=4)
    for cell in nb.cells:
        cell.metadata.pop("execution", None)
    nb.metadata.pop("widgets", None)
    nbformat.write(nb, path)
endef
export STRIP_VOLATILE

execute: $(STAMP)
	@for nb in $(NOTEBOOKS); do \
	  echo "jupyter execute --inplace $$nb"; \
	  $(BIN)/jupyter execute --inplace --timeout 600 "$$nb"; \
	done
	$(BIN)/python -c "$$STRIP_VOLATILE" $(NOTEBOOKS)

# JupyterLab is not part of requirements.txt (the book and the tests do not need it); `make lab`
# adds it to .venv on first use.
JUPYTERLAB := jupyterlab==4.6.6
lab: $(STAMP)
	@test -x $(BIN)/jupyter-lab || $(BIN)/python -m pip install --quiet --no-input "$(JUPYTERLAB)"
	$(BIN)/jupyter lab $(if $(filter 0,$(shell id -u)),--allow-root) notebooks/

bench: $(STAMP)
	MPLBACKEND=Agg $(BIN)/python benchmarks/bench_motion.py
	MPLBACKEND=Agg $(BIN)/python benchmarks/bench_sensors.py
	MPLBACKEND=Agg $(BIN)/python benchmarks/bench_filters.py
	MPLBACKEND=Agg $(BIN)/python benchmarks/bench_kinematics.py
	MPLBACKEND=Agg $(BIN)/python benchmarks/bench_mcl.py

# ---- cleaning ----------------------------------------------------------------------------
clean:
	rm -rf _build jupyter_execute .pytest_cache .ruff_cache .hypothesis
	find . -path ./$(VENV) -prune -o -name __pycache__ -type d -print0 | xargs -0 rm -rf
	find . -path ./$(VENV) -prune -o -name .ipynb_checkpoints -type d -print0 | xargs -0 rm -rf

distclean: clean
	rm -rf $(VENV) src/*.egg-info
