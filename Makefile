# Every target runs inside the project's virtual environment (.venv), made on demand.
PYTHON ?= python3
VENV   ?= .venv
PY      = $(VENV)/bin/python

CC       ?= gcc
STRICT    = -std=c99 -Wall -Wextra -Wpedantic -Wconversion -Wshadow -Werror
SANITIZE  = -std=c99 -g -O1 -fsanitize=address,undefined -fno-sanitize-recover=all

.PHONY: all venv analyze generate check build test test-all lint sanitize bench clean

all: generate build test

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

venv: $(VENV)/.installed
$(VENV)/.installed: pyproject.toml setup.py codegen/build_ext.py $(wildcard generated/*/*) $(PY)
	$(PY) -m pip install --quiet -e '.[test]'
	touch $@

generate: venv  ## regenerate generated/ from the model (byte-for-byte reproducible)
	$(PY) -m codegen generate

check: venv  ## fail if generated/ differs from what the generator emits now
	$(PY) -m codegen generate --check

build: venv  ## rebuild the cffi extension in place after editing generated/
	$(PY) -m pip install --quiet --no-build-isolation -e .

analyze: venv  ## the paper's example: every equilibrium and its vibration (Table 3)
	$(PY) -m codegen analyze

test: venv check  ## generated/ up to date, then the test suite without the slow property runs
	$(PY) -m pytest -m "not slow"

test-all: venv check  ## what CI runs: the whole suite, slow property runs included
	$(PY) -m pytest

LIBS = $(patsubst generated/%/,%,$(filter-out generated/runtime/,$(wildcard generated/*/)))

lint:  ## gcc and clang with strict warnings, and cppcheck, over every library in generated/
	for cc in gcc clang; do for lib in $(LIBS); do for f in generated/$$lib/*.c generated/runtime/*.c; do \
	  $$cc $(STRICT) -O2 -Igenerated/$$lib -Igenerated/runtime -c $$f -o /dev/null || exit 1; \
	done; done; done
	for lib in $(LIBS); do cppcheck --quiet --error-exitcode=1 \
	  --enable=warning,style,performance,portability --std=c99 --inline-suppr \
	  -Igenerated/$$lib -Igenerated/runtime generated/$$lib/*.c generated/runtime/*.c || exit 1; done

sanitize:  ## C drivers under AddressSanitizer + UBSan: every library (random/hostile sets), Table 2
	mkdir -p build
	$(CC) $(SANITIZE) -Igenerated/doughty -Igenerated/runtime tests/c/sanitize_driver.c \
	  generated/doughty/*.c generated/runtime/*.c -lm \
	  -o build/sanitize_driver
	ASAN_OPTIONS=detect_leaks=1 ./build/sanitize_driver 5000
	for lib in $(LIBS); do \
	  $(PYTHON) tests/c/make_driver.py generated/$$lib build/driver_$$lib.c && \
	  $(CC) $(SANITIZE) -Igenerated/$$lib -Igenerated/runtime build/driver_$$lib.c \
	    generated/$$lib/*.c generated/runtime/*.c -lm -o build/driver_$$lib && \
	  ASAN_OPTIONS=detect_leaks=1 ./build/driver_$$lib 800 || exit 1; done

bench: venv  ## time the compiled functions (see benchmarks/)
	$(PY) benchmarks/run.py

clean:
	rm -rf build dist *.egg-info codegen/_native_* .pytest_cache $(VENV)/.installed
