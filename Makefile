# deformflow — the two set-up commands and a few helpers.
#   make demo    install what is missing, build the tools, run the demo pipeline, show where results are
#   make test    install what is missing, build, run the test suite (ctest)
#   make bench   benchmarks (bench/), results under $(BUILD)/bench
#   make golden-update [CASE=tool/case]  rewrites the expected files of the golden-file cases
#                tests/golden/<tool>/<case>/expected (all, or one; only on purpose, then review)
#   make test-sanitize  the whole test suite built with ASan + UBSan (build-asan/)
#   make fuzz [FUZZ_SECONDS=60]  libFuzzer targets of the input parsers (clang; build-fuzz/)
#   make update-golden  rewrites tests/unit/render/golden/*.png (only on purpose, then review)
#   make format / make format-check  clang-format (.clang-format) on every C++ file: rewrite / check
BUILD ?= build
JOBS ?= 2
OUT ?= out
CMAKE_FLAGS ?=
CTEST_ARGS ?=

ifeq ($(CI),true)
  CMAKE_FLAGS += -DDEFORMFLOW_WERROR=ON
endif

.PHONY: all deps configure build tools test demo bench clean update-golden golden-update test-sanitize fuzz format format-check
all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@test -f $(BUILD)/CMakeCache.txt || cmake -S . -B $(BUILD) $(CMAKE_FLAGS)

build: configure
	cmake --build $(BUILD) -j$(JOBS)

# The tools and the HDF5 plugin only (no tests, no benchmarks): what the demo runs.
tools: configure
	cmake --build $(BUILD) -j$(JOBS) --target tools

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS) $(CTEST_ARGS)

# (the demo's steps -j$(JOBS) at a time: its three models train side by side)
demo: tools
	$(MAKE) --no-print-directory -j$(JOBS) -f Makefile.data demo BIN=$(abspath $(BUILD))/bin OUT=$(OUT)

bench: build
	@bash scripts/install-deps.sh --with-bench
	bash bench/run.sh $(BUILD)

# Rewrites the golden picture of the renderer's unit test (review the PNG before committing).
update-golden: build
	DF_UPDATE_GOLDEN=1 $(BUILD)/tests/unit_tests "[golden]"

# Rewrites the expected outputs of the golden-file cases from this build (review `git diff`).
CASE ?= */*
golden-update: build
	@for c in tests/golden/$(CASE); do [ -f $$c/cmd ] || continue; \
	  DF_BIN=$(abspath $(BUILD))/bin DF_TEST_BIN=$(abspath $(BUILD))/tests \
	  DF_TMP=$(abspath $(BUILD))/tests/golden-tmp bash tests/golden/run.sh --update $$c || exit 1; done

# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (a separate build tree).
SANITIZE_ENV = ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  LSAN_OPTIONS=suppressions=$(abspath tests/lsan.supp):print_suppressions=0
test-sanitize: deps
	@test -f build-asan/CMakeCache.txt || cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDEFORMFLOW_SANITIZE=ON
	cmake --build build-asan -j$(JOBS)
	cd build-asan && $(SANITIZE_ENV) ctest --output-on-failure -j$(JOBS) -LE shared-data $(CTEST_ARGS)

# Fuzz every parser of outside input for FUZZ_SECONDS each (clang + libFuzzer; build-fuzz/).
FUZZ_SECONDS ?= 60
fuzz:
	@bash scripts/install-deps.sh --with-fuzz
	@CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DDEFORMFLOW_FUZZ=ON -DDEFORMFLOW_FUZZ_SECONDS=$(FUZZ_SECONDS) >/dev/null
	cmake --build build-fuzz -j$(JOBS) --target fuzzers
	cd build-fuzz && ctest --output-on-failure -j$(JOBS) -L fuzz

clean:
	rm -rf $(BUILD)

# Every C++ file of the repository in .clang-format's style (CI runs format-check).
CXX_FILES = $(shell git ls-files '*.cpp' '*.h' '*.hpp')
format:
	@bash scripts/install-deps.sh --with-format
	clang-format -i $(CXX_FILES)
format-check:
	@bash scripts/install-deps.sh --with-format
	@clang-format --dry-run -Werror $(CXX_FILES) && echo "format-check: $(words $(CXX_FILES)) files as .clang-format says"
