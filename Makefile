# hullpose — entry points. Every target that builds first installs missing Debian
# packages (deploy/install-deps.sh), so `make demo` and `make test` work on a fresh machine.
BUILD       ?= build
BUILD_ASAN  ?= build-asan
BUILD_FUZZ  ?= build-fuzz
JOBS        ?= $(shell nproc)
CMAKE_FLAGS ?=
FUZZ_SECONDS ?= 60
CMAKE       := cmake
CTEST_FLAGS ?= --output-on-failure --timeout 900

.PHONY: all deps configure build test test-asan test-gpu demo bench fuzz format format-check clean

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

# The unit tests again under AddressSanitizer + UndefinedBehaviorSanitizer (CI runs this too).
test-asan: deps
	$(CMAKE) -S . -B $(BUILD_ASAN) -DCMAKE_BUILD_TYPE=Debug -DHULLPOSE_SANITIZE=address,undefined $(CMAKE_FLAGS)
	$(CMAKE) --build $(BUILD_ASAN) -j $(JOBS)
	cd $(BUILD_ASAN) && ctest $(CTEST_FLAGS) -j $(JOBS) -L unit

test-gpu: build
	cd $(BUILD) && ctest $(CTEST_FLAGS) -L gpu

demo: build
	@tools/demo/run-demo.sh $(BUILD)

bench: build
	@tools/bench/run-bench.sh $(BUILD)

fuzz: deps
	CC=clang CXX=clang++ $(CMAKE) -S . -B $(BUILD_FUZZ) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHULLPOSE_FUZZ=ON $(CMAKE_FLAGS)
	$(CMAKE) --build $(BUILD_FUZZ) -j $(JOBS) --target fuzz_targets
	@tools/fuzz/run-fuzz.sh $(BUILD_FUZZ) $(FUZZ_SECONDS)

# The repo's .clang-format over every tracked C++ file: `format` rewrites, `format-check` (CI)
# fails on the first file that differs.
FORMAT_FILES = git ls-files '*.cpp' '*.hpp' '*.cu' '*.cuh'

format: deps
	@$(FORMAT_FILES) | xargs clang-format -i

format-check: deps
	@$(FORMAT_FILES) | xargs clang-format --dry-run -Werror

clean:
	rm -rf $(BUILD) $(BUILD_ASAN) $(BUILD_FUZZ)
