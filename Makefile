# The README's two commands:
#   make run   - create .venv, install gridlib with the workflow, build every sample case
#   make test  - create .venv, install the test extras, run the whole test suite
# Needs only Python >= 3.11 and make; everything else comes from PyPI.

PYTHON ?= $(shell command -v python3.11 2>/dev/null || command -v python3 2>/dev/null)
VENV   := .venv
BIN    := $(VENV)/bin
CORES  ?= all
# make bench PEER_PYTHON=/path/to/venv/bin/python: peers (resdata, xtgeo) timed from that interpreter
PEER_PYTHON ?=
# gridlib is installed editable, so pip compiled none of its modules: Python writes their
# bytecode to __pycache__ on first import unless the environment sets PYTHONDONTWRITEBYTECODE
# (some CI images and containers do), and then every Snakemake job and test interpreter
# compiles gridlib from source again (about 0.2 s of CPU each). An empty value lets it write.
export PYTHONDONTWRITEBYTECODE :=

.PHONY: run simulate test system-tools opm-flow lint bench golden clean

$(BIN)/python:
	@test -n "$(PYTHON)" || { echo "make: no python3.11 or python3 on PATH" >&2; exit 1; }
	@$(PYTHON) -c 'import sys; sys.exit(sys.version_info < (3, 11))' || \
		{ echo "make: $(PYTHON) is older than Python 3.11" >&2; exit 1; }
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed-run: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[workflow]"
	touch $@

$(VENV)/.installed-test: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e ".[test]"
	touch $@ $(VENV)/.installed-run

run: $(VENV)/.installed-run opm-flow
	$(BIN)/snakemake --cores $(CORES) --workflow-profile workflow/profiles/default

# The sample cases with a `simulation` section through OPM Flow (`make system-tools` installs it)
simulate: $(VENV)/.installed-run opm-flow
	$(BIN)/snakemake --cores $(CORES) --workflow-profile workflow/profiles/default simulate

# One pytest worker per core, each taking whole test modules (their module fixtures run once);
# tests/conftest.py starts the longest modules first.
test: $(VENV)/.installed-test system-tools
	$(BIN)/python -m pytest -n auto --dist loadfile

# OPM Flow and SLURM, which the tests run against (apt-get, as root or with sudo; see the script)
system-tools:
	@sh tests/system_tools.sh

# OPM Flow alone: the sample study grid_choice simulates its variants in `make run`
opm-flow:
	@sh tests/system_tools.sh flow

lint: $(VENV)/.installed-test
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/lint-imports
	$(BIN)/snakefmt --check Snakefile workflow
	$(BIN)/snakemake --lint

bench: $(VENV)/.installed-run
	$(BIN)/python bench/geometry.py
	$(BIN)/python bench/quality.py
	$(BIN)/python bench/cornerpoint.py $(if $(PEER_PYTHON),--peer-python $(PEER_PYTHON))
	$(BIN)/python bench/pebi.py
	$(BIN)/python bench/petrophysics.py
	$(BIN)/python bench/coarsen.py
	$(BIN)/python bench/transmissibility.py
	$(BIN)/python bench/cartesian_deck.py
	$(BIN)/python bench/flow_deck.py
	$(BIN)/python bench/wells.py $(if $(PEER_PYTHON),--peer-python $(PEER_PYTHON))

golden: $(VENV)/.installed-run
	$(BIN)/python tests/regression/update_golden.py

clean:
	rm -rf results/*/ .snakemake
