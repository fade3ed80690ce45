# Two commands do everything on a fresh Debian 12 machine:
#   make demo   install what is missing, build Release, render the default scene into out/
#               (replacing the files of an earlier `make demo`)
#   make test   install what is missing, build, run every test with CTest
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: deps build demo test bench golden sanitize clean

deps:
	@bash scripts/install-deps.sh

$(BUILD)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

build: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j $(JOBS)

demo: build
	./$(BUILD)/tissu render scenes/demo.json --out out --stills 4 --overwrite

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# Rewrites the golden frames of tests/golden/ on purpose (review the new PNGs, then commit).
golden: build
	cd $(BUILD) && TISSU_UPDATE_GOLDEN=1 ctest -R golden_test --output-on-failure

bench: build
	./$(BUILD)/bench/tissu_bench

# LeakSanitizer reports from third-party libraries (Mesa, assimp) are suppressed by
# tests/lsan.supp, never the project's own; the tissu processes that tests start inherit it.
sanitize:
	LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp $(MAKE) test BUILD=build-asan CMAKE_FLAGS="-DCMAKE_BUILD_TYPE=RelWithDebInfo -DTISSU_SANITIZE=ON"

clean:
	rm -rf $(BUILD) build-asan
