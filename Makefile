# Every target runs inside the project's virtual environment (.venv), made on demand.
PYTHON ?= python3
VENV   ?= .venv
PY      = $(VENV)/bin/python

.PHONY: all venv analyze generate check build test bench clean

all: generate build test

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

venv: $(VENV)/.installed
$(VENV)/.installed: pyproject.toml setup.py codegen/build_ext.py $(wildcard generated/*) $(PY)
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

test: venv check  ## generated/ up to date, then the whole test suite (what CI runs)
	$(PY) -m pytest

bench: venv  ## time the compiled functions (see benchmarks/)
	$(PY) benchmarks/run.py

clean:
	rm -rf build dist *.egg-info codegen/_native.* .pytest_cache
