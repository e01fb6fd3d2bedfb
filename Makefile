# scalf-opt: `make run` and `make test` work from a fresh clone on a machine with Python >= 3.11.
PYTHON ?= python3
VENV   ?= .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
EXTRAS := $(VENV)/.installed-extras

.PHONY: install run test test-all docs lint format bench lock clean

# Every package is installed at the version pinned in constraints.txt (refresh it with `make lock`).
# `make install` installs scalf-opt with every extra (the 3-D view, MuJoCo, Dask, ROS 2 bags, the
# documentation tools): every command of the README's tour works afterwards; `make run` installs
# the same and reproduces the paper; `make test` adds the test tools and runs the suite's fast
# tier (about 13 minutes on two cores), `make test-all` the whole suite (CI's: .ci/run).
$(STAMP): pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip -c constraints.txt
	$(BIN)/python -m pip install --quiet -c constraints.txt -e '.[all,test]'
	touch $(STAMP) $(EXTRAS)

$(EXTRAS): pyproject.toml constraints.txt
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip -c constraints.txt
	$(BIN)/python -m pip install --quiet -c constraints.txt -e '.[all]'
	touch $(EXTRAS)

install: $(EXTRAS)
	@echo "installed in $(VENV): run $(BIN)/scalf-opt, or 'source $(BIN)/activate' first"

run: $(EXTRAS)
	$(BIN)/scalf-opt paper

# The tests marked `slow` (the long end-to-end runs: the documented command outputs that take
# more than a few seconds, the whole paper, the same commands twice, the longer studies and the
# examples; every family on every robot) are left out of `make test`; `make test-all` runs them
# with the rest.
PYTEST := MPLBACKEND=Agg $(BIN)/python -m pytest -q -n auto --dist loadgroup --max-worker-restart 0

test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy
	$(PYTEST) -m "not slow"

test-all: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy
	$(PYTEST)

# The documentation site (MkDocs, Material theme) into site/, offline; open site/index.html.
docs: $(STAMP)
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict

lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/mypy

format: $(STAMP)
	$(BIN)/ruff format .
	$(BIN)/ruff check --fix .

bench: $(STAMP)
	for b in benchmarks/bench_*.py; do $(BIN)/python $$b || exit 1; done

# Re-resolve the newest versions pyproject.toml allows, in a scratch environment, and pin them all.
lock:
	rm -rf .lock-venv
	$(PYTHON) -m venv .lock-venv
	.lock-venv/bin/python -m pip install --quiet --upgrade pip
	.lock-venv/bin/python -m pip install --quiet '.[all,test]'
	.lock-venv/bin/python -m pip freeze --all --exclude-editable | grep -iv '^scalf-opt' > constraints.txt
	rm -rf .lock-venv
	@echo "constraints.txt refreshed: review the diff, run make test, commit it"

clean:
	rm -rf $(VENV) build site *.egg-info .pytest_cache .mypy_cache .ruff_cache
