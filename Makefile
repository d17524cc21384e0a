# gfrf: `make demo` and `make test` work on a fresh machine with Python 3.11 and pip.
PYTHON ?= python3.11
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test test-slow bench report lint clean

$(BIN)/python:
	@command -v $(PYTHON) >/dev/null 2>&1 || { echo "need $(PYTHON) on PATH (or: make PYTHON=python3 ...)"; exit 2; }
	$(PYTHON) -m venv $(VENV)

$(STAMP): $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[test,fast,dask,identify]"
	@touch $(STAMP)

# Verdicts exit 1 when stability is not proven: the demo shows them and goes on.  One
# "[demo i/N]" line per step (also in a log, where no progress bar shows); the reports go
# to build/reports (REPORTS=reports/ writes the tracked ones: that is `make report`).
REPORTS ?= build/reports
demo: $(STAMP)
	@models=$$(for m in models/*.toml; do grep -q '^kind = "parametric"' $$m || echo $$m; done); \
	total=$$(( $$(echo $$models | wc -w) + 2 )); i=0; \
	for m in $$models; do \
	  i=$$((i + 1)); echo "== [demo $$i/$$total] gfrf verdict $$m"; $(BIN)/gfrf verdict $$m || true; echo; \
	done; \
	echo "== [demo $$((i + 1))/$$total] the parametric pendulum (models/parametric_pendulum.toml), eps = 0.2, x(0) = 0.5"; \
	for method in exact perturbation homotopy energy averaging; do \
	  $(BIN)/gfrf transition --eps 0.2 --amplitude 0.5 --branch 1/4 --method $$method || exit 1; \
	done; \
	echo "== [demo $$total/$$total] gfrf report --out $(REPORTS)"; \
	$(BIN)/gfrf report --out $(REPORTS)

# Regenerate the tracked reports (reports/*.md and their figures).
report: $(STAMP)
	$(BIN)/gfrf report --out reports/

# The static checks first (the layers with import-linter, ruff with unused-noqa detection,
# mypy; configured in pyproject.toml), then the suite on every core (pytest-xdist).
# `make test-slow` runs the tests marked slow (CI runs both: .ci/run).
JOBS ?= auto
test: $(STAMP)
	$(BIN)/lint-imports --no-cache
	$(BIN)/ruff check gfrf tests
	$(BIN)/mypy gfrf
	$(BIN)/python -m pytest -q -n $(JOBS)

test-slow: $(STAMP)
	$(BIN)/python -m pytest -q -n $(JOBS) -m slow

bench: $(STAMP)
	$(BIN)/gfrf bench --out reports/

lint: $(STAMP)
	$(BIN)/ruff check gfrf tests

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache
