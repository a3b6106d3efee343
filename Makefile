# laserfit — the two commands a new user needs are `make demo` and `make test`; both install the
# Debian packages they need first (only the missing ones), then configure, build and run.
SHELL := /bin/bash
BUILD ?= build
JOBS ?= $(shell nproc)
BIN := $(BUILD)/bin
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)

# Debian packages the build, tests and benchmarks need.
DEB_PACKAGES := cmake ninja-build ccache g++ pkg-config \
  libeigen3-dev libpcl-dev libflann-dev libembree-dev libcgal-dev libassimp-dev libceres-dev \
  libocct-data-exchange-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev \
  libocct-foundation-dev libyaml-cpp-dev libtbb-dev libgtest-dev libgmock-dev libbenchmark-dev \
  nlohmann-json3-dev libcli11-dev
# Only for the Open3D baseline of `make bench-registration` (large; not needed to build or test).
BENCH_PACKAGES := python3 python3-numpy python3-open3d

.PHONY: all deps deps-bench install-packages configure build test demo cad bench bench-cad bench-scan bench-registration bench-registration-speed clean format

all: build

deps:
	@$(MAKE) --no-print-directory install-packages PACKAGES="$(DEB_PACKAGES)"

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

# The main job on built-in data: import a real CAD file, make full and view-dependent reference
# clouds of the project's USB plug, and say where everything is.
demo: build
	@mkdir -p out/demo
	$(BIN)/laserfit import tests/data/o2ac/02-PANEL.step -o out/demo/panel.ply
	$(BIN)/laserfit refcloud cad/usb_a_plug.ply -o out/demo/usb_plug_full.pcd --count 200000 --method uniform --seed 1
	$(BIN)/laserfit refcloud cad/usb_a_plug.ply -o out/demo/usb_plug_front.pcd --count 100000 --view-dir 0,0,1 --seed 1
	$(BIN)/laserfit refcloud cad/needle.ply -o out/demo/needle_eye.pcd --density 2000 --method poisson --view "0 0 85 0 1 0 0" --seed 1
	$(BIN)/laserfit scan datasets/scenes/needle_thread.yaml -o out/demo/needle_thread_scan.pcd --gt out/demo/needle_thread_gt.json
	$(BIN)/laserfit scan datasets/scenes/usb_socket.yaml -o out/demo/usb_socket_scan.pcd --gt out/demo/usb_socket_gt.json
	@echo; echo "demo outputs in out/demo/:"; ls -l out/demo

# Regenerate the committed parametric CAD in cad/ (deterministic: same bytes every time).
cad: build
	$(BIN)/laserfit cad all -o cad

bench-cad: build
	@mkdir -p reports/cad
	$(BIN)/bench_cad --benchmark_out=reports/cad/bench_cad.json --benchmark_out_format=json \
	  --benchmark_counters_tabular=true | tee reports/cad/bench_cad.txt

bench-scan: build
	@mkdir -p reports/scan
	$(BIN)/bench_scan --benchmark_out=reports/scan/bench_scan.json --benchmark_out_format=json \
	  --benchmark_counters_tabular=true | tee reports/scan/bench_scan.txt

# Registration accuracy campaign (benchmarks/registration.yaml; TRIALS=N overrides its count,
# METHODS=a,b the methods) with the Open3D baseline on the same scans, table in reports/.
TRIALS ?= 0
METHODS ?= ceres,point_to_plane,point_to_point,gicp,ndt,paper
REG_OUT := reports/registration
bench-registration: build deps-bench bench-registration-speed
	@mkdir -p $(REG_OUT) out/registration_dump
	$(BIN)/registration_campaign benchmarks/registration.yaml --trials $(TRIALS) --methods $(METHODS) \
	  --out $(REG_OUT) --dump out/registration_dump --dump-trials 50
	/usr/bin/python3 benchmarks/registration/open3d_baseline.py out/registration_dump $(REG_OUT)/open3d.jsonl
	/usr/bin/python3 benchmarks/registration/summarize.py $(REG_OUT)/results.jsonl $(REG_OUT)/open3d.jsonl \
	  | tee $(REG_OUT)/table.md

# Registration speed on a 1 M-point scan (Google Benchmark, run on an otherwise idle machine).
bench-registration-speed: build
	@mkdir -p $(REG_OUT)
	$(BIN)/bench_registration --benchmark_out=$(REG_OUT)/bench_registration.json --benchmark_out_format=json \
	  --benchmark_counters_tabular=true | tee $(REG_OUT)/bench_registration.txt

bench: bench-cad bench-scan bench-registration

format:
	clang-format -i $$(git ls-files '*.cpp' '*.hpp')

clean:
	rm -rf $(BUILD) out
