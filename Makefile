# Two entry points: `make reproduce` and `make test`. Both create .venv on first use.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed

.PHONY: reproduce test lint bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e ".[dev]"
	touch $(STAMP)

# Every experiment on embedded defaults, then the benchmarks; writes results/.
reproduce: $(STAMP)
	$(BIN)/workbench run parametric-surfaces
	$(BIN)/workbench run discretization
	$(BIN)/python benchmarks/bench_wrench.py

test: $(STAMP) lint
	$(BIN)/python -m pytest -q

lint: $(STAMP)
	$(BIN)/ruff check workbench fem experiments tests benchmarks

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_wrench.py

clean:
	rm -rf $(VENV) .pytest_cache
