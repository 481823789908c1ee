# dem2d: reproduction of a DEM study of an intruder pulled out of a granular bed.
# Every target installs missing Debian packages first (make deps).
#
#   make deps       install the Debian packages the project needs (apt-get)
#   make build      optimised build: build/release/sim/dem2d
#   make test       unit + physics tests (optimised build), then the quick
#                   tests again under AddressSanitizer + UBSan
#   make bench      ns per particle-step on the standard settled bed
#   make reproduce  the whole study (not yet: see README, "Status")
#   make clean      remove build/

SHELL := /bin/bash
JOBS ?= $(shell nproc)
BUILD := build/release
SANITIZE_BUILD := build/sanitize
DEM2D := $(BUILD)/sim/dem2d

DEBIAN_PACKAGES := g++ cmake make pkg-config git \
  libeigen3-dev libboost-graph-dev libfftw3-dev libhdf5-dev \
  libgtest-dev libtomlplusplus-dev libcli11-dev nlohmann-json3-dev \
  python3-h5py python3-numpy python3-matplotlib
SUDO := $(shell [ "$$(id -u)" -eq 0 ] || echo sudo)

.PHONY: deps build test test-release test-sanitize bench reproduce clean

deps:
	@missing=$$(for p in $(DEBIAN_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "make deps: installing" $$missing; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	fi

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release

build: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

$(SANITIZE_BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(SANITIZE_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDEM2D_SANITIZE=ON

test: test-release test-sanitize

test-release: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

test-sanitize: deps $(SANITIZE_BUILD)/CMakeCache.txt
	cmake --build $(SANITIZE_BUILD) -j $(JOBS) --target unit_tests dem2d bed_metrics
	cd $(SANITIZE_BUILD) && ctest --output-on-failure -j $(JOBS) -L quick

bench: build
	$(DEM2D) bench

reproduce:
	@echo "make reproduce: the study's scenes (issue 3) and analysis stages (issues 4-7) are not"; \
	echo "implemented yet; this checkout provides the DEM engine only (see README.md, Status)."; \
	exit 1

clean:
	rm -rf build
