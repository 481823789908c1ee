# dem2d: reproduction of a DEM study of an intruder pulled out of a granular bed.
# Every target installs missing Debian packages first (make deps).
#
#   make deps       install the Debian packages the project needs (apt-get)
#   make build      optimised build: build/release/sim/dem2d
#   make test       unit + physics tests (optimised build), then the quick
#                   tests again under AddressSanitizer + UBSan
#   make bench      ns per particle-step on the standard settled bed
#   make reproduce  the study, PRESET=default (or paper), into results/<preset>/
#   make fill       stage: hopper filling, bed metrics   (results/<preset>/fill/)
#   make pulloff    stage: intruder pull-off, drag      (results/<preset>/pulloff/)
#   make pulloff-slice  the first 5 mm of the pull-off only: the preset's cost (results/<preset>/pulloff_5mm/)
#   make spectrum   stage: drag spectrum, loading/rupture events, top layer  (results/<preset>/spectrum/)
#   make cg         stage: coarse-grained fields, mobility zones, cone angle (results/<preset>/cg/)
#   make network    stage: force network, percolation, keystones             (results/<preset>/network/)
#   make friction   stage: friction mobilisation                             (results/<preset>/friction/)
#   make clean      remove build/ (results/ stays)

SHELL := /bin/bash
JOBS ?= $(shell nproc)
BUILD := build/release
SANITIZE_BUILD := build/sanitize
DEM2D := $(BUILD)/sim/dem2d
BED_METRICS := $(BUILD)/analysis/bed_metrics
PULLOFF_METRICS := $(BUILD)/analysis/pulloff_metrics
SPECTRUM := $(BUILD)/analysis/spectrum
CG := $(BUILD)/analysis/cg
NETWORK := $(BUILD)/analysis/network
FRICTION := $(BUILD)/analysis/friction

PRESET ?= default
PRESET_FILE := pipeline/presets/$(PRESET).toml
RESULTS := results/$(PRESET)
THREADS ?= $(JOBS)

DEBIAN_PACKAGES := g++ cmake make pkg-config git \
  libeigen3-dev libboost-graph-dev libfftw3-dev libhdf5-dev \
  libgtest-dev libtomlplusplus-dev libcli11-dev nlohmann-json3-dev \
  python3-h5py python3-numpy python3-matplotlib
SUDO := $(shell [ "$$(id -u)" -eq 0 ] || echo sudo)

.PHONY: deps build test test-release test-sanitize bench reproduce fill pulloff pulloff-slice spectrum cg \
  network friction clean FORCE

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
	cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	cd $(SANITIZE_BUILD) && ctest --output-on-failure -j $(JOBS) -L quick

bench: build
	$(DEM2D) bench

# --- the study's stages: file targets, so only what is stale reruns --------
# The programs are always asked to build (a no-op when up to date); a stage
# reruns only when its inputs or its program actually changed. An interrupted
# simulation stage resumes from its checkpoint when rerun.
$(DEM2D) $(BED_METRICS) $(PULLOFF_METRICS) $(SPECTRUM) $(CG) $(NETWORK) $(FRICTION): FORCE | $(BUILD)/CMakeCache.txt
	@cmake --build $(BUILD) -j $(JOBS) --target $(notdir $@) > $(BUILD)/$(notdir $@).build.log || \
	  (cat $(BUILD)/$(notdir $@).build.log; exit 1)

ifeq ($(wildcard $(PRESET_FILE)),)
$(error PRESET=$(PRESET): there is no $(PRESET_FILE); use PRESET=default or PRESET=paper)
endif

$(RESULTS)/fill/run.h5: pipeline/fill.toml $(PRESET_FILE) $(DEM2D)
	$(DEM2D) run pipeline/fill.toml --overlay $(PRESET_FILE) --out $(@D) --threads $(THREADS)

$(RESULTS)/fill/metrics.json: $(RESULTS)/fill/run.h5 data/bed_metrics.toml $(BED_METRICS)
	$(BED_METRICS) $< --out $@

$(RESULTS)/pulloff/run.h5: pipeline/pulloff.toml $(PRESET_FILE) $(RESULTS)/fill/run.h5 $(DEM2D)
	$(DEM2D) run pipeline/pulloff.toml --overlay $(PRESET_FILE) --initial $(RESULTS)/fill/run.h5 \
	  --out $(@D) --threads $(THREADS)

$(RESULTS)/pulloff/metrics.json: $(RESULTS)/pulloff/run.h5 data/study.toml $(PULLOFF_METRICS)
	$(PULLOFF_METRICS) $< --out $@ --csv $(@D)/drag.csv

$(RESULTS)/pulloff_5mm/run.h5: pipeline/pulloff.toml $(PRESET_FILE) pipeline/slice_5mm.toml $(RESULTS)/fill/run.h5 $(DEM2D)
	$(DEM2D) run pipeline/pulloff.toml --overlay $(PRESET_FILE) --overlay pipeline/slice_5mm.toml \
	  --initial $(RESULTS)/fill/run.h5 --out $(@D) --threads $(THREADS)

$(RESULTS)/pulloff_5mm/metrics.json: $(RESULTS)/pulloff_5mm/run.h5 data/study.toml $(PULLOFF_METRICS)
	$(PULLOFF_METRICS) $< --out $@ --csv $(@D)/drag.csv

PULLOFF_RUN := $(RESULTS)/pulloff/run.h5

$(RESULTS)/spectrum/metrics.json: $(PULLOFF_RUN) $(RESULTS)/fill/metrics.json data/spectrum.toml data/study.toml \
                                  $(SPECTRUM)
	$(SPECTRUM) $< --out $(@D) --fill-metrics $(RESULTS)/fill/metrics.json

$(RESULTS)/cg/metrics.json: $(PULLOFF_RUN) $(RESULTS)/spectrum/metrics.json data/cg.toml data/study.toml $(CG)
	$(CG) $< --out $(@D) --events $(RESULTS)/spectrum/spectrum.h5 --threads $(THREADS)

$(RESULTS)/network/metrics.json: $(PULLOFF_RUN) $(RESULTS)/spectrum/metrics.json data/network.toml data/study.toml \
                                 $(NETWORK)
	$(NETWORK) $< --out $(@D) --events $(RESULTS)/spectrum/spectrum.h5 \
	  --spectrum-metrics $(RESULTS)/spectrum/metrics.json

$(RESULTS)/friction/metrics.json: $(PULLOFF_RUN) data/friction.toml data/study.toml $(FRICTION)
	$(FRICTION) $< --out $(@D)

fill: $(RESULTS)/fill/metrics.json
pulloff: $(RESULTS)/pulloff/metrics.json
pulloff-slice: $(RESULTS)/pulloff_5mm/metrics.json
spectrum: $(RESULTS)/spectrum/metrics.json
cg: $(RESULTS)/cg/metrics.json
network: $(RESULTS)/network/metrics.json
friction: $(RESULTS)/friction/metrics.json

reproduce: fill pulloff spectrum cg network friction
	@echo "make reproduce: the stages of $(RESULTS) are up to date."
	@echo "Not implemented yet: the merged metrics.json, tolerance tests, figures and report (issue 7)."

clean:
	rm -rf build
