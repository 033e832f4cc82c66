"""The C runtime (runtime/) compiled and tested on its own: see conftest.py."""
