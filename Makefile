# The user's entry point. `make demo` and `make test` install missing Debian
# packages and build first, so both work on a fresh machine.
#
#   make            build everything (Release) into $(BUILD)
#   make deps       install missing Debian packages (says what it runs)
#   make test       unit, command-line and script tests (CTest)
#   make demo       fit a garment on a generated body (see pipelines/demo.mk)
#   make bench      benchmarks -> BENCHMARKS.md and bench-out/ plots
#   make clean      remove the build folder

BUILD  ?= build
JOBS   ?= $(shell nproc 2>/dev/null || echo 2)
PYTHON ?= /usr/bin/python3
CMAKE_BUILD_TYPE ?= Release
export GP_BIN := $(abspath $(BUILD))/bin

.PHONY: all build deps configure test demo bench clean help

all: build

help:
	@sed -n '1,12p' Makefile

deps:
	@scripts/install-deps.sh

configure: deps
	@if [ ! -f $(BUILD)/CMakeCache.txt ]; then \
	  echo "cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=$(CMAKE_BUILD_TYPE)"; \
	  cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=$(CMAKE_BUILD_TYPE) >/dev/null; \
	fi

build: configure
	cmake --build $(BUILD) -j$(JOBS)

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

demo: build
	@$(MAKE) --no-print-directory -f pipelines/demo.mk BIN=$(GP_BIN) PYTHON=$(PYTHON)

bench: build
	$(PYTHON) scripts/bench.py --bin $(GP_BIN) --out BENCHMARKS.md --plots bench-out

clean:
	rm -rf $(BUILD)
