"""The command line as a user runs it: a subprocess, its output and its exit status."""
