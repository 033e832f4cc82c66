"""Shared by the tests: independent references, model galleries, random mechanisms, the C drivers."""
