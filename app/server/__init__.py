"""Where the live runs compute: the thread pool, Dask actors, the socket guard and session cleanup."""
