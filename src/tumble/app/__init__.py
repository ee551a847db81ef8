"""What the commands do, as library functions: run and verify a scenario (:mod:`.runner`), a
sweep on Dask (:mod:`.sweep`), the papers' claims (:mod:`.reproduce`), the benchmark
(:mod:`.bench`). The public names are exported at :mod:`tumble`."""
