# `make demo` and `make test` work on a fresh machine: they create .venv when it is
# missing, install springbalance (editable, with its test extras) and run.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
DOCS_STAMP := $(VENV)/.docs-installed
# every package of the environment pinned (`make lock` writes it from .venv)
CONSTRAINTS := constraints.txt

.PHONY: lock bytecode demo lint test test-fast bench bench-buildable bench-clearance bench-explore bench-startup bench-workers bench-memory bench-cli-memory bench-evaluation bench-ipopt bench-distance-check bench-real clean chromium demo-check docs test-drake bench-demo

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(STAMP): $(BIN)/python pyproject.toml $(CONSTRAINTS)
	$(BIN)/python -m pip install --quiet -c $(CONSTRAINTS) -e ".[test]"
	touch $(STAMP)

# An editable install has no compiled bytecode (pip compiles a wheel's at install): without it, and
# where PYTHONDONTWRITEBYTECODE is set, every run compiles the package's sources again (0.2 s).
bytecode: $(STAMP)
	$(BIN)/python -m compileall -q src/springbalance

demo: bytecode
	$(BIN)/springbalance design examples/two_link.yaml --out design.json
	$(BIN)/springbalance evaluate design.json

# lint-imports checks that data flows one way through the subpackages (pyproject.toml [tool.importlinter]).
# `make test` runs every test (CI calls it); `make test-fast` leaves out the tests marked `slow` (whole
# studies, notebooks, the browser, the documentation's Python examples, anything over ~5 s).
test: lint chromium
	$(BIN)/python -m pytest -q -n auto --maxprocesses 4 --dist loadfile

test-fast: lint
	$(BIN)/python -m pytest -q -n auto --maxprocesses 4 --dist loadfile -m "not slow"

# Drake's check of an exported pseudo-base arm alone (tests/io/test_export_pseudo_bases.py). `make test`
# installs Drake with the test extras and runs it too; the test skips, saying why, where no wheel exists.
test-drake: $(STAMP)
	$(BIN)/python -m pip install --quiet -c $(CONSTRAINTS) drake
	$(BIN)/python -m pytest -q tests/io/test_export_pseudo_bases.py

# The code's shape before any test: ruff's format and lint (imports sorted), mypy on src/ (pyproject.toml),
# and the layers and cycles of the import contracts
LINTED := src tests benchmarks examples docs/griffe_extensions.py
lint: $(STAMP)
	$(BIN)/ruff format --check $(LINTED)
	$(BIN)/ruff check $(LINTED)
	$(BIN)/mypy
	$(BIN)/lint-imports --no-cache

# Headless Chromium renders scene.html in the browser test of tests/viz/test_viz.py and in
# `make demo-check`. It is installed here (Debian package `chromium`) when it is missing
# and this machine allows it: apt-get, run as root or through passwordless sudo.
# Otherwise the browser test is skipped with the reason. This step never fails the build.
chromium:
	@if command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 \
	    || [ -n "$$SPRINGBALANCE_CHROMIUM" ]; then \
	    :; \
	elif ! command -v apt-get >/dev/null 2>&1; then \
	    echo "make: chromium is missing and there is no apt-get: the browser test will be skipped"; \
	else \
	    if [ "$$(id -u)" = 0 ]; then sudo=""; \
	    elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then sudo="sudo -n"; \
	    else sudo="none"; fi; \
	    if [ "$$sudo" = none ]; then \
	        echo "make: chromium is missing and installing it needs root: the browser test will be skipped"; \
	    else \
	        echo "make: installing chromium with apt-get (for the browser test)"; \
	        { $$sudo env DEBIAN_FRONTEND=noninteractive apt-get update -qq \
	          && $$sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null; } \
	        || echo "make: could not install chromium: the browser test will be skipped"; \
	    fi; \
	fi

# The browser check of the demo: design the two-link arm, write its report, render
# out/demo/scene.html in headless Chromium and count the arm's and the springs' pixels on the
# screenshot (out/demo/scene.png). Prints PASSED, FAILED or SKIPPED (no Chromium).
demo-check: bytecode chromium
	$(BIN)/springbalance design examples/two_link.yaml --out design.json --quiet
	$(BIN)/springbalance report design.json --out out/demo
	@$(BIN)/python -m springbalance.viz.browser out/demo/scene.html --screenshot out/demo/scene.png || test $$? -eq 77

# The documentation site (mkdocs.yml): docs/*.md plus the API reference that mkdocstrings
# generates from the docstrings, built into site/. --strict makes every warning an error (a
# docstring that griffe cannot parse, a broken link). NO_MKDOCS_2_WARNING silences the banner
# that mkdocs-material prints about its end of life and MkDocs 2.0 (not a build warning).
$(DOCS_STAMP): $(BIN)/python pyproject.toml $(CONSTRAINTS)
	$(BIN)/python -m pip install --quiet -c $(CONSTRAINTS) -e ".[docs]"
	touch $(DOCS_STAMP)

docs: $(DOCS_STAMP)
	NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict --site-dir site

bench: $(STAMP)
	$(BIN)/python benchmarks/bench_ur5.py

# UR5 with 4 buildable helical extension springs against 4 ideal ones: the price of buildability
bench-buildable: $(STAMP)
	$(BIN)/python benchmarks/bench_buildable.py

# UR5 with 4 springs kept 5 mm clear of its collision meshes, beside the same design without clearance
bench-clearance: $(STAMP)
	$(BIN)/python benchmarks/bench_clearance.py

# A UR5 topology study (springbalance explore) on a Dask LocalCluster against the same study run sequentially
bench-explore: $(STAMP)
	$(BIN)/python benchmarks/bench_explore.py

# Start-up: import time, the compiled residual from an empty and from a warm disk cache, the CLI end to end
bench-startup: $(STAMP)
	$(BIN)/python benchmarks/bench_startup.py

# Both cores: 8 UR5 starts on a pool of worker processes against the same starts one after another
bench-workers: $(STAMP)
	$(BIN)/python benchmarks/bench_workers.py

# No full Jacobian: peak memory per sample and time per start at 25,000 and 100,000 UR5 samples
bench-memory: $(STAMP)
	$(BIN)/python benchmarks/bench_memory.py

# Through the command line: peak memory of `springbalance design` per sample, UR5, 1,024 and 65,536 samples
bench-cli-memory: $(STAMP)
	$(BIN)/python benchmarks/bench_cli_memory.py

# The least-squares path: residual + Jacobian at 4,096 UR5 samples, a normal-equations pass, a start at 100,000
bench-evaluation: $(STAMP)
	$(BIN)/python benchmarks/bench_evaluation.py

# The IPOPT path: one peak start at 4,096 UR5 samples and one coil-constrained two-link solve, structured vs plain NLP
bench-ipopt: $(STAMP)
	$(BIN)/python benchmarks/bench_ipopt.py

# The clearance fit's distance check on the UR5 (512 poses): capsules built by Eigen's rotation against the NumPy builder
bench-distance-check: $(STAMP)
	$(BIN)/python benchmarks/bench_distance_check.py

# the demo's solve with its coils' fatigue duty against the same demo without it (ratio in one run)
bench-demo: $(STAMP)
	$(BIN)/python benchmarks/bench_demo.py

# Real designs on real arms (UR5 and Panda; ideal springs and coils; with and without clearance): each case at
# its default settings against a 4× search and 5 seeds, every design checked densely. Hours on 2 cores;
# pass options through ARGS, e.g. make bench-real ARGS="--cases ur5-ideal --parts a" or ARGS=--quick
bench-real: $(STAMP)
	$(BIN)/python benchmarks/bench_real.py $(ARGS)

# Pin the environment .venv holds now (after an upgrade made on purpose, with the tests and bench_real run on it)
lock: $(STAMP) $(DOCS_STAMP)
	@{ sed -n '/^#/p' $(CONSTRAINTS); $(BIN)/python -m pip freeze --exclude-editable; } > $(CONSTRAINTS).new
	mv $(CONSTRAINTS).new $(CONSTRAINTS)

clean:
	rm -rf $(VENV) design.json site
