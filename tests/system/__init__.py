"""End to end: the paper's tables, every mechanism and user models against independent references, the docs, packaging, builds, FMUs, the benchmarks, the import layers."""
