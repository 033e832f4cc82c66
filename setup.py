# cffi's setuptools hook is only reachable from setup(); everything else is in pyproject.toml.
from setuptools import setup

setup(cffi_modules=["codegen/build_ext.py:ffibuilder"])
