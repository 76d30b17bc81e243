# deformflow — the two set-up commands and a few helpers.
#   make demo    install what is missing, build, run the demo pipeline, show where results are
#   make test    install what is missing, build, run the test suite (ctest)
#   make bench   benchmarks (bench/), results under $(BUILD)/bench
#   make golden-update [CASE=tool/case]  rewrites the expected files of the golden-file cases
#                tests/golden/<tool>/<case>/expected (all, or one; only on purpose, then review)
#   make update-golden  rewrites tests/unit/render/golden/*.png (only on purpose, then review)
BUILD ?= build
JOBS ?= 2
OUT ?= out
CMAKE_FLAGS ?=
CTEST_ARGS ?=

ifeq ($(CI),true)
  CMAKE_FLAGS += -DDEFORMFLOW_WERROR=ON
endif

.PHONY: all deps configure build test demo bench clean update-golden golden-update
all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@test -f $(BUILD)/CMakeCache.txt || cmake -S . -B $(BUILD) $(CMAKE_FLAGS)

build: configure
	cmake --build $(BUILD) -j$(JOBS)

test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS) $(CTEST_ARGS)

demo: build
	$(MAKE) --no-print-directory -f Makefile.data demo BIN=$(abspath $(BUILD))/bin OUT=$(OUT)

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

clean:
	rm -rf $(BUILD)
