# KineticGyro: the two commands of the quick start, and a few more.
#   make demo   installs what is missing, builds, runs the showcase
#   make test   installs what is missing, builds, runs every test (and again under ASan+UBSan)
BUILD       ?= build
ASAN_BUILD  ?= build-asan
JOBS        ?= $(shell nproc 2>/dev/null || echo 2)
CMAKE_FLAGS ?=

.PHONY: all deps build test test-release test-sanitize test-fuzz demo bench fuzz soak clean device-check

all: build

deps:
	@bash scripts/install-deps.sh test

build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) >/dev/null
	@cmake --build $(BUILD) -j$(JOBS)

test: test-release test-sanitize test-fuzz

test-release: build
	@cd $(BUILD) && ctest --output-on-failure -j$(JOBS)

# The tests again, built by clang with AddressSanitizer and UndefinedBehaviorSanitizer.
test-sanitize: deps
	@CC=clang cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DKGYRO_SANITIZE=ON -DKGYRO_BUILD_BENCH=OFF >/dev/null
	@cmake --build $(ASAN_BUILD) -j$(JOBS)
	@cd $(ASAN_BUILD) && KGYRO_SANITIZED=1 ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
		UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ctest --output-on-failure -j$(JOBS) -LE slow

# Short fuzzing runs of every parser (libFuzzer, clang, ASan+UBSan).
test-fuzz: deps
	@bash scripts/fuzz.sh --short

fuzz: deps
	@bash scripts/fuzz.sh

soak: deps
	@bash scripts/soak.sh

bench: build
	@bash scripts/bench.sh $(BUILD)

# The OpenCL backend on this machine's device: installs (offline, from .debs/), builds,
# runs the OpenCL tests, benches rain_N and particles_N on the device and the CPU.
device-check:
	@JOBS=$(JOBS) bash scripts/device-check.sh $(BUILD)

demo: build
	@bash scripts/demo.sh $(BUILD)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) out
