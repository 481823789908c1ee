# dem2d: reproduction of a DEM study of an intruder pulled out of a granular bed.
# A first build installs missing Debian packages when run as root, and names
# them otherwise (docs/install.md: other systems, no root).
#
#   make deps       install the Debian packages the project and its tests need (apt-get, sudo unless root)
#   make build      optimised portable build of the programs: build/release/sim/dem2d, the stages
#                   (NATIVE=ON: -march=native, build/native); the tests build with make test
#   make install    PREFIX=DIR (default /usr/local): bin/dem2d, libexec/dem2d/<stage>, share/dem2d/data,
#                   from the same build as make build
#   make test       the tests of the optimised build (make test-pipeline's and make test-cluster's among
#                   them), then those that exercise memory again under AddressSanitizer + UBSan
#   make bench      ns per particle-step on the standard settled bed
#   make bench-passes  where the step's time goes: each thread's time per pass, 1 and 2 threads
#   make bench-scaling  ns per particle-step for N = 1.6e3 ... 1e6 disks (copies of that bed side by side)
#   make bench-compare  dem2d against LAMMPS (installs lammps) on the same settled bed, 1 and 2 cores
#                   (results/bench_compare/compare.md)
#   make reproduce  the study, PRESET=default (or fast, paper), into results/<preset>/: every stage,
#                   metrics.json, the tolerance tests (check.json), figures/, report.md and report.html
#   make check      the tolerance tests: results/<preset>/metrics.json against data/paper_targets.toml
#   make test-pipeline  the whole pipeline on the small test scene (PRESET=quick), its outputs checked
#   make test-cluster   a 2-member quick ensemble through a real one-node Slurm cluster (started and
#                   stopped here; root) against the pipeline's, made locally: bitwise the same
#   make fill       stage: hopper filling, bed metrics   (results/<preset>/fill/)
#   make pulloff    stage: intruder pull-off, drag      (results/<preset>/pulloff/)
#   make pulloff-slice  the first 5 mm of the pull-off only: the preset's cost (results/<preset>/pulloff_5mm/;
#                   BED_FROM=<preset> starts it from another preset's bed)
#   make cyclic     cyclic loading from the preset's bed (pipeline/cyclic.toml): the intruder driven up
#                   and down, its drag cut into cycles (results/<preset>/cyclic/cycles.csv, metrics.json)
#   make spectrum   stage: drag spectrum, loading/rupture events, top layer  (results/<preset>/spectrum/)
#   make cg         stage: coarse-grained fields, mobility zones, cone angle (results/<preset>/cg/)
#   make network    stage: force network, percolation, keystones             (results/<preset>/network/)
#   make friction   stage: friction mobilisation                             (results/<preset>/friction/)
#   make metrics figures report   the merged metrics, the figures, the report of results/<preset>/
#   make paraview   the force network at H = 34 mm rendered by ParaView from the pull-off's run.xdmf
#                   (results/<preset>/figures/force_network_paraview.png)
#   make validate   validation cases against analytic and established results (Chung & Ooi impacts,
#                   rolling, statics, energy error order, stability limit, Janssen, Beverloo, repose):
#                   results/validate/table.md and figures
#   make ensemble   MEMBERS (default 4) independent realisations of the study (other grain seeds), each
#                   its whole pipeline, and their aggregate: results/<preset>/ensemble/ (stats.json,
#                   table.md; docs/ensemble.md). EXECUTOR=local runs JOBS members side by side
#   make params     the parametric study of the paper's claims (data/params.toml; PLAN=reduced, full, test;
#                   EXECUTOR=slurm): results/params/report.md (docs/params.md)
#   make accuracy   the accuracy/cost sweep of data/accuracy.toml (use make -j2): results/accuracy/
#                   table.md, pareto.png (pipeline/accuracy/README.md)
#   make clean      remove build/ (results/ stays)

SHELL := /bin/bash
include pipeline/make_vars.mk
JOBS ?= $(shell nproc)
$(call check_count,JOBS,1,1024)
# NATIVE=ON: optimised for this machine's CPU (-march=native) in build/native; by default one
# portable build (any x86-64) in build/release serves the study, the tests and make install
NATIVE ?= OFF
$(call check_name,NATIVE,ON OFF)
BUILD := build/$(if $(filter ON,$(NATIVE)),native,release)
# the analysis stages' registry (docs/stages.md)
STAGE_REGISTRY ?= pipeline/stages.toml
# the scripts make runs read the same registry (absolute: a test or a job may run elsewhere)
export DEM2D_STAGE_REGISTRY := $(abspath $(STAGE_REGISTRY))
SANITIZE_BUILD := build/sanitize
# INSTALLED=DIR: the study's targets run the programs of `make install PREFIX=DIR`
# (DIR/bin/dem2d, DIR/libexec/dem2d/<stage>) instead of building them here
INSTALLED ?=
ifeq ($(INSTALLED),)
DEM2D := $(BUILD)/sim/dem2d
STAGE_BIN := $(BUILD)/analysis
CHECK := $(BUILD)/tests/paper_targets/check_paper_targets
else
DEM2D := $(INSTALLED)/bin/dem2d
STAGE_BIN := $(INSTALLED)/libexec/dem2d
CHECK := $(STAGE_BIN)/check_paper_targets
endif
# any Python with h5py, numpy and matplotlib (Debian's python3-* by default): make PYTHON=...
ifeq ($(origin PYTHON),undefined)
PYTHON := $(shell [ -x /usr/bin/python3 ] && echo /usr/bin/python3 || echo python3)
endif
export PYTHON
REPORT_SCRIPTS := pipeline/report

PRESET ?= default
# INTRUDER=square: the experiment's square-ended 10 mm x 2 mm bar (pipeline/intruders/square.toml)
# instead of the paper's sphero-line (docs/paper.md), into results/<preset>_square/
INTRUDER ?=
RESULTS := results/$(PRESET)$(if $(INTRUDER),_$(INTRUDER))
ifeq ($(PRESET),quick)
# the pipeline's end-to-end test: the small scenes of the tests, as they are
FILL_SCENE := tests/scenes/quick_fill.toml
PULLOFF_SCENE := tests/scenes/quick_pulloff.toml
CYCLIC_SCENE := tests/scenes/quick_cyclic.toml
PRESET_FILE :=
else
FILL_SCENE := pipeline/fill.toml
PULLOFF_SCENE := pipeline/pulloff.toml
CYCLIC_SCENE := pipeline/cyclic.toml
PRESET_FILE := pipeline/presets/$(PRESET).toml
endif
# POINT_OVERLAY: more overlays after the preset's (make accuracy: one sweep point's knob);
# FILL_OVERLAY: one more for the fill only (make ensemble: a member's grain seeds).
OVERLAY_FILES := $(PRESET_FILE) $(if $(INTRUDER),pipeline/intruders/$(INTRUDER).toml) $(POINT_OVERLAY)
OVERLAY := $(foreach f,$(OVERLAY_FILES),--overlay $(f))
# FILL_RUN: the bed the pull-off starts from; by default the preset's own fill
# (make accuracy gives each sweep point a bed made elsewhere).
FILL_RUN ?= $(RESULTS)/fill/run.h5
# OpenMP threads per simulation and stage; unset: each simulation chooses from its size and the cores
# free when it starts (docs/engine.md, "Thread count"), each stage takes its own default
THREADS ?=
$(if $(THREADS),$(call check_count,THREADS,1,1024))
THREADS_OPTION = $(if $(THREADS),--threads $(THREADS))
$(call check_name,PRESET,$(PRESET_NAMES))
$(if $(INTRUDER),$(call check_name,INTRUDER,$(INTRUDER_NAMES)))
# seconds of wall time between a simulation's progress lines (in the make log and DIR/run.log)
PROGRESS ?= 60
$(call check_count,PROGRESS,1,86400)

# Debian's packages for building and running the study; the tests' own (pytest, ParaView's Python)
DEBIAN_PACKAGES := g++ cmake make pkg-config git \
  libeigen3-dev libboost-graph-dev libfftw3-dev libhdf5-dev libcairo2-dev \
  libgtest-dev libtomlplusplus-dev libcli11-dev nlohmann-json3-dev \
  python3-h5py python3-numpy python3-matplotlib python3-markdown
TEST_PACKAGES := python3-pytest python3-paraview xvfb
# how packages are installed: directly as root, else through sudo when there is one (SUDO= : none)
SUDO ?= $(shell [ "$$(id -u)" -eq 0 ] || command -v sudo)

.PHONY: paraview deps needs needs-test build build-tests install test test-release test-sanitize test-pipeline test-cluster fuzz bench bench-passes bench-scaling bench-compare reproduce check validate \
  pulloff-slice cyclic metrics figures report accuracy ensemble clean FORCE
.DEFAULT_GOAL := build
# a recipe that fails never leaves its target behind for a later make to take as done
.DELETE_ON_ERROR:

# $(call missing,PACKAGES): those of the Debian PACKAGES not installed (none off Debian)
missing = $$(command -v dpkg >/dev/null && for p in $(1); do dpkg -s $$p >/dev/null 2>&1 || echo $$p; done)
# $(call apt_install,SUDO): installs the packages in $$m with apt-get
apt_install = echo "make: installing Debian packages:" $$m; \
  $(1) apt-get update -qq && DEBIAN_FRONTEND=noninteractive $(1) apt-get install -y -qq --no-install-recommends $$m
# $(call for_admin,WHO): says what is missing ($$m) and the one command an administrator runs
for_admin = echo "$(1): missing Debian packages:" $$m; \
  echo "  an administrator installs them with: apt-get install -y --no-install-recommends" $$m
# make deps: what a user asks for: installs the missing packages (as root, or through sudo); without
# either, names the command an administrator runs (exit 2). It needs nothing it installs.
deps:
	@m="$(call missing,$(DEBIAN_PACKAGES) $(TEST_PACKAGES))"; \
	if [ -z "$$m" ]; then echo "make deps: nothing missing"; \
	elif [ "$$(id -u)" -eq 0 ] || [ -n "$(SUDO)" ]; then $(call apt_install,$(SUDO)); \
	else $(call for_admin,make deps); echo "  (this account is not root and has no sudo)"; exit 2; fi
# Before a first configure: the missing packages are installed when we are root
# on Debian (a fresh machine, CI); otherwise named, with how to get them (docs/install.md).
# Off Debian nothing is checked: CMake names what it cannot find. NO_DEPS=1 skips the check.
NO_DEPS ?=
needs needs-test: PACKAGES = $(DEBIAN_PACKAGES) $(if $(filter needs-test,$@),$(TEST_PACKAGES))
needs needs-test:
	@[ -n "$(NO_DEPS)" ] || { m="$(call missing,$(PACKAGES))"; [ -z "$$m" ] || \
	  if [ "$$(id -u)" -eq 0 ]; then $(call apt_install,); \
	  else $(call for_admin,make); \
	    echo "  (or \`make deps\`, through sudo; other systems: docs/install.md); NO_DEPS=1 skips this check"; exit 2; fi; }

# (configured again when the stage registry changes: a new stage's folder becomes a target)
$(BUILD)/CMakeCache.txt: $(STAGE_REGISTRY) | needs
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DDEM2D_NATIVE=$(NATIVE) -DDEM2D_PYTHON=$(PYTHON)
	@touch $@

# the programs only (what make install installs); the tests build with make test
build: $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS) --target installed

build-tests: $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

# ASan+UBSan where they find something: assertions on (no NDEBUG: Boost's own
# checks run), -g1, two specialised kernels (the rest on the generic one, which
# holds every term), only the tests that exercise memory (tests/CMakeLists.txt).
# -O2 for the engine and the readers (at -O1 everywhere the tests took 554
# processor-s instead of 498 and the build saved 104 of 635); the stages' own
# code at -O1 (analysis/CMakeLists.txt: the build 302 -> 243 s, the tests
# 228 -> 236 s); the test programs' own code at -O0 (CMakeLists.txt). In batches, as the
# optimised build: one object a source left 7 min of it after the optimised
# build's tests in a clean make test, against 5.3 min
$(SANITIZE_BUILD)/CMakeCache.txt: | needs
	cmake -S . -B $(SANITIZE_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1" \
	  -DDEM2D_SANITIZE=ON -DDEM2D_KERNEL_SETS=$(abspath tests/sanitize_kernel_sets.inc) -DDEM2D_PYTHON=$(PYTHON)

# The optimised build and its tests, then the ASan+UBSan build and its tests,
# one after the other, each at the full -j. Every phase keeps both cores busy
# (the optimised tests: 0.7 % idle), so nothing runs beside another: the
# ASan+UBSan build compiling beside the optimised tests, even at the lowest
# priority, stretched them from 400 to 486 s in a clean clone and itself got
# ~40 processor-s done; at normal priority, 449 -> 957 s (their multi-threaded
# runs wait at every step for the threads a compiler holds).
test: needs-test build-tests $(SANITIZE_BUILD)/CMakeCache.txt
	@$(MAKE) --no-print-directory test-release
	@$(MAKE) --no-print-directory test-sanitize

# ctest's output kept beside the build; tests/ctest_summary.sh prints the
# counts and fails on a failed, skipped or not-run test (a skip proves nothing).
# One job more than the cores: the cluster test mostly waits on Slurm.
# NO_CLUSTER=1: without the cluster tests (they need root), said in the summary.
NO_CLUSTER ?=
test-release: needs-test build-tests
	cd $(BUILD) && mkdir -p Testing && set -o pipefail && \
	  ctest --output-on-failure -j $$(($(JOBS) + 1)) $(if $(NO_CLUSTER),-E '^cluster') 2>&1 | tee Testing/make_test.log
	tests/ctest_summary.sh $(BUILD)/Testing/make_test.log "make test (optimised build)"
	$(if $(NO_CLUSTER),@echo "make test: the cluster tests were NOT run (NO_CLUSTER=1): the Slurm executor is untested")

test-sanitize: needs-test $(SANITIZE_BUILD)/CMakeCache.txt
	cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	cd $(SANITIZE_BUILD) && mkdir -p Testing && set -o pipefail && ctest --output-on-failure -j $(JOBS) 2>&1 | tee Testing/make_test.log
	tests/ctest_summary.sh $(SANITIZE_BUILD)/Testing/make_test.log "make test (ASan+UBSan build)"

# The whole pipeline on the small scene (into results/quick/), then its
# outputs and the Makefile's staleness rules checked.
test-pipeline: build-tests
	$(MAKE) --no-print-directory reproduce PRESET=quick THREADS=$(THREADS)
	tests/pipeline_test.sh results/quick

# The input-and-fault suite in full (docs/fuzz.md) on the release and the
# ASan+UBSan builds: counts per class and outcome; fails on any defect. The
# classes of the layers above the programs (pipeline, install, slurm) on the
# release build only (the ASan+UBSan build has the programs and the tests
# that exercise memory, not make check's program).
FUZZ_SEED ?= 1
fuzz: build-tests $(SANITIZE_BUILD)/CMakeCache.txt
	cmake --build $(SANITIZE_BUILD) -j $(JOBS)
	$(PYTHON) tests/fuzz/fuzz.py --bin $(BUILD) --seed $(FUZZ_SEED) --jobs $(JOBS)
	$(PYTHON) tests/fuzz/fuzz.py --bin $(SANITIZE_BUILD) --seed $(FUZZ_SEED) --jobs $(JOBS) \
	  --only scene,config,runfile,reader,fault

# The Slurm executor on a real one-node Slurm cluster started and stopped
# here (installs munge and slurm-wlm as root; otherwise it says loudly why it
# cannot, and fails: a skip proves nothing). make test runs it through ctest.
test-cluster: build-tests
	tests/slurm_test.sh

# make install PREFIX=DIR: dem2d in DIR/bin, the stages' programs in DIR/libexec/dem2d,
# data/ and code_version.txt in DIR/share/dem2d (found relative to the programs), the
# engine's libraries, headers and CMake package (find_package(dem2d); docs/install.md).
# The build make build made (portable unless NATIVE=ON): built now only if it is not yet.
PREFIX ?= /usr/local
install: $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS) --target installed
	cmake --install $(BUILD) --prefix $(PREFIX)

bench: build
	$(DEM2D) bench

# where the step's time goes: each thread's time per pass, 1 and 2 threads
bench-passes: build
	$(DEM2D) bench --passes --repeat 3 --json results/bench_passes.json

# N = 1600 x (1, 6, 63, 625) disks: copies of the settled bed in cells side by side
bench-scaling: build
	$(DEM2D) bench --tiles 1 6 63 625 --repeat 3 --json results/bench_scaling.json

bench-compare: build
	@$(MAKE) --no-print-directory needs DEBIAN_PACKAGES=lammps
	$(PYTHON) -m pipeline.bench_compare.compare data/bench/compare.toml $(DEM2D) results/bench_compare

# --- the study's stages: file targets, so only what is stale reruns --------
# The analysis stages' rules come from their registry, pipeline/stages.toml
# (generated into $(BUILD)/registries/<its path>.mk; docs/stages.md).
# one file per registry path (registries/<its absolute path>.mk): two registries named alike never share one
STAGES_MK := $(BUILD)/registries$(abspath $(STAGE_REGISTRY)).mk
# (not for make deps or clean alone: the installer must not need what it installs)
ifneq ($(if $(MAKECMDGOALS),$(filter-out clean deps,$(MAKECMDGOALS)),build),)
include $(STAGES_MK)
endif
$(STAGES_MK): $(STAGE_REGISTRY) pipeline/stages.py | needs
	@mkdir -p $(@D)
	$(PYTHON) -m pipeline.stages make $(STAGE_REGISTRY) > $@.tmp && mv $@.tmp $@


# The programs are always asked to build, all at once (CMake's target
# `installed`: a no-op when up to date, ~1 s where one build a program took ~1 s
# each; one build at a time in the tree, as make -j may ask for several at once);
# a stage reruns only when its inputs or its program actually changed. An
# interrupted simulation stage resumes from its checkpoint when rerun.
# PROGRAMS_BUILT=1 (internal): a sub-make of one that has just built them (an
# ensemble's members) takes them as they are (~2.5 processor-s a check).
ifeq ($(INSTALLED)$(PROGRAMS_BUILT),)
$(DEM2D) $(STAGE_PROGRAMS) $(CHECK) &: FORCE | $(BUILD)/CMakeCache.txt
	@MAKEFLAGS= flock $(BUILD)/.build.lock cmake --build $(BUILD) -j $(JOBS) --target installed > $(BUILD)/programs.build.log || \
	  (cat $(BUILD)/programs.build.log; exit 1)
else
$(DEM2D) $(STAGE_PROGRAMS) $(CHECK):
	@echo "make: $(if $(INSTALLED),INSTALLED=$(INSTALLED) has no $@: run make install PREFIX=$(INSTALLED) first,$@ is missing (the calling make built the programs))" >&2; exit 1
endif

# $(call timed,COMMAND): runs COMMAND (one program and its words, parsed by the
# shell into an array: never run as shell text), then records its wall time
# beside the target ($(@D)/timing.json, read into the cost table of the
# report). When it fails, says how to remake a missing or corrupt input.
# $(call started,WHAT): a line saying which stage starts, where, and when
started = echo "make: $(1) $(@D) started $$(date +%T)"
simulating = $(call started,simulation) && echo "  (a progress line every $(PROGRESS) s of wall time, also in $(@D)/run.log)"
# every simulation's: its threads, its progress lines; --overwrite: make
# reruns a simulation only when its run.h5 is out of date (its scene, an
# overlay, the run it starts from or dem2d is newer), and the new run then
# replaces the finished one (an unfinished one is resumed)
RUN_OPTIONS = $(THREADS_OPTION) --progress $(PROGRESS) --overwrite
timed = $(call started,stage) && cmd=($(1)) && echo "  $${cmd[*]}" && t0=$$(date +%s.%N) && \
  { "$${cmd[@]}" || { echo "make: $(@D) failed. If the message above names a missing or corrupt input file, delete it and run \`make reproduce PRESET=$(PRESET)\`, which remakes it." >&2; exit 1; }; } && awk -v t0=$$t0 -v t1=$$(date +%s.%N) \
  'BEGIN { printf "{\"wall_seconds\": %.3f}\n", t1 - t0 }' > $(@D)/timing.json.tmp && \
  mv $(@D)/timing.json.tmp $(@D)/timing.json

ifeq ($(FILL_RUN),$(RESULTS)/fill/run.h5)
$(RESULTS)/fill/run.h5: $(FILL_SCENE) $(OVERLAY_FILES) $(FILL_OVERLAY) $(DEM2D)
	@$(simulating)
	$(DEM2D) run $(FILL_SCENE) $(OVERLAY) $(if $(FILL_OVERLAY),--overlay $(FILL_OVERLAY)) --out $(@D) $(RUN_OPTIONS)
endif

$(RESULTS)/pulloff/run.h5: $(PULLOFF_SCENE) $(OVERLAY_FILES) $(FILL_RUN) $(DEM2D)
	@$(simulating)
	$(DEM2D) run $(PULLOFF_SCENE) $(OVERLAY) --initial $(FILL_RUN) --out $(@D) $(RUN_OPTIONS)

# The slice starts from the bed of preset BED_FROM (default: the same preset):
# `make pulloff-slice PRESET=paper BED_FROM=default` measures the paper's cost
# without its 1.7e8-step fill.
BED_FROM ?= $(PRESET)
SLICE_DIR := $(RESULTS)/pulloff_5mm$(if $(filter-out $(PRESET),$(BED_FROM)),_on_$(BED_FROM)_bed)
$(SLICE_DIR)/run.h5: $(PULLOFF_SCENE) $(PRESET_FILE) pipeline/slice_5mm.toml results/$(BED_FROM)/fill/run.h5 $(DEM2D)
	@$(simulating)
	$(DEM2D) run $(PULLOFF_SCENE) $(OVERLAY) --overlay pipeline/slice_5mm.toml \
	  --initial results/$(BED_FROM)/fill/run.h5 --out $(@D) $(RUN_OPTIONS)

$(SLICE_DIR)/metrics.json: $(SLICE_DIR)/run.h5 data/study.toml $(STAGE_PROGRAM_pulloff_metrics)
	$(STAGE_PROGRAM_pulloff_metrics) $< --out $(@D)

$(RESULTS)/cyclic/run.h5: $(CYCLIC_SCENE) $(OVERLAY_FILES) $(FILL_RUN) $(DEM2D)
	@$(simulating)
	$(DEM2D) run $(CYCLIC_SCENE) $(OVERLAY) --initial $(FILL_RUN) --out $(@D) $(RUN_OPTIONS)

$(RESULTS)/cyclic/metrics.json: $(RESULTS)/cyclic/run.h5 data/study.toml $(STAGE_PROGRAM_pulloff_metrics)
	$(STAGE_PROGRAM_pulloff_metrics) $< --out $(@D) --cycles

# --- metrics, tolerance tests, figures, report -------------------------------
$(RESULTS)/metrics.json: $(STAGE_METRICS) pipeline/stages.toml $(REPORT_SCRIPTS)/merge_metrics.py pipeline/files.py
	$(PYTHON) -m pipeline.report.merge_metrics $(RESULTS) $(PRESET) $(FILL_RUN)

# The tolerance tests' verdicts for the report: misses do not stop the
# reproduction (`make check` fails on them); a broken check program does.
# $(call check_into,ARGS): the tolerance tests of ARGS (metrics [--ensemble stats])
# into $@ (GoogleTest JSON) and $(@D)/check.log; says the verdicts in the report's words and each
# target that does not pass (value, target, source); for the quick scene only the counts, which check
# the pipeline and say nothing of the paper
check_into = $(CHECK) $(1) data/paper_targets.toml $(2) --gtest_output=json:$@.tmp > $(@D)/check.log 2>&1; rc=$$?; \
  if [ $$rc -gt 1 ] || [ ! -s $@.tmp ]; then cat $(@D)/check.log; exit 1; fi; mv $@.tmp $@; \
  if [ "$(PRESET)" = quick ]; then \
    grep -E '^\[  VERDICTS \]' $(@D)/check.log | sed 's/^\[  VERDICTS \]/  the quick test scene, not comparable with the paper:/'; \
  else grep -E '^\[  VERDICTS \]|: (fail|fails|undetermined)( \(about [0-9]+ members would decide\))? \[' $(@D)/check.log | \
    sed -e 's/^R[0-9]/  &/' -e 's/^\[  VERDICTS \]/  verdicts:/'; fi
$(RESULTS)/check.json: $(RESULTS)/metrics.json data/paper_targets.toml $(CHECK)
	@$(call check_into,$<)

FIGURE_SCRIPTS := $(filter-out %/report.py %/merge_metrics.py,$(wildcard $(REPORT_SCRIPTS)/*.py)) pipeline/files.py
$(RESULTS)/figures/index.json: $(STAGE_METRICS) data/study.toml $(FIGURE_SCRIPTS)
	$(PYTHON) -m pipeline.report.figures $(RESULTS) --preset $(PRESET)$(if $(INTRUDER),_$(INTRUDER))

$(RESULTS)/report.md: $(RESULTS)/metrics.json $(RESULTS)/check.json $(RESULTS)/figures/index.json \
                      $(REPORT_SCRIPTS)/report.py $(REPORT_SCRIPTS)/deviations.toml
	$(PYTHON) -m pipeline.report.report $(RESULTS) $(PRESET)

# ParaView's view of the force network (the paper's Fig. 6b) from the pull-off's run.xdmf, headless:
# pvbatch on an Xvfb of its own (ParaView renders only through X): pipeline/paraview/force_network.py
PVBATCH ?= pvbatch
$(RESULTS)/figures/force_network_paraview.png: $(RESULTS)/pulloff/run.h5 pipeline/paraview/force_network.py \
                                              pipeline/paraview/headless.py
	@mkdir -p $(@D)
	$(PYTHON) pipeline/paraview/headless.py $(PVBATCH) pipeline/paraview/force_network.py $(RESULTS)/pulloff $@
paraview: $(RESULTS)/figures/force_network_paraview.png

pulloff-slice: $(SLICE_DIR)/metrics.json
cyclic: $(RESULTS)/cyclic/metrics.json
metrics: $(RESULTS)/metrics.json
figures: $(RESULTS)/figures/index.json
report: $(RESULTS)/report.md

# Every paper target, one GoogleTest test each; fails on any miss.
check: $(RESULTS)/metrics.json $(CHECK)
	$(CHECK) $< data/paper_targets.toml

# --- make accuracy: the accuracy/cost sweep (data/accuracy.toml) ------------
ACCURACY := results/accuracy
ifneq ($(filter accuracy $(ACCURACY)/%,$(MAKECMDGOALS)),)
ifneq ($(PRESET),default)
$(error make accuracy sweeps around the preset of data/accuracy.toml; run it without PRESET=)
endif
include $(ACCURACY)/plan.mk
endif
$(ACCURACY)/plan.mk: data/accuracy.toml pipeline/accuracy/plan.py pipeline/pulloff.toml $(wildcard pipeline/presets/*.toml)
	$(PYTHON) -m pipeline.accuracy.plan data/accuracy.toml $(ACCURACY)

$(ACCURACY)/table.md: $(ACCURACY_TARGETS) data/accuracy.toml data/paper_targets.toml pipeline/accuracy/table.py
	$(PYTHON) -m pipeline.accuracy.table data/accuracy.toml $(ACCURACY)

accuracy: $(ACCURACY)/table.md

# an ensemble (by default the default preset's: make ensemble PRESET=default first) against the whole-run
# reference's members (pipeline/accuracy/ensemble_vs_reference.py)
ACCURACY_ENSEMBLE ?= results/default/ensemble
$(ACCURACY)/ensemble_vs_reference.md: $(ACCURACY_REFERENCE_TARGETS) $(wildcard $(ACCURACY_ENSEMBLE)/metrics.json $(ACCURACY_ENSEMBLE)/check.json) \
    data/accuracy.toml data/paper_targets.toml pipeline/accuracy/ensemble_vs_reference.py
	$(PYTHON) -m pipeline.accuracy.ensemble_vs_reference data/accuracy.toml $(ACCURACY) $(ACCURACY_ENSEMBLE)

# --- make validate: cases with analytic or established references ---------
# (pipeline/validate/README.md): results/validate/table.md and figures; fails on any miss
validate: build
	$(PYTHON) -m pipeline.validate.validate $(DEM2D) results/validate --jobs $(JOBS)

# --- make ensemble: MEMBERS independent realisations (docs/ensemble.md) ----
# Member k (results/<preset>/ensemble/member_NNN/) is the whole study with the
# fill's grain seeds moved by k (member 0: the single run's seeds), made by
# the same rules on one thread; EXECUTOR=local runs JOBS members side by side
# through make's own job server. The aggregate (stats.json, metrics.json of
# the means, drag.csv/png) and its tolerance tests (check.json, table.md)
# follow. A rerun skips finished members and resumes a killed one.
MEMBERS ?= 4
EXECUTOR ?= local
ENSEMBLE := $(RESULTS)/ensemble
$(call check_count,MEMBERS,1,1000)
MEMBER_DIRS := $(foreach k,$(shell seq -f '%03g' 0 $$(( $(MEMBERS) - 1 )) 2>/dev/null),$(ENSEMBLE)/member_$(k))

$(ENSEMBLE)/member_%/member.toml: $(FILL_SCENE) $(OVERLAY_FILES) pipeline/ensemble/member_overlay.py
	$(PYTHON) -m pipeline.ensemble.member_overlay $(FILL_SCENE) $$((10#$*)) $@ $(OVERLAY_FILES)

.PRECIOUS: $(ENSEMBLE)/member_%/member.toml
# the member's own make decides what is stale in it (under make -n, where member.toml is not written,
# it is shown, not run: it would stop for want of member.toml)
$(ENSEMBLE)/member_%/metrics.json: $(ENSEMBLE)/member_%/member.toml $(DEM2D) $(STAGE_PROGRAMS) $(CHECK) FORCE
	+@if [ -e $< ]; then $(MAKE) --no-print-directory metrics PRESET=$(PRESET) RESULTS=$(@D) FILL_OVERLAY=$< THREADS=1 PROGRAMS_BUILT=1; \
	  else echo "$(MAKE) metrics PRESET=$(PRESET) RESULTS=$(@D) FILL_OVERLAY=$< THREADS=1 PROGRAMS_BUILT=1"; fi

# the member list, rewritten only when MEMBERS changes it (then the aggregate is redone)
$(ENSEMBLE)/members.txt: FORCE
	@mkdir -p $(@D); echo '$(notdir $(MEMBER_DIRS))' | cmp -s - $@ || echo '$(notdir $(MEMBER_DIRS))' > $@

$(ENSEMBLE)/stats.json: $(addsuffix /metrics.json,$(MEMBER_DIRS)) $(ENSEMBLE)/members.txt pipeline/ensemble/aggregate.py $(STAGE_REGISTRY)
	$(PYTHON) -m pipeline.ensemble.aggregate --registry $(STAGE_REGISTRY) $(@D) $(PRESET) $(MEMBER_DIRS)

$(ENSEMBLE)/check.json: $(ENSEMBLE)/stats.json data/paper_targets.toml $(CHECK)
	@$(call check_into,$(@D)/metrics.json,--ensemble $<)

$(ENSEMBLE)/table.md: $(ENSEMBLE)/check.json pipeline/ensemble/table.py
	$(PYTHON) -m pipeline.ensemble.table $(@D)

# EXECUTOR=slurm: an array job of the same member targets, then the aggregate
# (pipeline/slurm/submit_ensemble.sh; SLURM_WAIT=1 waits for it, at most SLURM_WAIT_MINUTES)
SLURM_WAIT ?=
ifeq ($(EXECUTOR),local)
ensemble:
	+@$(MAKE) --no-print-directory -j$(JOBS) $(ENSEMBLE)/table.md
	@echo "make ensemble: $(MEMBERS) members of $(PRESET) in $(ENSEMBLE); the table is $(ENSEMBLE)/table.md"
else ifeq ($(EXECUTOR),slurm)
ensemble: $(DEM2D) $(STAGE_PROGRAMS) $(CHECK)
	pipeline/slurm/submit_ensemble.sh $(ENSEMBLE) $(MEMBERS) \
	  "$$($(PYTHON) -m pipeline.slurm.member_minutes $(FILL_SCENE) $(PULLOFF_SCENE) $(PRESET_FILE))" "$(SLURM_WAIT)" \
	  PRESET=$(PRESET) MEMBERS=$(MEMBERS) \
	  RESULTS=$(RESULTS) $(if $(INTRUDER),INTRUDER=$(INTRUDER)) $(if $(INSTALLED),INSTALLED=$(INSTALLED)) PYTHON=$(PYTHON)
else
ensemble:
	$(error EXECUTOR=$(EXECUTOR): use local or slurm)
endif

# --- make params: the parametric study of the paper's claims (docs/params.md) ---
# PLAN=reduced (default: here, ~2 h on 2 cores), full (with EXECUTOR=slurm) or test,
# from data/params.toml; every point an ensemble; results/params[_<plan>]/report.md.
PLAN ?= reduced
PARAMS := results/params$(if $(filter-out reduced,$(PLAN)),_$(PLAN))
ifneq ($(filter params $(PARAMS)/%,$(MAKECMDGOALS)),)
include $(PARAMS)/plan.mk
endif
$(PARAMS)/plan.mk: data/params.toml pipeline/params/plan.py pipeline/tomlwrite.py pipeline/fill.toml pipeline/pulloff.toml \
                   pipeline/params/fill_settle.toml pipeline/intruders/square.toml $(wildcard pipeline/presets/*.toml)
	$(PYTHON) -m pipeline.params.plan data/params.toml $(PLAN) $(PARAMS)

$(PARAMS)/report.md: $(PARAMS_STATS) data/params.toml pipeline/params/report.py
	$(PYTHON) -m pipeline.params.report $(PARAMS)

ifeq ($(EXECUTOR),local)
params: $(PARAMS)/plan.mk
	+@$(MAKE) --no-print-directory -j$(JOBS) $(PARAMS)/report.md PLAN=$(PLAN)
	@echo "make params: plan $(PLAN) in $(PARAMS); the report is $(PARAMS)/report.md"
else ifeq ($(EXECUTOR),slurm)
params: $(PARAMS)/plan.mk $(DEM2D) $(STAGE_PROGRAMS) $(CHECK)
	pipeline/slurm/submit_targets.sh $(PARAMS)/slurm "$(SLURM_WAIT)" $(PARAMS)/report.md $(PARAMS)/targets.txt \
	  PLAN=$(PLAN) $(if $(INSTALLED),INSTALLED=$(INSTALLED)) PYTHON=$(PYTHON)
endif

reproduce: $(RESULTS)/report.md
	@echo "make reproduce: $(RESULTS) is up to date; the report is $(RESULTS)/report.md (one page: report.html)"

clean:
	rm -rf build
