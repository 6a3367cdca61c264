# flexkane: two commands on a fresh machine with Python 3.11+ and make.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT ?= out
# exact versions of every library `make test` and `make bench` install; `make constraints` rewrites it
CONSTRAINTS := constraints.txt
PIP_INSTALL = $(BIN)/python -m pip install --quiet -c $(CONSTRAINTS)

.PHONY: run test bench notebook constraints clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed: pyproject.toml $(CONSTRAINTS) | $(BIN)/python
	$(PIP_INSTALL) -e .
	touch $@

# the test extra includes the sweep, video and dataframe extras the tests use
$(VENV)/.installed-test: pyproject.toml $(CONSTRAINTS) | $(BIN)/python
	$(PIP_INSTALL) -e '.[test]'
	touch $@ $(VENV)/.installed

$(VENV)/.installed-notebook: pyproject.toml $(CONSTRAINTS) | $(BIN)/python
	$(PIP_INSTALL) -e '.[notebook]'
	touch $@ $(VENV)/.installed

run: $(VENV)/.installed
	$(BIN)/flexkane run falling-beam --out $(OUT)/falling-beam --force

test: $(VENV)/.installed-test
	$(BIN)/python -m pytest

$(VENV)/.installed-bench: pyproject.toml $(CONSTRAINTS) | $(BIN)/python
	$(PIP_INSTALL) -e '.[test,bench]'
	touch $@ $(VENV)/.installed $(VENV)/.installed-test

bench: $(VENV)/.installed-bench
	$(BIN)/python benchmarks/run_all.py

# executes examples/chapter8.ipynb headless; the executed notebook goes to $(OUT)/notebook/chapter8.ipynb
notebook: $(VENV)/.installed-notebook
	$(BIN)/python examples/run_notebook.py $(OUT)/notebook

# what pip resolves today from pyproject.toml's lower bounds, in a throwaway venv without constraints
constraints:
	@set -e; venv=$$(mktemp -d); trap 'rm -rf "$$venv"' EXIT; \
	$(PYTHON) -m venv "$$venv"; \
	"$$venv/bin/python" -m pip install --quiet --upgrade pip; \
	"$$venv/bin/python" -m pip install --quiet -e '.[test,bench]'; \
	{ echo "# Exact versions that make test and make bench install (pip install -c $(CONSTRAINTS))."; \
	  echo "# Written by make constraints on $$("$$venv/bin/python" -c 'import platform, sys; print("Python", platform.python_version(), sys.platform, platform.machine())'); pyproject.toml keeps the lower bounds."; \
	  "$$venv/bin/python" -m pip freeze --exclude-editable; } > $(CONSTRAINTS).new
	mv $(CONSTRAINTS).new $(CONSTRAINTS)

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache
