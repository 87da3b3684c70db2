# hairlod entry points. `make demo` and `make test` set up everything they need (Debian packages
# through scripts/bootstrap.sh), build, and run.
PYTHON    := /usr/bin/python3
BUILD_DIR := build
JOBS      ?= 2
CMAKE_ARGS ?=

.PHONY: all bootstrap build demo test test-cpp test-python test-blender test-ui test-packages test-debian13 test-sid addon bench fuzz clean

all: build

bootstrap:
	@scripts/bootstrap.sh

$(BUILD_DIR)/CMakeCache.txt:
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=$(PYTHON) $(CMAKE_ARGS)

build: $(BUILD_DIR)/CMakeCache.txt
	cmake --build $(BUILD_DIR) -j $(JOBS)

demo: bootstrap build
	$(PYTHON) examples/demo.py

test: bootstrap build
	$(MAKE) --no-print-directory test-cpp test-python test-blender test-ui test-packages test-debian13 test-sid

test-cpp:
	ctest --test-dir $(BUILD_DIR) --output-on-failure -j $(JOBS)

test-python:
	$(PYTHON) -m pytest -q -rs tests/python

test-blender:
	scripts/run_blender_tests.sh

test-ui:
	scripts/run_ui_tests.sh

# The packages for this Python (cp311) unpacked in a bare Debian 12 (python3 and NumPy only), as the
# legacy add-on and as the extension's wheel: import, build an LoD, bake (tests/packages/bare_import.py).
test-packages: build
	rm -rf $(BUILD_DIR)/packages
	$(PYTHON) scripts/build_addon.py --output-dir $(BUILD_DIR)/packages
	scripts/chroot.sh bare12 setup
	scripts/chroot.sh bare12 run python3 tests/packages/bare_import.py $(BUILD_DIR)/packages/hairlod-*-linux_x64-legacy.zip legacy examples/data/bob.hair
	scripts/chroot.sh bare12 run python3 tests/packages/bare_import.py $(BUILD_DIR)/packages/hairlod-*-linux_x64.zip extension examples/data/bob.hair

# The same suites on Debian 13 (Blender 4.3, Python 3.13, Embree 4, TBB 2022, NumPy 2) in a chroot
# that scripts/chroot.sh makes once per machine (needs root). DEBIAN13_SUITES picks suites.
DEBIAN13_SUITES ?= cpp python blender ui package
test-debian13:
	scripts/chroot.sh debian13 setup
	scripts/chroot.sh debian13 run env JOBS=$(JOBS) scripts/chroot_suite.sh $(DEBIAN13_SUITES)

# The add-on in Blender 5.2 LTS (Debian unstable: Python 3.14, pybind11 3, GCC 16) in a third chroot:
# the headless-Blender and UI suites and the extension installed there. SID_SUITES picks suites (the
# C++ and Python suites run too with `make test-sid SID_SUITES="cpp python blender ui package"`).
SID_SUITES ?= blender ui package
test-sid:
	scripts/chroot.sh sid setup
	scripts/chroot.sh sid run env JOBS=$(JOBS) scripts/chroot_suite.sh $(SID_SUITES)

# dist/: the extension and the legacy zip for cp311 (here), cp313 (built in the Debian 13 chroot) and
# cp314 (in the sid chroot, for Debian's Blender 5.2).
addon: build
	$(PYTHON) scripts/build_addon.py
	scripts/chroot.sh debian13 setup
	scripts/chroot.sh debian13 run sh -c 'scripts/chroot_suite.sh core && python3 scripts/build_addon.py'
	scripts/chroot.sh sid setup
	scripts/chroot.sh sid run sh -c 'scripts/chroot_suite.sh core && python3 scripts/build_addon.py'

bench: bootstrap build
	scripts/bench.sh

FUZZ_TARGET  ?= cyhair
FUZZ_SECONDS ?= 60
# C++ readers (libFuzzer, scripts/fuzz.sh): cyhair usc_data ct2hair_bin ply_hair tfx.
# Python readers (scripts/fuzz_python.py, over the built package):
PYTHON_FUZZ_TARGETS := hairmesh manifest cameras params unpack
fuzz:
ifneq ($(filter $(FUZZ_TARGET),$(PYTHON_FUZZ_TARGETS)),)
	$(MAKE) --no-print-directory build
	$(PYTHON) scripts/fuzz_python.py $(FUZZ_TARGET) $(FUZZ_SECONDS)
else
	scripts/fuzz.sh $(FUZZ_TARGET) $(FUZZ_SECONDS)
endif

clean:
	rm -rf $(BUILD_DIR) build-debian13 build-sid dist addon/hairlod/_core*.so
