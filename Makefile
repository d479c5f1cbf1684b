# mpm-geo: the usual entry points. `make help` lists them.
# CMake does the building; this file only chains the steps and installs what is missing.

SHELL := /bin/sh
.DEFAULT_GOAL := help

BUILD_DIR       := build
DEBUG_DIR       := build-debug
CAF_DIR         := build-caf
FUZZ_DIR        := build-fuzz
FUZZ_SECONDS    := 600
VENV            := .venv
PYTHON          := $(VENV)/bin/python
CASE            := inputs/base_case.json
# the cores this process may use (GNU nproc honours OMP_NUM_THREADS, which is about runs, not builds)
JOBS            := $(shell env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc 2>/dev/null || echo 2)
CTEST_JOBS      := 2
# Python test folders that exist (tests/python may come later).
PYTEST_DIRS      = $(wildcard postproc/tests tests/python)
LINT_DIRS        = $(wildcard src app)

.PHONY: help deps deps-paraview deps-test build build-exe run test test-fortran test-python check lint \
        debug test-debug coarray caf-build test-coarray fuzz bench bench-peers study validate docs clean

help:
	@echo "mpm-geo make targets:"
	@echo "  make run         install what is missing, build, run $(CASE) into outputs/"
	@echo "  make test        install what is missing (with ParaView), build, run all tests (Release"
	@echo "                   and Debug builds) + linter"
	@echo "  make deps        install missing system packages and the Python environment ($(VENV))"
	@echo "  make build       configure $(BUILD_DIR)/ (Release) if needed and build"
	@echo "  make debug       configure $(DEBUG_DIR)/ (Debug: runtime checks, FPE traps) and build"
	@echo "  make test-debug  run the CTest suite of the debug build"
	@echo "  make coarray     install OpenCoarrays if missing, build $(CAF_DIR)/ (-DMPM_COARRAY=ON):"
	@echo "                   cafrun -np N $(CAF_DIR)/mpm_geo case.json (docs/hpc.md)"
	@echo "  make test-coarray  parallel suites of the coarray build on 2 images (skipped with a"
	@echo "                   message when OpenCoarrays is not available)"
	@echo "  make fuzz        install AFL++ if missing, build $(FUZZ_DIR)/, fuzz the case reader for"
	@echo "                   FUZZ_SECONDS=$(FUZZ_SECONDS) s; fails on a crash or hang (docs/testing.md)"
	@echo "  make check       Fortran linter (fortitude) on src/ and app/; 'make lint' is the same"
	@echo "  make bench       run the benchmarks (bench/run_bench.sh)"
	@echo "  make bench-peers B1 beside MPM-Geomechanics: PEER_SOURCE=/path/to/its/clone"
	@echo "  make study       accuracy against cost (bench/run_study.sh -> docs/accuracy-vs-cost.md)"
	@echo "  make validate    run the validation cases (validation/run_all.sh)"
	@echo "  make docs        API pages from the doc comments (FORD, docs/ford.md) -> build/docs/"
	@echo "  make clean       remove $(BUILD_DIR)/, $(DEBUG_DIR)/, $(CAF_DIR)/, $(FUZZ_DIR)/ (outputs/ and $(VENV)/"
	@echo "                   are kept)"

deps:
	@bash scripts/install_deps.sh

deps-paraview:
	@bash scripts/install_deps.sh --with-paraview

# what make test needs: ParaView (XDMF check) and OpenCoarrays (parallel suites)
deps-test:
	@bash scripts/install_deps.sh --with-paraview --with-coarray

# Configure only once: later builds keep the user's cache (options set with cmake -D...).
# A failed first configure leaves a cache behind; remove it so the next make tries again.
# A cache without a generated build system (configure failed later) is configured again.
$(BUILD_DIR)/CMakeCache.txt:
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release || { rm -f $@; exit 1; }

build: $(BUILD_DIR)/CMakeCache.txt
	@[ -f $(BUILD_DIR)/Makefile ] || [ -f $(BUILD_DIR)/build.ninja ] || cmake -S . -B $(BUILD_DIR)
	cmake --build $(BUILD_DIR) -j $(JOBS)

# Only the program (not the test and study programs).
build-exe: $(BUILD_DIR)/CMakeCache.txt
	@[ -f $(BUILD_DIR)/Makefile ] || [ -f $(BUILD_DIR)/build.ninja ] || cmake -S . -B $(BUILD_DIR)
	cmake --build $(BUILD_DIR) -j $(JOBS) --target mpm_geo

# --overwrite: the default run replaces its own previous output; other cases are not touched.
run: deps
	@$(MAKE) --no-print-directory build-exe
	./$(BUILD_DIR)/mpm_geo $(CASE) --overwrite

# The suites run one after the other; --keep-going runs all of them even when one fails
# (make still exits non-zero), so one CI run reports every failure. The Fortran suite runs in
# the Release build and again in the Debug build (bounds checks, floating-point traps).
test: deps-test
	@$(MAKE) --no-print-directory build
	@$(MAKE) --no-print-directory --keep-going -j1 test-fortran test-debug test-coarray \
	    test-python lint

# MPM_STRICT_TESTS=1: a test script whose Python lacks its modules fails instead of being
# skipped (tests/cli/lib.sh), so make test never passes by skipping.
test-fortran:
	MPM_STRICT_TESTS=1 ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(CTEST_JOBS)

test-python:
	@if [ -n "$(PYTEST_DIRS)" ]; then \
	    echo "$(PYTHON) -m pytest -q $(PYTEST_DIRS)"; \
	    $(PYTHON) -m pytest -q $(PYTEST_DIRS); \
	else \
	    echo "no Python tests found"; \
	fi

# Configuration in fortitude.toml; any finding fails.
check lint:
	@test -x $(VENV)/bin/fortitude || bash scripts/install_deps.sh
	$(VENV)/bin/fortitude check $(LINT_DIRS)

$(DEBUG_DIR)/CMakeCache.txt:
	cmake -S . -B $(DEBUG_DIR) -DCMAKE_BUILD_TYPE=Debug || { rm -f $@; exit 1; }

debug: $(DEBUG_DIR)/CMakeCache.txt
	@[ -f $(DEBUG_DIR)/Makefile ] || [ -f $(DEBUG_DIR)/build.ninja ] || cmake -S . -B $(DEBUG_DIR)
	cmake --build $(DEBUG_DIR) -j $(JOBS)

test-debug: debug
	MPM_STRICT_TESTS=1 ctest --test-dir $(DEBUG_DIR) --output-on-failure -j $(CTEST_JOBS)

# The coarray build: its own folder, so the serial builds stay MPI-free.
$(CAF_DIR)/CMakeCache.txt:
	cmake -S . -B $(CAF_DIR) -DCMAKE_BUILD_TYPE=Release -DMPM_COARRAY=ON \
	    -DMPM_SERIAL_EXE=$(CURDIR)/$(BUILD_DIR)/mpm_geo || { rm -f $@; exit 1; }

coarray:
	@bash scripts/install_deps.sh --with-coarray
	@$(MAKE) --no-print-directory caf-build

caf-build: $(CAF_DIR)/CMakeCache.txt
	@[ -f $(CAF_DIR)/Makefile ] || [ -f $(CAF_DIR)/build.ninja ] || cmake -S . -B $(CAF_DIR)
	cmake --build $(CAF_DIR) -j $(JOBS)

# The parallel suites compare with the serial build: build both. Without OpenCoarrays (not
# installed, e.g. MPM_SKIP_SYSTEM_DEPS=1 on another distribution) they are skipped, loudly.
test-coarray:
	@if ! command -v cafrun > /dev/null 2>&1; then \
	    echo "test-coarray: SKIPPED: cafrun not found (OpenCoarrays is not installed;" \
	         "scripts/install_deps.sh --with-coarray installs it)"; \
	else \
	    $(MAKE) --no-print-directory build caf-build && \
	    MPM_STRICT_TESTS=1 ctest --test-dir $(CAF_DIR) --output-on-failure -j 1; \
	fi

# Not part of make test: it runs for FUZZ_SECONDS. Findings go to $(FUZZ_DIR)/afl-out/.
fuzz:
	@bash scripts/install_deps.sh --with-fuzz
	FUZZ_BUILD_DIR=$(CURDIR)/$(FUZZ_DIR) bash tests/fuzz/run_fuzz.sh $(FUZZ_SECONDS)

bench: deps
	@$(MAKE) --no-print-directory build
	@if [ -f bench/run_bench.sh ]; then \
	    bash bench/run_bench.sh; \
	else \
	    echo "no benchmarks yet (bench/run_bench.sh is missing)"; \
	fi

# B1 beside MPM-Geomechanics built from PEER_SOURCE (a clone the user gives; skipped without it)
bench-peers: deps
	@$(MAKE) --no-print-directory build
	bash bench/run_peers.sh "$(PEER_SOURCE)"

# Accuracy against cost (bench/run_study.sh): writes docs/accuracy-vs-cost.md and its figures.
study: deps
	@$(MAKE) --no-print-directory build
	bash bench/run_study.sh $(BUILD_DIR)

validate: deps
	@$(MAKE) --no-print-directory build
	@if [ -f validation/run_all.sh ]; then \
	    bash validation/run_all.sh; \
	else \
	    echo "nothing to validate yet (validation/run_all.sh is missing)"; \
	fi

# API pages (FORD): build/docs/index.html; fails when FORD misreads a doc comment.
docs:
	@bash scripts/make_docs.sh

clean:
	rm -rf $(BUILD_DIR) $(DEBUG_DIR) $(CAF_DIR) $(FUZZ_DIR)
