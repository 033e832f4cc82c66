"""Symbolic mechanics of a mechanism -> a verified, embeddable C99 library."""

__version__ = "0.1.0"
