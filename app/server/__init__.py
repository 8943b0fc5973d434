"""Where the live runs compute and how the class is served: the thread pool, Dask actors, the socket guard,
session cleanup, and ``ringlab serve``'s server (its construction, accept loop and process family)."""
