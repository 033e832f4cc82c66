# Every target runs inside the project's virtual environment (.venv), made on demand.
PYTHON ?= python3
VENV   ?= .venv
PY      = $(VENV)/bin/python
CC     ?= gcc
STRICT  = -std=c99 -Wall -Wextra -Wpedantic -Wconversion -Wshadow -Werror

.PHONY: all venv generate check build test strict bench clean

all: generate build test

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

venv: $(VENV)/.installed
$(VENV)/.installed: pyproject.toml setup.py $(PY)
	$(PY) -m pip install --quiet -e '.[test]'
	touch $@

generate: venv  ## regenerate generated/ from the model (byte-for-byte reproducible)
	$(PY) -m codegen generate

check: venv  ## fail if generated/ differs from what the generator emits now
	$(PY) -m codegen generate --check

build: venv  ## rebuild the cffi extension in place after editing generated/
	$(PY) -m pip install --quiet --no-build-isolation -e .

strict:  ## compile the C library alone under the strict warning flags
	$(CC) $(STRICT) -O2 -c generated/*.c -Igenerated -o /dev/null 2>&1 || \
	  for f in generated/*.c; do $(CC) $(STRICT) -O2 -Igenerated -c $$f -o /dev/null || exit 1; done

test: venv  ## the whole test suite (what CI runs)
	$(PY) -m pytest

bench: venv  ## time the compiled functions (see benchmarks/)
	$(PY) benchmarks/run.py

clean:
	rm -rf build dist *.egg-info codegen/_native.* .pytest_cache
