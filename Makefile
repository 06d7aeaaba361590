# hullpose — entry points. Every target that builds first installs missing Debian
# packages (deploy/install-deps.sh), so `make demo` and `make test` work on a fresh machine.
BUILD       ?= build
BUILD_ASAN  ?= build-asan
BUILD_FUZZ  ?= build-fuzz
BUILD_PKG   ?= build-package
BUILD_ARM64 ?= build-arm64
JOBS        ?= $(shell nproc)
CMAKE_FLAGS ?=
FUZZ_SECONDS ?= 60
FUZZ_LONG_RUNS ?= 10000000
FUZZ_LONG_SECONDS ?= 14400
SOAK_MINUTES ?= 10
CMAKE       := cmake
CTEST_FLAGS ?= --output-on-failure --timeout 900

.PHONY: all deps configure build test test-asan test-gpu demo bench eval fuzz fuzz-long fuzz-build soak format format-check clean package cross

all: build

deps:
	@deploy/install-deps.sh

$(BUILD)/CMakeCache.txt: | deps
	$(CMAKE) -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo $(CMAKE_FLAGS)

configure: deps
	$(CMAKE) -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo $(CMAKE_FLAGS)

build: deps $(BUILD)/CMakeCache.txt
	$(CMAKE) --build $(BUILD) -j $(JOBS)

test: build
	cd $(BUILD) && ctest $(CTEST_FLAGS) -j $(JOBS) -LE gpu

# The unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer (CI runs this too);
# only their executables are built (target unit_tests).
test-asan: deps
	$(CMAKE) -S . -B $(BUILD_ASAN) -DCMAKE_BUILD_TYPE=Debug -DHULLPOSE_SANITIZE=address,undefined $(CMAKE_FLAGS)
	$(CMAKE) --build $(BUILD_ASAN) -j $(JOBS) --target unit_tests
	cd $(BUILD_ASAN) && ctest $(CTEST_FLAGS) -j $(JOBS) -L unit

test-gpu: build
	cd $(BUILD) && ctest $(CTEST_FLAGS) -L gpu

demo: build
	@tools/demo/run-demo.sh $(BUILD)

bench: build
	@tools/bench/run-bench.sh $(BUILD)

# Pose accuracy on every shared clip, both pose paths, 64^3 and 128^3 (tools/eval/run-eval.py).
eval: build
	@tools/eval/run-eval.py $(BUILD)

# FUZZ_RUNS=N stops each target at N executions (or FUZZ_SECONDS, if sooner); FUZZ_JOBS=N in parallel;
# FUZZ_TARGETS="fuzz_bvh fuzz_meta" runs only those (tools/fuzz/run-fuzz.sh).
fuzz: fuzz-build
	@tools/fuzz/run-fuzz.sh $(BUILD_FUZZ) $(FUZZ_SECONDS)

# The long run of issue 19: every target to FUZZ_LONG_RUNS executions (default 10 M) or
# FUZZ_LONG_SECONDS each (default 4 h), at nice 10. Not part of make test.
fuzz-long: fuzz-build
	FUZZ_RUNS=$(FUZZ_LONG_RUNS) nice -n 10 tools/fuzz/run-fuzz.sh $(BUILD_FUZZ) $(FUZZ_LONG_SECONDS)

fuzz-build: deps
	CC=clang CXX=clang++ $(CMAKE) -S . -B $(BUILD_FUZZ) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHULLPOSE_FUZZ=ON $(CMAKE_FLAGS)
	$(CMAKE) --build $(BUILD_FUZZ) -j $(JOBS) --target fuzz_targets

# The rig for SOAK_MINUTES in network namespaces (root): 8 nodes + master + host + listener at
# 30 Hz with 1 % loss; JSON summary in $(BUILD)/soak.json (tests/system/soak.sh).
soak: build
	tests/system/soak.sh $(BUILD) $(SOAK_MINUTES) $(BUILD)/soak.json

# The Debian packages per role (cmake/HullposePackaging.cmake) in $(BUILD_PKG)/packages, built for
# any CPU of this architecture (no -march=native), checked with lintian.
package: deps
	$(CMAKE) -S . -B $(BUILD_PKG) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHULLPOSE_NATIVE=OFF $(CMAKE_FLAGS)
	$(CMAKE) --build $(BUILD_PKG) -j $(JOBS) --target $$(sed -n 's/^HULLPOSE_PACKAGED_TARGETS=//p' $(BUILD_PKG)/hullpose-packaging.txt | tr ';' ' ')
	rm -rf $(BUILD_PKG)/packages && cd $(BUILD_PKG) && cpack -G DEB -B $(CURDIR)/$(BUILD_PKG)/packages && rm -rf packages/_CPack_Packages
	lintian --fail-on error,warning --suppress-tags-from-file deploy/debian/lintian-overrides.txt $(BUILD_PKG)/packages/*.deb

# The boards' build: arm64 packages from Debian's cross toolchain and an arm64 sysroot, unit tests
# under qemu-user-static (deploy/cross/build.sh; figures in $(BUILD_ARM64)/figures.txt).
cross: deps
	deploy/cross/build.sh $(BUILD_ARM64) $(JOBS)

# The repo's .clang-format over the project's C++ sources, i.e. the files git tracks (never a
# build dir or ../shared): `format` rewrites, `format-check` (CI)
# fails on the first file that differs.
FORMAT_FILES = git ls-files '*.cpp' '*.hpp' '*.cu' '*.cuh'

format: deps
	@$(FORMAT_FILES) | xargs clang-format -i

format-check: deps
	@$(FORMAT_FILES) | xargs clang-format --dry-run -Werror

clean:
	rm -rf $(BUILD) $(BUILD_ASAN) $(BUILD_FUZZ) $(BUILD_PKG) $(BUILD_ARM64)
