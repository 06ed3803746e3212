# The user's entry point. `make demo` and `make test` install missing Debian
# packages and build first, so both work on a fresh machine.
#
#   make            build everything, tests included (Release) into $(BUILD)
#   make deps       install missing Debian packages (says what it runs); the
#                   stages' targets (demo, fit, stages) install only theirs
#   make test       builds the tests too, then runs the unit, command-line and script tests (CTest)
#   make demo       builds the stages only, then fits a garment on a generated body
#                   (pipelines/customers/demo); prints the report's path
#   make fit CUSTOMER=dir [OUT=dir]   one customer's fit (see pipelines/fit.mk)
#   make -j2 fit-all CUSTOMERS="dir dir ..."   several customers in parallel
#   make fit-all CUSTOMERS="..." ENGINE=slurm   one Slurm job array on a cluster, summary in fit-batch/
#   make bench      benchmarks -> BENCHMARKS.md and benchmarks/*.png (under 15 min)
#   make fuzz       libFuzzer on the mesh and spec readers, FUZZ_SECONDS per target
#   make update-golden  rewrite testdata/golden/ from the current build, showing what changed
#   make clean      remove the build folder

BUILD  ?= build
JOBS   ?= $(shell nproc 2>/dev/null || echo 2)
PYTHON ?= /usr/bin/python3
CMAKE_BUILD_TYPE ?= Release
export GP_BIN := $(abspath $(BUILD))/bin

FUZZ_SECONDS ?= 600
FUZZ_BUILD ?= build-fuzz
FUZZ_TARGETS := read_mesh read_spec

.PHONY: all build stages deps deps-stages configure configure-stages test demo fit fit-all fit-summary bench fuzz update-golden clean help

all: build

help:
	@sed -n '1,14p' Makefile

deps:
	@scripts/install-deps.sh

# What the stages need to build and run, without the tests' and benchmarks'
# packages (Chromium, Slurm, poppler, the Python checks' modules): the first
# `make demo` of a fresh machine waits for no test tool.
deps-stages:
	@scripts/install-deps.sh --demo

define CONFIGURE
	@if [ ! -f $(BUILD)/CMakeCache.txt ]; then \
	  echo "cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=$(CMAKE_BUILD_TYPE) -DGP_UNITY_BUILD=ON"; \
	  cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=$(CMAKE_BUILD_TYPE) -DGP_UNITY_BUILD=ON >/dev/null; \
	fi
endef

configure: deps
	$(CONFIGURE)

configure-stages: deps-stages
	$(CONFIGURE)

build: configure
	cmake --build $(BUILD) -j$(JOBS)

# The stage executables alone (every tools/<stage>/), which is all that the
# demo and the fits run: the test binaries take more than half of the build's
# CPU time and are built by `make test` (README.md, "Building").
STAGE_TOOLS := $(notdir $(patsubst %/CMakeLists.txt,%,$(sort $(wildcard tools/*/CMakeLists.txt))))
stages: configure-stages
	cmake --build $(BUILD) -j$(JOBS) --target $(STAGE_TOOLS)

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

DEMO_OUT ?= demo-out
demo: stages
	@$(MAKE) --no-print-directory -f pipelines/fit.mk CUSTOMER=pipelines/customers/demo OUT=$(DEMO_OUT) BIN=$(GP_BIN)

fit: stages
	@$(MAKE) --no-print-directory -f pipelines/fit.mk CUSTOMER=$(CUSTOMER) $(if $(OUT),OUT=$(OUT)) BIN=$(GP_BIN)

# Several customers. ENGINE=local (the default): on this machine, in parallel
# with -j: make -j2 fit-all CUSTOMERS="a b". ENGINE=slurm: one Slurm job array
# on a cluster, one task per customer, and a summary job that writes
# $(BATCH)/summary.json and summary.html (scripts/fit_batch.py; README.md,
# "Many customers on a cluster"). The repository, $(BUILD), the customers and
# $(BATCH) must be on storage that the compute nodes share.
#   WAIT=1             return when the summary is written, with its exit code
#   SBATCH_FLAGS=...   more sbatch options, e.g. --partition=cpu --account=shop
#   OUT_ROOT=dir       fit outputs in dir/<customer name> (default: each customer's out/)
#   MAX_RUNNING=n      at most n fits at once
ENGINE ?= local
BATCH  ?= fit-batch
ifeq ($(ENGINE),slurm)
fit-all: stages
	$(PYTHON) scripts/fit_batch.py submit --batch $(BATCH) --bin $(GP_BIN) $(if $(WAIT),--wait) \
	  $(if $(SBATCH_FLAGS),--sbatch-flags '$(SBATCH_FLAGS)') $(if $(OUT_ROOT),--out-root $(OUT_ROOT)) \
	  $(if $(MAX_RUNNING),--max-running $(MAX_RUNNING)) $(CUSTOMERS)
else ifeq ($(ENGINE),local)
fit-all: stages
	@$(MAKE) --no-print-directory $(addprefix fit-customer/,$(CUSTOMERS))
else
fit-all:
	@echo "fit-all: ENGINE must be local or slurm, not '$(ENGINE)'" >&2; exit 2
endif

# The summary of a Slurm batch written again (the summary job writes it).
fit-summary:
	$(PYTHON) scripts/fit_batch.py summary --batch $(BATCH)

fit-customer/%:
	@$(MAKE) --no-print-directory -f pipelines/fit.mk CUSTOMER=$* BIN=$(GP_BIN)

# Builds only the stages (in $(BUILD); e.g. make bench BUILD=build-bench), then
# runs them; BENCH_FLAGS=--quick for a reduced run while developing.
BENCH_FLAGS ?=
bench: deps stages
	$(PYTHON) scripts/bench.py --bin $(GP_BIN) --out BENCHMARKS.md --plots benchmarks $(BENCH_FLAGS)

update-golden: build
	$(PYTHON) scripts/golden.py --bin $(GP_BIN) --update

# Crashes are written to $(FUZZ_BUILD)/crash-<target>-*; a crash input, once
# fixed, belongs in testdata/fuzz/<target>/ where a unit test replays it.
fuzz:
	@scripts/install-deps.sh --fuzz
	cmake -S . -B $(FUZZ_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
	  -DGP_BUILD_FUZZERS=ON -DGP_BUILD_TESTS=OFF >/dev/null
	cmake --build $(FUZZ_BUILD) -j$(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS))
	@set -e; for t in $(FUZZ_TARGETS); do \
	  mkdir -p $(FUZZ_BUILD)/corpus/$$t; cp testdata/fuzz/$$t/* $(FUZZ_BUILD)/corpus/$$t/; \
	  echo "fuzz: $$t for $(FUZZ_SECONDS) s"; \
	  status=0; LSAN_OPTIONS=suppressions=$(CURDIR)/testdata/fuzz/lsan-suppressions.txt $(FUZZ_BUILD)/bin/fuzz_$$t $(FUZZ_BUILD)/corpus/$$t -max_total_time=$(FUZZ_SECONDS) \
	    -max_len=65536 -artifact_prefix=$(FUZZ_BUILD)/crash-$$t- -print_final_stats=1 \
	    > $(FUZZ_BUILD)/$$t.log 2>&1 || status=$$?; \
	  tail -n 12 $(FUZZ_BUILD)/$$t.log; \
	  if [ $$status -ne 0 ]; then echo "fuzz: $$t found a problem (log: $(FUZZ_BUILD)/$$t.log)"; exit 1; fi; \
	done

clean:
	rm -rf $(BUILD) $(FUZZ_BUILD)
