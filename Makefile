# Everything runs in a local virtual environment, made on first use.
PYTHON ?= python3
VENV ?= .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed-stamp

# The test run: two pytest-xdist workers (the CI machine's two cores), each test
# module run whole by one worker (tests/_parallel.py groups them, longest first),
# and the 25 slowest tests listed at the end.
TEST_WORKERS ?= 2
PYTEST_FLAGS ?= -n $(TEST_WORKERS) --dist loadscope --durations=25

# The documentation site: strict (warnings are errors, every reference must resolve).
SPHINXOPTS ?= -W --keep-going -n
SITE ?= site

.PHONY: demo test lint docs bench urdf clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip setuptools wheel
	$(BIN)/python -m pip install --quiet -e '.[dev]'
	touch $(STAMP)

## demo: the main job: the prototype's torque-requirement report in out/report (prints its path)
demo: $(STAMP)
	$(BIN)/orthoglide report --out out/report

## test: the whole test suite (lint and type checks included), on two workers; lists the slowest tests
test: $(STAMP)
	$(BIN)/python -m pytest $(PYTEST_FLAGS)

lint: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy

## docs: the documentation site in site/ (offline, strict; the notebooks are executed); open site/index.html
docs: $(STAMP)
	$(BIN)/python -m sphinx -b html $(SPHINXOPTS) -d build/docs/doctrees docs $(SITE)

## bench: speed figures, printed as ratios measured in one run
bench: $(STAMP)
	$(BIN)/python benchmarks/bench_kinematics.py
	$(BIN)/python benchmarks/bench_closed_loop.py
	$(BIN)/python benchmarks/bench_indices.py
	$(BIN)/python benchmarks/bench_dynamics.py
	$(BIN)/python benchmarks/bench_requirements.py
	$(BIN)/python benchmarks/bench_sweep.py
	$(BIN)/python benchmarks/bench_stiffness.py
	$(BIN)/python benchmarks/bench_accuracy.py
	$(BIN)/python benchmarks/bench_modes.py
	$(BIN)/python benchmarks/bench_lobes.py
	$(BIN)/python benchmarks/bench_certify.py
	$(BIN)/python benchmarks/bench_calibrate.py
	$(BIN)/python benchmarks/bench_path_forms.py
	$(BIN)/python benchmarks/bench_plan.py
	$(BIN)/python benchmarks/bench_urdf_cache.py
	$(BIN)/python benchmarks/bench_path_forms.py
	$(BIN)/python benchmarks/bench_plan.py

## urdf: regenerate the shipped prototype URDF after editing description/
urdf: $(STAMP)
	$(BIN)/orthoglide urdf -o description/urdf/orthoglide_prototype.urdf

clean:
	rm -rf $(VENV) out build dist *.egg-info .pytest_cache .mypy_cache .ruff_cache $(SITE) docs/api
