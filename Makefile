# laserfit — the two commands a new user needs are `make demo` and `make test`; both install the
# Debian packages they need first (only the missing ones), then configure, build and run.
SHELL := /bin/bash
BUILD ?= build
JOBS ?= $(shell nproc)
# Sanitizer settings for test-asan and fuzz: every report is fatal; LeakSanitizer on, with the
# third-party libraries' own one-time allocations suppressed (tests/fuzz/lsan.supp).
ASAN_OPTIONS ?= detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=0
UBSAN_OPTIONS ?= print_stacktrace=1:halt_on_error=1
LSAN_OPTIONS ?= suppressions=$(CURDIR)/tests/fuzz/lsan.supp:print_suppressions=0
BIN := $(BUILD)/bin
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

# Debian packages the build, tests and benchmarks need.
DEB_PACKAGES := cmake ninja-build ccache g++ pkg-config \
  libeigen3-dev libpcl-dev libflann-dev libembree-dev libcgal-dev libassimp-dev libceres-dev \
  libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev \
  libocct-foundation-dev libyaml-cpp-dev libtbb-dev libgtest-dev libgmock-dev libbenchmark-dev \
  nlohmann-json3-dev libcli11-dev libboost-dev libvtk9-dev xvfb xauth \
  pybind11-dev python3-dev python3-numpy python3-pytest python3-open3d \
  libgrpc++-dev libprotobuf-dev protobuf-compiler protobuf-compiler-grpc python3-grpcio openssl \
  python3-protobuf
# The sanitizer and fuzzing build (make test-asan, make fuzz): clang with libFuzzer.
FUZZ_PACKAGES := clang libfuzzer-14-dev libclang-rt-14-dev llvm python3
# Only for the Open3D baseline of `make bench-registration` (large; not needed to build or test).
BENCH_PACKAGES := python3 python3-numpy python3-open3d

.PHONY: all install deps deps-bench deps-fuzz deps-slurm test-slurm build-asan test-asan fuzz fuzz-campaign fuzz-campaign-cli install-packages configure build test demo cad bench bench-cad bench-scan \
  bench-registration bench-registration-speed bench-global bench-quick bench-suites tune report paper clean format

all: build

deps:
	@$(MAKE) --no-print-directory install-packages PACKAGES="$(DEB_PACKAGES)"

deps-fuzz:
	@$(MAKE) --no-print-directory install-packages PACKAGES="$(FUZZ_PACKAGES)"

SLURM_PACKAGES := slurmctld slurmd slurm-client munge parallel python3
deps-slurm:
	@$(MAKE) --no-print-directory install-packages PACKAGES="$(SLURM_PACKAGES)"

deps-bench:
	@$(MAKE) --no-print-directory install-packages PACKAGES="$(BENCH_PACKAGES)"

install-packages:
	@missing=$$(for p in $(PACKAGES); do \
	  dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; \
	done); \
	if [ -n "$$missing" ]; then \
	  echo "make deps: installing $$missing"; \
	  $(SUDO) apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	else echo "make deps: all Debian packages present"; fi

$(BUILD)/build.ninja: CMakeLists.txt | deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release

configure: deps $(BUILD)/build.ninja

build: configure
	cmake --build $(BUILD) -j $(JOBS)

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

# Headers, static libraries, the two programs and the CMake package laserfit into PREFIX
# (find_package(laserfit COMPONENTS registration); see docs/cli.md "Using laserfit as a library").
PREFIX ?= /usr/local
install: build
	cmake --install $(BUILD) --prefix $(PREFIX)

# The test suite again, built by clang with AddressSanitizer + UndefinedBehaviorSanitizer (any
# report fails the test), plus the libFuzzer targets; a second build folder, $(ASAN_BUILD).
ASAN_BUILD ?= build-asan
$(ASAN_BUILD)/build.ninja: CMakeLists.txt | deps deps-fuzz
	CC=clang CXX=clang++ cmake -S . -B $(ASAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release \
	  -DLASERFIT_SANITIZE=ON -DLASERFIT_FUZZ=ON -DLASERFIT_BUILD_BENCHMARKS=OFF

build-asan: deps deps-fuzz $(ASAN_BUILD)/build.ninja
	cmake --build $(ASAN_BUILD) -j $(JOBS)

test-asan: build-asan
	ASAN_OPTIONS=$(ASAN_OPTIONS) UBSAN_OPTIONS=$(UBSAN_OPTIONS) LSAN_OPTIONS=$(LSAN_OPTIONS) \
	  ctest --test-dir $(ASAN_BUILD) --output-on-failure -j $(JOBS)

# Every fuzz target for FUZZ_SECONDS, from its committed seed corpus (tests/fuzz/corpus, read
# only; the growing corpus lives in out/fuzz/). Any finding fails: it is left in
# out/fuzz/findings/<target>/ to be fixed and committed to tests/fuzz/findings/<target>/.
FUZZ_SECONDS ?= 60
# FUZZ_SEED 0: libFuzzer picks one; CI fixes it so that a run is repeatable.
FUZZ_SEED ?= 0
FUZZ_TARGETS := cloud mesh raw_mesh scene cell benchmark thresholds manifest strings profiles scene_gt
# Memory: the fuzzer's RSS limit holds (but for mesh, below); its per-allocation limit is off
# because the isolated parsers' children (lib/core/isolate) run under their own limits and would
# otherwise report a parser's huge allocation, which the parent answers with an error line, as a
# finding.
# The mesh target runs without the RSS limit: libFuzzer checks it from a thread of its own, and with
# a second thread every fork takes ASan's locks (lib/core/src/isolate.cpp), whose unlocking copies
# the stack depot's pages in both processes: half the target's time. Its parent keeps only what
# the reader child answered, under the child's own limit, and raw_mesh fuzzes the decoding of that
# answer with the RSS limit on.
fuzz_limits = -rss_limit_mb=$(if $(filter mesh,$(1)),0,4096) -malloc_limit_mb=1048576
# A target that isolates a parser forks per input, and each child pays for what the parent maps
# and what it touches itself. Symbols bound at start: each child would otherwise resolve the
# parser's symbols lazily again (a fifth of the mesh target's time). A small ASan quarantine and
# shorter allocation stacks: the parent stays small (peak RSS 370 -> 164 MB) and the child copies
# fewer pages; inputs are <= 64 KiB, so 8 MB of freed memory still outlives any one input.
FUZZ_ASAN_OPTIONS := $(ASAN_OPTIONS):quarantine_size_mb=8:malloc_context_size=10
FUZZ_ENV := LD_BIND_NOW=1 ASAN_OPTIONS=$(FUZZ_ASAN_OPTIONS) UBSAN_OPTIONS=$(UBSAN_OPTIONS) \
  LSAN_OPTIONS=$(LSAN_OPTIONS)
fuzz: build-asan
	@$(MAKE) --no-print-directory -j $(JOBS) $(addprefix fuzz-run-,$(FUZZ_TARGETS))
	@echo "fuzz: no findings"

# One fuzz target for FUZZ_SECONDS (make fuzz runs JOBS of them at a time, one core each).
fuzz-run-%:
	@mkdir -p out/fuzz/corpus/$* out/fuzz/findings/$*
	@$(FUZZ_ENV) \
	  $(ASAN_BUILD)/bin/fuzz_$* out/fuzz/corpus/$* tests/fuzz/corpus/$* \
	    -max_total_time=$(FUZZ_SECONDS) -seed=$(FUZZ_SEED) -timeout=30 $(call fuzz_limits,$*) -max_len=65536 \
	    -artifact_prefix=out/fuzz/findings/$*/ -print_final_stats=1 \
	    > out/fuzz/$*.log 2>&1; rc=$$?; \
	  printf 'fuzz %s: %s s\n%s\n' $* $(FUZZ_SECONDS) \
	    "$$(grep -E '^(stat::number_of_executed_units|stat::peak_rss_mb)|cov:' out/fuzz/$*.log | tail -3)"; \
	  if [ $$rc -ne 0 ] || [ -n "$$(ls out/fuzz/findings/$*)" ]; then \
	    echo "fuzz $*: FINDING (exit $$rc), see out/fuzz/$*.log and out/fuzz/findings/$*/"; exit 1; fi

# The offline robustness campaign (a benchmark, not a test; hours on 2 cores, run with -j 2):
# FUZZ_RUNS executions of every fuzz target, then the black-box mutation of `laserfit import`
# (1000 mutated STEP files, 300 of each of a PLY, a binary and an ASCII STL and an OBJ, 120
# COLLADA), all into out/fuzz/campaign/. reports/fuzz/README.md summarises a run.
FUZZ_RUNS ?= 1000000
CAMPAIGN := out/fuzz/campaign
O2AC := tests/data/o2ac
fuzz-campaign: $(addprefix fuzz-campaign-,$(FUZZ_TARGETS)) fuzz-campaign-cli

fuzz-campaign-%: build-asan
	@mkdir -p $(CAMPAIGN)/corpus/$* $(CAMPAIGN)/findings/$*
	$(FUZZ_ENV) \
	  $(ASAN_BUILD)/bin/fuzz_$* $(CAMPAIGN)/corpus/$* tests/fuzz/corpus/$* -runs=$(FUZZ_RUNS) \
	  -timeout=30 $(call fuzz_limits,$*) -max_len=65536 -artifact_prefix=$(CAMPAIGN)/findings/$*/ \
	  -print_final_stats=1 > $(CAMPAIGN)/$*.log 2>&1

fuzz-campaign-cli: build deps-fuzz
	@mkdir -p $(CAMPAIGN)/cli
	$(BIN)/laserfit import $(O2AC)/02-PANEL.stl -o $(CAMPAIGN)/cli/panel.ply > /dev/null
	python3 benchmarks/fuzz/mutate_cli.py $(BIN)/laserfit $(CAMPAIGN)/cli/step --count 1000 --seed 1 \
	  --jobs $(JOBS) $(O2AC)/02-PANEL.step
	python3 benchmarks/fuzz/mutate_cli.py $(BIN)/laserfit $(CAMPAIGN)/cli/mesh --count 300 --seed 2 \
	  --jobs $(JOBS) $(CAMPAIGN)/cli/panel.ply $(O2AC)/02-PANEL.stl $(O2AC)/endcap_EDCS10.stl \
	  $(O2AC)/04_37D-GEARMOTOR-50-70.obj
	python3 benchmarks/fuzz/mutate_cli.py $(BIN)/laserfit $(CAMPAIGN)/cli/dae --count 120 --seed 3 \
	  --jobs $(JOBS) $(O2AC)/04_37D-GEARMOTOR-50-70.dae

# A real one-node Slurm (munge, slurmctld, slurmd on localhost, private configuration): the
# recipe tools/slurm/laserfit-bench-slurm as 4- and 16-task arrays, and GNU parallel, each merged
# and compared with a single run record by record.
test-slurm: build deps-slurm
	bash tests/slurm/test_slurm.sh $(BIN)

# The main job on built-in data: import a real CAD file, make reference clouds and scans of the
# built-in scenes, then the quick benchmark, the threshold tuning and the report.
demo: build
	@mkdir -p out/demo
	$(BIN)/laserfit import tests/data/o2ac/02-PANEL.step -o out/demo/panel.ply
	$(BIN)/laserfit refcloud cad/usb_a_plug.ply -o out/demo/usb_plug_full.pcd --count 200000 --method uniform --seed 1
	$(BIN)/laserfit refcloud cad/usb_a_plug.ply -o out/demo/usb_plug_front.pcd --count 100000 --view-dir 0,0,1 --seed 1
	$(BIN)/laserfit refcloud cad/needle.ply -o out/demo/needle_eye.pcd --density 2000 --method poisson --view "0 0 85 0 1 0 0" --seed 1
	$(BIN)/laserfit scan datasets/scenes/needle_thread.yaml -o out/demo/needle_thread_scan.pcd --gt out/demo/needle_thread_gt.json
	$(BIN)/laserfit scan datasets/scenes/usb_socket.yaml -o out/demo/usb_socket_scan.pcd --gt out/demo/usb_socket_gt.json
	@$(MAKE) --no-print-directory bench-quick tune report
	@echo; echo "demo outputs in out/demo/:"; ls -l out/demo
	@echo "quick benchmark: $(BENCH_OUT)/quick/ (results.jsonl, summary.csv)"
	@echo "tuned thresholds: $(THRESHOLDS)"
	@echo "report: $(REPORT_OUT)/README.md"

# --- benchmarks (batch work; see README "Benchmarks, tuning, reports") ---
BENCH_OUT ?= out/bench
# Where the benchmark targets write their results pages: out/, never a tracked file by default.
# The curated pages in reports/ are regenerated by the same target with RESULTS=reports (each
# page states its command); raw records are then committed xz-compressed (reports/README.md).
RESULTS ?= out/reports
BENCH_JOBS ?= $(JOBS)
SUITES ?= needle usb taskboard stress
THRESHOLDS ?= out/thresholds.yaml
TUNE_BENCH ?= benchmarks/quick.yaml
TUNE_PARAMS ?= rho_rot,rho_icp,min_overlap

# The quick profile (about a minute on 2 cores).
bench-quick: build
	$(BIN)/laserfit bench benchmarks/quick.yaml --out $(BENCH_OUT)/quick --jobs $(BENCH_JOBS)

# Threshold tuning on the first half of the repetitions, measured on the second half.
tune: build
	@mkdir -p $(dir $(THRESHOLDS))
	$(BIN)/laserfit tune $(TUNE_BENCH) --params $(TUNE_PARAMS) --jobs $(BENCH_JOBS) -o $(THRESHOLDS) \
	  --log $(basename $(THRESHOLDS))_search.json

# Report of the quick profile (REPORT_RESULTS / REPORT_OUT for others), into $(RESULTS)/quick.
REPORT_RESULTS ?= $(BENCH_OUT)/quick/results.jsonl
REPORT_OUT ?= $(RESULTS)/quick
report: build
	$(BIN)/laserfit report $(REPORT_RESULTS) -o $(REPORT_OUT)

# The full suites, one report each in $(RESULTS)/<suite>/ (hours on 2 cores; resumable: rerun).
bench-suites: build
	@for b in $(SUITES); do \
	  $(BIN)/laserfit bench benchmarks/$$b.yaml --out $(BENCH_OUT)/$$b --jobs $(BENCH_JOBS) && \
	  $(BIN)/laserfit report $(BENCH_OUT)/$$b/results.jsonl -o $(RESULTS)/$$b || exit 1; \
	done

# Regenerate the committed parametric CAD in cad/ (deterministic: same bytes every time).
cad: build
	$(BIN)/laserfit cad all -o cad

bench-cad: build
	@mkdir -p $(RESULTS)/cad
	$(BIN)/bench_cad --benchmark_out=$(RESULTS)/cad/bench_cad.json --benchmark_out_format=json \
	  --benchmark_counters_tabular=true | tee $(RESULTS)/cad/bench_cad.txt

bench-scan: build
	@mkdir -p $(RESULTS)/scan
	$(BIN)/bench_scan --benchmark_repetitions=5 --benchmark_min_time=2 \
	  --benchmark_out=$(RESULTS)/scan/bench_scan.json --benchmark_out_format=json \
	  --benchmark_counters_tabular=true | tee $(RESULTS)/scan/bench_scan.txt

# Registration accuracy campaign (benchmarks/registration.yaml, every method) with the Open3D
# baseline on the same scans: the first O3D_TRIALS of each scene are generated as a dataset, Open3D
# registers them, and one report puts everything side by side.
REG_OUT := $(RESULTS)/registration
O3D_TRIALS ?= 30
bench-registration: build deps-bench bench-registration-speed
	$(BIN)/laserfit bench benchmarks/registration.yaml --out $(BENCH_OUT)/registration --jobs $(BENCH_JOBS)
	$(BIN)/laserfit bench generate benchmarks/registration.yaml --repetitions 0:$(O3D_TRIALS) -o datasets/registration
	/usr/bin/python3 benchmarks/registration/open3d_baseline.py datasets/registration $(BENCH_OUT)/registration/open3d.jsonl
	$(BIN)/laserfit report $(BENCH_OUT)/registration/results.jsonl $(BENCH_OUT)/registration/open3d.jsonl -o $(REG_OUT)

# Registration with no prior (issue 35): real parts at random poses, and Open3D on the first
# GLOBAL_O3D_TRIALS scans of each part, after laserfit, so the timings do not share the CPUs.
GLOBAL_OUT := $(RESULTS)/registration/global
GLOBAL_O3D_TRIALS ?= 5
bench-global: build deps-bench
	$(BIN)/laserfit bench benchmarks/global.yaml --out $(BENCH_OUT)/global --jobs $(BENCH_JOBS)
	$(BIN)/laserfit bench generate benchmarks/global.yaml --repetitions 0:$(GLOBAL_O3D_TRIALS) -o datasets/global
	/usr/bin/python3 benchmarks/registration/open3d_baseline.py datasets/global $(BENCH_OUT)/global/open3d.jsonl
	$(BIN)/laserfit report $(BENCH_OUT)/global/results.jsonl $(BENCH_OUT)/global/open3d.jsonl -o $(GLOBAL_OUT)

# Registration speed on a 1 M-point scan (Google Benchmark, run on an otherwise idle machine).
bench-registration-speed: build
	@mkdir -p $(REG_OUT)
	$(BIN)/bench_registration --benchmark_out=$(REG_OUT)/bench_registration.json --benchmark_out_format=json \
	  --benchmark_counters_tabular=true | tee $(REG_OUT)/bench_registration.txt

bench: bench-cad bench-scan bench-registration bench-global bench-suites

# Reproduce the paper's Tables I and II in the simulated cell (3 needle poses x 10 starts; USB
# 10 starts), every strategy, with the tuned thresholds; outcomes and decision logs in $(RESULTS)/paper/.
PAPER_TRIALS ?= 0
paper: build
	@test -f $(THRESHOLDS) || $(MAKE) --no-print-directory tune
	@mkdir -p $(RESULTS)/paper
	@for c in needle usb; do \
	  $(BIN)/laserfit-controller sim --cell cells/$$c.yaml --thresholds $(THRESHOLDS) --strategy ic1,ic2,laser \
	    --trials $(PAPER_TRIALS) --jobs $(BENCH_JOBS) --out $(RESULTS)/paper/$${c}_trials.jsonl --json \
	    > $(RESULTS)/paper/$${c}_summary.json.tmp && mv $(RESULTS)/paper/$${c}_summary.json.tmp $(RESULTS)/paper/$${c}_summary.json \
	  || exit 1; cat $(RESULTS)/paper/$${c}_summary.json; \
	done

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) out
