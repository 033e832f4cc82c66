"""The Python runtime: the analysis, batches, sweeps, branches, the time and frequency responses, on compiled libraries."""
