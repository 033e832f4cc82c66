"""The generated C libraries, compiled: against their symbolic originals, each other, strict compilers and the float build."""
