# Every target that runs Python runs inside the project's virtual environment (.venv), made
# on demand. `make help` lists the targets: each is described by the `##` comment on its line.
PYTHON ?= python3
VENV   ?= .venv
PY      = $(VENV)/bin/python
# pyproject.toml's [build-system] requires (tests/system/test_packaging.py keeps the two equal),
# installed into .venv so that pip can build without isolation: fast, and offline.
BUILD_REQUIRES = 'setuptools>=77' 'wheel' 'cffi>=1.16'
INSTALL = $(PY) -m pip install --quiet --no-build-isolation -e '.[test]'

# The suite on every core (pytest-xdist): each test writes only under its own tmp_path (or
# into one build/ folder no other test writes), so neither order nor worker matters.
# `make test PYTEST_JOBS=` runs it in one process.
PYTEST_JOBS ?= -n auto

CC       ?= gcc
# The compiler flags' named sets (base, optimize, strict, promotion, sanitize), written once
# in runtime/cflags.txt for every build: the Makefile, CMake, embedded/ and Python read it.
include runtime/cflags.txt
STRICT    = $(base) $(strict)
SANITIZE  = $(base) $(sanitize)

.PHONY: all help venv analyze generate check build test test-all lint sanitize example bench same-results embedded clean
.DEFAULT_GOAL := all
# The targets share .venv, generated/ and the in-place extensions: one at a time, even with -j.
.NOTPARALLEL:

all:  ## generate, then rebuild the extensions if generated/ changed, then `make test`
	$(MAKE) --no-print-directory generate
	$(MAKE) --no-print-directory test

help:  ## list the targets
	@awk 'BEGIN {FS = ":.*## "} /^[a-z][a-z-]*:.*## / {printf "  %-12s %s\n", $$1, $$2}' \
	  $(MAKEFILE_LIST)

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

$(VENV)/.build-requires: | $(PY)
	$(PY) -m pip install --quiet $(BUILD_REQUIRES)
	touch $@

venv: $(VENV)/.installed  ## make .venv: build requirements, then this package (editable) and its test extras
$(VENV)/.installed: pyproject.toml setup.py codegen/__init__.py codegen/compiler/build.py \
                    runtime/cflags.txt $(wildcard generated/*/*) $(VENV)/.build-requires
	$(INSTALL)
	touch $@

generate: venv  ## regenerate generated/ from the models (byte-for-byte reproducible; unchanged files untouched)
	$(PY) -m codegen generate

check: venv  ## fail if generated/ differs from what the generator emits now
	$(PY) -m codegen generate --check

build: $(VENV)/.build-requires  ## rebuild the cffi extensions in place now (`venv` does it when generated/ changed)
	$(INSTALL)
	touch $(VENV)/.installed

analyze: venv  ## the paper's example: every equilibrium and its vibration (Table 3)
	$(PY) -m codegen analyze

test: venv check  ## generated/ up to date, then the test suite without the slow runs
	$(PY) -m pytest $(PYTEST_JOBS) -m "not slow"

test-all: venv check  ## what CI runs: the whole suite, slow runs (property runs, the wheel) included
	$(PY) -m pytest $(PYTEST_JOBS)

LIBS = $(patsubst generated/%/,%,$(filter-out generated/runtime/,$(wildcard generated/*/)))

# Both real types: the same sources compile as the double and as the float library.
# (cppcheck 2.10 sizes an array of codegen_real with 4-byte items across translation units
# and reports offsets inside it as overflows: ctuPointerArith is suppressed.)
REALS = double float

lint:  ## gcc and clang with strict warnings, and cppcheck, over every library in generated/, in double and float
	for real in $(REALS); do for cc in gcc clang; do for lib in $(LIBS); do \
	  for f in generated/$$lib/*.c generated/runtime/*.c; do \
	    $$cc $(STRICT) $(promotion) $(optimize) $$( [ $$real = float ] && echo -DCODEGEN_FLOAT ) \
	      -Igenerated/$$lib -Igenerated/runtime -c $$f -o /dev/null || exit 1; \
	done; done; done; done
	for real in $(REALS); do for lib in $(LIBS); do cppcheck --quiet --error-exitcode=1 \
	  --enable=warning,style,performance,portability --std=c99 --inline-suppr \
	  --suppress=ctuPointerArith $$( [ $$real = float ] && echo -DCODEGEN_FLOAT ) \
	  -Igenerated/$$lib -Igenerated/runtime generated/$$lib/*.c generated/runtime/*.c || exit 1; done; done

sanitize:  ## C drivers under AddressSanitizer + UBSan: every library (random/hostile sets), Table 2
	mkdir -p build
	$(CC) $(SANITIZE) -Igenerated/doughty -Igenerated/runtime tests/support/c/sanitize_driver.c \
	  generated/doughty/*.c generated/runtime/*.c -lm \
	  -o build/sanitize_driver
	ASAN_OPTIONS=detect_leaks=1 ./build/sanitize_driver 5000
	for lib in $(LIBS); do \
	  $(PYTHON) tests/support/c/make_driver.py generated/$$lib build/driver_$$lib.c && \
	  $(CC) $(SANITIZE) -Igenerated/$$lib -Igenerated/runtime build/driver_$$lib.c \
	    generated/$$lib/*.c generated/runtime/*.c -lm -o build/driver_$$lib && \
	  ASAN_OPTIONS=detect_leaks=1 ./build/driver_$$lib 800 || exit 1; done

example: build/minimal  ## compile examples/minimal.c with the doughty library into build/minimal, and run it
	./build/minimal

build/minimal: examples/minimal.c $(wildcard generated/doughty/*.[ch] generated/runtime/*.[ch])
	mkdir -p build
	$(CC) $(STRICT) $(optimize) -Igenerated/doughty -Igenerated/runtime examples/minimal.c \
	  generated/doughty/*.c generated/runtime/*.c -lm -o $@

# BENCH_ARGS=--quick: a smoke run of ~40 s (the derivations dominate); `--help` lists the sizes.
bench: venv  ## the library side by side with naive SymPy C and numpy: writes benchmarks/results.md and .json (~3 min)
	$(PY) benchmarks/run.py $(BENCH_ARGS)

# Every numerics change is checked with it: BASE's generated/ (`git archive`) against the
# working tree's, each mechanism built in double and float with both interval forms, every
# result of SETS parameter sets compared byte for byte; exit 1 if any differs. Python's
# standard library and gcc ($CC if set) only: no .venv. SAME_RESULTS_ARGS: more options
# (`python3 benchmarks/same_results.py --help`).
BASE ?= HEAD
SETS ?= 2000
same-results:  ## every analysis of every library, BASE's generated/ against the working tree's, bit for bit (BASE=HEAD SETS=2000)
	$(PYTHON) benchmarks/same_results.py --base '$(BASE)' --sets $(SETS) $(SAME_RESULTS_ARGS)

# The cross toolchain and QEMU: apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi
# qemu-system-arm. Its own makefile, which may run two compilers at once (.NOTPARALLEL is ours).
EMBEDDED_REPORT ?= embedded/report
embedded:  ## every library on a Cortex-M4F under QEMU (double, float) vs the host: writes embedded/report.md and .json
	$(MAKE) --no-print-directory -j2 -f embedded/embedded.mk LIBS="$(LIBS)" PYTHON=$(PYTHON) \
	  REPORT=$(EMBEDDED_REPORT)

clean:  ## remove what builds leave (build/, dist/, egg-info, the in-place extensions); the next target reinstalls
	rm -rf build dist *.egg-info codegen/_native_* .pytest_cache $(VENV)/.installed minimal
	rm -f generated/*/*.o
