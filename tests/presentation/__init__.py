"""The figures and drawings of codegen.presentation."""
