# flexkane: two commands on a fresh machine with Python 3.11+ and make.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT ?= out

.PHONY: run test bench notebook clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e .
	touch $@

# the test extra includes the sweep, video and dataframe extras the tests use
$(VENV)/.installed-test: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[test]'
	touch $@ $(VENV)/.installed

$(VENV)/.installed-notebook: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[notebook]'
	touch $@ $(VENV)/.installed

run: $(VENV)/.installed
	$(BIN)/flexkane run falling-beam --out $(OUT)/falling-beam --force

test: $(VENV)/.installed-test
	$(BIN)/python -m pytest

$(VENV)/.installed-bench: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[test,bench]'
	touch $@ $(VENV)/.installed $(VENV)/.installed-test

bench: $(VENV)/.installed-bench
	$(BIN)/python benchmarks/run_all.py

# executes examples/chapter8.ipynb headless; the executed notebook goes to $(OUT)/notebook/chapter8.ipynb
notebook: $(VENV)/.installed-notebook
	$(BIN)/python examples/run_notebook.py $(OUT)/notebook

clean:
	rm -rf $(VENV) $(OUT) .pytest_cache
