"""Code the benchmarks share; a package so that `make bench`, which runs bench/*.py, does not run it."""
